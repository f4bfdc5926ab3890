"""The design's own measures (docs/design.md, "Measures"), checked on the source.

Each test reads lagcli's files (with `ast` for imports), so a change that breaks a
rule of the layout fails here with the file and the rule it broke.
"""
from __future__ import annotations

import tomllib
from collections import Counter
from pathlib import Path

ROOT = Path(__file__).resolve().parents[1]
PACKAGE = ROOT / "lagcli"
FACES = {"__init__", "__main__", "cli", "cli_options", "commands", "system", "interface", "errors", "trajectory",
         "version"}


def modules() -> list[Path]:
    return sorted(p for p in PACKAGE.rglob("*.py") if "__pycache__" not in p.parts)


def test_the_package_root_holds_only_the_faces():
    at_root = {p.stem for p in PACKAGE.glob("*.py")}
    assert at_root <= FACES, f"move these into a folder by concept: {sorted(at_root - FACES)}"


def test_no_two_modules_share_a_name():
    names = Counter(p.stem for p in modules() if p.stem != "__init__")
    shared = sorted(n for n, k in names.items() if k > 1)
    assert not shared, f"modules sharing a name: {shared}"


def test_every_folder_is_a_listed_package():
    """CI installs non-editably: a folder missing from pyproject's list is missing from the wheel."""
    listed = set(tomllib.loads((ROOT / "pyproject.toml").read_text())["tool"]["setuptools"]["packages"])
    folders = {".".join(p.parent.relative_to(ROOT).parts) for p in PACKAGE.rglob("__init__.py")
               if "__pycache__" not in p.parts}
    assert folders <= listed, f"add to [tool.setuptools] packages: {sorted(folders - listed)}"


# -- import directions ------------------------------------------------------------------

import ast  # noqa: E402

BELOW_THE_SYSTEM = ("lagcli.run", "lagcli.targets", "lagcli.runtime", "lagcli.interface")
ABOVE = ("lagcli.system", "lagcli.commands", "lagcli.cli", "lagcli.sweep", "lagcli.viz", "lagcli.trajectory")
NOT_BETWEEN = {"lagcli.run": ("lagcli.targets", "lagcli.analysis", "lagcli.report", "lagcli.derive"),
               "lagcli.targets": ("lagcli.run",),
               "lagcli.runtime": ("lagcli.run", "lagcli.targets"),
               "lagcli.interface": ()}     # data only: nothing of lagcli but errors, the version, run rules and limits


def module_name(path: Path) -> str:
    parts = path.relative_to(ROOT).with_suffix("").parts
    return ".".join(parts[:-1] if parts[-1] == "__init__" else parts)


def imports_of(path: Path) -> set[str]:
    """Every lagcli module `path` imports, at the top or inside a function."""
    found = set()
    for node in ast.walk(ast.parse(path.read_text())):
        if isinstance(node, ast.ImportFrom) and node.module and node.level == 0:
            found.add(node.module)
            found.update(f"{node.module}.{a.name}" for a in node.names)
        elif isinstance(node, ast.Import):
            found.update(a.name for a in node.names)
    return {name for name in found if name.startswith("lagcli")}


def in_room(name: str, room: str) -> bool:
    return name == room or name.startswith(room + ".")


def test_the_run_layer_and_the_targets_import_only_down():
    """No import from the run layer, the code targets, the runtime or the interface up to
    the System, the commands, the CLI, sweeps, pictures, nor between run layer and targets."""
    wrong = []
    for path in modules():
        name = module_name(path)
        room = next((r for r in BELOW_THE_SYSTEM if in_room(name, r)), None)
        if room is None:
            continue
        for target in imports_of(path):
            up = any(in_room(target, r) for r in ABOVE)
            across = any(in_room(target, r) for r in NOT_BETWEEN[room])
            if room == "lagcli.interface":
                across = not (in_room(target, "lagcli.errors") or in_room(target, "lagcli.runtime.run_rules")
                              or in_room(target, "lagcli.runtime.run_limits")
                              or target in ("lagcli", "lagcli.__version__", "lagcli.version",
                                             "lagcli.version.__version__"))
            if up or across:
                wrong.append(f"{name} imports {target}")
    assert not wrong, "imports against the direction of the design:\n" + "\n".join(sorted(wrong))


# -- floors: no import arrow runs up ------------------------------------------------------

def room_of(name: str) -> str:
    """The room of a lagcli module: its folder (`lagcli.run`), or the face itself at the root."""
    parts = name.split(".")
    return ".".join(parts[:2])


