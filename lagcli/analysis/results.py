"""What the System's analyses return: typed values holding numpy arrays.

    lin = system.linearize(at={"theta": 0})        # Linearization: A, B, M, C, K, eigenvalues, point
    found = system.equilibria()                    # Equilibria: a sequence of Equilibrium
    system.hamiltonian(); system.routh(momenta={"p_phi": 0.5})

Each value shows itself in Jupyter (`_repr_latex_` and/or `_repr_html_`) and in a
console (a one-line `__repr__`); the commands `lagcli linearize`, `equilibria`,
`hamiltonian` and `routh` print the same values (`lagcli.analysis.report`). Symbolic
results (the Hamiltonian, the Routhian) hold sympy expressions; their LaTeX is made
by the reports' printer of the derivation they came from, kept for that only.
"""
from __future__ import annotations

from dataclasses import dataclass, field
from html import escape

import numpy as np

from lagcli.analysis.report import bmatrix, shown, shown_point
from lagcli.analysis.wording import complex_text, drift_sentence, number
from lagcli.analysis.stability import Mode, modes_of, oscillation_frequencies
from lagcli.render.escape import latex_text

_HTML_DIGITS = 6


@dataclass(frozen=True)
class OperatingPoint:
    """The point a linearization is about, by name (dependent values solved for)."""

    coordinates: dict[str, float]
    velocities: dict[str, float]
    t: float
    parameters: dict[str, float]        # every parameter's value used
    inputs: dict[str, float]            # every declared input's value held
    notes: tuple[str, ...] = ()         # what was solved for

    @property
    def state(self) -> dict[str, float]:
        return {**self.coordinates, **self.velocities}


@dataclass(frozen=True, eq=False)
class Linearization:
    """x' = A x + B u about `point`, x = `states` (independent coordinates, then
    independent speeds), u = `inputs`; the second-order form
    M v' + C v + K q = F u over v = `speeds` and q = `coordinates`, F = `B_second`.
    Displays write these letters as `letters` gives them (none a spec name).
    `eigenvalues` are A's without the zero modes there by structure (`neutral` names
    their states, `drift` the states that grow linearly through them); `verdict` and its
    `evidence` as docs/analysis.md, "Stability verdict"."""

    name: str
    point: OperatingPoint
    states: tuple[str, ...]
    inputs: tuple[str, ...]
    coordinates: tuple[str, ...]
    speeds: tuple[str, ...]
    dependent: tuple[str, ...]          # eliminated by the constraints
    A: np.ndarray
    B: np.ndarray
    M: np.ndarray
    C: np.ndarray
    K: np.ndarray
    B_second: np.ndarray
    speed_rates: np.ndarray             # u' at the point: 0 at an equilibrium or steady motion
    eigenvalues: np.ndarray
    neutral: tuple[str, ...]
    negative_stiffness: bool
    verdict: str
    evidence: str = ""                  # the numbers the verdict rests on (one sentence)
    drift: tuple[str, ...] = ()         # states growing linearly with time (a defective s = 0)
    defective: tuple[complex, ...] = () # eigenvalues on the axis with fewer eigenvectors than repeats
    latex_names: dict = field(default_factory=dict, repr=False)   # state/input name -> LaTeX

    @property
    def letters(self) -> dict[str, str]:
        """The letters its displays use for x, u, v, q, A, B, M, C, K, F, G: each one a
        letter no name of the spec in the output takes (`lagcli.report.notation`)."""
        from lagcli.report.notation import linear_letters

        return linear_letters((*self.point.state, *self.point.parameters, *self.point.inputs,
                               *self.states, *self.inputs))

    @property
    def gyroscopic(self) -> np.ndarray:
        from lagcli.analysis.linearize import gyroscopic_part

        return gyroscopic_part(self.C)

    @property
    def damping(self) -> np.ndarray:
        from lagcli.analysis.linearize import damping_part

        return damping_part(self.C)

    @property
    def modes(self) -> tuple[Mode, ...]:
        return modes_of(self.eigenvalues, self.defective)

    @property
    def frequencies(self) -> tuple[float, ...]:
        """Small-oscillation frequencies (rad/s): only of pairs on the imaginary axis with their
        own eigenvectors (`stability.oscillation_frequencies`)."""
        return oscillation_frequencies(self.modes)

    def __repr__(self) -> str:
        where = ", ".join(f"{k} = {number(v, 6)}" for k, v in self.point.state.items())
        values = ", ".join(complex_text(s, 6) for s in self.eigenvalues) or "none"
        drift = f"; drift: {', '.join(self.drift)}" if self.drift else ""
        return f"<Linearization of {self.name} about {where}: {self.verdict}; eigenvalues {values}{drift}>"

    def _repr_latex_(self) -> str:
        from lagcli.report.notation import linear_equations, linear_latex_letters

        name, n = self.latex_names.get, linear_latex_letters(self.letters)

        def vector(names) -> str:
            return r"\left(" + ", ".join(name(s, _texttt(s)) for s in names) + r"\right)^\mathsf{T}"

        inputs = self.inputs
        first, second = (e.replace(" = ", " &= ") for e in linear_equations(n, bool(inputs), r"\,"))
        rows = [first + rf", \quad {n['x']} = {vector(self.states)}"
                + (rf", \quad {n['u']} = {vector(inputs)}" if inputs else ""),
                rf"{n['A']} &= {bmatrix(self.A)}" + (rf", \quad {n['B']} = {bmatrix(self.B)}" if inputs else ""),
                second + rf", \quad {n['v']} = {vector(self.speeds)}, \quad {n['q']} = {vector(self.coordinates)}",
                rf"{n['M']} &= {bmatrix(self.M)}, \quad {n['C']} = {bmatrix(self.C)}, \quad {n['K']} = {bmatrix(self.K)}"
                + (rf", \quad {n['F']} = {bmatrix(self.B_second)}" if inputs else ""),
                r"\text{eigenvalues} &: " + (", ".join(complex_text(s, 6).replace("i", r"\,i")
                                                       for s in self.eigenvalues) or r"\text{none}"),
                rf"\text{{verdict}} &: \text{{{latex_text(self.verdict)} ({latex_text(self.evidence)})}}"]
        if self.drift:
            rows.insert(-1, rf"\text{{drift}} &: \text{{{latex_text(drift_sentence(self.drift))}}}")
        return r"$$\begin{aligned}" + r" \\ ".join(rows) + r"\end{aligned}$$"

    def _repr_html_(self) -> str:
        where = ", ".join(f"{k} = {number(v, _HTML_DIGITS)}" for k, v in self.point.state.items())
        from lagcli.report.notation import linear_equations

        n = self.letters
        first, second = linear_equations(n, bool(self.inputs))
        parts = [f"<p><b>{escape(self.name)}</b> linearized about {escape(where)}: "
                 f"{escape(first)}; {escape(second)}</p>",
                 _html_matrix(n["A"], self.A, self.states, self.states)]
        if self.inputs:
            parts.append(_html_matrix(n["B"], self.B, self.states, self.inputs))
        parts += [_html_matrix(n["M"], self.M, self.speeds, self.speeds),
                  _html_matrix(n["C"], self.C, self.speeds, self.speeds),
                  _html_matrix(n["K"], self.K, self.speeds, self.coordinates)]
        if self.inputs:
            parts.append(_html_matrix(n["F"], self.B_second, self.speeds, self.inputs))
        drift = f"<br/>drift: {escape(drift_sentence(self.drift))}" if self.drift else ""
        parts.append(f"<p>eigenvalues: {escape(', '.join(complex_text(s, _HTML_DIGITS) for s in self.eigenvalues))}"
                     f"{drift}<br/>verdict: <b>{escape(self.verdict)}</b> ({escape(self.evidence)})</p>")
        return "<div>" + "".join(parts) + "</div>"


