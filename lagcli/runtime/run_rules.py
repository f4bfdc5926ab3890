"""lagcli's rules of a run, in Python, written once: the run layer and targets import them;
the generated Python module carries this file's code, verbatim, after its imports
(`lagcli.runtime.python_run_rules`). Standard library only, no `from __future__`
(the text is pasted into another module): the generated module stays self-contained.

    EXPLICIT_METHODS    explicit Runge-Kutta: the ones the C driver implements, and
                        the ones whose step is capped on constrained systems (max_step)
    output_times        t_k = k dt, k = 0 .. floor(t_end/dt + OUTPUT_SLACK), then
                        t_end when the last t_k < t_end - END_TOLERANCE max(1, t_end);
                        output_time_windows: the same times a window at a time
    max_step            the step cap of the explicit methods on a constrained system

The C runtime states the same rules once in C (lagcli/runtime/c/lagcli_driver.c);
tests/test_c_runtime.py checks the constants agree.
"""
# --- lagcli's run rules (lagcli/runtime/run_rules.py) ---
import math

EXPLICIT_METHODS = ("RK45", "DOP853")
OUTPUT_SLACK = 1e-9          # t_end/dt this close below an integer still counts as reaching it
END_TOLERANCE = 1e-12        # relative: a last t_k this close to t_end is t_end


def output_times(t_end, dt):
    """The output times of a run from t = 0, as a list (docs/design.md, "Output times")."""
    return [t for window in output_time_windows(t_end, dt) for t in window]


def output_time_windows(t_end, dt, size=4096):
    """`output_times` as consecutive lists of at most `size` times, computed as they are
    needed: a run of 1e8 rows never holds them all."""
    count = math.floor(t_end / dt + OUTPUT_SLACK)
    for start in range(0, count + 1, size):
        window = [k * dt for k in range(start, min(start + size, count + 1))]
        if start + size > count and window[-1] < t_end - END_TOLERANCE * max(1.0, t_end):
            window.append(t_end)
        yield window


def max_step(method, alpha, beta, constrained):
    """The largest step of an explicit Runge-Kutta method on a Baumgarte-stabilised system.

    The constraint error e obeys e'' + 2 alpha e' + beta^2 e = 0, with eigenvalues
    lambda = -alpha +- sqrt(alpha^2 - beta^2). Left alone, the step controller of a
    system with slow (or polynomial) physical motion lets h |lambda| grow to the edge
    of the method's stability region (about 3.3 for RK45, 6 for DOP853), where the
    error estimate is unreliable: the constraints then drift to ~1e-6 and tiny rounding
    differences change the steps (lagcli's docs/simulate.md, "Constraint stabilisation").
    h |lambda| <= 1 keeps that mode well resolved; inf (no cap) when there is no such
    mode (unconstrained, zero gains) or for the implicit methods."""
    if not constrained or method not in EXPLICIT_METHODS:
        return math.inf
    alpha, beta = abs(alpha), abs(beta)
    rate = max(alpha + math.sqrt(max(alpha * alpha - beta * beta, 0.0)), beta)
    return 1.0 / rate if rate > 0 else math.inf
