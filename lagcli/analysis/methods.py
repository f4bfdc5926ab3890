"""What `System.linearize`, `linearize_sweep`, `linearize_symbolic`, `equilibria`,
`hamiltonian` and `routh` do: the API's arguments (dicts by name, checked) handed to the
analysis machinery, its answers made into the typed values of `results`.

The commands call the same methods and only format what they return
(`lagcli.analysis.report`). The compiled Jacobians of a system are made once per
System and set of extra inputs (a notebook's second linearization costs milliseconds).
"""
from __future__ import annotations

from lagcli.analysis.operating_point import Assignments, assignments_of
from lagcli.analysis.results import Equilibria, Equilibrium, Hamiltonian, Linearization, OperatingPoint, Routh
from lagcli.errors import UsageError


def point_of(system, at, parameters=None, inputs=None, sweep: str | None = None) -> Assignments:
    """`at` ({name: number or expression text}, or the parsed `--at` values) with the
    `parameters` and `inputs` of this call added (their names checked as `simulate`'s);
    on a constrained system, what `at` does not give is solved for from the spec's
    consistent initial state."""
    fixed = {**system._parameters(parameters), **_held_inputs(system, inputs)}
    if not isinstance(at, Assignments):
        at = assignments_of(system.derivation, dict(at or {}), sweep)
    if system.derivation.constraints:
        at = at.starting_at(initial_coordinates(system))
    return at.given(fixed)


def initial_coordinates(system) -> dict[str, float]:
    """The coordinates of the spec's consistent initial state (`System.spec_start`): where
    a constrained point's dependent coordinates are solved from."""
    start, _ = system.spec_start()
    return {q.name: float(v) for q, v in zip(system.model.q, start.values)}


def derivation(system, closed_loop: bool = False):
    """The System's derivation, or (`closed_loop`) with the spec's input laws substituted
    (`lagcli.derive.closed_loop`), made once."""
    if not closed_loop:
        return system.derivation
    from lagcli.derive.closed_loop import closed_loop as close

    return system._once("_closed_loop", lambda: close(system.derivation))


def compiled(system, extra_inputs=(), closed_loop: bool = False):
    """The derivation's matrices and Jacobians compiled (`linearize.CompiledSystem`), once."""
    from lagcli.analysis.linearize import CompiledSystem

    extra = tuple(extra_inputs)
    key = "_compiled:" + ",".join(extra) + (":closed" if closed_loop else "")
    return system._once(key, lambda: CompiledSystem(derivation(system, closed_loop), extra))


def linearize(system, at=None, parameters=None, inputs=None, independent=(), extra_inputs=(),
              closed_loop: bool = False) -> Linearization:
    from lagcli.analysis.linearize import linearize as linear_model
    from lagcli.analysis.operating_point import evaluate
    from lagcli.analysis.stability import stability

    d = derivation(system, closed_loop)
    lm = linear_model(compiled(system, extra_inputs, closed_loop), evaluate(d, point_of(system, at, parameters, inputs)),
                      tuple(independent))
    lin = linearization(d, lm, stability(lm))
    return _closed_loop_noted(lin, d.model) if closed_loop else lin


def _closed_loop_noted(lin: Linearization, model) -> Linearization:
    """`lin` with a note on its point naming the laws substituted (their inputs' columns
    of B are then zero: the law, not the input, drives the closed loop)."""
    import dataclasses

    from lagcli.render.spec_printer import spec_str

    laws = "; ".join(f"{law.symbol.name} = {spec_str(law.expr)}" for law in model.laws)
    note = f"closed loop: the input laws substituted ({laws})"
    return dataclasses.replace(lin, point=dataclasses.replace(lin.point, notes=(*lin.point.notes, note)))


def linearize_sweep(system, variable: str, values, at=None, parameters=None, inputs=None, independent=(),
                    extra_inputs=(), find_critical: bool = False, closed_loop: bool = False):
    """Stability at each of `values` of `variable` (a parameter, or a name `at` uses)."""
    from lagcli.analysis.sweep import LinearizationSweep, critical_values, sweep

    points = point_of(system, at, parameters, inputs, variable)
    linear = compiled(system, extra_inputs, closed_loop)
    table = sweep(linear, points, [float(v) for v in values], tuple(independent))
    critical = critical_values(linear, points, table, tuple(independent)) if find_critical else []
    return LinearizationSweep(variable, tuple(table), tuple(critical))


def linearize_symbolic(system, at=None, extra_inputs=(), closed_loop: bool = False):
    """A and B as sympy matrices of the parameters (`lagcli.analysis.symbolic.SymbolicLinear`)."""
    from lagcli.analysis.symbolic import symbolic_linear

    if not isinstance(at, Assignments):
        at = assignments_of(system.derivation, dict(at or {}))
    return symbolic_linear(derivation(system, closed_loop), at, tuple(extra_inputs))


