"""lagcli's C runtime (lagcli/runtime/c/) used on its own, as someone embedding a
generated model would: a C++ program that includes a generated header, a C program
that drives the shipped integrator on a generated right-hand side, and the numbers
the driver shares with lagcli/interface.py.
"""
from __future__ import annotations

import io
import re
import shutil
import subprocess
from pathlib import Path

import numpy as np
import pytest
from click.testing import CliRunner

from conftest import ROOT, SPECS

CC = shutil.which("cc")
CXX = shutil.which("g++") or shutil.which("c++")
CFLAGS = ["-std=c99", "-O2", "-Wall", "-Wextra", "-Werror", "-pedantic"]
RUNTIME = ROOT / "lagcli" / "runtime" / "c"

CXX_PROGRAM = r"""
#include <cmath>
#include <cstdio>
#include "cartesian_pendulum.h"

int main()
{
    double y[CARTESIAN_PENDULUM_NSTATE], p[CARTESIAN_PENDULUM_NPARAM];
    double M[CARTESIAN_PENDULUM_NQ * CARTESIAN_PENDULUM_NQ], F[CARTESIAN_PENDULUM_NQ];
    double A[CARTESIAN_PENDULUM_NLAMBDA * CARTESIAN_PENDULUM_NQ], b[CARTESIAN_PENDULUM_NLAMBDA];
    double inv[CARTESIAN_PENDULUM_NINV];
    const lagcli_model &model = cartesian_pendulum_model;
    for (int i = 0; i < model.nstate; ++i)
        y[i] = model.initial_state[i];
    for (int i = 0; i < model.nparam; ++i)
        p[i] = model.parameter_defaults[i];
    p[CARTESIAN_PENDULUM_P_l] = 2.0;
    y[CARTESIAN_PENDULUM_Q_x] = 1.2;
    y[CARTESIAN_PENDULUM_Q_y] = -1.6;
    if (cartesian_pendulum_mass_matrix(0.0, y, p, M) || cartesian_pendulum_forcing(0.0, y, p, F)
        || cartesian_pendulum_constraint_matrix(0.0, y, p, A) || cartesian_pendulum_constraint_bias(0.0, y, p, b)
        || cartesian_pendulum_invariants(0.0, y, p, inv))
        return 1;
    std::printf("%.17g %.17g %.17g %.17g %.17g %.17g %.17g\n", M[0], M[1], F[1], A[0], A[1],
                b[0], inv[CARTESIAN_PENDULUM_INV_constraint_residual]);
    return 0;
}
"""

C_PROGRAM = r"""
#include <stdio.h>
#include "double_pendulum.h"
#include "lagcli_ode.h"

static int rhs(double t, const double *y, double *dydt, void *ctx)
{
    return double_pendulum_rhs(t, y, (const double *)ctx, dydt);
}

static int print(double t, const double *y, void *ctx)
{
    double inv[DOUBLE_PENDULUM_NINV];
    int i;
    (void)double_pendulum_invariants(t, y, (const double *)ctx, inv);
    printf("%.17g", t);
    for (i = 0; i < DOUBLE_PENDULUM_NSTATE; ++i)
        printf(",%.17g", y[i]);
    printf(",%.17g\n", inv[DOUBLE_PENDULUM_INV_energy]);
    return 0;
}

int main(void)
{
    const double times[] = {0.5, 1.0};
    lagcli_ode_stats stats;
    int rc = lagcli_ode_integrate("DOP853", rhs, print, (void *)double_pendulum_parameter_defaults,
                                  DOUBLE_PENDULUM_NSTATE, 0.0, double_pendulum_initial_state, 1.0,
                                  times, 2, 1e-10, 1e-12, 1e300, &stats);
    return rc == LAGCLI_ODE_OK ? 0 : 1;
}
"""


def generate(spec: str, directory: Path) -> Path:
    from lagcli import commands

    commands.generate(str(SPECS / f"{spec}.yaml"), "c", str(directory))
    return directory


