/* lagcli's variational integrator in C: see lagcli_variational.h. The same steps, in the
 * same order, as lagcli/runtime/variational.py (tests/test_variational.py checks that the
 * two backends agree to 1e-10 and that the constants below equal the Python ones). */
#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "lagcli_variational.h"

/* The workspace, in v->work (sizes: n coordinates, d holonomic rows, N = n + d). */
typedef struct {
    double *ymid, *yq;                 /* 2n each: the model's y at the midpoint / at (q, 0) */
    double *g, *f, *a, *q1, *P;        /* n each */
    double *gq, *gv, *fq, *fv, *M;     /* n*n each */
    double *phi, *phit, *mu, *lam;     /* d each */
    double *A0, *A1;                   /* d*n each */
    double *J, *R, *dydt;              /* N*N, N, 2n */
} workspace;

static workspace parts(const lagcli_variational *v)
{
    workspace w;
    int n = v->n, d = v->d, N = n + d;
    double *x = v->work;
    w.ymid = x; x += 2 * n;
    w.yq = x; x += 2 * n;
    w.g = x; x += n;
    w.f = x; x += n;
    w.a = x; x += n;
    w.q1 = x; x += n;
    w.P = x; x += n;
    w.gq = x; x += n * n;
    w.gv = x; x += n * n;
    w.fq = x; x += n * n;
    w.fv = x; x += n * n;
    w.M = x; x += n * n;
    w.phi = x; x += d;
    w.phit = x; x += d;
    w.mu = x; x += d;
    w.lam = x; x += d + 1;             /* + 1: the model may be asked for 0 multipliers */
    w.A0 = x; x += d * n;
    w.A1 = x; x += d * n;
    w.J = x; x += N * N;
    w.R = x; x += N;
    w.dydt = x;
    return w;
}

static size_t workspace_size(int n, int d)
{
    int N = n + d;
    return (size_t)(4 * n + 5 * n + 5 * n * n + 4 * d + 1 + 2 * d * n + N * N + N + 2 * n);
}

static int fail(lagcli_variational *v, double t, int code, const char *reason)
{
    v->t_fail = t;
    sprintf(v->message, "%.160s", reason);
    return code;
}

/* Solve K x = r (size x size, row-major; r becomes x) by Gaussian elimination with partial
 * pivoting, as the generated model's solve. 1: singular, 2: not finite. */
static int solve(int size, double *K, double *r)
{
    int i, j, k;
    for (k = 0; k < size; ++k) {
        int pivot = k;
        double big = fabs(K[k * size + k]);
        for (i = k + 1; i < size; ++i)
            if (fabs(K[i * size + k]) > big) {
                big = fabs(K[i * size + k]);
                pivot = i;
            }
        if (!(big > 0.0))
            return big == 0.0 ? 1 : 2;
        if (pivot != k) {
            double swap;
            for (j = k; j < size; ++j) {
                swap = K[k * size + j];
                K[k * size + j] = K[pivot * size + j];
                K[pivot * size + j] = swap;
            }
            swap = r[k];
            r[k] = r[pivot];
            r[pivot] = swap;
        }
        for (i = k + 1; i < size; ++i) {
            const double factor = K[i * size + k] / K[k * size + k];
            for (j = k + 1; j < size; ++j)
                K[i * size + j] -= factor * K[k * size + j];
            r[i] -= factor * r[k];
        }
    }
    for (k = size - 1; k >= 0; --k) {
        double sum = r[k];
        for (j = k + 1; j < size; ++j)
            sum -= K[k * size + j] * r[j];
        r[k] = sum / K[k * size + k];
        if (!isfinite(r[k]))
            return 2;
    }
    return 0;
}

/* max |dx| <= tolerance (1 + max |x|) */
static int small(int count, const double *dx, const double *x)
{
    double step = 0.0, size = 0.0;
    int i;
    for (i = 0; i < count; ++i) {
        if (fabs(dx[i]) > step)
            step = fabs(dx[i]);
        if (fabs(x[i]) > size)
            size = fabs(x[i]);
    }
    return step <= LAGCLI_NEWTON_TOLERANCE * (1.0 + size);
}

static void at_rest(int n, const double *q, double *y)
{
    memcpy(y, q, (size_t)n * sizeof *q);
    memset(y + n, 0, (size_t)n * sizeof *y);
}

