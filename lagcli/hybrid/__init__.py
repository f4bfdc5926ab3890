"""Hybrid motion: input laws and events (spec `simulate: inputs:` and `events:`).

    model.py     the laws and events parsed into sympy (the safe parser), with their checks
    derive.py    event functions g(t, q, q'), and for an impact G = dg/dq and g_t
    impact.py    the impact law solved numerically, like the augmented system
    numeric.py   laws, event functions and actions as numpy functions of (t, y, p)
    loop.py      the Python backend's event loop (scipy's DOP853 dense output + brentq)
    records.py   what happened: one record per event, the --events CSV, the summary line
    report.py    what `derive` and `check` say about the events
"""
