/* A run with the spec's events: see lagcli_events.h. Shipped with lagcli
 * (lagcli/runtime/c/) and copied next to every generated C model; C99 + libm. */
#include <float.h>
#include <math.h>
#include <stdlib.h>
#include <string.h>

#include "lagcli_events.h"
#include "lagcli_linalg.h"

static const char *const ACTION_NAMES[3] = {"impact", "reset", "stop"};

typedef struct {
    const lagcli_event_run *run;
    const lagcli_events *ev;
    lagcli_ode_stepper *stepper;
    lagcli_event_result *result;
    int n;                      /* nstate */
    double *y, *y_minus, *y_plus, *y_dense;
    double *g_old, *g_new, *g_scratch;
    double *last, *fastest;     /* per event: its last time, its largest approach speed */
    double *inv;                /* the invariants (the constraint residual after a reset) */
    double *G, *d;              /* an impact's dg/dq (nq) and the constraint rows' d (nlambda) */
    double t;                   /* the time of the last event (its y+ in y) */
    int from_zero;              /* its g starts at exactly 0 (an impact, a reset that left g) */
    long used;                  /* steps taken, over every segment */
} event_loop;

enum { END = 200 };             /* act(), segment(): the run ends at this event */
enum { UNRESOLVED = -2 };       /* earliest(): the event just handled recurs unresolved */

static int crossed(int direction, double before, double after)
{
    int falling = before > 0.0 && after <= 0.0, rising = before < 0.0 && after >= 0.0;
    return direction < 0 ? falling : direction > 0 ? rising : (falling || rising);
}

/* g_k on the last step's interpolant at t. */
static double g_at(event_loop *L, int k, double t)
{
    lagcli_ode_stepper_dense(L->stepper, t, L->y_dense);
    L->ev->functions(t, L->y_dense, L->run->p, L->g_scratch);
    return L->g_scratch[k];
}

/* Brent's method (scipy's brentq, scipy/optimize/Zeros/brentq.c) for g_k on [a, b]: lagcli
 * ships C99 + libm only, so it is written out here. */
static double brent(event_loop *L, int k, double xa, double xb)
{
    const double rtol = 4.0 * DBL_EPSILON, xtol = rtol * (fabs(xb) > 1.0 ? fabs(xb) : 1.0);
    double xpre = xa, xcur = xb, xblk = 0.0, fblk = 0.0, spre = 0.0, scur = 0.0;
    double fpre = g_at(L, k, xpre), fcur = g_at(L, k, xcur);
    int i;
    if (fpre == 0.0)
        return xpre;
    if (fcur == 0.0 || signbit(fpre) == signbit(fcur))
        return xcur;
    for (i = 0; i < 100; ++i) {
        double delta, sbis, stry;
        if (fpre != 0.0 && fcur != 0.0 && signbit(fpre) != signbit(fcur)) {
            xblk = xpre;
            fblk = fpre;
            spre = scur = xcur - xpre;
        }
        if (fabs(fblk) < fabs(fcur)) {
            xpre = xcur; xcur = xblk; xblk = xpre;
            fpre = fcur; fcur = fblk; fblk = fpre;
        }
        delta = (xtol + rtol * fabs(xcur)) / 2.0;
        sbis = (xblk - xcur) / 2.0;
        if (fcur == 0.0 || fabs(sbis) < delta)
            return xcur;
        if (fabs(spre) > delta && fabs(fcur) < fabs(fpre)) {
            if (xpre == xblk) {
                stry = -fcur * (xcur - xpre) / (fcur - fpre);
            } else {
                double dpre = (fpre - fcur) / (xpre - xcur), dblk = (fblk - fcur) / (xblk - xcur);
                stry = -fcur * (fblk * dblk - fpre * dpre) / (dblk * dpre * (fblk - fpre));
            }
            if (2.0 * fabs(stry) < fmin(fabs(spre), 3.0 * fabs(sbis) - delta)) {
                spre = scur;
                scur = stry;
            } else {
                spre = scur = sbis;
            }
        } else {
            spre = scur = sbis;
        }
        xpre = xcur;
        fpre = fcur;
        xcur += fabs(scur) > delta ? scur : (sbis > 0.0 ? delta : -delta);
        fcur = g_at(L, k, xcur);
    }
    return xcur;
}

