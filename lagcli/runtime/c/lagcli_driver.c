/* The command-line driver of a generated lagcli model: options, output times, the CSV
 * of `lagcli simulate`. Shipped with lagcli (lagcli/runtime/c/) and copied next to every
 * generated C model; C99 + libm. The model is a lagcli_model (lagcli_model.h).
 *
 *   ./<name> [--t-end T] [--dt DT] [--method RK45|DOP853|variational] [--rtol R] [--atol A]
 *       [--set NAME=VALUE]... [--init NAME=VALUE]... [--baumgarte ALPHA BETA] [--steps-per-row K]
 *       [--max-steps N] [--events FILE]
 *
 * Defaults: the model's (the spec's simulate: and initial: blocks), Baumgarte
 * alpha = beta = LAGCLI_BAUMGARTE. Integrates from t = 0 and prints a header (t, state,
 * multipliers, invariants), then one row (%.17g) per output time t_k = k dt,
 * k = 0 .. floor(t_end/dt + LAGCLI_OUTPUT_SLACK), and t_end if not reached, through a
 * 64 KiB stdout buffer (a reader gets rows in blocks, not one write per row). Memory does
 * not grow with the number of rows: the output times are made LAGCLI_WINDOW at a time and
 * the integrator restarts from the last row's state at the end of each window (a run of
 * up to LAGCLI_WINDOW rows is one integration). On failure: "error: at t = ...: reason" on stderr, exit status 1, the rows
 * so far kept. Bad options: exit status 2.
 * Constrained models: the step is capped at 1/|lambda| of the Baumgarte-damped
 * constraint error (max_step), and an initial state that violates the constraints by
 * more than LAGCLI_CONSTRAINT_TOLERANCE is integrated as given, with a warning on stderr.
 * --method variational: lagcli_variational.c, K = --steps-per-row fixed steps of (the interval
 * between output times) / K, carrying (q, p) from row to row; the rows' multipliers are those of
 * the exact equations (alpha = beta = 0). A model without the variational functions
 * (nonholonomic constraints) refuses it with exit status 2.
 * A model with events (model->events) runs them with lagcli_events.c (RK45, DOP853; the
 * run may end early at an event, exit status 0); --events FILE writes their log
 * (lagcli_events.h), which lagcli reads. A restitution outside [0, 1] is exit status 2.
 *
 * The numbers below are the C side of lagcli/interface.py (tests/test_c_runtime.py
 * checks that both say the same).
 */
#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <time.h>

#include "lagcli_driver.h"
#include "lagcli_events.h"
#include "lagcli_ode.h"
#include "lagcli_variational.h"

#define LAGCLI_OUTPUT_SLACK 1e-9          /* t_end/dt this close below an integer reaches it */
#define LAGCLI_END_TOLERANCE 1e-12        /* relative: a last t_k this close to t_end is t_end */
#define LAGCLI_CONSTRAINT_TOLERANCE 1e-08 /* largest |constraint| of a consistent initial state */
#define LAGCLI_CONSTRAINT_TOLERANCE_TEXT "1e-08"
#define LAGCLI_BAUMGARTE 10.0             /* default alpha = beta of the constraint stabilisation */
#define LAGCLI_METHODS "RK45|DOP853|variational"   /* lagcli_ode's explicit methods, lagcli_variational */
#define LAGCLI_WINDOW 65536               /* output times per integration (see the top) */
#define LAGCLI_MAX_EXCEED 16              /* --exceed options of a batch */
#define LAGCLI_STEP_BUDGET_BASE 20000     /* default --max-steps: this many steps ... */
#define LAGCLI_STEP_BUDGET_PER_OUTPUT 1000 /* ... plus this many per output interval (t_end/dt) */
#define STEP_BUDGET_TEXT "the integration reached its bound of %ld steps before t_end " \
    "(a stiff or blowing-up solution?); raise the bound with --max-steps N"

typedef struct {
    const lagcli_model *model;
    double *p, *dydt, *lambda, *inv;   /* nparam, nstate, nlambda, ninv values */
    double *last;                      /* nstate: the state at the last output time */
    double alpha, beta;
    int code;      /* nonzero return of the model function that failed */
    double when;   /* and the time it failed at */
    void *batch;   /* the batch_run of a --batch run (the output callback's context is run_state) */
} run_state;

typedef struct {
    double t_end, dt, rtol, atol;
    const char *method;
    double max_steps; /* --max-steps: accepted steps a run may take (0: the default rule) */
    long bench;    /* --bench-integration N: time N silent integrations instead of printing */
    long steps_per_row;   /* --steps-per-row K (variational) */
    const char *events;   /* --events FILE: the log of the events (lagcli_events.h), or NULL */
    int batch;     /* --batch: many runs read from stdin (batch_main); 2 with --batch-rows */
    int nexceed;   /* --exceed NAME=VALUE: first time |NAME| > VALUE, in the batch summaries */
    int exceed_index[LAGCLI_MAX_EXCEED];
    double exceed_value[LAGCLI_MAX_EXCEED];
} run_settings;

static const char *reason(int code)
{
    return code == 1 ? "singular mass matrix or constraint matrix"
                     : "the accelerations are not finite (inf/nan)";
}