@pytest.mark.skipif(CC is None or CXX is None, reason="no C and C++ compilers")
def test_cpp_program_includes_the_header_and_links_the_model(tmp_path):
    folder = generate("cartesian_pendulum", tmp_path)
    (folder / "use.cpp").write_text(CXX_PROGRAM)
    subprocess.run([CC, *CFLAGS, "-c", "cartesian_pendulum.c"], cwd=folder, check=True)
    done = subprocess.run([CXX, "-std=c++11", "-Wall", "-Wextra", "-Werror", "use.cpp",
                           "cartesian_pendulum.o", "-o", "use", "-lm"], cwd=folder, capture_output=True, text=True)
    assert done.returncode == 0, done.stderr
    run = subprocess.run([str(folder / "use")], capture_output=True, text=True, check=True)
    M00, M01, F1, A0, A1, b0, residual = map(float, run.stdout.split())
    # by hand, m = 1, g = 9.81, phi = x^2 + y^2 - l^2 at rest: M = m I, F = (0, -m g),
    # A = (2x, 2y), b = -(A' q') = -2 (x'^2 + y'^2)
    x, y, xd, yd = 1.2, -1.6, 0.4, 0.3
    assert (M00, M01, F1) == pytest.approx((1.0, 0.0, -9.81))
    assert (A0, A1) == pytest.approx((2 * x, 2 * y))
    assert b0 == pytest.approx(-2 * (xd ** 2 + yd ** 2))
    assert residual < 1e-12


@pytest.mark.skipif(CC is None, reason="no C compiler (cc)")
def test_c_program_uses_the_shipped_integrator_on_the_generated_rhs(tmp_path, monkeypatch):
    folder = generate("double_pendulum", tmp_path)
    (folder / "use.c").write_text(C_PROGRAM)
    done = subprocess.run([CC, *CFLAGS, "use.c", "double_pendulum.c", "lagcli_ode.c", "-o", "use", "-lm"],
                          cwd=folder, capture_output=True, text=True)
    assert done.returncode == 0, done.stderr
    rows = np.loadtxt(io.StringIO(subprocess.run([str(folder / "use")], capture_output=True, text=True,
                                                 check=True).stdout), delimiter=",")
    # the Python backend (scipy's DOP853) over the same interval, an independent integrator
    from lagcli.cli import cli

    monkeypatch.setenv("XDG_CACHE_HOME", str(tmp_path / "cache"))
    result = CliRunner().invoke(cli, ["simulate", str(SPECS / "double_pendulum.yaml"), "--backend", "python",
                                      "--t-end", "1", "--dt", "0.5", "--rtol", "1e-10"])
    assert result.exit_code == 0, result.output
    scipy_rows = np.loadtxt(io.StringIO(result.stdout), delimiter=",", skiprows=1)
    assert np.max(np.abs(rows[:, :5] - scipy_rows[1:, :5])) < 1e-7
    assert np.max(np.abs(rows[:, 5] - scipy_rows[0, 5])) < 1e-8          # energy is conserved


def test_driver_numbers_are_those_of_numerics():
    from lagcli import interface
    from lagcli.runtime import run_rules

    text = (RUNTIME / "lagcli_driver.c").read_text()
    value = {name: float(v) for name, v in re.findall(r"#define LAGCLI_(\w+) ([0-9.e+-]+)\b", text)}
    assert value["OUTPUT_SLACK"] == run_rules.OUTPUT_SLACK
    assert value["END_TOLERANCE"] == run_rules.END_TOLERANCE
    assert value["CONSTRAINT_TOLERANCE"] == interface.CONSTRAINT_TOLERANCE
    assert (value["BAUMGARTE"], value["BAUMGARTE"]) == interface.DEFAULT_BAUMGARTE
    assert re.search(r'#define LAGCLI_METHODS "(.*)"', text).group(1) == "|".join(interface.C_METHODS)


def test_spec_named_like_a_runtime_file_is_refused(tmp_path):
    from lagcli.cli import cli

    spec = tmp_path / "s.yaml"
    spec.write_text("name: lagcli_ode\ncoordinates: [x]\nkinetic: x_dot**2/2\n")
    result = CliRunner().invoke(cli, ["generate", str(spec), "--lang", "c", "-o", str(tmp_path / "out")])
    assert result.exit_code == 2
    assert "name: the name 'lagcli_ode' gives a file name of lagcli's C runtime" in result.output
