/* What a generated lagcli model tells a driver about itself: sizes, names, defaults and
 * its functions (lagcli_model). Shipped with lagcli (lagcli/runtime/c/) and copied next to
 * every generated C model, whose header declares `extern const lagcli_model <name>_model;`.
 * C99; usable from C++. Documented in docs/codegen.md. */
#ifndef LAGCLI_MODEL_H
#define LAGCLI_MODEL_H

#ifdef __cplusplus
extern "C" {
#endif

/* The model functions return 0 on success, 1 for a singular matrix, 2 for a non-finite result. */
typedef int (*lagcli_rhs_stabilized_fn)(double t, const double *y, const double *p, double alpha,
                                        double beta, double *dydt, double *lambda);
typedef int (*lagcli_invariants_fn)(double t, const double *y, const double *p, double *out);
/* The variational integrator's (lagcli_variational.c): g = dL/dq', f = dL/dq + Q'; their
 * Jacobians (n x n each); phi, A = dphi/dq, phi_t of the holonomic rows; M. */
typedef int (*lagcli_discrete_momenta_fn)(double t, const double *y, const double *p, double *g, double *f);
typedef int (*lagcli_discrete_jacobian_fn)(double t, const double *y, const double *p, double *gq,
                                           double *gv, double *fq, double *fv);
typedef int (*lagcli_holonomic_fn)(double t, const double *y, const double *p, double *phi, double *A,
                                   double *phit);
typedef int (*lagcli_matrix_fn)(double t, const double *y, const double *p, double *M);

/* The spec's events (NULL in a model without them): see lagcli_events.h. */
enum { LAGCLI_EVENT_IMPACT = 0, LAGCLI_EVENT_RESET = 1, LAGCLI_EVENT_STOP = 2 };
typedef void (*lagcli_event_functions_fn)(double t, const double *y, const double *p, double *g);
typedef void (*lagcli_impact_terms_fn)(int k, double t, const double *y, const double *p, double *G,
                                       double *g_t, double *e, double *d);
typedef void (*lagcli_reset_fn)(int k, double t, const double *y, const double *p, double *y_new);

typedef struct {
    int nevent;
    const char *const *names;               /* NULL-terminated, nevent names */
    const int *actions;                     /* LAGCLI_EVENT_* */
    const int *directions;                  /* -1 falling (+ to -), 1 rising, 0 either */
    lagcli_event_functions_fn functions;    /* g[k] = g_k(t, y, p), k < nevent */
    lagcli_impact_terms_fn impact_terms;    /* impact k: G = dg_k/dq (nq), g_t, e; d (nlambda) */
    lagcli_reset_fn reset;                  /* reset k: y_new (nstate) from y */
    lagcli_matrix_fn constraint_matrix;     /* A (nlambda x nq, row-major) */
} lagcli_events;

typedef struct {
    const char *name;                       /* the spec's name */
    int nq, nstate, nparam, nlambda, ninv;  /* sizes; nstate = 2 nq */
    const char *const *state_names;         /* NULL-terminated, nstate names */
    const char *const *parameter_names;     /* NULL-terminated, nparam names; for a spec with
                                               `inputs:` the parameters then the inputs (the
                                               values a driver's --set may change), and the
                                               functions below take p in that order */
    const double *parameter_defaults;       /* nparam values */
    const char *const *multiplier_names;    /* NULL-terminated, nlambda names */
    const char *const *invariant_names;     /* NULL-terminated, ninv names (CSV order) */
    int residual_column;                    /* index of constraint_residual in the invariants, or -1 */
    const double *initial_state;            /* nstate values: the spec's initial: block */
    double t_end, dt, rtol, atol;           /* the spec's simulate: block (with lagcli's defaults) */
    const char *method;                     /* a method the C driver implements */
    lagcli_rhs_stabilized_fn rhs_stabilized;
    lagcli_invariants_fn invariants;
    int nholonomic;                         /* holonomic constraint rows */
    lagcli_discrete_momenta_fn discrete_momenta;    /* NULL (and the next two) when the */
    lagcli_discrete_jacobian_fn discrete_jacobian;  /* variational integrator cannot run: */
    lagcli_holonomic_fn holonomic;                  /* variational_refusal says why */
    lagcli_matrix_fn mass_matrix;
    const char *variational_refusal;       /* NULL, or why --method variational is refused */
    const lagcli_events *events;            /* NULL, or the spec's events (lagcli_events.c runs them) */
} lagcli_model;

#ifdef __cplusplus
}
#endif

#endif /* LAGCLI_MODEL_H */
