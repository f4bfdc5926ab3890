"""The bundled example specs, installed as package data (see lagcli/spec/examples.py)."""