static void end_line(event_loop *L, const char *kind, int k, double t, double value)
{
    char *note = L->result->end_note;
    const size_t size = sizeof L->result->end_note;
    const char *name = L->ev->names[k];
    if (L->run->log != NULL)
        fprintf(L->run->log, "end,%s,%s,%.17g,%.17g\n", kind, name, t, value);
    L->result->ended = 1;
    /* the words of lagcli/runtime/run_limits.py, end_note */
    if (strcmp(kind, "recurred") == 0)
        snprintf(note, size, "event '%.100s' recurred after %.3g s at t = %.10g (accumulation: closer than "
                 "%g x max(1, t)); the run ends there", name, value, t, LAGCLI_EVENTS_GAP);
    else if (strcmp(kind, "resting") == 0)
        snprintf(note, size, "event '%.100s' at t = %.10g: separation speed %.3g after the impact (below %g x "
                 "the largest approach speed: the contact has come to rest); the run ends there", name, t,
                 value, LAGCLI_EVENTS_RESTING);
    else if (strcmp(kind, "unresolved") == 0)
        snprintf(note, size, "event '%.100s' recurs at t = %.10g faster than the integrator's step can "
                 "resolve (accumulation); the run ends there", name, t);
    else
        snprintf(note, size, "%ld events (the budget of one run) by t = %.10g; the run ends there",
                 LAGCLI_EVENTS_BUDGET, t);
}

/* The event just handled, in the first step after it: a crossing in its direction on
 * LAGCLI_EVENTS_SAMPLES samples of the step (L->from_zero: g starts at exactly 0, after an
 * impact or a reset that left g as it was; only an impact must turn back, else it
 * accumulates). 1 with the bracket, 0 for none, -1 when it returns faster than the
 * samples resolve. */
static int bracket_after_event(event_loop *L, int k, double t_old, double t_new, double *a, double *b)
{
    const int from_zero = L->from_zero, impact = L->ev->actions[k] == LAGCLI_EVENT_IMPACT;
    const double step = (t_new - t_old) / LAGCLI_EVENTS_SAMPLES;
    const int direction = L->ev->directions[k];
    double before = 0.0, first = 0.0;
    int i, found_first = 0;
    for (i = 0; i <= LAGCLI_EVENTS_SAMPLES; ++i) {
        double t = i == LAGCLI_EVENTS_SAMPLES ? t_new : (double)i * step + t_old;
        double value = from_zero && i == 0 ? 0.0 : g_at(L, k, t);
        if (i > 0 && crossed(direction, before, value)) {
            *a = (double)(i - 1) * step + t_old;
            *b = t;
            return 1;
        }
        if (!found_first && value != 0.0) {
            first = value;
            found_first = 1;
        }
        before = value;
    }
    if (!found_first || (impact && ((direction < 0 && first < 0.0) || (direction > 0 && first > 0.0)))) {
        end_line(L, "unresolved", k, t_old, t_old);
        return -1;
    }
    return 0;
}

/* The earliest event in the last step: its index (its time in *t_hit, the state there in
 * y_minus), -1 for none, or UNRESOLVED. `fired`: the event handled just before this step, or -1. */
static int earliest(event_loop *L, int fired, double *t_hit)
{
    const double t_old = lagcli_ode_stepper_t_old(L->stepper), t_new = lagcli_ode_stepper_t(L->stepper);
    int k, best = -1;
    for (k = 0; k < L->ev->nevent; ++k) {
        double a = t_old, b = t_new, root;
        int found;
        if (k == fired) {
            found = bracket_after_event(L, k, t_old, t_new, &a, &b);
            if (found < 0)
                return UNRESOLVED;
        } else {
            found = crossed(L->ev->directions[k], L->g_old[k], L->g_new[k]);
        }
        if (!found)
            continue;
        root = a < b ? brent(L, k, a, b) : b;
        if (best < 0 || root < *t_hit) {
            best = k;
            *t_hit = root;
        }
    }
    if (best >= 0)
        lagcli_ode_stepper_dense(L->stepper, *t_hit, L->y_minus);
    return best;
}