static int rhs(double t, const double *y, double *dydt, void *ctx)
{
    run_state *run = (run_state *)ctx;
    int rc = run->model->rhs_stabilized(t, y, run->p, run->alpha, run->beta, dydt, NULL);
    if (rc != 0) {
        run->code = rc;
        run->when = t;
    }
    return rc;
}

/* One CSV row: t, y, the multipliers of the stabilised system, the invariants. */
static int row(double t, const double *y, void *ctx)
{
    run_state *run = (run_state *)ctx;
    const lagcli_model *m = run->model;
    int i, rc;
    memcpy(run->last, y, (size_t)m->nstate * sizeof *y);
    rc = m->rhs_stabilized(t, y, run->p, run->alpha, run->beta, run->dydt, run->lambda);
    if (rc != 0) {
        run->code = rc;
        run->when = t;
        return 1;
    }
    (void)m->invariants(t, y, run->p, run->inv);   /* non-finite values are printed as such */
    printf("%.17g", t);
    for (i = 0; i < m->nstate; ++i)
        printf(",%.17g", y[i]);
    for (i = 0; i < m->nlambda; ++i)
        printf(",%.17g", run->lambda[i]);
    for (i = 0; i < m->ninv; ++i)
        printf(",%.17g", run->inv[i]);
    printf("\n");
    return 0;
}

static void header(const lagcli_model *m)
{
    const char *const *lists[3];
    int k, i;
    lists[0] = m->state_names;
    lists[1] = m->multiplier_names;
    lists[2] = m->invariant_names;
    printf("t");
    for (k = 0; k < 3; ++k)
        for (i = 0; lists[k][i] != NULL; ++i)
            printf(",%s", lists[k][i]);
    printf("\n");
    fflush(stdout);
}

static int usage(const char *program, const char *problem)
{
    if (problem != NULL)
        fprintf(stderr, "error: %s\n", problem);
    fprintf(problem != NULL ? stderr : stdout,
            "usage: %s [--t-end T] [--dt DT] [--method " LAGCLI_METHODS "] [--rtol R] [--atol A]\n"
            "       [--set NAME=VALUE]... [--init NAME=VALUE]... [--baumgarte ALPHA BETA]\n"
            "       [--max-steps N] [--steps-per-row K]   (variational: K fixed steps between rows)\n"
            "       [--events FILE]   (a model with events: one line per event, lagcli_events.h)\n",
            program);
    return problem != NULL ? 2 : 0;
}

/* A finite number, the whole of `text`. */
static int number(const char *text, double *value)
{
    char *end;
    if (text == NULL || *text == '\0')
        return 0;
    *value = strtod(text, &end);
    return *end == '\0' && isfinite(*value);
}

/* NAME=VALUE into values[index of NAME in names]; on failure a message (exit status 2). */
static int assign(const char *option, const char *item, const char *const *names, const char *what,
                  double *values, char *message)
{
    const char *eq = strchr(item, '=');
    int i;
    if (eq == NULL || eq == item) {
        sprintf(message, "%s %.200s: expected NAME=VALUE", option, item);
        return 0;
    }
    for (i = 0; names[i] != NULL; ++i)
        if (strlen(names[i]) == (size_t)(eq - item) && strncmp(names[i], item, (size_t)(eq - item)) == 0) {
            if (number(eq + 1, &values[i]))
                return 1;
            sprintf(message, "%s %.200s: '%.200s' is not a number", option, item, eq + 1);
            return 0;
        }
    sprintf(message, "%s %.200s: unknown %s '%.*s'", option, item, what, (int)(eq - item < 200 ? eq - item : 200),
            item);
    return 0;
}

/* The value of option argv[*i] (`--opt VALUE` or `--opt=VALUE`), or NULL if it is not `option`. */
static const char *option(int argc, char **argv, int *i, const char *name, int *missing)
{
    size_t len = strlen(name);
    if (strncmp(argv[*i], name, len) != 0)
        return NULL;
    if (argv[*i][len] == '=')
        return argv[*i] + len + 1;
    if (argv[*i][len] != '\0')
        return NULL;
    if (*i + 1 >= argc) {
        *missing = 1;
        return NULL;
    }
    return argv[++*i];
}

static int exceed_option(const char *item, const lagcli_model *m, run_settings *s, char *message);
static int batch_main(const run_settings *s, run_state *run, const double *y0);

