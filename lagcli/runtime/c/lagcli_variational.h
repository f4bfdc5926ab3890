/* lagcli's variational integrator in C (`simulate --method variational`): shipped with
 * lagcli (lagcli/runtime/c/) and copied next to every generated C model. C99 + libm.
 * The same algorithm as lagcli/runtime/variational.py (the scheme: lagcli/derive/discrete.py,
 * docs/simulate.md): the midpoint discrete Lagrangian, its position-momentum equations
 * solved by Newton with the generated Jacobian, holonomic constraints RATTLE-type.
 *
 *   lagcli_variational v;
 *   rc = lagcli_variational_start(&v, &model, p, y0);    y0 = [q..., q'...]: 0 or an error code
 *   rc = lagcli_variational_step(&v, t, h);              v.y = [q..., q'...] at t + h
 *   lagcli_variational_free(&v);
 *
 * On an error v.message says why and v.t_fail when. The workspace is
 * malloc'ed once by start; nothing is allocated by a step. */
#ifndef LAGCLI_VARIATIONAL_H
#define LAGCLI_VARIATIONAL_H

#include "lagcli_model.h"

#ifdef __cplusplus
extern "C" {
#endif

#define LAGCLI_NEWTON_TOLERANCE 1e-12      /* relative size of the last Newton update */
#define LAGCLI_NEWTON_MAX_ITERATIONS 30    /* without convergence: the step fails */

enum {
    LAGCLI_VARIATIONAL_OK = 0,
    LAGCLI_VARIATIONAL_ERR_MODEL = 1,      /* a model function failed (singular, non-finite) */
    LAGCLI_VARIATIONAL_ERR_NEWTON = 2,     /* no convergence, a singular Jacobian or inf/nan */
    LAGCLI_VARIATIONAL_ERR_REFUSED = 3,    /* the model has no variational functions (nonholonomic) */
    LAGCLI_VARIATIONAL_ERR_NOMEM = 4
};

typedef struct {
    const lagcli_model *model;
    const double *p;        /* the model table's parameters (then inputs) */
    int n, d;               /* coordinates, holonomic rows */
    double *y;              /* nstate: [q, q'] now */
    double *mom;            /* n: the momenta p = dL/dq' now */
    double *work;           /* everything else (one allocation) */
    long steps, iterations; /* counts so far (each iteration evaluates the momenta and the Jacobian) */
    double t_fail;
    char message[200];      /* why the last call failed */
} lagcli_variational;

int lagcli_variational_start(lagcli_variational *v, const lagcli_model *model, const double *p,
                             const double *y0);
int lagcli_variational_step(lagcli_variational *v, double t, double h);
void lagcli_variational_free(lagcli_variational *v);

#ifdef __cplusplus
}
#endif

#endif /* LAGCLI_VARIATIONAL_H */