int lagcli_events_impact(const lagcli_model *m, int k, double t, const double *y, const double *p,
                         double *qd_plus, double *P)
{
    const int n = m->nq, nl = m->nlambda, N = n + 1 + nl;
    double *K = (double *)calloc((size_t)(N * N + N + n * n + nl * n + nl + n + 2), sizeof *K);
    double *r = K + N * N, *M = r + N, *A = M + n * n, *d = A + nl * n, *G = d + nl, g_t, e, Gv = 0.0;
    const double *v = y + n;
    int i, j, rc;
    if (K == NULL)
        return 2;
    rc = m->mass_matrix(t, y, p, M) != 0 || (nl > 0 && m->events->constraint_matrix(t, y, p, A) != 0);
    m->events->impact_terms(k, t, y, p, G, &g_t, &e, d);
    for (i = 0; i < n; ++i) {       /* [[M, -G^T, -A^T], [G, 0, 0], [A, 0, 0]] [q'+; P; Lambda] */
        r[i] = 0.0;
        for (j = 0; j < n; ++j) {
            K[i * N + j] = M[i * n + j];
            r[i] += M[i * n + j] * v[j];
        }
        K[i * N + n] = -G[i];
        K[n * N + i] = G[i];
        Gv += G[i] * v[i];
        for (j = 0; j < nl; ++j) {
            K[i * N + n + 1 + j] = -A[j * n + i];
            K[(n + 1 + j) * N + i] = A[j * n + i];
        }
    }
    r[n] = -e * (Gv + g_t) - g_t;   /* = [M q'-; -e (G q'- + g_t) - g_t; -d] */
    for (j = 0; j < nl; ++j)
        r[n + 1 + j] = -d[j];
    if (rc == 0)
        rc = lagcli_solve_lu(N, K, r);
    if (rc == 0) {
        memcpy(qd_plus, r, (size_t)n * sizeof *r);
        *P = r[n];
    }
    free(K);
    return rc;
}

/* dg/dt = G q' + g_t at the state before the impact k, with the velocities qd. */
static double approach_speed(event_loop *L, int k, double t, const double *qd)
{
    const lagcli_model *m = L->run->model;
    double g_t, e, speed = 0.0;
    int i;
    L->ev->impact_terms(k, t, L->y_minus, L->run->p, L->G, &g_t, &e, L->d);
    for (i = 0; i < m->nq; ++i)
        speed += L->G[i] * qd[i];
    return speed + g_t;
}

static void record(event_loop *L, int k, double t, double impulse)
{
    FILE *log = L->run->log;
    int i;
    if (log == NULL)
        return;
    fprintf(log, "event,%s,%s,%.17g", L->ev->names[k], ACTION_NAMES[L->ev->actions[k]], t);
    for (i = 0; i < L->n; ++i)
        fprintf(log, ",%.17g", L->y_minus[i]);
    for (i = 0; i < L->n; ++i)
        fprintf(log, ",%.17g", L->y_plus[i]);
    if (isnan(impulse))
        fprintf(log, ",\n");
    else
        fprintf(log, ",%.17g\n", impulse);
}

static int fail(event_loop *L, const char *format, int k, double t, double value)
{
    char text[600];
    snprintf(text, sizeof text, format, L->ev->names[k], value);     /* a long name is cut, not overrun */
    snprintf(L->result->message, sizeof L->result->message, "at t = %.10g: %s", t, text);
    return LAGCLI_EVENTS_FAILED;
}

/* An impact: y_plus, and whether the contact has come to rest (the run ends). */
static int impact(event_loop *L, int k, double t, double *impulse)
{
    const lagcli_model *m = L->run->model;
    const int nq = m->nq;
    double before, after;
    int rc;
    memcpy(L->y_plus, L->y_minus, (size_t)L->n * sizeof *L->y_plus);
    rc = lagcli_events_impact(m, k, t, L->y_minus, L->run->p, L->y_plus + nq, impulse);
    if (rc == 1)
        return fail(L, "event '%s' (impact): the impact's direction dg/dq lies in the span of the constraint "
                    "rows (or the mass matrix is singular): no impulse can change the approach speed", k, t, 0.0);
    if (rc != 0)
        return fail(L, "event '%s' (impact): the velocities after it are not finite (inf/nan)", k, t, 0.0);
    before = fabs(approach_speed(L, k, t, L->y_minus + nq));
    after = fabs(approach_speed(L, k, t, L->y_plus + nq));
    if (before > L->fastest[k])
        L->fastest[k] = before;
    record(L, k, t, *impulse);
    if (after <= LAGCLI_EVENTS_RESTING * L->fastest[k]) {
        end_line(L, "resting", k, t, after);
        return END;
    }
    return LAGCLI_ODE_OK;
}

