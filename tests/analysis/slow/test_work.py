"""The work of many map runs, estimated before any starts (analysis.slow.work): the estimate against the maxima a run
counts, and the calls that make thousands of runs refused within the budget before any work."""

from __future__ import annotations

import math

import numpy as np
import pytest

from rocknroller.analysis.model.body import Body
from rocknroller.analysis.slow.atlas import atlas_from_rest
from rocknroller.analysis.slow.ensemble_statistics import StartBall, map_ensemble
from rocknroller.analysis.slow.prediction import predict_slow_motion
from rocknroller.analysis.slow.work import MAX_PERIOD_KNOTS, check_map_work, map_maxima, rocking_period
from rocknroller.numerics.budget import WorkBudgetError

BODY = Body.paper(5e-3)
TH = 0.95 * math.pi


def test_the_estimate_is_the_count_of_a_run():
    """t_end/T_θ(0) against the θ-maxima a run of the map counts (ε = 5e-3, K = 2.1: T_θ varies along the orbit,
    by a few per cent here)."""
    pred = predict_slow_motion(BODY, TH, 0.3, 3000.0, order=1, indicators=False)
    estimate = float(map_maxima(BODY, [TH], 3000.0)[0])
    assert estimate == pytest.approx(pred.series.t.size, rel=0.1)
    assert estimate == 3000.0 / rocking_period(BODY, TH)


def test_a_long_grid_of_release_angles_is_estimated_from_above():
    """More θ0 than knots: each takes the period of a knot at or below it, which is shorter (T_θ(0) grows with the
    amplitude), so the estimate is at least the exact count t_end/T_θ(0) of every θ0."""
    th = np.linspace(0.5 * math.pi, 0.99 * math.pi, 3 * MAX_PERIOD_KNOTS + 1)
    exact = np.array([1000.0 / rocking_period(BODY, t) for t in th])
    assert np.all(np.diff(exact) < 0.0)  # T_θ(0) grows with θ0
    estimate = map_maxima(BODY, th, 1000.0)
    assert np.all(estimate >= exact) and estimate[0] == exact[0] and estimate[-1] == exact[-1]
    assert np.max(estimate / exact) < 1.25  # a knot every ~3 values of θ0


def test_the_campaign_s_map_ensemble_is_refused_before_any_work():
    """rr.map_ensemble(..., StartBall(..., 10000), 6.6e6): ~5e9 maxima, hours; refused naming the estimate."""
    ball = StartBall(TH, 0.3, 1e-3, 10_000)
    with pytest.raises(WorkBudgetError, match=r"an ensemble of 10000 map runs .* about 5e\+09 theta-maxima .* would "
                                              r"take about \d+\.\d h of CPU"):
        map_ensemble(BODY, ball, 6.6e6, order=1)
    with pytest.raises(ValueError, match="budget must be a number of seconds > 0"):
        map_ensemble(BODY, ball, 100.0, budget=0.0)
    with pytest.raises(ValueError, match="t_end must be a finite number > 0"):
        map_ensemble(BODY, ball, math.nan)


def test_a_small_map_ensemble_is_within_the_budget():
    ens = map_ensemble(BODY, StartBall(TH, 0.3, 1e-3, 3), 200.0, order=1, budget=60.0)
    assert ens.values["QR_extent"].size == 3


@pytest.mark.parametrize("n_psi", [2000, 250_000])
def test_the_campaign_s_atlases_are_refused_before_any_work(n_psi):
    """atlas --theta0 0.95pi --psi0 0:3:2000 --t-end 6e6 (~1.1 h measured) and with 250 000 points (~140 h)."""
    with pytest.raises(WorkBudgetError, match=f"the atlas's {n_psi} points .* over t_end = 6e\\+06"):
        atlas_from_rest(BODY, [TH], np.linspace(0.0, 3.0, n_psi), 6e6)


def test_check_map_work_counts_runs_and_order():
    n = check_map_work(BODY, [TH, TH], 3, 1000.0, 2, "six runs", None)
    assert n == pytest.approx(6 * 1000.0 / rocking_period(BODY, TH), rel=1e-12)
    with pytest.raises(WorkBudgetError, match="six runs, about 4.5e\\+02 theta-maxima of the order-2 map"):
        check_map_work(BODY, [TH, TH], 3, 1000.0, 2, "six runs", 1e-6)
