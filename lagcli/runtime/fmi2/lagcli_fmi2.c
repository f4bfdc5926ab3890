/* The FMI 2.0 functions of a lagcli FMU (Model Exchange and Co-Simulation), wrapping a
 * generated model (a lagcli_model, lagcli_model.h). Shipped with lagcli
 * (lagcli/runtime/fmi2/) and copied, unchanged, into the sources/ folder of every FMU
 * `lagcli generate --lang fmu` writes; docs/codegen.md ("FMI 2.0 FMU").
 * C99 + libm, with the standard's headers fmi2Functions.h, fmi2FunctionTypes.h and
 * fmi2TypesPlatform.h. The generated lagcli_fmu_model.h names the model (LAGCLI_FMU_MODEL),
 * its GUID, the number of inputs and the integration settings of Co-Simulation.
 *
 * Value references, in this order (modelDescription.xml lists the same):
 *   [0, nstate)                  the states y = [q..., q'...]
 *   [nstate, 2 nstate)           their derivatives [q'..., q''...]
 *   then the parameters and LAGCLI_FMU_NINPUT inputs (together the model's nparam
 *   settable values: for a spec with `inputs:` the model table lists the parameters, then
 *   the inputs), nlambda multipliers and ninv invariants (energy, jacobi, p_<q>,
 *   constraint_residual: the CSV of `lagcli simulate`).
 *
 * Constrained models are integrated in the stabilised index-1 form of the C driver:
 * the augmented system with Baumgarte terms, alpha = LAGCLI_FMU_ALPHA, beta =
 * LAGCLI_FMU_BETA. Inputs live at the end of the model's value vector p, so setting one
 * changes the equations like a parameter. Co-Simulation integrates each communication step
 * with lagcli_ode (LAGCLI_FMU_METHOD, the spec's tolerances, the step cap of the C driver),
 * in at most LAGCLI_FMU_MAX_STEPS steps (then fmi2Error, logged: a run never goes on for ever).
 *
 * A spec with `events:` defines LAGCLI_FMU_NEVENT (lagcli_fmu_model.h), and its model
 * carries the event functions (<name>.c): they are the event indicators, and where one has
 * crossed zero in its event's direction since the last event or accepted step, the
 * action happens in fmi2NewDiscreteStates (impact: the impact law of the C runtime,
 * lagcli_events_impact; reset: the new state; stop: terminateSimulation). Such an FMU is
 * Model Exchange only (its modelDescription.xml has no CoSimulation element).
 */
#include <float.h>
#include <math.h>
#include <stdarg.h>
#include <stdio.h>
#include <string.h>

#include "fmi2Functions.h"
#include "lagcli_fmu_model.h"
#include "lagcli_ode.h"
#ifdef LAGCLI_FMU_NEVENT
#include "lagcli_events.h"
#endif

#define MODEL (&LAGCLI_FMU_MODEL)

typedef struct {
    fmi2CallbackFunctions callbacks;
    const char *name;             /* the instance name, copied */
    fmi2Boolean logging;
    double t;
    double *y, *p, *u;            /* nstate states, nparam values; u = the inputs at p's end */
    double *dydt, *lambda, *inv;  /* derived values, valid while !stale */
    int stale;                    /* a state, time, parameter or input changed since they were computed */
    int failed;                   /* the model function's code when they could not be computed */
#ifdef LAGCLI_FMU_NEVENT
    double g_before[LAGCLI_FMU_NEVENT];   /* each event function at the last event or accepted step */
    double last[LAGCLI_FMU_NEVENT];       /* each event's last time */
    double fastest[LAGCLI_FMU_NEVENT];    /* each impact's largest approach speed */
    long events;                          /* the events so far */
    double *y_minus, *G, *d;              /* the state before an event; an impact's dg/dq, d */
#endif
} instance;

static size_t count_states(void) { return (size_t)MODEL->nstate; }