/* The action of event k at t (the state before in y_minus): the state after in y; 0, END
 * (the run ends here), or LAGCLI_EVENTS_FAILED. */
static int act(event_loop *L, int k, double t)
{
    const lagcli_model *m = L->run->model;
    const int action = L->ev->actions[k];
    double impulse = nan(""), gap;
    int rc = LAGCLI_ODE_OK;
    L->t = t;
    ++L->result->events;
    if (action == LAGCLI_EVENT_STOP) {
        memcpy(L->y_plus, L->y_minus, (size_t)L->n * sizeof *L->y_plus);
        memcpy(L->y, L->y_minus, (size_t)L->n * sizeof *L->y);
        record(L, k, t, impulse);
        L->result->ended = 1;
        return END;
    }
    L->from_zero = 1;
    if (action == LAGCLI_EVENT_RESET) {
        double g_before;
        L->ev->reset(k, t, L->y_minus, L->run->p, L->y_plus);
        L->ev->functions(t, L->y_minus, L->run->p, L->g_scratch);
        g_before = L->g_scratch[k];
        L->ev->functions(t, L->y_plus, L->run->p, L->g_scratch);
        L->from_zero = L->g_scratch[k] == g_before;    /* g left at its root: it has crossed */
        if (m->residual_column >= 0) {
            (void)m->invariants(t, L->y_plus, L->run->p, L->inv);
            if (L->inv[m->residual_column] > L->run->constraint_tolerance)
                return fail(L, "event '%s' (reset) gives a state that violates the constraints "
                            "(constraint_residual = %.3g); reset the dependent coordinates and velocities "
                            "consistently", k, t, L->inv[m->residual_column]);
        }
        record(L, k, t, impulse);
    } else if ((rc = impact(L, k, t, &impulse)) == LAGCLI_EVENTS_FAILED) {
        return rc;
    }
    memcpy(L->y, L->y_plus, (size_t)L->n * sizeof *L->y);
    if (rc == END)
        return END;
    gap = t - L->last[k];
    L->last[k] = t;
    if (gap < LAGCLI_EVENTS_GAP * (fabs(t) > 1.0 ? fabs(t) : 1.0)) {
        end_line(L, "recurred", k, t, gap);
        return END;
    }
    if (L->result->events >= LAGCLI_EVENTS_BUDGET) {
        end_line(L, "budget", k, t, (double)LAGCLI_EVENTS_BUDGET);
        return END;
    }
    return LAGCLI_ODE_OK;
}

/* Every impact's restitution in [0, 1] with the run's parameters (it is a constant). */
static int check_restitution(event_loop *L, const double *y0)
{
    int k;
    for (k = 0; k < L->ev->nevent; ++k) {
        double g_t, e;
        if (L->ev->actions[k] != LAGCLI_EVENT_IMPACT)
            continue;
        L->ev->impact_terms(k, 0.0, y0, L->run->p, L->G, &g_t, &e, L->d);
        if (!(e >= 0.0 && e <= 1.0)) {
            sprintf(L->result->message, "event '%.200s': restitution = %g with these parameter values; "
                    "it must be in [0, 1]", L->ev->names[k], e);
            return LAGCLI_EVENTS_BAD_VALUES;
        }
    }
    return LAGCLI_ODE_OK;
}

static void add_stats(event_loop *L)
{
    lagcli_ode_stats s;
    lagcli_ode_stepper_stats(L->stepper, &s);
    L->result->stats.t = s.t;
    L->result->stats.nfev += s.nfev;
    L->result->stats.n_accepted += s.n_accepted;
    L->result->stats.n_rejected += s.n_rejected;
}

/* One segment: steps from (L->t, L->y) until an event or t_end, the rows of the output
 * times before it (*next: the next output time's index). LAGCLI_ODE_OK with *hit the
 * event (t* in *t_hit, y- in y_minus) or -1 at t_end; END; or a LAGCLI_ODE_* error. */