@dataclass(frozen=True, eq=False)
class Equilibrium:
    """A point of rest (q' = 0): `point` {coordinate: value}, `closed_form` {coordinate:
    sympy expression of the parameters} when solved symbolically, and its linearization
    (None where the mass matrix is singular); `free`: the coordinates along which it is one
    of a family (a disc upright anywhere, at any heading), shown at the member nearest the
    first guess."""

    point: dict[str, float]
    closed_form: dict | None
    linearization: Linearization | None
    free: tuple[str, ...] = ()
    singular: object = None     # where M is singular because of the coordinates: what lagcli can say
                                # (`singular_chart.CoordinateSingularity`: `notes`); the linearization
                                # is then in a regular chart assembled there (states w1, ..), if any

    @property
    def eigenvalues(self) -> np.ndarray:
        return self.linearization.eigenvalues if self.linearization else np.zeros(0, dtype=complex)

    @property
    def verdict(self) -> str:
        if self.linearization:
            return self.linearization.verdict
        return "not decided" if self.singular is not None else "not linearizable here (singular mass matrix)"

    @property
    def modes(self) -> tuple[Mode, ...]:
        """The modes of its eigenvalues (`Mode`: frequency, damping ratio, kind)."""
        return self.linearization.modes if self.linearization else ()

    @property
    def frequencies(self) -> tuple[float, ...]:
        """Small-oscillation frequencies (rad/s): only where the motion is small oscillations
        (pairs on the imaginary axis with their own eigenvectors; a spiral has none)."""
        return oscillation_frequencies(self.modes)

    @property
    def evidence(self) -> str:
        """The numbers its verdict rests on (docs/analysis.md, "Stability verdict")."""
        return self.linearization.evidence if self.linearization else ""

    @property
    def drift(self) -> tuple[str, ...]:
        return self.linearization.drift if self.linearization else ()

    def __repr__(self) -> str:
        where = ", ".join(f"{k} = {number(v, 6)}" for k, v in zip(self.point, shown_point(self.point)))
        return f"<Equilibrium {where}: {self.verdict}>"