/* First value references of each block (see the top). */
static fmi2ValueReference derivative_base(void) { return (fmi2ValueReference)MODEL->nstate; }
static fmi2ValueReference parameter_base(void) { return 2u * (fmi2ValueReference)MODEL->nstate; }
static fmi2ValueReference input_base(void) { return parameter_base() + (fmi2ValueReference)MODEL->nparam - LAGCLI_FMU_NINPUT; }
static fmi2ValueReference multiplier_base(void) { return parameter_base() + (fmi2ValueReference)MODEL->nparam; }
static fmi2ValueReference invariant_base(void) { return multiplier_base() + (fmi2ValueReference)MODEL->nlambda; }
static fmi2ValueReference end_of_references(void) { return invariant_base() + (fmi2ValueReference)MODEL->ninv; }

static void say(instance *c, fmi2Status status, const char *category, const char *format, ...)
{
    char message[512];
    va_list args;
    if (c == NULL || c->callbacks.logger == NULL || (status == fmi2OK && !c->logging))
        return;
    va_start(args, format);
    vsnprintf(message, sizeof message, format, args);
    va_end(args);
    c->callbacks.logger(c->callbacks.componentEnvironment, c->name, status, category, "%s", message);
}

static const char *reason(int code)
{
    return code == 1 ? "singular mass matrix or constraint matrix"
                     : "the accelerations or invariants are not finite (inf/nan)";
}

/* dydt, lambda and inv at (t, y, p); fmi2Error (logged) when the model fails there. */
static fmi2Status compute(instance *c)
{
    int rc;
    if (!c->stale)
        return c->failed ? fmi2Error : fmi2OK;
    rc = MODEL->rhs_stabilized(c->t, c->y, c->p, LAGCLI_FMU_ALPHA, LAGCLI_FMU_BETA, c->dydt, c->lambda);
    if (rc == 0)
        rc = MODEL->invariants(c->t, c->y, c->p, c->inv);
    c->stale = 0;
    c->failed = rc;
    if (rc != 0) {
        say(c, fmi2Error, "logStatusError", "at t = %.17g: %s", c->t, reason(rc));
        return fmi2Error;
    }
    return fmi2OK;
}

static void *allocate(instance *c, size_t count)
{
    return c->callbacks.allocateMemory(count ? count : 1, sizeof(double));
}

static void defaults(instance *c)
{
    memcpy(c->y, MODEL->initial_state, count_states() * sizeof(double));
    if (MODEL->nparam > 0)
        memcpy(c->p, MODEL->parameter_defaults, (size_t)MODEL->nparam * sizeof(double));
    c->t = 0.0;
    c->stale = 1;
}

/* --- common functions ------------------------------------------------------------- */

const char *fmi2GetTypesPlatform(void) { return fmi2TypesPlatform; }
const char *fmi2GetVersion(void) { return fmi2Version; }

fmi2Status fmi2SetDebugLogging(fmi2Component component, fmi2Boolean loggingOn, size_t nCategories,
                               const fmi2String categories[])
{
    (void)nCategories;
    (void)categories;
    ((instance *)component)->logging = loggingOn;
    return fmi2OK;
}

fmi2Component fmi2Instantiate(fmi2String instanceName, fmi2Type fmuType, fmi2String fmuGUID,
                              fmi2String fmuResourceLocation, const fmi2CallbackFunctions *functions,
                              fmi2Boolean visible, fmi2Boolean loggingOn)
{
    instance *c;
    char *name;
    (void)fmuType;               /* one instance serves both interfaces */
    (void)fmuResourceLocation;
    (void)visible;
    if (functions == NULL || functions->allocateMemory == NULL || functions->freeMemory == NULL)
        return NULL;
    if (fmuGUID == NULL || strcmp(fmuGUID, LAGCLI_FMU_GUID) != 0) {
        if (functions->logger != NULL)
            functions->logger(functions->componentEnvironment, instanceName, fmi2Error, "logStatusError",
                              "GUID %s does not match this FMU's %s", fmuGUID ? fmuGUID : "(null)",
                              LAGCLI_FMU_GUID);
        return NULL;
    }
    c = (instance *)functions->allocateMemory(1, sizeof(instance));
    name = (char *)functions->allocateMemory(strlen(instanceName ? instanceName : "") + 1, 1);
    if (c == NULL || name == NULL) {
        functions->freeMemory(c);
        functions->freeMemory(name);
        return NULL;
    }
    strcpy(name, instanceName ? instanceName : "");
    c->callbacks = *functions;
    c->name = name;
    c->logging = loggingOn;
    c->y = (double *)allocate(c, count_states());
    c->p = (double *)allocate(c, (size_t)MODEL->nparam);
    c->u = c->p ? c->p + (MODEL->nparam - LAGCLI_FMU_NINPUT) : NULL;
    c->dydt = (double *)allocate(c, count_states());
    c->lambda = (double *)allocate(c, (size_t)MODEL->nlambda);
    c->inv = (double *)allocate(c, (size_t)MODEL->ninv);
#ifdef LAGCLI_FMU_NEVENT
    c->y_minus = (double *)allocate(c, count_states());
    c->G = (double *)allocate(c, (size_t)MODEL->nq);
    c->d = (double *)allocate(c, (size_t)MODEL->nlambda);
    if (!c->y_minus || !c->G || !c->d) {
        fmi2FreeInstance(c);
        return NULL;
    }
#endif
    if (!c->y || !c->p || !c->u || !c->dydt || !c->lambda || !c->inv) {
        fmi2FreeInstance(c);
        return NULL;
    }
    defaults(c);
    return c;
}