static int parse(int argc, char **argv, run_settings *s, run_state *run, double *y0)
{
    int i, missing = 0;
    const char *v;
    char message[720];
    for (i = 1; i < argc; ++i) {
        const char *arg = argv[i];
        if (strcmp(arg, "-h") == 0 || strcmp(arg, "--help") == 0)
            exit(usage(argv[0], NULL));
        if ((v = option(argc, argv, &i, "--t-end", &missing)) != NULL) {
            if (!number(v, &s->t_end) || s->t_end < 0)
                return usage(argv[0], "--t-end: expected a non-negative number");
        } else if ((v = option(argc, argv, &i, "--dt", &missing)) != NULL) {
            if (!number(v, &s->dt) || !(s->dt > 0))
                return usage(argv[0], "--dt: expected a positive number");
        } else if ((v = option(argc, argv, &i, "--rtol", &missing)) != NULL) {
            if (!number(v, &s->rtol) || !(s->rtol > 0))
                return usage(argv[0], "--rtol: expected a positive number");
        } else if ((v = option(argc, argv, &i, "--atol", &missing)) != NULL) {
            if (!number(v, &s->atol) || !(s->atol > 0))
                return usage(argv[0], "--atol: expected a positive number");
        } else if ((v = option(argc, argv, &i, "--method", &missing)) != NULL) {
            if (strcmp(v, "RK45") != 0 && strcmp(v, "DOP853") != 0 && strcmp(v, "variational") != 0)
                return usage(argv[0], "--method: the C driver implements RK45, DOP853 and variational");
            s->method = v;
        } else if ((v = option(argc, argv, &i, "--steps-per-row", &missing)) != NULL) {
            double count;
            if (!number(v, &count) || count < 1 || count > 1e9 || count != floor(count))
                return usage(argv[0], "--steps-per-row: expected a whole number from 1 to 1000000000");
            s->steps_per_row = (long)count;
        } else if ((v = option(argc, argv, &i, "--set", &missing)) != NULL) {
            if (!assign("--set", v, run->model->parameter_names, "parameter", run->p, message))
                return usage(argv[0], message);
        } else if ((v = option(argc, argv, &i, "--init", &missing)) != NULL) {
            if (!assign("--init", v, run->model->state_names, "coordinate or velocity", y0, message))
                return usage(argv[0], message);
        } else if ((v = option(argc, argv, &i, "--events", &missing)) != NULL) {
            s->events = v;
        } else if ((v = option(argc, argv, &i, "--max-steps", &missing)) != NULL) {
            if (!number(v, &s->max_steps) || s->max_steps < 1 || s->max_steps > 1e15
                || s->max_steps != floor(s->max_steps))
                return usage(argv[0], "--max-steps: expected a whole number of steps from 1 to 1e15");
        } else if ((v = option(argc, argv, &i, "--bench-integration", &missing)) != NULL) {
            double count;
            if (!number(v, &count) || count < 1 || count > 1e6 || count != floor(count))
                return usage(argv[0], "--bench-integration: expected a count from 1 to 1000000");
            s->bench = (long)count;
        } else if (strcmp(arg, "--batch") == 0 || strcmp(arg, "--batch-rows") == 0) {
            s->batch = strcmp(arg, "--batch") == 0 ? 1 : 2;
        } else if ((v = option(argc, argv, &i, "--exceed", &missing)) != NULL) {
            if (!exceed_option(v, run->model, s, message))
                return usage(argv[0], message);
        } else if (strcmp(arg, "--baumgarte") == 0) {
            if (i + 2 >= argc || !number(argv[i + 1], &run->alpha) || !number(argv[i + 2], &run->beta))
                return usage(argv[0], "--baumgarte: expected two numbers ALPHA BETA");
            i += 2;
        } else {
            sprintf(message, "%.200s: %s", arg, missing ? "missing value" : "unknown option");
            return usage(argv[0], message);
        }
    }
    return 0;
}

/* Largest step on a constrained system: h |lambda| <= 1 for the eigenvalues lambda =
 * -alpha +- sqrt(alpha^2 - beta^2) of the Baumgarte-damped constraint error, so that the
 * step controller never runs that mode at the edge of the stability region. */
static double max_step(const lagcli_model *m, double alpha, double beta)
{
    double a = fabs(alpha), b = fabs(beta), d = a * a - b * b, rate;
    if (m->nlambda == 0)
        return HUGE_VAL;
    rate = a + sqrt(d > 0.0 ? d : 0.0);
    if (b > rate)
        rate = b;
    return rate > 0.0 ? 1.0 / rate : HUGE_VAL;
}

/* A warning (the run goes on) when the initial state violates the constraints by more
 * than the tolerance: `lagcli simulate` solves for dependent coordinates and velocities,
 * this driver integrates the state exactly as given. */
static void check_initial(const double *y0, run_state *run)
{
    double residual;
    if (run->model->residual_column < 0)
        return;
    (void)run->model->invariants(0.0, y0, run->p, run->inv);    /* a non-finite residual warns too */
    residual = run->inv[run->model->residual_column];
    if (!(residual <= LAGCLI_CONSTRAINT_TOLERANCE))
        fprintf(stderr, "warning: the initial state violates the constraints: constraint_residual = %.3g "
                "(more than " LAGCLI_CONSTRAINT_TOLERANCE_TEXT "); integrating it as given\n", residual);
}

static int no_row(double t, const double *y, void *ctx)
{
    run_state *run = (run_state *)ctx;
    (void)t;
    memcpy(run->last, y, (size_t)run->model->nstate * sizeof *y);
    return 0;
}

/* The output times t_k = k dt, k = 0 .. floor(t_end/dt + LAGCLI_OUTPUT_SLACK), then t_end
 * if not reached: `count` of them, made on demand by time_at. */
typedef struct {
    double t_end, dt;
    size_t regular, count;
} output_times;

static output_times times_of(double t_end, double dt)
{
    output_times times;
    times.t_end = t_end;
    times.dt = dt;
    times.regular = (size_t)floor(t_end / dt + LAGCLI_OUTPUT_SLACK) + 1;
    times.count = times.regular;
    if ((double)(times.regular - 1) * dt < t_end - LAGCLI_END_TOLERANCE * (t_end > 1.0 ? t_end : 1.0))
        ++times.count;
    return times;
}

