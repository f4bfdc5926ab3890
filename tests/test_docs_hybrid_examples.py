"""The examples of events and input laws in docs/spec.md and docs/simulate.md are bundled
specs (issue 20: "docs/spec.md and docs/simulate.md explain both keys with these
examples, and the examples are bundled specs (`lagcli examples`)").

- Each `events:` item shown in a YAML block of those pages is, key for key (a default
  direction filled in), an event of
  the bundled spec its comment names (`specs/hybrid/<name>.yaml`), or of some bundled spec
  when it names none; each `simulate: inputs:` law shown is a bundled spec's law.
- The specs the pages name are listed by `lagcli examples`.
- docs/simulate.md's Python example runs as written, and its three kinds of law agree
  with each other where they are the same law: the expression string and a Python
  callable of the same formula give the same motion (two evaluation paths, the parsed
  law and Python), the law holds the pole up, and a number (held input) gives another motion.
"""
from __future__ import annotations

import re

import numpy as np
import pytest
import yaml
from click.testing import CliRunner

import lagcli
from lagcli.cli import cli
from conftest import ROOT, SPECS

PAGES = [ROOT / "docs" / "spec.md", ROOT / "docs" / "simulate.md"]
FENCE = re.compile(r"^```(\w*)\n(.*?)^```", re.M | re.S)
NAMED = re.compile(r"specs/hybrid/(\w+)\.yaml")


def bundled() -> dict[str, dict]:
    return {p.stem: yaml.safe_load(p.read_text()) for p in [*SPECS.glob("*.yaml"), *SPECS.glob("hybrid/*.yaml")]}


def yaml_blocks(key: str) -> list[tuple[str, str]]:
    return [(page.name, text) for page in PAGES for lang, text in FENCE.findall(page.read_text(encoding="utf-8"))
            if lang == "yaml" and re.search(rf"^\s*{key}", text, re.M)]


def event_items(text: str) -> list[tuple[str, dict]]:
    """(the spec its comment names or "", the item) of each `events:` item of a block."""
    body = text.split("events:", 1)[1]
    chunks = re.split(r"^(?=  - )", body, flags=re.M)
    out = []
    for chunk in chunks:
        if chunk.strip():
            (item,) = yaml.safe_load(chunk)
            named = NAMED.search(chunk)
            out.append((named.group(1) if named else "", item))
    return out


def test_the_pages_show_events_and_laws():
    assert len(yaml_blocks("events:")) >= 1 and len(yaml_blocks("inputs: {")) >= 1
    shown = {name for _, text in yaml_blocks("events:") for name, _ in event_items(text)}
    assert {"bouncing_ball", "rimless_wheel", "projectile_landing"} <= shown


def test_every_event_shown_is_an_event_of_a_bundled_spec():
    specs = bundled()
    for page, text in yaml_blocks("events:"):
        for name, item in event_items(text):
            where = [specs[name]] if name else list(specs.values())
            events = [with_defaults(e) for spec in where for e in spec.get("events") or []]
            assert with_defaults(item) in events, (page, name, item)


def with_defaults(event: dict) -> dict:
    return {"direction": "falling", **event}            # the default direction (docs/spec.md)


def test_every_law_shown_is_a_law_of_a_bundled_spec():
    laws = [spec["simulate"]["inputs"] for spec in bundled().values() if "inputs" in (spec.get("simulate") or {})]
    for page, text in yaml_blocks("inputs: {"):
        shown = yaml.safe_load(text)["simulate"]["inputs"]
        assert shown in laws, (page, shown)


def test_the_specs_the_pages_name_are_listed_by_lagcli_examples():
    listed = {line.split()[0] for line in CliRunner().invoke(cli, ["examples"]).output.splitlines()}
    named = {m for page in PAGES for m in NAMED.findall(page.read_text(encoding="utf-8"))}
    assert named and named <= listed, named - listed


def test_the_python_example_of_simulate_md_runs_and_its_laws_agree():
    text = (ROOT / "docs" / "simulate.md").read_text(encoding="utf-8")
    (example,) = [b for lang, b in FENCE.findall(re.sub(r"^  ", "", text, flags=re.M))
                  if lang == "python" and "inputs=" in b]
    runs = []
    namespace = {"lagcli": lagcli}
    for line in example.splitlines():
        line = line.split("  #")[0].replace("specs/", str(SPECS) + "/")
        if line.startswith("system.simulate("):
            runs.append(eval(line, namespace))                  # the docs' own lines, not a spec
        elif line.strip():
            exec(line, namespace)
    text_law, callable_law, held = runs
    system = namespace["system"]
    k2, k4 = (system.layout.parameter_defaults[k] for k in ("k2", "k4"))
    same = system.simulate(inputs={"F": lambda t, y: -(k2 * y[1] + k4 * y[3])})
    np.testing.assert_allclose(same.states, text_law.states, rtol=0, atol=1e-8)
    assert abs(text_law["theta"][-1]) < 1e-3                    # the law holds the pole up
    assert abs(callable_law["theta"][-1]) < 1e-3                # so does the callable (k2, k4 rounded)
    np.testing.assert_allclose(callable_law["theta"], text_law["theta"], rtol=0, atol=1e-3)
    assert np.max(np.abs(held["theta"])) > 1.0                  # held at 0 the pole falls
    assert held["x"][0] == 0.0 and np.all(np.diff(held.t) > 0)