void fmi2FreeInstance(fmi2Component component)
{
    instance *c = (instance *)component;
    fmi2CallbackFreeMemory release;
    if (c == NULL)
        return;
    release = c->callbacks.freeMemory;
    release(c->y);
    release(c->p);
    release(c->dydt);
    release(c->lambda);
    release(c->inv);
#ifdef LAGCLI_FMU_NEVENT
    release(c->y_minus);
    release(c->G);
    release(c->d);
#endif
    release((void *)c->name);
    release(c);
}

fmi2Status fmi2SetupExperiment(fmi2Component component, fmi2Boolean toleranceDefined, fmi2Real tolerance,
                               fmi2Real startTime, fmi2Boolean stopTimeDefined, fmi2Real stopTime)
{
    instance *c = (instance *)component;
    (void)toleranceDefined;
    (void)tolerance;
    (void)stopTimeDefined;
    (void)stopTime;
    c->t = startTime;
    c->stale = 1;
    return fmi2OK;
}

/* The modes change nothing here: every variable is computed from the current values
 * when asked for. Leaving initialization checks that the model can be evaluated. */
fmi2Status fmi2EnterInitializationMode(fmi2Component component)
{
    (void)component;
    return fmi2OK;
}

#ifdef LAGCLI_FMU_NEVENT
static fmi2Status check_restitution(instance *c);
#endif

fmi2Status fmi2ExitInitializationMode(fmi2Component component)
{
#ifdef LAGCLI_FMU_NEVENT
    instance *c = (instance *)component;
    int k;
    MODEL->events->functions(c->t, c->y, c->p, c->g_before);
    for (k = 0; k < LAGCLI_FMU_NEVENT; ++k) {
        c->last[k] = -HUGE_VAL;
        c->fastest[k] = 0.0;
    }
    c->events = 0;
    if (check_restitution(c) != fmi2OK)
        return fmi2Error;
#endif
    return compute((instance *)component);
}

fmi2Status fmi2Terminate(fmi2Component component)
{
    (void)component;
    return fmi2OK;
}

fmi2Status fmi2Reset(fmi2Component component)
{
    defaults((instance *)component);
    return fmi2OK;
}

/* --- values ----------------------------------------------------------------------- */

fmi2Status fmi2GetReal(fmi2Component component, const fmi2ValueReference vr[], size_t nvr, fmi2Real value[])
{
    instance *c = (instance *)component;
    size_t k;
    for (k = 0; k < nvr; ++k) {
        fmi2ValueReference r = vr[k];
        if (r < derivative_base()) {
            value[k] = c->y[r];
        } else if (r < parameter_base() || r >= multiplier_base()) {
            if (r >= end_of_references()) {
                say(c, fmi2Error, "logStatusError", "fmi2GetReal: no variable has value reference %u", r);
                return fmi2Error;
            }
            if (compute(c) != fmi2OK)
                return fmi2Error;
            value[k] = r < parameter_base() ? c->dydt[r - derivative_base()]
                     : r < invariant_base() ? c->lambda[r - multiplier_base()]
                                            : c->inv[r - invariant_base()];
        } else if (r < input_base()) {
            value[k] = c->p[r - parameter_base()];
        } else {
            value[k] = c->u[r - input_base()];
        }
    }
    return fmi2OK;
}

