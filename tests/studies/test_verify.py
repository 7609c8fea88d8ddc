"""The verification suite and the ``gridlbc verify`` command, at small sizes."""

import json
import math
import subprocess
import sys

import numpy as np
import pytest
from conftest import SMOKE_SIZES

from gridlbc.reference import lq_solution
from gridlbc.studies.verify import (
    CheckResult,
    VerificationReport,
    check_superposition,
    exact_coordination,
    result_row,
    run_verification,
)


def test_row_status():
    assert result_row("c", "x", 1.0, 1.05, bound=0.1).passed is True
    assert result_row("c", "x", 1.0, 1.2, bound=0.1).passed is False
    assert result_row("c", "x", 1e-12, bound=1e-10).passed is True  # no reference: measured ≤ bound
    assert result_row("c", "x", 3.0).passed is None


def test_superposition_rows_pass_at_small_size():
    rows = check_superposition(n=24, n_states=200)
    assert len(rows) == 8 and all(r.passed for r in rows)
    assert max(r.measured for r in rows) < 1e-12  # rounding, measured ~1e-15


def test_exact_coordination_reference_is_the_log_sum_exp(rng):
    import gridlbc as g
    from gridlbc.systems import PointMass

    grid = g.Grid([g.Axis(-3, 3, 5), g.Axis(-3, 3, 5)])
    base = g.Problem(PointMass(), grid, 1.0, g.Quadratic([-1, 0], [1, 1]), temperature=0.4)
    refs = [lq_solution(base), lq_solution(base.replace(terminal_cost=g.Quadratic([1, 0], [1, 1])))]
    value, policy = exact_coordination(refs, 0.4)
    x = rng.uniform(-2, 2, (20, 2))
    z = sum(np.exp(-r.value(x, 0.2) / 0.4) for r in refs)
    np.testing.assert_allclose(value(x, 0.2), -0.4 * np.log(z), rtol=1e-12)
    alpha = np.exp(-refs[1].value(x, 0.2) / 0.4) / z
    expected = (1 - alpha)[:, None] * refs[0].policy(x, 0.2) + alpha[:, None] * refs[1].policy(
        x, 0.2
    )
    np.testing.assert_allclose(policy(x, 0.2), expected, rtol=1e-10, atol=1e-12)


@SMOKE_SIZES
def test_report_table_and_json(tmp_path):
    report = run_verification(grid_size=32, samples=100, quick=True)
    checks = {r.check for r in report.results}
    assert checks == {"superposition", "optimality", "interpolation", "coordination"}
    # Rounding-level and clear-cut rows hold even at smoke-test sizes.
    for r in report.results:
        if r.check == "superposition" or r.case.startswith(("start x=-1.5", "start x=+1.5")):
            assert r.passed, r
    table = report.table()
    assert table.splitlines()[0].split()[:2] == ["check", "case"]
    assert len(table.splitlines()) > len(report.results)
    path = tmp_path / "v.json"
    report.to_json(path)
    data = json.loads(path.read_text())
    assert data["passed"] == report.passed
    assert len(data["results"]) == len(report.results)
    first = CheckResult(**data["results"][0])
    assert (first.case, first.measured) == (report.results[0].case, report.results[0].measured)
    assert math.isnan(first.reference)  # NaN round-trips through JSON


def test_report_fails_when_a_row_fails():
    ok = result_row("c", "x", 1.0, 1.0, bound=0.1)
    bad = result_row("c", "y", 2.0, 1.0, bound=0.1)
    assert VerificationReport((ok,)).passed
    assert not VerificationReport((ok, bad)).passed
    assert "FAIL" in VerificationReport((ok, bad)).table()


@pytest.mark.parametrize("argv", [["--grid", "16", "--samples", "50", "--quick", "--quiet"]])
def test_cli_verify_runs(tmp_path, argv):
    out = tmp_path / "verify.json"
    proc = subprocess.run(
        [sys.executable, "-m", "gridlbc.cli", "verify", *argv, "--json", str(out)],
        capture_output=True,
        text=True,
        timeout=600,
        check=False,
    )
    # 0: all passed, 1: a check failed (at this tiny grid the swing-up may miss its 10% bound).
    assert proc.returncode in (0, 1), proc.stderr
    assert "superposition" in proc.stdout and out.exists()
    data = json.loads(out.read_text())
    assert (proc.returncode == 0) == data["passed"]


def test_cli_verify_bad_argument():
    proc = subprocess.run(
        [sys.executable, "-m", "gridlbc.cli", "verify", "--samples", "x"],
        capture_output=True,
        text=True,
        timeout=60,
        check=False,
    )
    assert proc.returncode == 2 and "invalid int" in proc.stderr