@dataclass(frozen=True, eq=False)
class Equilibria:
    """The equilibria found (a sequence of `Equilibrium`, in order of their coordinates)."""

    name: str
    parameters: dict[str, float]        # the parameter and input values they are for
    found: tuple[Equilibrium, ...]
    proved_none: bool = False           # none found, and the closed forms show there is none

    def __len__(self) -> int:
        return len(self.found)

    def __iter__(self):
        return iter(self.found)

    def __getitem__(self, k: int) -> Equilibrium:
        return self.found[k]

    def __repr__(self) -> str:
        return (f"<Equilibria of {self.name}: " + ("none exists" if self.proved_none else f"{len(self)} found") + "".join(
            f"; {', '.join(f'{k} = {number(v, 6)}' for k, v in zip(e.point, shown_point(e.point)))} {e.verdict}"
            for e in self) + ">")

    def _repr_html_(self) -> str:
        names = list(self.found[0].point) if self.found else []
        head = "".join(f"<th>{escape(n)}</th>" for n in ["", *names, "verdict", "eigenvalues"])
        rows = "".join(
            f"<tr><td>{k}</td>" + "".join(f"<td>{number(v, _HTML_DIGITS)}</td>" for v in shown_point(e.point))
            + f"<td>{escape(e.verdict)}{_because_html(e)}{_notes_html(e)}</td>"
            + f"<td>{escape(', '.join(complex_text(s, _HTML_DIGITS) for s in e.eigenvalues))}</td></tr>"
            for k, e in enumerate(self, 1))
        caption = f"equilibria of {self.name} (q' = 0): " + ("none exists (the equations at rest have no solution)"
                                                          if self.proved_none else f"{len(self)} found")
        return f"<table><caption>{escape(caption)}</caption><tr>{head}</tr>{rows}</table>"


def _because_html(e: Equilibrium) -> str:
    """The verdict's evidence and the drift, as the text report words them."""
    lines = [f"because: {e.evidence}"] if e.evidence else []
    lines += [f"drift: {drift_sentence(e.drift)}"] if e.drift else []
    return "".join(f"<br/><small>{escape(line)}</small>" for line in lines)


def _notes_html(e: Equilibrium) -> str:
    """The family and coordinate-singularity notes of `e`, as the text report words them."""
    notes = ([f"one of a family along {', '.join(e.free)}"] if e.free else []) \
        + list(e.singular.notes if e.singular is not None else ())
    return "".join(f"<br><small>{escape(n)}</small>" for n in notes)


@dataclass(frozen=True, eq=False)
class Hamiltonian:
    """p = M q' + a (`momenta`, expressions of q and q'), H(q, p, t) and Hamilton's
    equations (`equations`: q_dot and p_<q>_dot by name); `H` and `equations` are None
    when M is full and larger than 2 x 2 (the solved form of docs/analysis.md)."""

    name: str
    momenta: dict
    H: object
    equations: dict | None
    derivation: object = field(repr=False, default=None)
    form: object = field(repr=False, default=None)

    def __repr__(self) -> str:
        from lagcli.render.spec_printer import spec_str

        return f"<Hamiltonian of {self.name}: H = {spec_str(self.H) if self.H is not None else '(solved form)'}>"

    def _repr_latex_(self) -> str:
        from lagcli.analysis.report import hamilton_rows

        return r"$$\begin{aligned}" + r" \\ ".join(hamilton_rows(self.form, self.derivation)) + r"\end{aligned}$$"


@dataclass(frozen=True, eq=False)
class Routh:
    """The Routhian R over the `cyclic` coordinates at momenta `momenta` (symbols
    p_<q>), the effective potential, the cyclic velocities, the reduced equations
    (each = 0; `reduced_terms`: their terms as printed, q'' terms first) and, when momenta
    were given, the steady motions (`lagcli.analysis.routh.SteadyMotion`: coordinates,
    cyclic rates, eigenvalues)."""

    name: str
    cyclic: tuple[str, ...]
    momenta: tuple[str, ...]
    R: object
    effective_potential: object
    cyclic_velocities: dict
    reduced_equations: tuple
    steady_motions: tuple
    derivation: object = field(repr=False, default=None)
    reduced_terms: tuple = field(repr=False, default=())

    def __repr__(self) -> str:
        return (f"<Routh reduction of {self.name} over {', '.join(self.cyclic)}: "
                f"{len(self.steady_motions)} steady motions>")

    def _repr_latex_(self) -> str:
        from lagcli.analysis.report import routh_rows

        return r"$$\begin{aligned}" + r" \\ ".join(routh_rows(self, self.derivation)) + r"\end{aligned}$$"


def _texttt(name: str) -> str:
    return r"\mathtt{" + name.replace("_", r"\_") + "}"


def _html_matrix(label: str, a: np.ndarray, rows, cols) -> str:
    if a.size == 0:
        return f"<p>{escape(label)} = (empty)</p>"
    head = "".join(f"<th>{escape(c)}</th>" for c in cols)
    body = "".join(f"<tr><th>{escape(r)}</th>" + "".join(f"<td>{number(x, _HTML_DIGITS)}</td>" for x in row)
                   + "</tr>" for r, row in zip(rows, shown(a)))
    return f"<table><caption>{escape(label)}</caption><tr><th></th>{head}</tr>{body}</table>"