fmi2Status fmi2SetReal(fmi2Component component, const fmi2ValueReference vr[], size_t nvr, const fmi2Real value[])
{
    instance *c = (instance *)component;
    size_t k;
    for (k = 0; k < nvr; ++k) {
        fmi2ValueReference r = vr[k];
        if (r < derivative_base()) {
            c->y[r] = value[k];
        } else if (r >= parameter_base() && r < input_base()) {
            c->p[r - parameter_base()] = value[k];
        } else if (r >= input_base() && r < multiplier_base()) {
            c->u[r - input_base()] = value[k];
        } else {
            say(c, fmi2Error, "logStatusError", "fmi2SetReal: value reference %u is not a state, "
                "parameter or input", r);
            return fmi2Error;
        }
        c->stale = 1;
    }
    return fmi2OK;
}

/* No Integer, Boolean or String variables. */
static fmi2Status none(instance *c, const char *function, size_t nvr)
{
    if (nvr == 0)
        return fmi2OK;
    say(c, fmi2Error, "logStatusError", "%s: this FMU has no variables of that type", function);
    return fmi2Error;
}

fmi2Status fmi2GetInteger(fmi2Component c, const fmi2ValueReference vr[], size_t nvr, fmi2Integer value[])
{
    (void)vr;
    (void)value;
    return none((instance *)c, "fmi2GetInteger", nvr);
}

fmi2Status fmi2GetBoolean(fmi2Component c, const fmi2ValueReference vr[], size_t nvr, fmi2Boolean value[])
{
    (void)vr;
    (void)value;
    return none((instance *)c, "fmi2GetBoolean", nvr);
}

fmi2Status fmi2GetString(fmi2Component c, const fmi2ValueReference vr[], size_t nvr, fmi2String value[])
{
    (void)vr;
    (void)value;
    return none((instance *)c, "fmi2GetString", nvr);
}

fmi2Status fmi2SetInteger(fmi2Component c, const fmi2ValueReference vr[], size_t nvr, const fmi2Integer value[])
{
    (void)vr;
    (void)value;
    return none((instance *)c, "fmi2SetInteger", nvr);
}

fmi2Status fmi2SetBoolean(fmi2Component c, const fmi2ValueReference vr[], size_t nvr, const fmi2Boolean value[])
{
    (void)vr;
    (void)value;
    return none((instance *)c, "fmi2SetBoolean", nvr);
}

fmi2Status fmi2SetString(fmi2Component c, const fmi2ValueReference vr[], size_t nvr, const fmi2String value[])
{
    (void)vr;
    (void)value;
    return none((instance *)c, "fmi2SetString", nvr);
}

/* --- what this FMU does not offer (canGetAndSetFMUstate, providesDirectionalDerivative
 * and canInterpolateInputs are false in modelDescription.xml) ---------------------- */

static fmi2Status unsupported(fmi2Component component, const char *function)
{
    say((instance *)component, fmi2Error, "logStatusError", "%s is not supported by this FMU", function);
    return fmi2Error;
}

fmi2Status fmi2GetFMUstate(fmi2Component c, fmi2FMUstate *s)
{
    (void)s;
    return unsupported(c, "fmi2GetFMUstate");
}

fmi2Status fmi2SetFMUstate(fmi2Component c, fmi2FMUstate s)
{
    (void)s;
    return unsupported(c, "fmi2SetFMUstate");
}

fmi2Status fmi2FreeFMUstate(fmi2Component c, fmi2FMUstate *s)
{
    (void)s;
    return unsupported(c, "fmi2FreeFMUstate");
}

fmi2Status fmi2SerializedFMUstateSize(fmi2Component c, fmi2FMUstate s, size_t *size)
{
    (void)s;
    (void)size;
    return unsupported(c, "fmi2SerializedFMUstateSize");
}

fmi2Status fmi2SerializeFMUstate(fmi2Component c, fmi2FMUstate s, fmi2Byte bytes[], size_t size)
{
    (void)s;
    (void)bytes;
    (void)size;
    return unsupported(c, "fmi2SerializeFMUstate");
}

fmi2Status fmi2DeSerializeFMUstate(fmi2Component c, const fmi2Byte bytes[], size_t size, fmi2FMUstate *s)
{
    (void)bytes;
    (void)size;
    (void)s;
    return unsupported(c, "fmi2DeSerializeFMUstate");
}