static double time_at(const output_times *times, size_t k)
{
    return k < times->regular ? (double)k * times->dt : times->t_end;
}

/* The steps a run may take: --max-steps, else LAGCLI_STEP_BUDGET_BASE plus
 * LAGCLI_STEP_BUDGET_PER_OUTPUT per output interval (lagcli.interface.default_max_steps). */
static long step_budget(const run_settings *s)
{
    if (s->max_steps > 0)
        return (long)s->max_steps;
    return LAGCLI_STEP_BUDGET_BASE + LAGCLI_STEP_BUDGET_PER_OUTPUT * (long)ceil(s->t_end / s->dt - LAGCLI_OUTPUT_SLACK);
}

/* Integrate from y0 at t = 0, calling `out` at every output time after 0: LAGCLI_WINDOW
 * output times per integration, each continuing from the last row's state. */
static int integrate_windows(const run_settings *s, run_state *run, const double *y0,
                             lagcli_ode_out_fn out, lagcli_ode_stats *stats)
{
    static double window[LAGCLI_WINDOW];
    output_times times = times_of(s->t_end, s->dt);
    double t0 = 0.0, t_stop;
    size_t next = 1, n, i;
    long used = 0, budget = step_budget(s);
    int rc = LAGCLI_ODE_OK;
    memset(stats, 0, sizeof *stats);
    memcpy(run->last, y0, (size_t)run->model->nstate * sizeof *y0);
    while (next < times.count && rc == LAGCLI_ODE_OK) {
        n = times.count - next < LAGCLI_WINDOW ? times.count - next : LAGCLI_WINDOW;
        for (i = 0; i < n; ++i)
            window[i] = time_at(&times, next + i);
        t_stop = window[n - 1];
        if (next + n == times.count && t_stop < s->t_end)
            t_stop = s->t_end;                 /* the last window: integrate to t_end */
        rc = lagcli_ode_integrate_bounded(s->method, rhs, out, run, run->model->nstate, t0, run->last, t_stop,
                                          window, n, s->rtol, s->atol,
                                          max_step(run->model, run->alpha, run->beta), budget - used, stats);
        used += stats->n_accepted;
        t0 = window[n - 1];
        next += n;
    }
    return rc;
}

/* --bench-integration N (for bench/simulate.py; not in the usage text): integrate N times
 * with the same steps and dense output but no rows (no invariants, no printf), timing each
 * run with clock() (processor time: no process start-up, no output), and report on stderr. */
static int integrate_events(const run_settings *s, run_state *run, const double *y0, lagcli_ode_out_fn out,
                            FILE *log, lagcli_event_result *result);

/* The integration of a run without a log: with the model's events when it has them
 * (the run ends early as lagcli_events.h says), else LAGCLI_WINDOW output times at a time. */
static int integrate_plain(const run_settings *s, run_state *run, const double *y0, lagcli_ode_out_fn out,
                           lagcli_ode_stats *stats)
{
    static char message[sizeof ((lagcli_event_result *)0)->message];   /* one integration at a time */
    lagcli_event_result result;
    int rc;
    if (run->model->events == NULL)
        return integrate_windows(s, run, y0, out, stats);
    rc = integrate_events(s, run, y0, out, NULL, &result);
    *stats = result.stats;
    if (rc >= LAGCLI_EVENTS_FAILED) {
        memcpy(message, result.message, sizeof message);
        stats->message = message;
    }
    return rc;
}

static int bench(const run_settings *s, run_state *run, const double *y0)
{
    lagcli_ode_stats stats;
    double best = HUGE_VAL, total = 0.0, seconds;
    clock_t start;
    long k;
    int rc;
    for (k = 0; k < s->bench; ++k) {
        start = clock();
        rc = integrate_plain(s, run, y0, no_row, &stats);
        seconds = (double)(clock() - start) / CLOCKS_PER_SEC;
        if (rc != LAGCLI_ODE_OK) {
            fprintf(stderr, "error: at t = %.10g: %s\n", stats.t, stats.message);
            return 1;
        }
        total += seconds;
        if (seconds < best)
            best = seconds;
    }
    fprintf(stderr, "integration: method %s, runs %ld, mean_s %.9g, min_s %.9g, steps %ld, rejected %ld, nfev %ld\n",
            s->method, s->bench, total / (double)s->bench, best, stats.n_accepted, stats.n_rejected, stats.nfev);
    return 0;
}

static int variational(const run_settings *s, run_state *run, const double *y0);
static void failure_text(int rc, const run_settings *s, const run_state *run, const lagcli_ode_stats *st,
                         char *text);

/* "error: at t = ...: reason" of a failed integration on stderr; exit status 1. */
static int report_failure(int rc, const run_settings *s, const run_state *run, const lagcli_ode_stats *stats)
{
    char text[800];
    failure_text(rc, s, run, stats, text);
    fprintf(stderr, "error: %s\n", text);
    return 1;
}

static double event_time_at(const void *times, size_t k)
{
    return time_at((const output_times *)times, k);
}

/* Integrate from y0 with the model's events (lagcli_events.c), `out` at every output time
 * after 0 and at an early end; the log to `log` (may be NULL). */
