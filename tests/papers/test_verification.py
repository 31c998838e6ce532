"""`rocknroller verify`: the table passes, --json emits it, and a failing check gives status 1."""

from __future__ import annotations

import json

from rocknroller.cli import main
from rocknroller.papers import verification


def test_verify_passes_and_emits_json(capsys):
    assert main(["verify", "--json", "--quiet"]) == 0
    rows = json.loads(capsys.readouterr().out)
    assert rows and all(r["passed"] for r in rows)
    assert {"group", "name", "reference", "error", "tolerance", "passed"} <= set(rows[0])


def test_failure_gives_status_1(monkeypatch, capsys):
    def failing():
        return [verification.Check("demo", "deliberately failing", "nothing", 1.0, 0.5)]

    monkeypatch.setattr(verification, "CHECKS", (failing,))
    assert main(["verify", "--quiet"]) == 1
    assert "FAIL" in capsys.readouterr().out


def test_nan_error_fails():
    assert not verification.Check("g", "n", "r", float("nan"), 1.0).passed


def test_a_formula_shown_wrong_reads_as_such(monkeypatch, capsys):
    """The row for the paper's misprinted cos(theta_z) printed the ratio 0.01/error against 1.0 under "must fail:
    error > 0.01" (e.g. "PASS 6.26e-03 1.0e+00"): it now prints the error itself and the bound it must exceed."""
    rows = verification.check_criticality()
    (row,) = [r for r in rows if r.must_exceed]
    assert "as printed in the paper" in row.name and row.tolerance == 0.01
    assert row.error > row.tolerance and row.passed
    monkeypatch.setattr(verification, "CHECKS", (lambda: [row],))
    assert main(["verify", "--quiet"]) == 0
    line = capsys.readouterr().out.splitlines()[1]
    assert line.split()[:4] == ["PASS", f"{row.error:.2e}", ">", "1.0e-02"]


def test_must_exceed_fails_below_its_bound():
    assert not verification.Check("g", "n", "r", 0.001, 0.01, must_exceed=True).passed
    assert not verification.Check("g", "n", "r", 0.01, 0.01, must_exceed=True).passed
    assert not verification.Check("g", "n", "r", float("nan"), 0.01, must_exceed=True).passed
    assert verification.Check("g", "n", "r", 0.02, 0.01, must_exceed=True).passed
    assert verification.Check("g", "n", "r", 0.001, 0.01).bound == "<= 1.0e-02"


def test_an_unmeasured_quantity_fails_its_averaging_row(monkeypatch):
    """A relative error of None (a quantity the map or the ODE did not measure, e.g. no slow period within the run)
    made check_averaging raise TypeError (abs(None)) and `rocknroller verify` stop; it is now a failed row."""
    import types

    from rocknroller.analysis.slow.dynamics import pendulum
    from rocknroller.analysis.slow import prediction
    from rocknroller.papers import averaging_check

    errors = {"slow_period": None, "QR_extent": 0.0, "Phi": 0.0}
    monkeypatch.setattr(prediction, "load_or_build_table", lambda body, theta0: None)
    monkeypatch.setattr(pendulum, "pendulum_constants", lambda body, theta0: None)
    monkeypatch.setattr(averaging_check, "compare_with_ode",
                        lambda *args, **kwargs: types.SimpleNamespace(map_errors=errors, pendulum_errors=errors))
    rows = verification.check_averaging()
    failed = [r.name for r in rows if not r.passed]
    assert len(rows) == 7 and len(failed) == 3 and all("slow" in name for name in failed)