fmi2Status fmi2GetDirectionalDerivative(fmi2Component c, const fmi2ValueReference vUnknown[], size_t nUnknown,
                                        const fmi2ValueReference vKnown[], size_t nKnown,
                                        const fmi2Real dvKnown[], fmi2Real dvUnknown[])
{
    (void)vUnknown;
    (void)nUnknown;
    (void)vKnown;
    (void)nKnown;
    (void)dvKnown;
    (void)dvUnknown;
    return unsupported(c, "fmi2GetDirectionalDerivative");
}

/* --- Model Exchange ---------------------------------------------------------------- */

fmi2Status fmi2EnterEventMode(fmi2Component c)
{
    (void)c;
    return fmi2OK;
}

/* No new discrete states, no changed states, no time event: what an event iteration ends with. */
static void nothing_new(fmi2EventInfo *info)
{
    info->newDiscreteStatesNeeded = fmi2False;
    info->terminateSimulation = fmi2False;
    info->nominalsOfContinuousStatesChanged = fmi2False;
    info->valuesOfContinuousStatesChanged = fmi2False;
    info->nextEventTimeDefined = fmi2False;
    info->nextEventTime = 0.0;
}

#ifdef LAGCLI_FMU_NEVENT
/* --- events (the model's event functions, lagcli_fmu_model.h) ---------------------- *
 * The rules of `lagcli simulate` (lagcli_events.h): after an impact, or a reset that
 * leaves g as it was, the event has crossed (its g counts as 0 where the importer goes
 * on; an impact's must turn back); a reset's new state must satisfy the constraints; the
 * simulation terminates (terminateSimulation, with a warning saying why) where an event
 * recurs within LAGCLI_EVENTS_GAP max(1, |t|), an impact leaves slower than
 * LAGCLI_EVENTS_RESTING times the largest approach speed of its event, or after
 * LAGCLI_EVENTS_BUDGET events. */

#define EVENTS (MODEL->events)

static int crossed(int direction, double before, double after)
{
    int falling = before > 0.0 && after <= 0.0, rising = before < 0.0 && after >= 0.0;
    return direction < 0 ? falling : direction > 0 ? rising : (falling || rising);
}

/* The first event whose function crossed zero in its direction since g_before, or -1. */
static int crossing(instance *c, double *g)
{
    int k;
    EVENTS->functions(c->t, c->y, c->p, g);
    for (k = 0; k < LAGCLI_FMU_NEVENT; k++)
        if (crossed(EVENTS->directions[k], c->g_before[k], g[k]))
            return k;
    return -1;
}

/* dg/dt = G q' + g_t of impact k at the state before it, with the velocities qd. */
static double approach_speed(instance *c, int k, const double *qd)
{
    double g_t, e, speed = 0.0;
    int i;
    EVENTS->impact_terms(k, c->t, c->y_minus, c->p, c->G, &g_t, &e, c->d);
    for (i = 0; i < MODEL->nq; ++i)
        speed += c->G[i] * qd[i];
    return speed + g_t;
}

/* Every impact's restitution in [0, 1] with the parameters set (fmi2ExitInitializationMode). */
static fmi2Status check_restitution(instance *c)
{
    int k;
    for (k = 0; k < LAGCLI_FMU_NEVENT; ++k) {
        double g_t, e;
        if (EVENTS->actions[k] != LAGCLI_EVENT_IMPACT)
            continue;
        EVENTS->impact_terms(k, c->t, c->y, c->p, c->G, &g_t, &e, c->d);
        if (!(e >= 0.0 && e <= 1.0)) {
            say(c, fmi2Error, "logStatusError", "event '%s': restitution = %g with these parameter values; "
                "it must be in [0, 1]", EVENTS->names[k], e);
            return fmi2Error;
        }
    }
    return fmi2OK;
}

/* The action of event k at c->t, the state before it in y_minus: the state after it in
 * c->y; 1 when the contact has come to rest (an impact), 0, or -1 (failed, logged). */