static int integrate_events(const run_settings *s, run_state *run, const double *y0, lagcli_ode_out_fn out,
                            FILE *log, lagcli_event_result *result)
{
    output_times times = times_of(s->t_end, s->dt);
    lagcli_event_run e;
    e.model = run->model;
    e.p = run->p;
    e.rhs = rhs;
    e.row = out;
    e.ctx = run;
    e.method = s->method;
    e.rtol = s->rtol;
    e.atol = s->atol;
    e.max_step = max_step(run->model, run->alpha, run->beta);
    e.t_end = s->t_end;
    e.max_steps = step_budget(s);
    e.constraint_tolerance = LAGCLI_CONSTRAINT_TOLERANCE;
    e.time_at = event_time_at;
    e.times = &times;
    e.ntimes = times.count;
    e.log = log;
    memcpy(run->last, y0, (size_t)run->model->nstate * sizeof *y0);
    return lagcli_events_integrate(&e, y0, result);
}

/* The rows of a run with events, the log to --events FILE; the exit status. */
static int run_events(const run_settings *s, run_state *run, const double *y0)
{
    lagcli_event_result result;
    FILE *log = NULL;
    int rc;
    if (s->events != NULL && (log = fopen(s->events, "w")) == NULL) {
        fprintf(stderr, "error: --events %.200s: cannot open it for writing\n", s->events);
        return 2;
    }
    rc = integrate_events(s, run, y0, row, log, &result);
    if (log != NULL && fclose(log) != 0 && rc == LAGCLI_ODE_OK) {
        fprintf(stderr, "error: --events %.200s: cannot write it\n", s->events);
        return 1;
    }
    if (rc == LAGCLI_EVENTS_BAD_VALUES) {
        fprintf(stderr, "error: %s\n", result.message);
        return 2;
    }
    if (log == NULL && result.end_note[0] != '\0')      /* with --events, lagcli notes it from the log */
        fprintf(stderr, "note: %s\n", result.end_note);
    if (rc == LAGCLI_EVENTS_FAILED)
        fprintf(stderr, "error: %s\n", result.message);
    else if (rc != LAGCLI_ODE_OK)
        return report_failure(rc, s, run, &result.stats);
    return rc == LAGCLI_ODE_OK ? 0 : 1;
}

/* Integrate from y0 and print the rows; the exit status. */
static int integrate(const run_settings *s, run_state *run, const double *y0)
{
    lagcli_ode_stats stats;
    int rc;
    if (strcmp(s->method, "variational") == 0)
        return variational(s, run, y0);
    if (s->bench > 0)
        return bench(s, run, y0);
    setvbuf(stdout, NULL, _IOFBF, 1 << 16);
    header(run->model);
    if (row(0.0, y0, run) != 0) {
        fprintf(stderr, "error: at t = %.10g: %s\n", run->when, reason(run->code));
        return 1;
    }
    if (run->model->events != NULL)
        return run_events(s, run, y0);
    rc = integrate_windows(s, run, y0, row, &stats);
    return rc == LAGCLI_ODE_OK ? 0 : report_failure(rc, s, run, &stats);
}

int lagcli_driver_main(const lagcli_model *model, int argc, char **argv)
{
    run_settings s;
    run_state run;
    double *work, *y0;
    size_t size = (size_t)(model->nparam + 3 * model->nstate + model->nlambda + model->ninv) + 1;
    int rc;

    work = (double *)calloc(size, sizeof *work);
    if (work == NULL) {
        fprintf(stderr, "error: at t = 0: out of memory\n");
        return 1;
    }
    run.model = model;
    run.p = work;
    y0 = run.p + model->nparam;
    run.dydt = y0 + model->nstate;
    run.lambda = run.dydt + model->nstate;
    run.inv = run.lambda + model->nlambda;
    run.last = run.inv + model->ninv;
    memcpy(run.p, model->parameter_defaults, (size_t)model->nparam * sizeof *run.p);
    memcpy(y0, model->initial_state, (size_t)model->nstate * sizeof *y0);
    run.alpha = run.beta = LAGCLI_BAUMGARTE;
    run.code = 0;
    run.when = 0.0;
    run.batch = NULL;
    s.t_end = model->t_end;
    s.dt = model->dt;
    s.method = model->method;
    s.rtol = model->rtol;
    s.atol = model->atol;
    s.max_steps = 0;
    s.bench = 0;
    s.steps_per_row = 1;
    s.events = NULL;
    s.batch = 0;
    s.nexceed = 0;
    if ((rc = parse(argc, argv, &s, &run, y0)) == 0) {
        if (s.t_end / s.dt > 1e8) {
            rc = usage(argv[0], "--dt: more than 1e8 output rows");
        } else if (strcmp(s.method, "variational") == 0 && model->discrete_momenta == NULL) {
            fprintf(stderr, "error: %s\n", model->variational_refusal);
            rc = 2;
        } else if (model->events != NULL && strcmp(s.method, "variational") == 0) {
            rc = usage(argv[0], "--method variational does not run events: use RK45 or DOP853");
        } else if (s.batch && strcmp(s.method, "variational") == 0) {
            rc = usage(argv[0], "--batch: runs RK45 or DOP853");
        } else if (s.batch) {
            rc = batch_main(&s, &run, y0);
        } else {
            check_initial(y0, &run);
            rc = integrate(&s, &run, y0);
        }
    }
    free(work);
    return rc;
}

