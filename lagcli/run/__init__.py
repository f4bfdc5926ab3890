"""The run layer: integrate a system and hand its rows to a sink.

    simulate.py        simulate(request) -> Outcome: `lagcli simulate` (warm cached C
                       driver first, else through the Python API)
    options.py         Request (the command line), RunSettings, NAME=VALUE parsing
    python_backend.py  the generated Python module + scipy's integrators
    c_backend.py       the generated C driver: compile, cache, run
    cache.py           the cache: key, private verified entries (only what lagcli built runs)
    cache_admin.py     lagcli cache info / clear
    rows.py            the row sinks (CSV stream, in memory, the plot's copy), output times

The consistent initial state is computed above this layer
(lagcli/analysis/initial_state.py); the pictures are in lagcli/viz/.
Importing this package (and options, simulate, c_backend, rows) imports neither
sympy nor numpy, so a warm C run starts in a few tens of milliseconds.  See
docs/simulate.md.
"""
