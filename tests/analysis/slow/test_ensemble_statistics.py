"""Statistics over a ball of starts, by the map and the ODE, and the stated two-sample test
(:mod:`rocknroller.analysis.slow.ensemble_statistics`)."""

from __future__ import annotations

import math

import numpy as np
import pytest
from scipy.stats import ks_2samp

from rocknroller.analysis.criticality.lines import region
from rocknroller.analysis.model.body import Body
from rocknroller.analysis.slow.ensemble_statistics import (DISTRIBUTION_STATISTICS, STATISTICS, EnsembleStatistics,
                                                           StartBall, compare_ensembles, map_ensemble,
                                                           member_statistics, ode_ensemble)
from rocknroller.analysis.slow.map.limits import AveragingValidityWarning

THETA0 = 0.95 * math.pi
BODY = Body.paper(1e-3)


def test_ball_is_seeded_uniform_and_checked():
    ball = StartBall(THETA0, 0.3, 1e-3, 500, seed=7)
    a, b = ball.psi0_values(), StartBall(THETA0, 0.3, 1e-3, 500, seed=7).psi0_values()
    np.testing.assert_array_equal(a, b)  # the same ball, the same starts
    assert not np.array_equal(a, StartBall(THETA0, 0.3, 1e-3, 500, seed=8).psi0_values())
    assert a.min() >= 0.3 - 1e-3 and a.max() <= 0.3 + 1e-3
    # uniform on [psi0 - delta, psi0 + delta]: mean within 4 standard errors (sd of U(-d, d) is d/sqrt(3))
    assert abs(a.mean() - 0.3) < 4 * 1e-3 / math.sqrt(3 * a.size)
    for kwargs, name in (({"delta": 0.0}, "delta"), ({"delta": math.nan}, "delta"), ({"delta": 2.0}, "delta"),
                         ({"members": 1}, "members"), ({"members": True}, "members"), ({"members": 2.5}, "members"),
                         ({"seed": -1}, "seed"), ({"psi0": math.inf}, "psi0"), ({"theta0": 1.0 * math.pi}, "theta0")):
        args = {"theta0": THETA0, "psi0": 0.3, "delta": 1e-3, "members": 8} | kwargs
        with pytest.raises(ValueError, match=name):
            StartBall(**args)


def test_member_statistics_of_samples_placed_in_known_regions():
    """Samples placed by the paper's region definitions (I: Q_R > 0 between the lines, II above both, III: Q_R < 0
    between them, IV below both; §criticality): on Q_J = 0 with Q_R = ±0.01 (I, III) and on Q_R = 0 with
    Q_J = ±0.01 (II, IV).  Crossings between consecutive samples, counted by hand: I→III and III→I cross both lines,
    I→II only Q_J,0^crit, II→IV both."""
    QR = np.array([0.01, 0.01, -0.01, 0.01, 0.0, 0.0])
    QJ = np.array([0.0, 0.0, 0.0, 0.0, 0.01, -0.01])
    t = np.arange(1.0, 7.0)
    assert list(region(QR, QJ, BODY)) == ["I", "I", "III", "I", "II", "IV"]  # the other classification agrees
    s = member_statistics(BODY, t, QR, QJ, t_end=10.0)
    assert s["fraction_I"] == 3 / 6 and s["fraction_II"] == s["fraction_III"] == s["fraction_IV"] == 1 / 6
    assert s["full_reversals"] == 4 * 1000.0 / 10.0 and s["visible_reversals"] == 3 * 1000.0 / 10.0
    assert s["QR_extent"] == 0.02 and s["QJ_extent"] == 0.02
    assert set(s) == set(STATISTICS)


@pytest.mark.parametrize("bad, match", [
    (dict(t=[]), "theta-maxima"), (dict(QR=[0.0, 0.0]), "theta-maxima"), (dict(t_end=0.5), "t_end"),
    (dict(t_end=math.nan), "t_end"),
])
def test_member_statistics_refuses_bad_input(bad, match):
    args = dict(t=[1.0], QR=[0.0], QJ=[0.0], t_end=2.0) | bad
    with pytest.raises(ValueError, match=match):
        member_statistics(BODY, **args)


def _ensemble(values: dict[str, np.ndarray], method: str = "map", ball: StartBall | None = None) -> EnsembleStatistics:
    ball = ball or StartBall(THETA0, 0.3, 1e-3, 64)
    full = {name: np.asarray(values.get(name, np.zeros(ball.members)), float) for name in STATISTICS}
    return EnsembleStatistics(method=method, eps=1e-3, ball=ball, t_end=1000.0, values=full,
                              rocks=np.full(ball.members, 10))


def test_comparison_applies_the_stated_test():
    """KS p-value as scipy's; the difference of the means in standard errors by hand; consistent = p > 0.01 or
    within 3 standard errors.  Samples of one distribution pass, samples one standard deviation apart (64 each: the
    means then differ by ~5.7 standard errors, KS p ~ 1e-7) fail."""
    rng = np.random.default_rng(1)
    x, y, z = rng.normal(0.0, 1.0, 64), rng.normal(0.0, 1.0, 64), rng.normal(1.0, 1.0, 64)
    same = compare_ensembles(_ensemble({"QR_extent": x}), _ensemble({"QR_extent": y}, "ode"))
    s = same["QR_extent"]
    assert s.ks_pvalue == ks_2samp(x, y).pvalue and s.consistent
    se = math.sqrt(np.var(x, ddof=1) / 64 + np.var(y, ddof=1) / 64)
    assert s.n_se == pytest.approx(abs(x.mean() - y.mean()) / se, rel=1e-12)
    assert same.consistent and same.consistent_on(DISTRIBUTION_STATISTICS)
    apart = compare_ensembles(_ensemble({"QR_extent": x}), _ensemble({"QR_extent": z}, "ode"))
    s = apart["QR_extent"]
    assert s.ks_pvalue < 0.01 and s.n_se > 3.0 and not s.consistent
    assert not apart.consistent and apart.consistent_on(DISTRIBUTION_STATISTICS)  # the extents are not among them
    # constants: equal ones are consistent (the zero fractions here), different ones not
    ones = compare_ensembles(_ensemble({"fraction_I": np.ones(64)}), _ensemble({"fraction_I": np.zeros(64)}, "ode"))
    assert ones["fraction_II"].consistent and ones["fraction_II"].n_se == 0.0
    assert not ones["fraction_I"].consistent and ones["fraction_I"].n_se == math.inf


