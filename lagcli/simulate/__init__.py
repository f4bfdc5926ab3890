"""`lagcli simulate`: integrate a spec's equations of motion and write the CSV (and a PNG).

    options.py         Request (the command line), RunSettings, NAME=VALUE parsing
    run.py             simulate(request) -> Outcome: warm cached C driver first, else
                       through the Python API (lagcli.system.System.start / run)
    initial.py         consistent initial states of constrained systems (sympy + numpy)
    python_backend.py  the generated Python module + scipy's integrators
    c_backend.py       the generated C driver: compile, cache, run
    cache.py           the cache: key, private verified entries (only what lagcli built runs)
    cache_admin.py     lagcli cache info / clear
    trajectory.py      the row sinks (CSV stream, in memory, the plot's copy), output times
    plot.py            --plot: coordinates and conserved-quantity drift (matplotlib)

Importing this package (and options, run, c_backend, trajectory) imports neither
sympy nor numpy, so a warm C run starts in a few tens of milliseconds.  See
docs/simulate.md.
"""
