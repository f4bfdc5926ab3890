/* ------------------------------------------------------------------------
 * Explicit embedded Runge-Kutta integrator: RK45 (Dormand-Prince 5(4)) and
 * DOP853 (Hairer's 8(5,3)).  The step-size control, error norms and dense
 * output are those of scipy.integrate.solve_ivp (scipy/integrate/_ivp/rk.py,
 * common.py), so the same rtol/atol give the same accepted steps and the
 * same number of right-hand-side evaluations (nfev) as solve_ivp(t_eval=...).
 *
 *   int lagcli_ode_integrate(method, rhs, out, ctx, n, t0, y0, t_end,
 *                     t_out, n_out, rtol, atol, max_step, &stats);
 *
 * method    "RK45" or "DOP853" (scipy's names, case-sensitive)
 * rhs       int rhs(double t, const double *y, double *dydt, void *ctx),
 *           nonzero return = failure (LAGCLI_ODE_ERR_RHS)
 * out       int out(double t, const double *y, void *ctx), called once per
 *           output time with the dense-output value; nonzero return stops
 *           the integration (LAGCLI_ODE_INTERRUPTED).  May be NULL if n_out == 0.
 * n, y0     state size (>= 1) and initial state at t0
 * t_out     n_out output times, strictly monotonic towards t_end and
 *           inside [t0, t_end] (solve_ivp's t_eval)
 * rtol,atol scalar tolerances; rtol below 100*DBL_EPSILON is raised to it
 * max_step  largest step size; INFINITY (or HUGE_VAL) for no limit
 * stats     may be NULL; receives the time reached (on failure: the last
 *           accepted step), nfev, step counts and a message
 *
 * Returns LAGCLI_ODE_OK or one of the LAGCLI_ODE_ERR_* / LAGCLI_ODE_INTERRUPTED codes below.
 * The workspace is malloc'ed once on entry and freed on return; nothing is
 * allocated inside the step loop.
 * ------------------------------------------------------------------------ */
#ifndef LAGCLI_ODE_H
#define LAGCLI_ODE_H

#include <stddef.h>

#ifdef __cplusplus
extern "C" {
#endif

/* Return codes of lagcli_ode_integrate. */
enum {
    LAGCLI_ODE_OK = 0,                 /* reached t_end; every output time was emitted */
    LAGCLI_ODE_ERR_STEP_TOO_SMALL = 1, /* step size fell below 10 ulp(t), as scipy's status -1 */
    LAGCLI_ODE_ERR_RHS = 2,            /* the rhs callback returned nonzero */
    LAGCLI_ODE_ERR_NONFINITE = 3,      /* y0, f(t0, y0) or an accepted state is inf/nan, or
                                   the step shrank to nothing because every trial
                                   step produced inf/nan (scipy: status -1) */
    LAGCLI_ODE_INTERRUPTED = 4,        /* the output callback returned nonzero */
    LAGCLI_ODE_ERR_ARGS = 5,           /* unknown method, bad tolerances or output times */
    LAGCLI_ODE_ERR_NOMEM = 6,          /* the workspace could not be allocated */
    LAGCLI_ODE_ERR_MAX_STEPS = 7       /* max_steps steps were accepted before t_end */
};

typedef int (*lagcli_ode_rhs_fn)(double t, const double *y, double *dydt, void *ctx);
typedef int (*lagcli_ode_out_fn)(double t, const double *y, void *ctx);

typedef struct {
    double t;            /* t_end on success; else the time of the last accepted step */
    long nfev;           /* rhs evaluations, counted like scipy's nfev */
    long n_accepted;     /* accepted steps */
    long n_rejected;     /* rejected step attempts */
    const char *message; /* static description of the return code */
} lagcli_ode_stats;

int lagcli_ode_integrate(const char *method, lagcli_ode_rhs_fn rhs, lagcli_ode_out_fn out, void *ctx,
                         int n, double t0, const double *y0, double t_end,
                         const double *t_out, size_t n_out, double rtol, double atol,
                         double max_step, lagcli_ode_stats *stats);

/* The same, stopping with LAGCLI_ODE_ERR_MAX_STEPS after `max_steps` accepted steps
 * (0: no bound); lagcli_ode_integrate is this with max_steps = 0. */
int lagcli_ode_integrate_bounded(const char *method, lagcli_ode_rhs_fn rhs, lagcli_ode_out_fn out, void *ctx,
                                 int n, double t0, const double *y0, double t_end,
                                 const double *t_out, size_t n_out, double rtol, double atol,
                                 double max_step, long max_steps, lagcli_ode_stats *stats);

/* Step by step (lagcli_events.c: events located on each step's interpolant):
 *
 *   lagcli_ode_stepper *s = lagcli_ode_stepper_new(method, rhs, ctx, n, rtol, atol, max_step);
 *   lagcli_ode_stepper_start(s, t0, y0, t_end);     f(t0, y0) and the initial step, as scipy's
 *                                                   solver constructor (also to restart after an event)
 *   lagcli_ode_stepper_step(s);                     one accepted step (scipy's OdeSolver.step)
 *   lagcli_ode_stepper_dense(s, t, y);              y = the step's interpolant at t in [t_old, t]
 *   lagcli_ode_stepper_free(s);
 *
 * The same steps as lagcli_ode_integrate. Each function returns a LAGCLI_ODE_* code;
 * lagcli_ode_stepper_stats gives the time reached and the counts since the last start. */
typedef struct lagcli_ode_stepper lagcli_ode_stepper;

lagcli_ode_stepper *lagcli_ode_stepper_new(const char *method, lagcli_ode_rhs_fn rhs, void *ctx, int n,
                                           double rtol, double atol, double max_step);
int lagcli_ode_stepper_start(lagcli_ode_stepper *s, double t0, const double *y0, double t_end);
int lagcli_ode_stepper_step(lagcli_ode_stepper *s);
int lagcli_ode_stepper_dense(lagcli_ode_stepper *s, double t, double *y);
double lagcli_ode_stepper_t(const lagcli_ode_stepper *s);      /* the end of the last step */
double lagcli_ode_stepper_t_old(const lagcli_ode_stepper *s);  /* its start */
const double *lagcli_ode_stepper_y(const lagcli_ode_stepper *s);
void lagcli_ode_stepper_stats(const lagcli_ode_stepper *s, lagcli_ode_stats *stats);
void lagcli_ode_stepper_free(lagcli_ode_stepper *s);

/* A static description of a return code of lagcli_ode_integrate. */
const char *lagcli_ode_message(int code);

#ifdef __cplusplus
}
#endif

#endif /* LAGCLI_ODE_H */