static void midpoint(int n, const double *q, const double *q1, double h, double *y)
{
    int i;
    for (i = 0; i < n; ++i) {
        y[i] = 0.5 * (q[i] + q1[i]);
        y[n + i] = (q1[i] - q[i]) / h;
    }
}

int lagcli_variational_start(lagcli_variational *v, const lagcli_model *model, const double *p,
                             const double *y0)
{
    double *f;
    memset(v, 0, sizeof *v);
    v->model = model;
    v->p = p;
    v->n = model->nq;
    v->d = model->nholonomic;
    if (model->discrete_momenta == NULL)
        return fail(v, 0.0, LAGCLI_VARIATIONAL_ERR_REFUSED,
                    model->variational_refusal != NULL ? model->variational_refusal : "not available");
    v->y = (double *)malloc((size_t)(3 * v->n) * sizeof *v->y + workspace_size(v->n, v->d) * sizeof *v->y);
    if (v->y == NULL)
        return fail(v, 0.0, LAGCLI_VARIATIONAL_ERR_NOMEM, "out of memory");
    v->mom = v->y + 2 * v->n;
    v->work = v->mom + v->n;
    memcpy(v->y, y0, (size_t)(2 * v->n) * sizeof *y0);
    f = parts(v).f;
    if (model->discrete_momenta(0.0, v->y, p, v->mom, f) != 0)
        return fail(v, 0.0, LAGCLI_VARIATIONAL_ERR_MODEL, "the momenta are not finite at the initial state");
    return LAGCLI_VARIATIONAL_OK;
}

void lagcli_variational_free(lagcli_variational *v)
{
    free(v->y);
    v->y = v->mom = v->work = NULL;
}

/* The Newton iteration for (q1, mu); w.q1, w.mu hold the predictor on entry. */
static int newton(lagcli_variational *v, workspace *w, double t, double h)
{
    const lagcli_model *m = v->model;
    const double *q = v->y;
    int n = v->n, d = v->d, N = n + d, i, j, it;
    double half = 0.5 * h;
    char text[160];
    for (it = 1; it <= LAGCLI_NEWTON_MAX_ITERATIONS; ++it) {
        midpoint(n, q, w->q1, h, w->ymid);
        if (m->discrete_momenta(t + half, w->ymid, v->p, w->g, w->f) != 0
            || m->discrete_jacobian(t + half, w->ymid, v->p, w->gq, w->gv, w->fq, w->fv) != 0)
            return fail(v, t, LAGCLI_VARIATIONAL_ERR_NEWTON, "the Newton iteration diverged (inf/nan); reduce dt");
        memset(w->J, 0, (size_t)(N * N) * sizeof *w->J);
        for (i = 0; i < n; ++i) {
            for (j = 0; j < n; ++j)
                w->J[i * N + j] = 0.5 * (w->gq[i * n + j] - half * w->fq[i * n + j])
                                  + (w->gv[i * n + j] - half * w->fv[i * n + j]) / h;
            w->R[i] = w->g[i] - half * w->f[i] - v->mom[i];
        }
        if (d) {
            at_rest(n, w->q1, w->yq);
            if (m->holonomic(t + h, w->yq, v->p, w->phi, w->A1, w->phit) != 0)
                return fail(v, t, LAGCLI_VARIATIONAL_ERR_NEWTON, "the Newton iteration diverged (inf/nan); reduce dt");
            for (i = 0; i < n; ++i) {
                double impulse = 0.0;
                for (j = 0; j < d; ++j) {
                    impulse += w->A0[j * n + i] * w->mu[j];
                    w->J[i * N + n + j] = -half * w->A0[j * n + i];
                    w->J[(n + j) * N + i] = w->A1[j * n + i];
                }
                w->R[i] -= half * impulse;
            }
            for (j = 0; j < d; ++j)
                w->R[n + j] = w->phi[j];
        }
        for (i = 0; i < N; ++i)
            w->R[i] = -w->R[i];
        if (solve(N, w->J, w->R) != 0)
            return fail(v, t, LAGCLI_VARIATIONAL_ERR_NEWTON,
                        "the Newton iteration's Jacobian is singular; reduce dt");
        for (i = 0; i < n; ++i)
            w->q1[i] += w->R[i];
        for (j = 0; j < d; ++j)
            w->mu[j] += w->R[n + j];
        ++v->iterations;
        if (small(n, w->R, w->q1) && small(d, w->R + n, w->mu))
            return LAGCLI_VARIATIONAL_OK;
    }
    sprintf(text, "the Newton iteration did not converge in %d iterations (step %.6g); reduce dt",
            LAGCLI_NEWTON_MAX_ITERATIONS, h);
    return fail(v, t, LAGCLI_VARIATIONAL_ERR_NEWTON, text);
}

