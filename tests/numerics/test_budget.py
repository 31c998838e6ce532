"""Bounds on the total work of a call (issue 25, item 24): estimated before any work, refused past the budget with
the estimate named, and allowed when asked for."""

from __future__ import annotations

import math

import pytest

from rocknroller.analysis.model.body import Body
from rocknroller.analysis.model.equations import EulerState
from rocknroller.analysis.slow.atlas import atlas_from_rest, atlas_of_rates
from rocknroller.cli import main
from rocknroller.numerics import budget
from rocknroller.numerics.budget import WorkBudgetError, check_budget, check_work, format_seconds
from rocknroller.numerics.ensembles.ensemble import Job, run_ensemble
from rocknroller.numerics.integrate import MAX_RADIANS, simulate

BODY = Body.paper(1e-3)
START = EulerState(0.95 * math.pi, 0.0, 0.5)


def test_check_work_names_the_estimate_and_the_way_out():
    with pytest.raises(WorkBudgetError, match=r"^10 things would take about 3\.0 h of CPU .* over the budget of "
                                              r"60 min; to run it anyway give budget=SECONDS"):
        check_work(3 * 3600.0, "10 things", 3600.0)
    check_work(3 * 3600.0, "10 things", None)  # no limit
    check_work(10.0, "10 things", 3600.0)
    for bad in (0.0, -1.0, math.nan, "x"):
        with pytest.raises(ValueError, match="budget must be a number of seconds > 0"):
            check_budget(bad)
    assert [format_seconds(s) for s in (45, 720, 11520, 5 * 86400)] == ["45 s", "12 min", "3.2 h", "5.0 days"]


def test_the_default_budget_holds_every_double_precision_heyoka_run():
    """One run within ``MAX_RADIANS`` is within the default budget with heyoka in double precision: only the slower
    integrations (extended precision, DOP853) and calls made of many runs or tables can exceed it."""
    assert MAX_RADIANS * budget.HEYOKA_SECONDS_PER_RADIAN < budget.WORK_BUDGET_SECONDS
    assert MAX_RADIANS * budget.HEYOKA_EXTENDED_SECONDS_PER_RADIAN > budget.WORK_BUDGET_SECONDS
    assert MAX_RADIANS * budget.DOP853_SECONDS_PER_RADIAN > budget.WORK_BUDGET_SECONDS


def test_a_long_dop853_run_is_refused_before_any_work():
    """``simulate --method scipy --turning-points-only --t-end 1e7`` was accepted (limits calibrated on heyoka) and
    ran ~5 h; now refused at once, naming ~8 h."""
    with pytest.raises(WorkBudgetError, match=r"this run \(scipy, double precision, .* radians\) would take about "
                                              r"[\d.]+ h of CPU"):
        simulate(BODY, START, 1e7, method="scipy", samples=False)
    with pytest.raises(WorkBudgetError, match=r"this run \(heyoka, extended precision, "):  # 5.6x double's cost
        simulate(BODY, START, 3e7, samples=False, precision="extended", dt=1.0)
    # the same length with heyoka, and a short DOP853 run, are within the budget (the latter runs)
    assert len(simulate(BODY, START, 20.0, method="scipy", samples=False).maxima) > 0


def test_an_ensemble_of_long_runs_is_refused_before_any_work():
    """100 runs of 1e7 time units (each within its own limits: hours together) are refused; a budget that covers
    them is the user's explicit choice."""
    jobs = [Job(BODY, START, 1e7)] * 100
    with pytest.raises(WorkBudgetError, match=r"100 direct runs \(Λ t_end up to .* radians\) would take about"):
        run_ensemble(jobs, progress=False)
    with pytest.raises(WorkBudgetError, match="over the budget of 1 s"):
        run_ensemble([Job(BODY, START, 1e5)] * 2, progress=False, budget=1.0)
    assert len(run_ensemble([Job(BODY, START, 10.0)], progress=False, budget=60.0)) == 1


def test_an_atlas_of_many_uncached_tables_is_refused(monkeypatch, tmp_path):
    """``atlas --theta0 0.8pi:0.95pi:3000`` built one table per θ0 for hours; refused up front, counting only the
    tables not cached (an empty cache here)."""
    from rocknroller.analysis.slow.map import table as slow_table
    from rocknroller.numerics.cache import MemoryCache

    monkeypatch.setenv("ROCKNROLLER_CACHE", str(tmp_path))
    monkeypatch.setattr(slow_table, "_TABLES", MemoryCache(slow_table.TABLE_CACHE_BYTES))  # none in memory either
    theta0 = [0.8 * math.pi + k * 1e-5 for k in range(3000)]
    with pytest.raises(WorkBudgetError, match=r"3000 release and 0 region tables to build"):
        atlas_from_rest(BODY, theta0, [0.5], progress=False)
    with pytest.raises(WorkBudgetError, match=r"0 release and 200 region tables to build"):
        atlas_from_rest(BODY, [0.3 * math.pi + k * 1e-4 for k in range(200)], [0.5], progress=False)
    with pytest.raises(WorkBudgetError, match=r"direct runs"):
        atlas_of_rates(BODY, 0.95 * math.pi, 0.5, [0.0, 0.1], [0.0, 0.1] * 50, 1e7, progress=False)


def test_the_commands_take_a_budget(tmp_path, capsys):
    assert main(["table", "--dps", "1000", "--QR", "-0.01:0.01:40", "--QJ", "0:0.01:50",
                 "--out", str(tmp_path / "t.csv")]) == 2
    err = capsys.readouterr().err
    assert "2000 mpmath points at 1000 digits would take about" in err and "--budget SECONDS" in err
    assert not (tmp_path / "t.csv").exists()
    assert main(["simulate", "--method", "scipy", "--turning-points-only", "--t-end", "1e7"]) == 2
    assert "--budget SECONDS" in capsys.readouterr().err
    assert main(["simulate", "--t-end", "5", "--budget", "inf", "--quiet", "--json"]) == 0
    capsys.readouterr()
    assert main(["simulate", "--t-end", "5", "--budget", "-3"]) == 2
    assert "--budget must be a number of seconds > 0 or 'inf', got '-3'" in capsys.readouterr().err


@pytest.mark.parametrize("budget", ["10", b"10", True, 0.0, -1.0, math.nan])
def test_a_budget_is_a_number_of_seconds(budget):
    """budget='10' was accepted as ten seconds: text is not a number of seconds."""
    from rocknroller.numerics.budget import check_budget

    with pytest.raises(ValueError, match="budget must be a number of seconds > 0"):
        check_budget(budget)
