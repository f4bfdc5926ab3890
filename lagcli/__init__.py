"""lagcli: equations of motion from a short spec, by Lagrange's method.

    import lagcli
    system = lagcli.load("specs/double_pendulum.yaml")   # or the spec's YAML text
    trajectory = system.simulate(t_end=1.0)

docs/api.md describes the Python API; `import lagcli` stays light (sympy and numpy
are imported on first use), so the command line's warm path stays fast.
"""

from lagcli.version import __version__  # noqa: F401  (lagcli.__version__)


def load(source):
    """A `lagcli.system.System` from a spec file path or the spec's YAML text."""
    from lagcli.system import load as load_system

    return load_system(source)
