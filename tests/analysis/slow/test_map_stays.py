"""The map stays on its tables where the motion does (:mod:`rocknroller.analysis.slow.map.compiled_map`'s implicit kick
near the chart's edge), and an ensemble member that still leaves is counted, the others kept
(:func:`rocknroller.analysis.slow.ensemble_statistics.map_ensemble`)."""

from __future__ import annotations

import math

import numpy as np
import pytest

from rocknroller.analysis.model.body import Body
from rocknroller.analysis.slow import prediction as av
from rocknroller.analysis.slow.map.compiled_map import iterate_slow_map
from rocknroller.analysis.slow.ensemble_statistics import STATISTICS, StartBall, map_ensemble
from rocknroller.analysis.slow.map.exact_step import exact_step
from rocknroller.analysis.slow.map.family import rest_energy
from rocknroller.analysis.slow.map.limits import AveragingValidityWarning
from rocknroller.analysis.slow.map.second_order import load_or_build_second_order_table

THETA0 = 0.85 * math.pi
EPS = 0.04  # K = eps*kappa = 1.97 < 4


def test_the_implicit_kick_does_not_stop_at_an_overshooting_first_iterate():
    """At 0.85pi, eps = 0.04, a member of the ball psi0 = 0.003 +- 1e-3 (order 2) reaches a maximum from which the
    explicit first iterate of the midpoint, a + (eps/2) k(a), lies beyond the chart's |v| <= V, although the
    midpoint and the next maximum lie inside (the orbit sweeps v as the kick turns): the step is taken, and agrees
    with the exact step of the direct ODE as the map's other steps do (its error is the map's O(eps^3) per step)."""
    body = Body.paper(EPS)
    table = av.load_or_build_table(body, THETA0)
    second = load_or_build_second_order_table(body, THETA0)
    runs = [iterate_slow_map(table, EPS, float(p), 1000.0, second=second)  # main: AveragingRangeError (one member)
            for p in StartBall(THETA0, 0.003, 1e-3, 32, seed=0).psi0_values()]
    vs = [r.QR * table.n[0] + r.QJ * table.n[1] for r in runs]
    assert max(np.abs(v).max() for v in vs) < table.w_coef[0]
    i = int(np.argmax([np.abs(v).max() for v in vs]))
    s, v = runs[i], vs[i]
    # the steps along the run near the edge, map against exact: the largest |v| of the run and its neighbours
    sym, k = body.symmetric(), int(np.argmax(np.abs(v[:100])))
    E = rest_energy(sym, THETA0)
    for j in (k - 1, k):
        y = exact_step(sym, EPS, E, float(s.QR[j]), float(s.QJ[j]), 0.5 * float(s.Theta[j]))
        err = math.hypot(y[0] - s.QR[j + 1], y[1] - s.QJ[j + 1])
        assert err < 2e-3 * float(np.ptp(s.QR))  # map - exact per step: ~1e-4 of the extent at this eps


def test_an_ensemble_goes_on_past_a_member_that_leaves():
    """Far past the period doubling (0.95pi, eps = 0.03, K = 12.8) some orbits leave the release tables along the kick
    direction (|u| > U): those members are counted in ``left``, the statistics are over the others; order 2 keeps
    every member of the ball psi0 = 0.003 +- 1e-3 at 0.85pi, eps = 0.04 (on main one of them stopped the ensemble)."""
    body = Body.paper(0.03)
    ball = StartBall(0.95 * math.pi, 0.5 * math.pi, 0.5 * math.pi, 16, seed=1)  # the whole circle of psi0
    with pytest.warns(AveragingValidityWarning, match="K = eps"):
        ens = map_ensemble(body, ball, 1000.0, order=1)
    assert 0 < len(ens.left) < ball.members
    assert set(ens.left) <= set(ball.psi0_values().tolist())
    for name in STATISTICS:
        assert ens.values[name].size == ball.members - len(ens.left)
    for psi0 in ens.left:
        with pytest.raises(av.AveragingRangeError, match="left the tabulated region"):
            av.predict_slow_motion(body, 0.95 * math.pi, psi0, 1000.0, order=1)
    with pytest.raises(av.AveragingRangeError, match="fewer than two"):  # both members of a tiny ball about one leave
        map_ensemble(body, StartBall(0.95 * math.pi, ens.left[0], 1e-6, 2, seed=1), 1000.0, order=1)
    ens2 = map_ensemble(Body.paper(EPS), StartBall(THETA0, 0.003, 1e-3, 32, seed=0), 1000.0, order=2)
    assert ens2.left == () and ens2.values["QR_extent"].size == 32


def test_an_orbit_wider_than_the_release_chart_is_sent_to_the_region_tables(capsys):
    """At 0.85pi, K = 3 the motion spreads across the kick direction beyond the release chart's |v| <= V (the direct
    ODE's orbits reach 1.5 V): the release tables' error says so (ChartWidthError), and a release is predicted on the
    region tables of its energy instead, which hold it, with a warning; slow does the same and says so."""
    import json

    from rocknroller.analysis.model.equations import EulerState
    from rocknroller.analysis.slow.map.limits import ChartWidthError
    from rocknroller.cli import main

    table = av.load_or_build_table(Body.paper(0.0), THETA0)
    eps = 3.0 / table.kappa
    body = Body.paper(eps)
    with pytest.raises(ChartWidthError, match=r"across the kick direction grows like eps\^2.*--theta-dot0 0"):
        iterate_slow_map(table, eps, 0.01, 1000.0)
    with pytest.raises(ChartWidthError):  # a table given by the caller is used as given
        av.predict_slow_motion(body, THETA0, 0.01, 1000.0, table=table, order=1)
    with pytest.warns(AveragingValidityWarning, match="predicted on the region tables of its energy"):
        pred = av.predict_slow_motion(body, THETA0, 0.01, 1000.0)  # main: AveragingRangeError
    assert pred.order == 1 and pred.start == EulerState(THETA0, 0.0, 0.01)  # the region tables' default order
    assert pred.chaos is not None and pred.series.t[-1] > 900.0
    assert main(["slow", "--theta0", "0.85pi", "--eps", repr(eps), "--psi0", "0.01", "--t-end", "500", "--statistics",
                 "0", "--json", "--quiet"]) == 0
    out = json.loads(capsys.readouterr().out)
    assert out["order"] == 1 and out["chaos"] is not None
    assert any("predicted on the region tables of its energy (map of order 1)" in w for w in out["warnings"])


def test_slow_statistics_goes_on_without_an_ensemble(monkeypatch, capsys):
    """An ensemble of which fewer than two members stay on the tables gives no statistics, and slow says why."""
    import json

    from rocknroller.analysis.slow import ensemble_statistics
    from rocknroller.cli import main

    def leaves(*args, **kwargs):
        raise av.AveragingRangeError("2 of the 2 members' slow orbits left the tables: fewer than two remain")

    monkeypatch.setattr(ensemble_statistics, "map_ensemble", leaves)
    assert main(["slow", "--theta0", "0.95pi", "--eps", "1e-3", "--psi0", "0.3", "--t-end", "200", "--statistics",
                 "2", "--json", "--quiet"]) == 0
    out = json.loads(capsys.readouterr().out)
    assert out["statistics"] is None and "fewer than two remain" in out["statistics_note"]