def test_comparison_refuses_other_balls_and_bad_levels():
    a = _ensemble({})
    with pytest.raises(ValueError, match="share ball"):
        compare_ensembles(a, _ensemble({}, ball=StartBall(THETA0, 0.3, 1e-3, 64, seed=1)))
    for kwargs, name in (({"alpha": 0.0}, "alpha"), ({"alpha": 1.0}, "alpha"), ({"n_se_limit": -1.0}, "n_se_limit"),
                         ({"n_se_limit": math.inf}, "n_se_limit")):
        with pytest.raises(ValueError, match=name):
            compare_ensembles(a, a, **kwargs)
    with pytest.raises(ValueError, match="must be an EnsembleStatistics"):
        compare_ensembles(a, None)  # type: ignore[arg-type]
    with pytest.raises(ValueError, match="name must be one of"):
        compare_ensembles(a, a)["Phi"]
    with pytest.raises(ValueError, match="ball must be a StartBall"):
        map_ensemble(BODY, (THETA0, 0.3), 100.0)  # type: ignore[arg-type]


def test_map_and_ode_members_agree_before_the_horizon():
    """A regular release (ε = 1e-3, ψ0 = π/4 ± 1e-3, 500 time units, 8 members): member by member, the same rocks,
    region fractions and reversal counts (a sample would have to lie within the map's error of a line to differ),
    and extents within the map's error: docs/slow_validation.md, "Releases from rest, second order", gives the
    order-2 map's largest sample error |ΔQ| ≤ 6.1e-5 of the Q_R extent at ψ0 = π/4 over 1000 time units, so a span
    of Q_R or Q_J differs by at most twice that."""
    ball = StartBall(THETA0, math.pi / 4, 1e-3, 8, seed=3)
    m = map_ensemble(BODY, ball, 500.0)
    o = ode_ensemble(BODY, ball, 500.0, progress=False)
    assert (m.method, m.order, o.method, o.order) == ("map", 2, "ode", None)
    np.testing.assert_array_equal(m.rocks, o.rocks)
    for name in DISTRIBUTION_STATISTICS:
        np.testing.assert_array_equal(m.values[name], o.values[name], err_msg=name)
    bound = 2 * 6.1e-5 * o.values["QR_extent"]
    assert np.all(np.abs(m.values["QR_extent"] - o.values["QR_extent"]) <= bound)
    assert np.all(np.abs(m.values["QJ_extent"] - o.values["QJ_extent"]) <= bound)
    c = compare_ensembles(m, o)
    assert c.consistent
    assert m.mean("QR_extent") == pytest.approx(float(np.mean(m.values["QR_extent"])))
    assert m.standard_error("QR_extent") == pytest.approx(float(np.std(m.values["QR_extent"], ddof=1)) / math.sqrt(8))


def test_map_ensemble_warns_once_past_the_period_doubling():
    ball = StartBall(THETA0, 0.1, 1e-3, 4)
    with pytest.warns(AveragingValidityWarning, match="K = eps") as record:
        m = map_ensemble(Body.paper(1e-2), ball, 200.0, order=1)
    assert len([w for w in record if issubclass(w.category, AveragingValidityWarning)]) == 1
    assert len(m.warnings) == 1 and m.order == 1


@pytest.mark.slow
def test_chaotic_start_ensembles_are_consistent():
    """Issue 23's acceptance for one chaotic start below the period doubling (θ0 = 0.95π, ε = 5e-3, ψ0 = 0.05,
    K = 2.13; two runs 1e-10 apart separate to 5e-3 in 100 rocks): 64 members in ψ0 ± 1e-3 over 10⁴ time units, map
    (order 2) and ODE consistent on the region fractions and reversal counts under the stated test
    (validation/chaotic_statistics.py; past the period doubling, at ε = 1e-2, the map's region-II fraction is not:
    docs/chaos_statistics.md)."""
    body = Body.paper(5e-3)
    ball = StartBall(THETA0, 0.05, 1e-3, 64, seed=23)
    m = map_ensemble(body, ball, 1e4)
    o = ode_ensemble(body, ball, 1e4, progress=False)
    c = compare_ensembles(m, o)
    assert c.consistent_on(DISTRIBUTION_STATISTICS), [s for s in c.statistics if not s.consistent]
    # chaotic: the members spread (measured: 0.8 to 12.6 per 1000 time units by the map, 0.2 to 13.4 by the ODE;
    # the regular ball ψ0 = π/4 ± 1e-3 at ε = 1e-2 keeps 33.8 for all 64 members)
    assert np.ptp(o.values["full_reversals"]) > 8.0 and np.ptp(m.values["full_reversals"]) > 8.0
