"""Trust marks (analysis/slow/trust.py and `rocknroller slow`'s status): a chaotic start's slow period is undefined,
numbers past the predictability horizon are statistical, a closed form outside its range is undefined, and the
table, --json and the CSV header all say so.  The reproducer: `slow --theta0 0.9pi --psi0 0.01 --eps 1e-2 --t-end
2000 --check --statistics 0` printed `slow_period 200.324 ... direct ODE 1604.13 ... map rel.err -0.87512` with no
mark."""

from __future__ import annotations

import json
import math

import pytest

from rocknroller.analysis.slow.dynamics.pendulum import REGIME_TOLERANCE, pendulum_regime_error
from rocknroller.analysis.slow.trust import (PREDICTED, QUANTITIES, STATISTICAL, UNDEFINED, closed_form_trust,
                                             map_trust)
from rocknroller.cli import main


@pytest.mark.parametrize("verdict, beyond, period, others", [
    ("chaotic", True, UNDEFINED, STATISTICAL), ("chaotic", False, UNDEFINED, PREDICTED),
    ("regular", True, STATISTICAL, STATISTICAL), ("regular", False, PREDICTED, PREDICTED),
    ("undecided", True, STATISTICAL, STATISTICAL), (None, None, PREDICTED, PREDICTED)])
def test_the_map_rule(verdict, beyond, period, others):
    assert map_trust("slow_period", 200.0, verdict, beyond).status == period
    assert all(map_trust(q, 0.1, verdict, beyond).status == others for q in QUANTITIES[1:])
    assert map_trust("Phi", None, verdict, beyond).status == UNDEFINED


def test_the_closed_form_rule():
    """Undefined past the period doubling, on a chaotic orbit, and where the pendulum's regime bound passes
    REGIME_TOLERANCE (R² below 1/((1 + tol)² − 1) = 9.76); predicted inside."""
    edge = 1.0 / ((1.0 + REGIME_TOLERANCE) ** 2 - 1.0)
    assert pendulum_regime_error(edge) == pytest.approx(REGIME_TOLERANCE, rel=1e-12)
    assert closed_form_trust("QR_extent", 0.07, "regular", 1.0, 1.01 * edge).status == PREDICTED
    assert closed_form_trust("QR_extent", 0.07, "regular", 1.0, 0.99 * edge).status == UNDEFINED
    assert closed_form_trust("QR_extent", 0.07, "regular", 4.01, 100.0).status == UNDEFINED
    assert closed_form_trust("QR_extent", 0.07, "chaotic", 1.0, 100.0).status == UNDEFINED
    assert closed_form_trust("slow_period", 150.0, "regular", 0.0, None).status == PREDICTED  # ε = 0: no regime
    with pytest.raises(ValueError, match="quantity"):
        closed_form_trust("period", 1.0, None, 0.0, None)


def test_slow_marks_every_number_of_a_chaotic_start(capsys, tmp_path):
    argv = ["slow", "--theta0", "0.9pi", "--psi0", "0.01", "--eps", "1e-2", "--t-end", "2000", "--statistics", "0"]
    assert main(argv + ["--json", "--csv", str(tmp_path)]) == 0
    s = json.loads(capsys.readouterr().out)
    assert s["chaos"]["verdict"] == "chaotic" and s["beyond_horizon"]
    assert s["status"]["map"] == {"slow_period": UNDEFINED, "QR_extent": STATISTICAL, "QJ_extent": STATISTICAL,
                                  "Phi": STATISTICAL}
    assert s["slow_period"] is None and s["QR_extent"] > 0.0
    assert set(s["status"]["closed_form"].values()) == {UNDEFINED}
    assert all(s["pendulum"][q] is None for q in QUANTITIES)
    assert "chaotic orbit has no slow period" in s["status_reasons"]["map"]["slow_period"]
    header = (tmp_path / "slow_maxima.csv").read_text().split("\n# columns")[0]
    assert "map slow_period undefined" in header and "map QR_extent statistical" in header
    assert main(argv) == 0
    table = capsys.readouterr().out.splitlines()
    row = next(line.split() for line in table if line.startswith("slow_period"))
    assert row[1:5] == ["n/a", UNDEFINED, "n/a", UNDEFINED]
    assert any(line.startswith("status, averaged map: slow_period undefined") for line in table)


def test_a_regular_start_within_its_horizon_is_predicted(capsys):
    assert main(["slow", "--order", "1", "--eps", "1e-3", "--psi0", "3pi/8", "--t-end", "400", "--json"]) == 0
    s = json.loads(capsys.readouterr().out)
    assert s["chaos"]["verdict"] == "regular" and not s["beyond_horizon"]
    assert set(s["status"]["map"].values()) == {PREDICTED} and s["status_reasons"]["map"] == {}
    assert all(math.isfinite(s[q]) for q in QUANTITIES)
