"""The numbers and rules of a simulation that every stage shares (no sympy, no numpy).

Imported by the spec schema (`METHODS`), the command line, the simulator and the
code generators: a rule written here once is the rule of `lagcli simulate` (either
backend), of the generated Python module and of the generated C driver
(docs/simulate.md, docs/design.md "Where each fact of a run is written").

    METHODS                 scipy's integrators `simulate` accepts, and `variational`
    C_METHODS               the ones the compiled driver implements
    DEFAULT_BAUMGARTE       (alpha, beta) of the constraint stabilisation
    CONSTRAINT_TOLERANCE    largest |constraint| of a consistent initial state

The rules the generated Python module carries too — `EXPLICIT_METHODS`,
`output_times`, `output_time_windows`, `max_step` and their constants — are
written in `lagcli/runtime/run_rules.py`, whose code the module template inserts
verbatim; they are re-exported here.
"""
from __future__ import annotations

from lagcli.runtime.run_rules import (END_TOLERANCE, EXPLICIT_METHODS, OUTPUT_SLACK,  # noqa: F401
                                      max_step, output_time_windows, output_times)

VARIATIONAL = "variational"     # lagcli's own fixed-step integrator (lagcli/derive/discrete.py)
METHODS = ("RK45", "DOP853", "Radau", "BDF", "LSODA", VARIATIONAL)
C_METHODS = (*EXPLICIT_METHODS, VARIATIONAL)    # the ones the C driver implements
DEFAULT_BAUMGARTE = (10.0, 10.0)
CONSTRAINT_TOLERANCE = 1e-8
