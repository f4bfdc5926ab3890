"""Pictures of a run: plot.py (`simulate --plot`, `Trajectory.plot`), animate.py (`lagcli animate`)."""