def room_arrows() -> dict[str, dict[str, set[str]]]:
    """room -> {room it imports: the modules that do}, between different rooms. `lagcli` and
    `lagcli.__version__` (the package's version, imported everywhere) are no room."""
    arrows: dict[str, dict[str, set[str]]] = {}
    for path in modules():
        name = module_name(path)
        here = room_of(name)
        arrows.setdefault(here, {})
        for target in imports_of(path):
            there = room_of(target)
            if there in ("lagcli", "lagcli.__version__") or there == here:
                continue
            if (PACKAGE / there.split(".")[1]).is_dir() or (PACKAGE / f"{there.split('.')[1]}.py").exists():
                arrows[here].setdefault(there, set()).add(name)
    return arrows


def a_circle(arrows: dict[str, dict[str, set[str]]]) -> list[str]:
    """One circle of rooms importing each other (empty when the rooms stand on floors)."""
    state: dict[str, str] = {}
    path: list[str] = []

    def visit(room: str) -> list[str]:
        state[room] = "open"
        path.append(room)
        for there in sorted(arrows.get(room, {})):
            if state.get(there) == "open":
                return path[path.index(there):] + [there]
            if there not in state and (found := visit(there)):
                return found
        state[room] = "done"
        path.pop()
        return []

    for room in sorted(arrows):
        if room not in state and (found := visit(room)):
            return found
    return []


def test_no_import_arrow_runs_up():
    """The rooms (folders, and the faces at the root) stand on floors: spec -> model ->
    derive -> targets / run -> analysis -> System -> commands -> cli, each importing only
    rooms below it. A circle of rooms means some arrow runs back up; this names it with
    the modules that make each of its arrows."""
    arrows = room_arrows()
    circle = a_circle(arrows)
    steps = [f"{a} -> {b} (by {', '.join(sorted(arrows[a][b]))})" for a, b in zip(circle, circle[1:])]
    assert not circle, "rooms importing each other in a circle:\n" + "\n".join(steps)


# -- facts written once ---------------------------------------------------------------------

def test_the_column_order_is_written_once():
    """The CSV column order (t, states, multipliers, invariants) is built by
    `lagcli.interface.layout_of` alone: no module or template of lagcli concatenates it
    again (targets read `Layout.header`; the generated Python module writes `HEADER`)."""
    import re

    order = re.compile(r'\["t", \*|\("t",\) \+|\*MULTIPLIERS, \*INVARIANTS|\*multipliers, \*invariants')
    found = [f"{path.relative_to(ROOT)}:{k}" for path in (*modules(), *(ROOT / "templates").rglob("*.jinja"))
             for k, line in enumerate(path.read_text().splitlines(), 1) if order.search(line)]
    assert not found, "the column order restated at:\n" + "\n".join(found)


def test_code_targets_take_the_systems_layout():
    """Every code target reads the run interface it is given; only the registry makes one
    (`layout_of`) for a caller that has none."""
    calls = [path.name for path in (PACKAGE / "targets").glob("*.py")
             if "layout_of(" in path.read_text() and path.name != "__init__.py"]
    assert not calls, f"targets computing their own layout: {calls}"


def test_the_settings_defaults_in_help_come_from_the_interface(monkeypatch):
    """--help of simulate and sweep quotes the run interface's defaults (`RunSettings`,
    `DEFAULT_BAUMGARTE`, the step budget): changed there, the help changes with them; no
    module but interface.py writes those numbers."""
    import dataclasses
    import re

    import click
    from click.testing import CliRunner

    from lagcli import cli_options
    from lagcli.cli import cli
    from lagcli.interface import RunSettings

    other = dataclasses.make_dataclass("Other", [("t_end", float, 12.5), ("dt", float, 0.025),
                                                 ("method", str, "RK45"), ("rtol", float, 3e-8),
                                                 ("atol", float, 4e-11), ("steps_per_row", int, 3)])
    monkeypatch.setattr(cli_options, "RunSettings", other)
    monkeypatch.setattr(cli_options, "DEFAULT_BAUMGARTE", (7.0, 8.0))
    monkeypatch.setattr(cli_options, "STEP_BUDGET_BASE", 31_000)
    command = cli_options.step_options(cli_options.settings_options(["RK45"], "M")(click.command()(lambda **k: 0)))
    text = " ".join(CliRunner().invoke(command, ["--help"]).output.split())
    for shown in ("else 12.5)", "else 0.025)", "else RK45)", "else 3e-8)", "else 4e-11)", "(default 7 8)",
                  "(default 31000 + 1000 per", "(default 3)"):
        assert shown in text, shown
    s = RunSettings()
    for name in ("simulate", "sweep"):
        text = " ".join(CliRunner().invoke(cli, [name, "--help"]).output.split())
        assert f"else {cli_options.number_text(s.rtol)})" in text and f"else {s.method})" in text
    numbers = re.compile(r"else (10|0\.01|1e-9|1e-12|DOP853)\)|default 10 10|20000 \+")
    quoted = [p.name for p in modules() if p.name != "interface.py" and numbers.search(p.read_text())]
    assert not quoted, f"settings defaults quoted outside lagcli/interface.py: {quoted}"