static int act(instance *c, int k)
{
    const int action = EVENTS->actions[k];
    double P;
    int rc;
    if (action == LAGCLI_EVENT_RESET) {
        EVENTS->reset(k, c->t, c->y_minus, c->p, c->y);
        c->stale = 1;
        if (MODEL->residual_column >= 0 && compute(c) == fmi2OK
            && !(c->inv[MODEL->residual_column] <= LAGCLI_FMU_CONSTRAINT_TOLERANCE)) {
            say(c, fmi2Error, "logStatusError", "at t = %.10g: event '%s' (reset) gives a state that violates "
                "the constraints (constraint_residual = %.3g); reset the dependent coordinates and velocities "
                "consistently", c->t, EVENTS->names[k], c->inv[MODEL->residual_column]);
            return -1;
        }
        return c->failed ? -1 : 0;
    }
    if (action == LAGCLI_EVENT_STOP)
        return 0;
    rc = lagcli_events_impact(MODEL, k, c->t, c->y_minus, c->p, c->y + MODEL->nq, &P);
    if (rc != 0) {
        say(c, fmi2Error, "logStatusError", rc == 1
            ? "at t = %.10g: event '%s' (impact): the impact's direction dg/dq lies in the span of the constraint "
              "rows (or the mass matrix is singular): no impulse can change the approach speed"
            : "at t = %.10g: event '%s' (impact): the velocities after it are not finite (inf/nan)",
            c->t, EVENTS->names[k]);
        return -1;
    }
    say(c, fmi2OK, "logEvents", "at t = %.17g: event '%s' (impact), impulse %.17g", c->t, EVENTS->names[k], P);
    {
        double before = fabs(approach_speed(c, k, c->y_minus + MODEL->nq));
        double after = fabs(approach_speed(c, k, c->y + MODEL->nq));
        if (before > c->fastest[k])
            c->fastest[k] = before;
        if (after <= LAGCLI_EVENTS_RESTING * c->fastest[k]) {
            say(c, fmi2Warning, "logEvents", "event '%s' at t = %.10g: separation speed %.3g after the impact "
                "(below %g x the largest approach speed: the contact has come to rest); the simulation "
                "terminates there", EVENTS->names[k], c->t, after, LAGCLI_EVENTS_RESTING);
            return 1;
        }
    }
    return 0;
}

/* Does the run end at event k, just handled (accumulation, budget)? Logged when it does. */
static int accumulates(instance *c, int k)
{
    const double gap = c->t - c->last[k];
    c->last[k] = c->t;
    if (gap < LAGCLI_EVENTS_GAP * (fabs(c->t) > 1.0 ? fabs(c->t) : 1.0)) {
        say(c, fmi2Warning, "logEvents", "event '%s' recurred after %.3g s at t = %.10g (accumulation: closer "
            "than %g x max(1, t)); the simulation terminates there", EVENTS->names[k], gap, c->t,
            LAGCLI_EVENTS_GAP);
        return 1;
    }
    if (++c->events >= LAGCLI_EVENTS_BUDGET) {
        say(c, fmi2Warning, "logEvents", "%ld events (the budget of one run) by t = %.10g; the simulation "
            "terminates there", (long)LAGCLI_EVENTS_BUDGET, c->t);
        return 1;
    }
    return 0;
}

fmi2Status fmi2NewDiscreteStates(fmi2Component component, fmi2EventInfo *info)
{
    instance *c = (instance *)component;
    double g[LAGCLI_FMU_NEVENT], g_minus;
    int k = crossing(c, g), ended;
    nothing_new(info);
    if (k < 0) {
        memcpy(c->g_before, g, sizeof g);
        return fmi2OK;
    }
    g_minus = g[k];
    memcpy(c->y_minus, c->y, count_states() * sizeof(double));
    if ((ended = act(c, k)) < 0)
        return fmi2Error;
    c->stale = 1;
    if (EVENTS->actions[k] == LAGCLI_EVENT_STOP) {
        say(c, fmi2OK, "logEvents", "at t = %.17g: event '%s' (stop)", c->t, EVENTS->names[k]);
        info->terminateSimulation = fmi2True;
        return fmi2OK;
    }
    info->valuesOfContinuousStatesChanged = fmi2True;
    EVENTS->functions(c->t, c->y, c->p, c->g_before);
    /* After an impact (its g = 0 here; the impact law sends it back to the side before) or a
     * reset that left g as it was, g counts as 0: it has crossed, and a round-off sign of g
     * at its root (where the importer's solver stops next, as g leaves 0) fires nothing. */
    if (EVENTS->actions[k] == LAGCLI_EVENT_IMPACT || c->g_before[k] == g_minus)
        c->g_before[k] = 0.0;
    if (ended || accumulates(c, k))
        info->terminateSimulation = fmi2True;
    return fmi2OK;
}
#else
fmi2Status fmi2NewDiscreteStates(fmi2Component c, fmi2EventInfo *info)
{
    (void)c;
    nothing_new(info);
    return fmi2OK;
}
#endif

