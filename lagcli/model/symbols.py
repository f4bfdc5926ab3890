"""The symbols of a model's velocities and accelerations: `q_dot` to the machine, q̇ to the eye.

`Velocity("theta_dot", real=True)` is a `sympy.Symbol` named `theta_dot` (the name
the spec language, the code printers and the JSON reports use) that sympy's own
display printers show as the lecture notes write it:

    latex(theta_dot)    \\dot{\\theta}          (theta1_dot -> \\dot{\\theta}_{1})
    pretty(theta_dot)   θ̇                      (a combining dot over the first letter)
    str(theta_dot)      theta_dot              (the spec language: reports parse back)

Only `_latex` and `_pretty` are defined: the code printers (`_ccode`, `_pythoncode`,
slot printers) and the spec printer (a `StrPrinter`) never see a special case. A
printer given its own `symbol_names` (lagcli's LaTeX printer) keeps them.

`class_key` is `Symbol`'s, so sorting (and therefore the order of printed terms) is
the same as for plain symbols of the same name.
"""
from __future__ import annotations

import sympy as sp
from sympy.printing.conventions import split_super_sub
from sympy.printing.pretty.stringpict import prettyForm

from lagcli.interface import ACCELERATION_SUFFIX, VELOCITY_SUFFIX

COMBINING = {r"\dot": "\N{COMBINING DOT ABOVE}", r"\ddot": "\N{COMBINING DIAERESIS}"}


class _Derived(sp.Symbol):
    """`<coordinate><suffix>`, shown with `accent` over the coordinate (class attributes)."""

    accent = suffix = ""

    @property
    def coordinate(self) -> str:
        return self.name[: -len(self.suffix)]

    @classmethod
    def class_key(cls):
        return sp.Symbol.class_key()

    def _latex(self, printer) -> str:
        own = printer._settings.get("symbol_names", {})
        if self in own:
            return own[self]
        base, supers, subs = split_super_sub(self.coordinate)
        tex = f"{self.accent}{{{printer._deal_with_super_sub(base)}}}"
        if supers:
            tex += "^{%s}" % " ".join(printer._deal_with_super_sub(s) for s in supers)
        if subs:
            tex += "_{%s}" % " ".join(printer._deal_with_super_sub(s) for s in subs)
        return tex

    def _pretty(self, printer):
        base = printer._print(sp.Symbol(self.coordinate))
        if not printer._use_unicode or base.height() != 1:
            return prettyForm(self.name)
        text = base.picture[0]
        return prettyForm(text[0] + COMBINING[self.accent] + text[1:])


class Velocity(_Derived):
    accent, suffix = r"\dot", VELOCITY_SUFFIX


class Acceleration(_Derived):
    accent, suffix = r"\ddot", ACCELERATION_SUFFIX