/* ---- batch mode: many runs in one process (lagcli sweep, lagcli/sweep/driver.py) -------
 *
 *   ./<name> --batch [--batch-rows] [--exceed NAME=VALUE]... [the options above]
 *
 * The options set what every run starts from (settings, parameters, initial state).
 * Then stdin is read one run per line:  ID [NAME=VALUE]...  (ID a run number; NAME a
 * parameter or a state name; whitespace-separated; at most LAGCLI_BATCH_LINE bytes),
 * and each run is integrated from the options' values with its own overrides. stdout:
 *
 *   #summary t_last,rows,steps,rejected,nfev,final_<column>...,min_<state>...,
 *            max_<state>...,drift_<invariant>...,exceed_<NAME>...      (once, first)
 *   <the run's CSV rows, header-less>          (only with --batch-rows)
 *   @ID<TAB>ok|failed<TAB>reason<TAB>values    (one per run, the columns of #summary)
 *
 * final_<column>: the last row reached (state, multipliers, invariants); min_/max_: over
 * the rows; drift_<invariant>: max |x - x(0)| / |x(0)| over the rows (absolute when
 * |x(0)| < 1e-12), for constraint_residual its largest value; exceed_<NAME>: the first
 * output time with |NAME| > VALUE (nan if never). A failed run (bad line, integration
 * failure) still has its line, with the values up to the failure. The initial state is
 * integrated as given (lagcli sweep makes it consistent first). Exit status 0 unless
 * stdin cannot be read; runs never stop the batch. With --bench-integration N (any N):
 * each run is integrated without rows or summary, and the summed clock() time of the
 * integrations is reported on stderr (bench/sweep.py's bare C cost). */

#define LAGCLI_BATCH_LINE 65536
#define LAGCLI_DRIFT_ABSOLUTE 1e-12      /* |x(0)| below this: absolute drift (as the plot) */

typedef struct {
    run_state *run;
    const run_settings *s;
    double *low, *high;                   /* nstate extrema */
    double *inv0, *drift;                 /* ninv */
    double exceed[LAGCLI_MAX_EXCEED];
    double t_last;
    long rows;
    double bench_seconds;                 /* with --bench-integration: integration time, */
    long bench_runs;                      /* summed over the runs */
} batch_run;

static int exceed_option(const char *item, const lagcli_model *m, run_settings *s, char *message)
{
    double *slots;
    int i, ok;
    if (s->nexceed >= LAGCLI_MAX_EXCEED) {
        sprintf(message, "--exceed: at most %d of them", LAGCLI_MAX_EXCEED);
        return 0;
    }
    slots = (double *)malloc((size_t)m->nstate * sizeof *slots);
    if (slots == NULL) {
        sprintf(message, "--exceed: out of memory");
        return 0;
    }
    for (i = 0; i < m->nstate; ++i)
        slots[i] = nan("");
    ok = assign("--exceed", item, m->state_names, "coordinate or velocity", slots, message);
    for (i = 0; ok && i < m->nstate; ++i)
        if (!isnan(slots[i])) {
            s->exceed_index[s->nexceed] = i;
            s->exceed_value[s->nexceed++] = slots[i];
        }
    free(slots);
    return ok;
}

static void batch_header(const run_settings *s, const lagcli_model *m)
{
    static const char *const prefixes[2] = {"min_", "max_"};
    int i, k;
    printf("#summary t_last,rows,steps,rejected,nfev");
    for (i = 0; i < m->nstate; ++i)
        printf(",final_%s", m->state_names[i]);
    for (i = 0; i < m->nlambda; ++i)
        printf(",final_%s", m->multiplier_names[i]);
    for (i = 0; i < m->ninv; ++i)
        printf(",final_%s", m->invariant_names[i]);
    for (k = 0; k < 2; ++k)
        for (i = 0; i < m->nstate; ++i)
            printf(",%s%s", prefixes[k], m->state_names[i]);
    for (i = 0; i < m->ninv; ++i)
        printf(",drift_%s", m->invariant_names[i]);
    for (i = 0; i < s->nexceed; ++i)
        printf(",exceed_%s", m->state_names[s->exceed_index[i]]);
    printf("\n");
}

/* The output callback of a batch run: extrema, drift and thresholds (and the row itself
 * with --batch-rows). */
static int batch_row(double t, const double *y, void *ctx)
{
    run_state *run = (run_state *)ctx;
    batch_run *b = (batch_run *)run->batch;
    const lagcli_model *m = run->model;
    int i;
    if (b->s->batch == 2) {
        if (row(t, y, run) != 0)
            return 1;
    } else {
        memcpy(run->last, y, (size_t)m->nstate * sizeof *y);
        (void)m->invariants(t, y, run->p, run->inv);
    }
    for (i = 0; i < m->nstate; ++i) {
        if (b->rows == 0 || y[i] < b->low[i])
            b->low[i] = y[i];
        if (b->rows == 0 || y[i] > b->high[i])
            b->high[i] = y[i];
    }
    for (i = 0; i < m->ninv; ++i) {
        double d, x = run->inv[i];
        if (b->rows == 0)
            b->inv0[i] = x;
        if (i == m->residual_column)
            d = x;
        else if (fabs(b->inv0[i]) < LAGCLI_DRIFT_ABSOLUTE)
            d = fabs(x - b->inv0[i]);
        else
            d = fabs(x - b->inv0[i]) / fabs(b->inv0[i]);
        if (b->rows == 0 || d > b->drift[i] || isnan(d))
            b->drift[i] = d;
    }
    for (i = 0; i < b->s->nexceed; ++i)
        if (isnan(b->exceed[i]) && fabs(y[b->s->exceed_index[i]]) > b->s->exceed_value[i])
            b->exceed[i] = t;
    b->t_last = t;
    ++b->rows;
    return 0;
}