def linearization(d, lm, st) -> Linearization:
    """The typed value of a `linearize.LinearModel` and its `stability.Stability`."""
    from lagcli.report.latex_printer import LatexPrinter

    model, p = d.model, lm.point
    point = OperatingPoint({s.name: float(v) for s, v in zip(model.q, p.q)},
                           {s.name: float(v) for s, v in zip(model.qd, p.qd)}, p.t,
                           {x.symbol.name: p.parameters[x.symbol.name] for x in model.parameters},
                           {u.symbol.name: p.parameters[u.symbol.name] for u in model.inputs}, tuple(p.notes))
    printer = LatexPrinter(model)
    spec_names = {s.name for s in (*model.q, *model.qd, *model.parameter_symbols, *model.input_symbols)}
    names = {n: printer.doprint(model.symbol(n)) if n in spec_names else _chart_latex(printer, model, n)
             for n in (*lm.states, *lm.inputs)}
    return Linearization(model.name, point, lm.states, lm.inputs, lm.coordinates, lm.speeds, lm.dependent,
                         lm.A, lm.B, lm.M, lm.C, lm.K, lm.B2, lm.speed_rates, st.eigenvalues, st.neutral,
                         st.negative_stiffness, st.verdict, st.evidence, st.drift, st.defective, names)


def _chart_latex(printer, model, name: str) -> str:
    """`theta'` -> theta's LaTeX primed, `theta'_dot` -> dotted: a coordinate of the chart
    lagcli assembled at a coordinate singularity (singular_chart.py)."""
    base = name.removesuffix("_dot")
    primes = len(base) - len(base.rstrip("'"))
    letter = printer.doprint(model.symbol(base.rstrip("'")))
    return (rf"\dot{{{letter}}}" if name != base else letter) + "'" * primes


def equilibria(system, parameters=None, inputs=None, guesses=None) -> Equilibria:
    from lagcli.analysis.equilibria import default_guesses, equilibria as find

    d = system.derivation
    values = _constants(system, parameters, inputs)
    found = find(d, values, default_guesses(d, _guesses(d, guesses)))
    return Equilibria(d.model.name, values, tuple(
        Equilibrium(e.coordinates, e.symbolic, linearization(d, e.linear, e.stability) if e.linear else None,
                    e.free, e.singular)
        for e in found), found.proved_none)


def _constants(system, parameters, inputs) -> dict[str, float]:
    """Every parameter's and input's value: the spec's, overridden by this call's."""
    model = system.derivation.model
    spec = {p.symbol.name: float(p.value) for p in (*model.parameters, *model.inputs)}
    return spec | system._parameters(parameters) | _held_inputs(system, inputs)


def _held_inputs(system, inputs) -> dict[str, float]:
    """{input: number}: an analysis holds each input at a value (a law is for `simulate`)."""
    constants, laws = system._inputs(inputs)
    if laws:
        raise UsageError(f"inputs=: {next(iter(laws))!r}: an analysis holds an input at a number, "
                         "not a law\n  hint: give its value")
    return constants


def _guesses(d, guesses) -> list[dict]:
    """Starting points [{coordinate or multiplier: value}], names checked."""
    from lagcli.run.options import _hint

    names = [s.name for s in (*d.model.q, *d.multipliers)]
    for guess in guesses or []:
        unknown = [name for name in guess if name not in names]
        if unknown:
            raise UsageError(f"guesses=: unknown coordinate {unknown[0]!r}" + _hint(unknown[0], names, "coordinates"))
    return [{k: float(v) for k, v in g.items()} for g in guesses or []]


def hamiltonian(system) -> Hamiltonian:
    from lagcli.derive.hamilton_form import hamilton_form

    d = system.derivation
    form = hamilton_form(d)
    q = d.model.q
    equations = None
    if form.H is not None:
        equations = {**{f"{s.name}_dot": e for s, e in zip(q, form.qdot)},
                     **{f"{p.name}_dot": e for p, e in zip(form.momenta, form.pdot)}}
    return Hamiltonian(d.model.name, {p.name: e for p, e in zip(form.momenta, form.momentum_exprs)},
                       form.H, equations, d, form)


def routh(system, momenta=None, parameters=None, inputs=None, guesses=None) -> Routh:
    from lagcli.analysis.routh import routhian, steady_motions

    d = system.derivation
    reduction = routhian(d)
    names = [p.name for p in reduction.momenta]
    given = {k: float(v) for k, v in (momenta or {}).items()}
    unknown = [k for k in given if k not in names]
    if unknown:
        from lagcli.run.options import _hint
        raise UsageError(f"momenta=: unknown momentum {unknown[0]!r}" + _hint(unknown[0], names, "momenta"))
    motions = ()
    if given:
        missing = [n for n in names if n not in given]
        if missing:
            raise UsageError(f"give every cyclic momentum (--momentum, momenta=): missing {', '.join(missing)}")
        starts = _guesses(d, guesses) or [dict(d.model.initial), {}]
        motions = tuple(steady_motions(d, reduction, given, _constants(system, parameters, inputs), starts))
    model = d.model
    return Routh(model.name, tuple(c.name for c in reduction.cyclic), tuple(names), reduction.R,
                 reduction.effective_potential,
                 {model.qd[model.q.index(c)].name: e for c, e in zip(reduction.cyclic, reduction.cyclic_velocities)},
                 reduction.equations, motions, d, reduction.equation_terms)