fmi2Status fmi2EnterContinuousTimeMode(fmi2Component c)
{
    (void)c;
    return fmi2OK;
}

fmi2Status fmi2CompletedIntegratorStep(fmi2Component component, fmi2Boolean noSetFMUStatePriorToCurrentPoint,
                                       fmi2Boolean *enterEventMode, fmi2Boolean *terminateSimulation)
{
#ifdef LAGCLI_FMU_NEVENT
    /* A crossing in an event's direction enters event mode (its g_before is kept for
     * fmi2NewDiscreteStates); otherwise the step's values become the ones to compare with. */
    instance *c = (instance *)component;
    double g[LAGCLI_FMU_NEVENT];
    *enterEventMode = crossing(c, g) >= 0 ? fmi2True : fmi2False;
    if (!*enterEventMode)
        memcpy(c->g_before, g, sizeof g);
#else
    (void)component;
    *enterEventMode = fmi2False;
#endif
    (void)noSetFMUStatePriorToCurrentPoint;
    *terminateSimulation = fmi2False;
    return fmi2OK;
}

fmi2Status fmi2SetTime(fmi2Component component, fmi2Real time)
{
    instance *c = (instance *)component;
    c->t = time;
    c->stale = 1;
    return fmi2OK;
}

static fmi2Status check_states(instance *c, const char *function, size_t nx)
{
    if (nx == count_states())
        return fmi2OK;
    say(c, fmi2Error, "logStatusError", "%s: %u states asked for, the model has %u", function,
        (unsigned)nx, (unsigned)count_states());
    return fmi2Error;
}

fmi2Status fmi2SetContinuousStates(fmi2Component component, const fmi2Real x[], size_t nx)
{
    instance *c = (instance *)component;
    if (check_states(c, "fmi2SetContinuousStates", nx) != fmi2OK)
        return fmi2Error;
    memcpy(c->y, x, nx * sizeof(double));
    c->stale = 1;
    return fmi2OK;
}

fmi2Status fmi2GetDerivatives(fmi2Component component, fmi2Real derivatives[], size_t nx)
{
    instance *c = (instance *)component;
    if (check_states(c, "fmi2GetDerivatives", nx) != fmi2OK || compute(c) != fmi2OK)
        return fmi2Error;
    memcpy(derivatives, c->dydt, nx * sizeof(double));
    return fmi2OK;
}

fmi2Status fmi2GetEventIndicators(fmi2Component c, fmi2Real eventIndicators[], size_t ni)
{
#ifdef LAGCLI_FMU_NEVENT
    instance *self = (instance *)c;
    if (ni == LAGCLI_FMU_NEVENT) {
        MODEL->events->functions(self->t, self->y, self->p, eventIndicators);
        return fmi2OK;
    }
#endif
    (void)eventIndicators;
    return ni == 0 ? fmi2OK : unsupported(c, "event indicators");
}

fmi2Status fmi2GetContinuousStates(fmi2Component component, fmi2Real x[], size_t nx)
{
    instance *c = (instance *)component;
    if (check_states(c, "fmi2GetContinuousStates", nx) != fmi2OK)
        return fmi2Error;
    memcpy(x, c->y, nx * sizeof(double));
    return fmi2OK;
}

fmi2Status fmi2GetNominalsOfContinuousStates(fmi2Component component, fmi2Real x_nominal[], size_t nx)
{
    size_t k;
    if (check_states((instance *)component, "fmi2GetNominalsOfContinuousStates", nx) != fmi2OK)
        return fmi2Error;
    for (k = 0; k < nx; ++k)
        x_nominal[k] = 1.0;
    return fmi2OK;
}

/* --- Co-Simulation ----------------------------------------------------------------- */