/* The reason of a failed run, as `integrate` prints it (without "error: "). */
static void failure_text(int rc, const run_settings *s, const run_state *run, const lagcli_ode_stats *st,
                         char *text)
{
    if (rc == LAGCLI_ODE_ERR_RHS || rc == LAGCLI_ODE_INTERRUPTED)
        sprintf(text, "at t = %.10g: %s", run->when, reason(run->code));
    else if (rc == LAGCLI_ODE_ERR_NONFINITE)
        sprintf(text, "at t = %.10g: the state is no longer finite (inf/nan): the solution blows up", st->t);
    else if (rc == LAGCLI_ODE_ERR_MAX_STEPS)
        sprintf(text, "at t = %.10g: " STEP_BUDGET_TEXT, st->t, step_budget(s));
    else if (rc >= LAGCLI_EVENTS_FAILED)
        sprintf(text, "%.790s", st->message);
    else
        sprintf(text, "at t = %.10g: the %s integrator failed: %s", st->t, s->method, st->message);
}

static void batch_summary(const char *id, const char *failure, const batch_run *b, const lagcli_ode_stats *st)
{
    const run_state *run = b->run;
    const lagcli_model *m = run->model;
    int i;
    printf("@%s\t%s\t%s\t%.17g,%ld,%ld,%ld,%ld", id, failure[0] ? "failed" : "ok", failure, b->t_last, b->rows,
           st->n_accepted, st->n_rejected, st->nfev);
    for (i = 0; i < m->nstate; ++i)
        printf(",%.17g", b->rows ? run->last[i] : nan(""));
    for (i = 0; i < m->nlambda; ++i)
        printf(",%.17g", b->rows ? run->lambda[i] : nan(""));
    for (i = 0; i < m->ninv; ++i)
        printf(",%.17g", b->rows ? run->inv[i] : nan(""));
    for (i = 0; i < m->nstate; ++i)
        printf(",%.17g", b->rows ? b->low[i] : nan(""));
    for (i = 0; i < m->nstate; ++i)
        printf(",%.17g", b->rows ? b->high[i] : nan(""));
    for (i = 0; i < m->ninv; ++i)
        printf(",%.17g", b->rows ? b->drift[i] : nan(""));
    for (i = 0; i < b->s->nexceed; ++i)
        printf(",%.17g", b->exceed[i]);
    printf("\n");
}

/* Whether NAME=VALUE `item` names one of `names`. */
static int is_named(const char *item, const char *const *names)
{
    size_t len = strcspn(item, "=");
    int i;
    for (i = 0; names[i] != NULL; ++i)
        if (strlen(names[i]) == len && strncmp(names[i], item, len) == 0)
            return 1;
    return 0;
}

/* One run of a batch line (already split off its ID): overrides, integration, summary. */
static void batch_run_line(const run_settings *s, batch_run *b, const double *p0, const double *y0,
                           double *y, const char *id, char *rest)
{
    run_state *run = b->run;
    const lagcli_model *m = run->model;
    lagcli_ode_stats st;
    char failure[800] = "", *token;
    int i, rc = LAGCLI_ODE_OK;
    memcpy(run->p, p0, (size_t)m->nparam * sizeof *p0);
    memcpy(y, y0, (size_t)m->nstate * sizeof *y0);
    memset(&st, 0, sizeof st);
    b->rows = 0;
    b->t_last = nan("");
    for (i = 0; i < s->nexceed; ++i)
        b->exceed[i] = nan("");
    run->code = 0;
    for (token = strtok(rest, " \t\r\n"); token != NULL; token = strtok(NULL, " \t\r\n")) {
        char message[720];
        if (!assign("run", token, is_named(token, m->parameter_names) ? m->parameter_names : m->state_names,
                    "parameter or state name", is_named(token, m->parameter_names) ? run->p : y, message)) {
            sprintf(failure, "%.790s", message);
            break;
        }
    }
    if (s->bench > 0) {             /* the bare integration cost (bench/sweep.py): no rows, no summary */
        clock_t start = clock();
        if (failure[0] == '\0')
            (void)integrate_plain(s, run, y, no_row, &st);
        b->bench_seconds += (double)(clock() - start) / CLOCKS_PER_SEC;
        ++b->bench_runs;
        return;
    }
    if (failure[0] == '\0') {
        if (batch_row(0.0, y, run) != 0)
            failure_text(LAGCLI_ODE_ERR_RHS, s, run, &st, failure);
        else if ((rc = integrate_plain(s, run, y, batch_row, &st)) != LAGCLI_ODE_OK)
            failure_text(rc, s, run, &st, failure);
    }
    if (b->rows > 0)     /* the multipliers at the last row reached */
        (void)m->rhs_stabilized(b->t_last, run->last, run->p, run->alpha, run->beta, run->dydt, run->lambda);
    batch_summary(id, failure, b, &st);
}