@pytest.mark.parametrize("command", ["animate", "sweep"])
def test_input_on_animate_and_sweep_runs_the_law_of_simulate_input(command, tmp_path, monkeypatch):
    """`--input NAME=EXPR` on animate and sweep (issue 20) gives the run `simulate --input`
    gives: the states animate draws, and sweep's one-point final state, are simulate's."""
    import lagcli.viz.animate as drawing

    spec, law = str(SPECS / "cart_pole.yaml"), "F=-(-30.6*theta - 6.7*theta_dot - x - 2.2*x_dot)"
    out = tmp_path / "sim.csv"
    assert CliRunner().invoke(cli, ["simulate", spec, "--t-end", "1", "--input", law, "-o", str(out)]).exit_code == 0
    rows = np.loadtxt(out, delimiter=",", skiprows=1)
    if command == "animate":
        seen = {}
        real = drawing.animate
        monkeypatch.setattr(drawing, "animate", lambda system, times, states, *a, **k: (
            seen.update(t=np.asarray(times), y=np.asarray(states)), real(system, times, states, *a, **k))[1])
        result = CliRunner().invoke(cli, ["animate", spec, "--t-end", "1", "--input", law, "--frame", "1",
                                          "-o", str(tmp_path / "f.png")])
        assert result.exit_code == 0, result.output
        np.testing.assert_allclose(seen["y"], rows[:, 1:5], rtol=0, atol=1e-9)
        assert abs(rows[-1, 2]) < 0.05                      # the law keeps the pole near upright
        return
    summary = tmp_path / "sweep.csv"
    result = CliRunner().invoke(cli, ["sweep", spec, "--grid", "g=9.81:9.81:1", "--t-end", "1", "--input", law,
                                      "-o", str(summary)])
    assert result.exit_code == 0, result.output
    header, values = (line.split(",") for line in summary.read_text().splitlines()[:2])
    final = {h: float(v) for h, v in zip(header, values) if h.startswith("final_")}
    assert final, header
    for k, name in enumerate(["x", "theta", "x_dot", "theta_dot"], start=1):
        if f"final_{name}" in final:
            assert final[f"final_{name}"] == pytest.approx(rows[-1, k], abs=1e-7)


HYBRID = sorted((SPECS / "hybrid").glob("*.yaml"))


@pytest.mark.parametrize("path", HYBRID, ids=[p.stem for p in HYBRID])
def test_derive_and_check_list_each_event_with_its_action_and_an_impacts_G_row(path):
    """Issue 20: "`derive` and `check` list the events with their action, and for an
    impact its G row" — G against sympy's own gradient of the spec's `when`."""
    import json

    import sympy as sp

    from lagcli.render.spec_printer import parse_output

    spec = yaml.safe_load(path.read_text())
    system = lagcli.load(path)
    listed = json.loads(system.report("json")).get("events") or []
    assert [e["name"] for e in listed] == [e.get("name", f"event_{k}") for k, e in enumerate(spec.get("events") or [], 1)]
    check = CliRunner().invoke(cli, ["check", str(path)]).output
    for shown, event in zip(listed, spec.get("events") or []):
        assert shown["action"] == event["action"] and f"{shown['name']}: {event['action']} where" in check
        if event["action"] == "impact":
            gap = parse_output(str(event["when"]), system.model)
            G = [sp.diff(gap, q) for q in system.model.q]
            assert [sp.simplify(parse_output(g, system.model) - want) for g, want in zip(shown["G"], G)] == [0] * len(G)
            assert "G = [" + ", ".join(shown["G"]) + "]" in check


def test_the_api_linearizes_the_closed_loop_like_the_command():
    """System.linearize(closed_loop=True): A - B K of the open loop (K the spec's gains)."""
    system = lagcli.load(SPECS / "hybrid" / "cart_pole_lqr.yaml")
    p = system.layout.parameter_defaults
    open_loop, closed = system.linearize(), system.linearize(closed_loop=True)
    K = np.array([[p["k1"], p["k2"], p["k3"], p["k4"]]])            # F = -(k1 x + k2 theta + ...)
    np.testing.assert_allclose(closed.A, open_loop.A - open_loop.B @ K, rtol=1e-10, atol=1e-12)
    expected = np.sort_complex(np.linalg.eigvals(open_loop.A - open_loop.B @ K))
    np.testing.assert_allclose(np.sort_complex(np.asarray(closed.eigenvalues)), expected, rtol=1e-9)
    assert max(e.real for e in closed.eigenvalues) < 0 < max(e.real for e in open_loop.eigenvalues)
