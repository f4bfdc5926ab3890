"""`lagcli sweep` and `System.sweep`: many runs of one system through the compiled driver.

    plan.py       which runs: --grid, --sample/--count/--seed, --runs table.csv
    driver.py     the driver's batch interface (many runs per process)
    executors.py  local driver processes, or a Dask cluster (--scheduler)
    summary.py    the summary columns, the journal of a running sweep, the output file
    run.py        the whole sweep: consistent initial states, chunks, summary

docs/sweep.md is the user's guide.
"""
from lagcli.sweep.plan import Plan, make_plan
from lagcli.sweep.run import SweepOptions, SweepResult, sweep

__all__ = ["Plan", "make_plan", "SweepOptions", "SweepResult", "sweep"]