static int batch_main(const run_settings *s, run_state *run, const double *y0)
{
    const lagcli_model *m = run->model;
    size_t n = (size_t)(m->nparam + 4 * m->nstate + 2 * m->ninv) + 1;
    double *work = (double *)calloc(n, sizeof *work), *p0, *y;
    static char line[LAGCLI_BATCH_LINE];
    batch_run b;
    int rc = 0;
    if (work == NULL) {
        fprintf(stderr, "error: out of memory\n");
        return 1;
    }
    p0 = work;
    y = p0 + m->nparam;
    b.low = y + m->nstate;
    b.high = b.low + m->nstate;
    b.inv0 = b.high + m->nstate;
    b.drift = b.inv0 + m->ninv;
    b.run = run;
    b.s = s;
    b.bench_seconds = 0.0;
    b.bench_runs = 0;
    run->batch = &b;
    memcpy(p0, run->p, (size_t)m->nparam * sizeof *p0);
    setvbuf(stdout, NULL, _IOFBF, 1 << 16);
    batch_header(s, m);
    while (fgets(line, sizeof line, stdin) != NULL) {
        char *id = strtok(line, " \t\r\n"), *rest;
        if (id == NULL)
            continue;                       /* a blank line */
        rest = id + strlen(id);
        if (rest < line + sizeof line - 1 && rest[1] != '\0')
            ++rest;                         /* past the '\0' strtok wrote: the overrides */
        batch_run_line(s, &b, p0, y0, y, id, rest);
        fflush(stdout);
    }
    if (s->bench > 0)
        fprintf(stderr, "integration: method %s, runs %ld, total_s %.9g\n", s->method, b.bench_runs,
                b.bench_seconds);
    if (ferror(stdin)) {
        fprintf(stderr, "error: cannot read the runs from stdin\n");
        rc = 1;
    }
    free(work);
    return rc;
}

/* ---- --method variational (lagcli_variational.c) -------------------------------------- */

/* The rows (or, with --bench-integration, nothing) of one variational run from y0. */
static int variational_run(const run_settings *s, run_state *run, const double *y0, int rows,
                           long *steps, long *iterations)
{
    lagcli_variational v;
    output_times times = times_of(s->t_end, s->dt);
    double t_row = 0.0;
    size_t k;
    long j;
    int rc = lagcli_variational_start(&v, run->model, run->p, y0);
    for (k = 1; rc == LAGCLI_VARIATIONAL_OK && k < times.count; ++k) {
        double t_next = time_at(&times, k), h = (t_next - t_row) / (double)s->steps_per_row;
        if ((double)k * (double)s->steps_per_row > (double)step_budget(s)) {
            lagcli_variational_free(&v);
            fprintf(stderr, "error: at t = %.10g: " STEP_BUDGET_TEXT "\n", t_row, step_budget(s));
            return 1;
        }
        for (j = 0; rc == LAGCLI_VARIATIONAL_OK && j < s->steps_per_row; ++j)
            rc = lagcli_variational_step(&v, t_row + (double)j * h, h);
        t_row = t_next;
        if (rc == LAGCLI_VARIATIONAL_OK && rows && row(t_next, v.y, run) != 0) {
            lagcli_variational_free(&v);
            fprintf(stderr, "error: at t = %.10g: %s\n", run->when, reason(run->code));
            return 1;
        }
    }
    if (rc != LAGCLI_VARIATIONAL_OK)
        fprintf(stderr, "error: at t = %.10g: %s\n", v.t_fail, v.message);
    *steps = v.steps;
    *iterations = v.iterations;
    lagcli_variational_free(&v);
    return rc == LAGCLI_VARIATIONAL_OK ? 0 : 1;
}

/* --method variational: the rows, or --bench-integration's timing (steps and Newton
 * iterations in place of nfev). */
static int variational(const run_settings *s, run_state *run, const double *y0)
{
    long steps = 0, iterations = 0, k;
    double best = HUGE_VAL, total = 0.0, seconds;
    clock_t start;
    run->alpha = run->beta = 0.0;     /* the rows' multipliers: the exact equations' */
    if (s->bench == 0) {
        setvbuf(stdout, NULL, _IOFBF, 1 << 16);
        header(run->model);
        if (row(0.0, y0, run) != 0) {
            fprintf(stderr, "error: at t = %.10g: %s\n", run->when, reason(run->code));
            return 1;
        }
        return variational_run(s, run, y0, 1, &steps, &iterations);
    }
    for (k = 0; k < s->bench; ++k) {
        start = clock();
        if (variational_run(s, run, y0, 0, &steps, &iterations) != 0)
            return 1;
        seconds = (double)(clock() - start) / CLOCKS_PER_SEC;
        total += seconds;
        if (seconds < best)
            best = seconds;
    }
    fprintf(stderr, "integration: method variational, runs %ld, mean_s %.9g, min_s %.9g, steps %ld, "
            "iterations %ld\n", s->bench, total / (double)s->bench, best, steps, iterations);
    return 0;
}