static int step_rhs(double t, const double *y, double *dydt, void *ctx)
{
    instance *c = (instance *)ctx;
    int rc = MODEL->rhs_stabilized(t, y, c->p, LAGCLI_FMU_ALPHA, LAGCLI_FMU_BETA, dydt, NULL);
    if (rc != 0)
        say(c, fmi2Error, "logStatusError", "at t = %.17g: %s", t, reason(rc));
    return rc;
}

static int step_end(double t, const double *y, void *ctx)
{
    instance *c = (instance *)ctx;
    c->t = t;
    memcpy(c->y, y, count_states() * sizeof(double));
    return 0;
}

fmi2Status fmi2DoStep(fmi2Component component, fmi2Real currentCommunicationPoint,
                      fmi2Real communicationStepSize, fmi2Boolean noSetFMUStatePriorToCurrentPoint)
{
    instance *c = (instance *)component;
    double end = currentCommunicationPoint + communicationStepSize;
    lagcli_ode_stats stats;
    int rc;
    (void)noSetFMUStatePriorToCurrentPoint;
    if (communicationStepSize <= 0.0) {
        say(c, fmi2Error, "logStatusError", "fmi2DoStep: the step size must be positive");
        return fmi2Error;
    }
    rc = lagcli_ode_integrate_bounded(LAGCLI_FMU_METHOD, step_rhs, step_end, c, MODEL->nstate,
                                      currentCommunicationPoint, c->y, end, &end, 1, MODEL->rtol, MODEL->atol,
                                      LAGCLI_FMU_MAX_STEP, LAGCLI_FMU_MAX_STEPS, &stats);
    c->stale = 1;
    if (rc == LAGCLI_ODE_ERR_MAX_STEPS) {
        say(c, fmi2Error, "logStatusError", "fmi2DoStep: at t = %.17g: the integration reached its bound of %ld "
            "steps in one communication step (a stiff or blowing-up solution?); use shorter communication steps",
            stats.t, LAGCLI_FMU_MAX_STEPS);
        return fmi2Error;
    }
    if (rc != LAGCLI_ODE_OK) {
        say(c, fmi2Error, "logStatusError", "fmi2DoStep: integration failed at t = %.17g: %s", stats.t,
            stats.message);
        return fmi2Error;
    }
    c->t = end;
    return compute(c);
}

fmi2Status fmi2CancelStep(fmi2Component c) { return unsupported(c, "fmi2CancelStep"); }

fmi2Status fmi2SetRealInputDerivatives(fmi2Component c, const fmi2ValueReference vr[], size_t nvr,
                                       const fmi2Integer order[], const fmi2Real value[])
{
    (void)vr;
    (void)nvr;
    (void)order;
    (void)value;
    return unsupported(c, "fmi2SetRealInputDerivatives");
}

fmi2Status fmi2GetRealOutputDerivatives(fmi2Component c, const fmi2ValueReference vr[], size_t nvr,
                                        const fmi2Integer order[], fmi2Real value[])
{
    (void)vr;
    (void)nvr;
    (void)order;
    (void)value;
    return unsupported(c, "fmi2GetRealOutputDerivatives");
}

static fmi2Status no_status(fmi2Component c)
{
    return unsupported(c, "asynchronous steps (fmi2Get*Status)");
}

fmi2Status fmi2GetStatus(fmi2Component c, const fmi2StatusKind s, fmi2Status *value)
{
    (void)s;
    (void)value;
    return no_status(c);
}

fmi2Status fmi2GetRealStatus(fmi2Component c, const fmi2StatusKind s, fmi2Real *value)
{
    (void)s;
    (void)value;
    return no_status(c);
}

fmi2Status fmi2GetIntegerStatus(fmi2Component c, const fmi2StatusKind s, fmi2Integer *value)
{
    (void)s;
    (void)value;
    return no_status(c);
}

fmi2Status fmi2GetBooleanStatus(fmi2Component c, const fmi2StatusKind s, fmi2Boolean *value)
{
    (void)s;
    (void)value;
    return no_status(c);
}

fmi2Status fmi2GetStringStatus(fmi2Component c, const fmi2StatusKind s, fmi2String *value)
{
    (void)s;
    (void)value;
    return no_status(c);
}
