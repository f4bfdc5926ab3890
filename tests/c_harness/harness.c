/* Test driver for lagcli/runtime/c/lagcli_ode.c, compiled by tests/test_c_integrator.py.
 * It includes the integrator's source (not just its header) to reach the static
 * coefficient tables.
 *
 *   harness coeffs
 *       print every coefficient table, one number per line (%.17g)
 *   harness run SYSTEM METHOD RTOL ATOL T0 T_END MAX_STEP STOP_AFTER < times
 *       stdin: the number of output times, then the times; stdout: one row
 *       "t y..." per output time, then "# rc nfev n_accepted n_rejected t"
 *       STOP_AFTER > 0 makes the output callback stop after that many rows.
 */
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "lagcli_ode.c"

typedef struct {
    const char *name;
    int n;
    int (*rhs)(double t, const double *y, double *dydt, void *ctx);
    double y0[3];
} system_def;

typedef struct {
    long rows;
    long stop_after;
    int n;
} run_ctx;

static const double OMEGA = 2.0;    /* harmonic oscillator frequency */
static const double VDP_MU = 1.0;   /* Van der Pol damping */
static const double L_SIGMA = 10.0; /* Lorenz parameters */
static const double L_RHO = 28.0;
static const double L_BETA = 8.0 / 3.0;
static const double FAIL_AT = 0.5;  /* the failing right-hand sides fail after this */

static int harmonic(double t, const double *y, double *dydt, void *ctx)
{
    (void)t;
    (void)ctx;
    dydt[0] = y[1];
    dydt[1] = -(OMEGA * OMEGA) * y[0];
    return 0;
}

static int vdp(double t, const double *y, double *dydt, void *ctx)
{
    (void)t;
    (void)ctx;
    dydt[0] = y[1];
    dydt[1] = VDP_MU * (1 - y[0] * y[0]) * y[1] - y[0];
    return 0;
}

static int lorenz(double t, const double *y, double *dydt, void *ctx)
{
    (void)t;
    (void)ctx;
    dydt[0] = L_SIGMA * (y[1] - y[0]);
    dydt[1] = y[0] * (L_RHO - y[2]) - y[1];
    dydt[2] = y[0] * y[1] - L_BETA * y[2];
    return 0;
}

/* y' = y^2, y(0) = 1: y = 1 / (1 - t) blows up at t = 1. */
static int blowup(double t, const double *y, double *dydt, void *ctx)
{
    (void)t;
    (void)ctx;
    dydt[0] = y[0] * y[0];
    return 0;
}

/* The harmonic oscillator whose rhs reports failure after FAIL_AT. */
static int rhsfail(double t, const double *y, double *dydt, void *ctx)
{
    return t > FAIL_AT ? 1 : harmonic(t, y, dydt, ctx);
}

/* The harmonic oscillator whose rhs returns nan after FAIL_AT. */
static int nanrhs(double t, const double *y, double *dydt, void *ctx)
{
    harmonic(t, y, dydt, ctx);
    if (t > FAIL_AT)
        dydt[1] = nan("");
    return 0;
}

static const system_def SYSTEMS[] = {
    {"harmonic", 2, harmonic, {1.0, 0.0, 0.0}},
    {"vdp", 2, vdp, {2.0, 0.0, 0.0}},
    {"lorenz", 3, lorenz, {1.0, 1.0, 1.0}},
    {"blowup", 1, blowup, {1.0, 0.0, 0.0}},
    {"rhsfail", 2, rhsfail, {1.0, 0.0, 0.0}},
    {"nanrhs", 2, nanrhs, {1.0, 0.0, 0.0}},
};

static int print_row(double t, const double *y, void *ctx)
{
    run_ctx *rc = (run_ctx *)ctx;
    int i;
    printf("%.17g", t);
    for (i = 0; i < rc->n; ++i)
        printf(" %.17g", y[i]);
    printf("\n");
    rc->rows++;
    return rc->stop_after > 0 && rc->rows >= rc->stop_after;
}

static void print_table(const char *name, const double *v, size_t count)
{
    size_t i;
    printf("%s", name);
    for (i = 0; i < count; ++i)
        printf(" %.17g", v[i]);
    printf("\n");
}

#define TABLE(a) print_table(#a, &(a)[0], sizeof(a) / sizeof(a)[0])
#define MATRIX(a) print_table(#a, &(a)[0][0], sizeof(a) / sizeof(a)[0][0])

static int print_coefficients(void)
{
    MATRIX(LAGCLI_ODE_RK45_A);
    TABLE(LAGCLI_ODE_RK45_B);
    TABLE(LAGCLI_ODE_RK45_C);
    TABLE(LAGCLI_ODE_RK45_E);
    MATRIX(LAGCLI_ODE_RK45_P);
    MATRIX(LAGCLI_ODE_DOP853_A);
    TABLE(LAGCLI_ODE_DOP853_C);
    TABLE(LAGCLI_ODE_DOP853_E3);
    TABLE(LAGCLI_ODE_DOP853_E5);
    MATRIX(LAGCLI_ODE_DOP853_D);
    return 0;
}

static int run(char **argv)
{
    const system_def *sys = NULL;
    run_ctx ctx = {0, 0, 0};
    lagcli_ode_stats stats;
    double *t_out;
    long n_out, i;
    size_t k;
    int rc;

    for (k = 0; k < sizeof SYSTEMS / sizeof SYSTEMS[0]; ++k)
        if (strcmp(argv[2], SYSTEMS[k].name) == 0)
            sys = &SYSTEMS[k];
    if (!sys || scanf("%ld", &n_out) != 1 || n_out < 0)
        return 2;
    t_out = (double *)malloc((size_t)(n_out > 0 ? n_out : 1) * sizeof *t_out);
    if (!t_out)
        return 2;
    for (i = 0; i < n_out; ++i)
        if (scanf("%lf", &t_out[i]) != 1)
            return 2;
    ctx.n = sys->n;
    ctx.stop_after = strtol(argv[9], NULL, 10);

    rc = lagcli_ode_integrate(argv[3], sys->rhs, print_row, &ctx, sys->n, strtod(argv[6], NULL),
                       sys->y0, strtod(argv[7], NULL), t_out, (size_t)n_out,
                       strtod(argv[4], NULL), strtod(argv[5], NULL), strtod(argv[8], NULL),
                       &stats);
    printf("# %d %ld %ld %ld %.17g\n", rc, stats.nfev, stats.n_accepted, stats.n_rejected,
           stats.t);
    fprintf(stderr, "%s\n", stats.message);
    free(t_out);
    return 0;
}

int main(int argc, char **argv)
{
    if (argc == 2 && strcmp(argv[1], "coeffs") == 0)
        return print_coefficients();
    if (argc == 10 && strcmp(argv[1], "run") == 0)
        return run(argv);
    fprintf(stderr, "usage: harness coeffs | harness run SYSTEM METHOD RTOL ATOL T0 T_END"
                    " MAX_STEP STOP_AFTER < times\n");
    return 2;
}