static int segment(event_loop *L, int fired, size_t *next, int *hit, double *t_hit)
{
    const lagcli_event_run *run = L->run;
    int rc, first = 1;
    if ((rc = lagcli_ode_stepper_start(L->stepper, L->t, L->y, run->t_end)) != LAGCLI_ODE_OK)
        return rc;
    L->ev->functions(L->t, L->y, run->p, L->g_old);
    for (;;) {
        double *swap, end, t;
        if (run->max_steps > 0 && L->used >= run->max_steps)
            return LAGCLI_ODE_ERR_MAX_STEPS;
        ++L->used;
        if ((rc = lagcli_ode_stepper_step(L->stepper)) != LAGCLI_ODE_OK)
            return rc;
        t = lagcli_ode_stepper_t(L->stepper);
        L->ev->functions(t, lagcli_ode_stepper_y(L->stepper), run->p, L->g_new);
        *hit = earliest(L, first ? fired : -1, t_hit);
        if (*hit == UNRESOLVED)
            return END;
        end = *hit >= 0 ? *t_hit : t;
        while (*next < run->ntimes) {
            double t_out = run->time_at(run->times, *next);
            if (!(t_out < end || (*hit < 0 && t_out <= end)))
                break;
            lagcli_ode_stepper_dense(L->stepper, t_out, L->y_dense);
            if (run->row(t_out, L->y_dense, run->ctx) != 0)
                return LAGCLI_ODE_INTERRUPTED;
            ++*next;
        }
        if (*hit >= 0 || t == run->t_end)
            return LAGCLI_ODE_OK;
        swap = L->g_old;
        L->g_old = L->g_new;
        L->g_new = swap;
        first = 0;
    }
}

static int run_loop(event_loop *L)
{
    size_t next = 1;
    int fired = -1, rc;
    for (;;) {
        double t_hit = 0.0;
        int hit = -1;
        rc = segment(L, fired, &next, &hit, &t_hit);
        add_stats(L);
        if (rc == LAGCLI_ODE_OK && hit < 0)
            return LAGCLI_ODE_OK;
        if (rc == LAGCLI_ODE_OK) {
            rc = act(L, hit, t_hit);
            fired = hit;
        }
        if (rc == END)     /* the last row: the state after the last event (before a stop) */
            return L->run->row(L->t, L->y, L->run->ctx) != 0 ? LAGCLI_ODE_INTERRUPTED : LAGCLI_ODE_OK;
        if (rc != LAGCLI_ODE_OK)
            return rc;
    }
}

int lagcli_events_integrate(const lagcli_event_run *run, const double *y0, lagcli_event_result *result)
{
    const lagcli_model *m = run->model;
    const int n = m->nstate, ne = m->events->nevent;
    size_t size = (size_t)(5 * n + 5 * ne + m->ninv + m->nq + m->nlambda) + 1;
    event_loop L;
    double *work = (double *)calloc(size, sizeof *work);
    int k, rc;
    memset(result, 0, sizeof *result);
    memset(&L, 0, sizeof L);
    L.stepper = lagcli_ode_stepper_new(run->method, run->rhs, run->ctx, n, run->rtol, run->atol, run->max_step);
    if (work == NULL || L.stepper == NULL) {
        free(work);
        lagcli_ode_stepper_free(L.stepper);
        return L.stepper == NULL && work != NULL ? LAGCLI_ODE_ERR_ARGS : LAGCLI_ODE_ERR_NOMEM;
    }
    L.run = run;
    L.ev = m->events;
    L.result = result;
    L.n = n;
    L.y = work;
    L.y_minus = L.y + n;
    L.y_plus = L.y_minus + n;
    L.y_dense = L.y_plus + n;
    L.g_old = L.y_dense + n;
    L.g_new = L.g_old + ne;
    L.g_scratch = L.g_new + ne;
    L.last = L.g_scratch + ne;
    L.fastest = L.last + ne;
    L.inv = L.fastest + ne;
    L.G = L.inv + m->ninv;
    L.d = L.G + m->nq;
    for (k = 0; k < ne; ++k)
        L.last[k] = -HUGE_VAL;
    memcpy(L.y, y0, (size_t)n * sizeof *y0);
    if ((rc = check_restitution(&L, y0)) == LAGCLI_ODE_OK)
        rc = run_loop(&L);
    result->stats.message = lagcli_ode_message(rc >= LAGCLI_EVENTS_FAILED ? LAGCLI_ODE_OK : rc);
    lagcli_ode_stepper_free(L.stepper);
    free(work);
    return rc;
}
