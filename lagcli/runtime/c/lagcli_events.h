/* ------------------------------------------------------------------------
 * A run with the spec's events (lagcli_events.c), the C side of
 * lagcli/run/event_loop.py: the same steps, the same location, the same actions and
 * the same rules for ending a run, so that both backends give the same events.
 *
 * After each step of lagcli_ode's stepper, every event function g_k is compared at the
 * step's two ends; a sign change in the event's direction is located by Brent's method
 * on the step's interpolant (to 4 ulp of t). Rows before the event come from that
 * interpolant; then the action happens and the stepper restarts from (t*, y+):
 *
 *   impact  the velocities from the impact law (lagcli_events_impact), P recorded
 *   reset   the model's reset map; the new state must satisfy the constraints
 *   stop    the run ends at t* (its last row the state there)
 *
 * After an impact, or a reset that leaves g as it was, g counts as exactly 0 where the
 * next step starts (it has crossed; a round-off sign at its root does not fire it again).
 * A run ends early (exit status 0, its last row at that event) where the same event
 * recurs within LAGCLI_EVENTS_GAP max(1, |t|) of its last time, an impact leaves slower
 * than LAGCLI_EVENTS_RESTING times the largest approach speed of that event, the event
 * just handled returns within the first step after it faster than
 * LAGCLI_EVENTS_SAMPLES samples of that step resolve, or LAGCLI_EVENTS_BUDGET events
 * have happened. The step budget (max_steps) counts the steps of every segment.
 *
 * The log (lagcli reads it and writes the --events CSV and the notes), one line each:
 *   event,NAME,ACTION,t,y-...,y+...,IMPULSE      (IMPULSE empty but for an impact)
 *   end,KIND,NAME,t,VALUE     KIND: recurred (VALUE the gap), resting (the speed after),
 *                             unresolved, budget (VALUE the budget)
 * ------------------------------------------------------------------------ */
#ifndef LAGCLI_EVENTS_H
#define LAGCLI_EVENTS_H

#include <stddef.h>
#include <stdio.h>

#include "lagcli_model.h"
#include "lagcli_ode.h"

#ifdef __cplusplus
extern "C" {
#endif

/* The rules of lagcli/run/event_loop.py (tests/test_c_events.py checks they agree). */
#define LAGCLI_EVENTS_GAP 1e-9         /* ACCUMULATION_GAP */
#define LAGCLI_EVENTS_RESTING 1e-9     /* RESTING_SPEED */
#define LAGCLI_EVENTS_BUDGET 100000L   /* EVENT_BUDGET */
#define LAGCLI_EVENTS_SAMPLES 8        /* FIRST_STEP_SAMPLES */

enum {
    LAGCLI_EVENTS_FAILED = 100,       /* an event's action failed: the result's message says why */
    LAGCLI_EVENTS_BAD_VALUES = 101    /* a restitution outside [0, 1] with these parameters (exit 2) */
};

typedef double (*lagcli_time_fn)(const void *times, size_t k);

typedef struct {
    const lagcli_model *model;
    const double *p;                  /* the table's values: parameters, then inputs */
    lagcli_ode_rhs_fn rhs;            /* the right-hand side integrated ... */
    lagcli_ode_out_fn row;            /* ... and a row at an output time or at the end */
    void *ctx;                        /* of both */
    const char *method;
    double rtol, atol, max_step, t_end;
    long max_steps;                   /* accepted steps over the whole run (0: no bound) */
    double constraint_tolerance;      /* largest constraint residual after a reset */
    lagcli_time_fn time_at;           /* output time k = 1 .. ntimes - 1 (row 0 is the caller's) */
    const void *times;
    size_t ntimes;
    FILE *log;                        /* the event records, or NULL */
} lagcli_event_run;

typedef struct {
    lagcli_ode_stats stats;           /* t reached, steps and nfev summed over the segments */
    long events;
    int ended;                        /* ended early at an event (stop, accumulation, budget) */
    char end_note[400];               /* why it ended before t_end but at a stop, in the words of
                                         lagcli simulate's note; "" otherwise */
    char message[800];                /* LAGCLI_EVENTS_FAILED: "at t = ...: event '...' ...";
                                         LAGCLI_EVENTS_BAD_VALUES: "event '...': restitution = ..." */
} lagcli_event_result;

/* Integrate from y0 at t = 0 to t_end with the model's events; a LAGCLI_ODE_* code or
 * LAGCLI_EVENTS_FAILED. */
int lagcli_events_integrate(const lagcli_event_run *run, const double *y0, lagcli_event_result *result);

/* The impact law for impact k at (t, y): qd_plus (nq) and the impulse P. Returns 0, 1
 * (singular: G in the span of the constraint rows) or 2 (not finite). */
int lagcli_events_impact(const lagcli_model *m, int k, double t, const double *y, const double *p,
                         double *qd_plus, double *P);

#ifdef __cplusplus
}
#endif

#endif /* LAGCLI_EVENTS_H */
