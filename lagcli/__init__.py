"""lagcli: equations of motion from a short spec, by Lagrange's method."""

__version__ = "0.1.0"