/* (q', p) at (t1, q1) from the momentum P before the constraint impulse: M q' = P - a + A^T s
 * with A q' + phi_t = 0, p = P + A^T s. */
static int legendre(lagcli_variational *v, workspace *w, double t, double t1)
{
    const lagcli_model *m = v->model;
    int n = v->n, d = v->d, N = n + d, i, j;
    at_rest(n, w->q1, w->yq);
    if (m->discrete_momenta(t1, w->yq, v->p, w->a, w->f) != 0 || m->mass_matrix(t1, w->yq, v->p, w->M) != 0
        || (d && m->holonomic(t1, w->yq, v->p, w->phi, w->A1, w->phit) != 0))
        return fail(v, t, LAGCLI_VARIATIONAL_ERR_MODEL, "the model is not finite at the new point; reduce dt");
    memset(w->J, 0, (size_t)(N * N) * sizeof *w->J);
    for (i = 0; i < n; ++i) {
        for (j = 0; j < n; ++j)
            w->J[i * N + j] = w->M[i * n + j];
        for (j = 0; j < d; ++j) {
            w->J[i * N + n + j] = -w->A1[j * n + i];
            w->J[(n + j) * N + i] = w->A1[j * n + i];
        }
        w->R[i] = w->P[i] - w->a[i];
    }
    for (j = 0; j < d; ++j)
        w->R[n + j] = -w->phit[j];
    if (solve(N, w->J, w->R) != 0)
        return fail(v, t, LAGCLI_VARIATIONAL_ERR_MODEL,
                    "the mass matrix (with the constraints) is singular at the new point; reduce dt");
    for (i = 0; i < n; ++i) {
        double impulse = 0.0;
        for (j = 0; j < d; ++j)
            impulse += w->A1[j * n + i] * w->R[n + j];
        v->y[i] = w->q1[i];
        v->y[n + i] = w->R[i];
        v->mom[i] = w->P[i] + impulse;
    }
    return LAGCLI_VARIATIONAL_OK;
}

int lagcli_variational_step(lagcli_variational *v, double t, double h)
{
    const lagcli_model *m = v->model;
    workspace w = parts(v);
    int n = v->n, d = v->d, i, j, rc;
    double half = 0.5 * h;
    /* predictor: q1 = q + h q' + h^2/2 q'' and mu = lambda of the exact equations */
    if (m->rhs_stabilized(t, v->y, v->p, 0.0, 0.0, w.dydt, w.lam) != 0)
        return fail(v, t, LAGCLI_VARIATIONAL_ERR_MODEL, "singular mass matrix or constraint matrix");
    for (i = 0; i < n; ++i)
        w.q1[i] = v->y[i] + h * v->y[n + i] + half * h * w.dydt[n + i];
    for (j = 0; j < d; ++j)
        w.mu[j] = w.lam[j];
    if (d) {
        at_rest(n, v->y, w.yq);
        if (m->holonomic(t, w.yq, v->p, w.phi, w.A0, w.phit) != 0)
            return fail(v, t, LAGCLI_VARIATIONAL_ERR_MODEL, "the constraints are not finite");
    }
    if ((rc = newton(v, &w, t, h)) != 0)
        return rc;
    /* p1 as the momentum balance over the step (see variational.py) */
    midpoint(n, v->y, w.q1, h, w.ymid);
    if (m->discrete_momenta(t + half, w.ymid, v->p, w.g, w.f) != 0)
        return fail(v, t, LAGCLI_VARIATIONAL_ERR_MODEL, "the forces are not finite; reduce dt");
    for (i = 0; i < n; ++i) {
        double impulse = 0.0;
        for (j = 0; j < d; ++j)
            impulse += w.A0[j * n + i] * w.mu[j];
        w.P[i] = v->mom[i] + h * w.f[i];
        if (d)
            w.P[i] += half * impulse;
    }
    if ((rc = legendre(v, &w, t, t + h)) != 0)
        return rc;
    ++v->steps;
    return LAGCLI_VARIATIONAL_OK;
}
