"""The second-order kick of the drift–kick–drift map (``analysis/slow/map/second_order.py``): the exact one-step map minus
one step of the first-order map, over ε², tends to what k₂ predicts, linearly in ε (the derivation's check)."""

from __future__ import annotations

import math
import warnings

import numpy as np
import pytest

from rocknroller.analysis.model.body import Body
from rocknroller.analysis.slow import prediction as av
from rocknroller.analysis.slow.map.second_order import dkd_residual, drift_derivatives, second_order_kick


@pytest.fixture(scope="module")
def table():
    return av.load_or_build_table(Body.paper(1e-3), 0.95 * math.pi)


#: (u/U along the kick direction, Θ): inside the release table; the second lies in the layer of W near Q = 0.
POINTS = ((0.3, 0.9), (0.05, 4.0))


@pytest.mark.parametrize("x, theta", POINTS)
def test_first_order_map_misses_exactly_k2(table, x, theta):
    """(exact − first-order step)/ε² = P + a ε + O(ε²), P = (k₂_Q, k₂_X + ½ ∇F·k₂_Q): at ε = 4e-4, 2e-4, 1e-4 the
    differences from P halve with ε (ratios in [0.4, 0.6]) for every component, while P itself is far from zero
    (the first-order map's second-order error is what k₂ accounts for).  Noise: each exact step carries ~1e-13 of
    its values (≤ 60), i.e. ≤ 6e-4 after the division by ε² = 1e-8, below the smallest difference compared (5e-3)."""
    Q = x * table.U * np.asarray(table.e, float)
    W = float(table.evaluate(Q)[1])
    k2 = second_order_kick(table, Q, theta + 0.5 * W)
    P = k2.copy()
    for i, drift in zip((2, 3, 4), ("W", "T", "dphi")):
        P[i] += 0.5 * drift_derivatives(table, drift, Q)[0] @ k2[:2]
    diffs = [dkd_residual(table, eps, Q, theta) - P for eps in (4e-4, 2e-4, 1e-4)]
    for a, b in zip(diffs[:-1], diffs[1:]):
        ratio = np.abs(b) / np.abs(a)
        assert np.all((0.4 <= ratio) & (ratio <= 0.6)), (ratio, diffs)
    assert np.all(np.abs(diffs[-1]) < 0.2 * np.abs(P) + 5e-3)
    assert np.abs(P).max() > 10.0


from rocknroller.analysis.model.diagnostics import wrap_angle  # noqa: E402
from rocknroller.analysis.slow.map.compiled_map import iterate_slow_map  # noqa: E402
# ----------------------------------------------------------------------------- the order-2 map
from rocknroller.analysis.slow.map.exact_step import exact_step  # noqa: E402
from rocknroller.analysis.slow.map.second_order import (K2_ACCURACY, k2_harmonics,  # noqa: E402
                                                    load_or_build_second_order_table)
from rocknroller.papers.averaging_check import loglog_slope, ode_slow_summary, sample_errors  # noqa: E402

THETA0 = 0.95 * math.pi
U = float(np.finfo(float).eps) / 2


@pytest.fixture(scope="module")
def second():
    """Built once per cache (~60 s on 2 cores), then read."""
    return load_or_build_second_order_table(Body.paper(0.0), THETA0, workers=2)


def test_second_order_table_interpolates_k2(table, second):
    """Checked when built at three off-grid points (≤ K2_ACCURACY of each component's largest harmonic), and here
    at a fourth, against direct evaluations."""
    assert second.interp_error <= K2_ACCURACY
    Q = np.array([float(c) for c in table.chart(-0.44, 0.63)])
    direct = k2_harmonics(table, Q)
    scale = np.abs(second.coef).sum(axis=(1, 2)).reshape(5, 5).max(axis=1)  # bounds each component's values
    assert np.all(np.abs(second.harmonics(table, Q) - direct).max(axis=1) <= K2_ACCURACY * scale)


@pytest.mark.parametrize("x, theta", POINTS + ((-0.6, 2.5),))
def test_order2_step_error_is_third_order(table, second, x, theta):
    """One step of the order-2 map against the exact step: the largest error (Q, Θ, t, φ mod π) falls as ε³ (ratio
    1/8 per halving, in [0.09, 0.17]), where order 1's falls as ε² (ratio 1/4)."""
    Q = x * table.U * np.asarray(table.e, float)

    def err(eps, sec):
        ex = exact_step(table.body, eps, table.E0, float(Q[0]), float(Q[1]), 0.5 * theta)
        s = iterate_slow_map(table, eps, 0.5 * theta, 1e6, Q0=Q, n_steps=1, second=sec)
        r = ex - np.array([s.QR[0], s.QJ[0], s.Theta[0], s.t[0], s.phi[0]])
        r[2], r[4] = wrap_angle(r[2]), wrap_angle(r[4], math.pi)
        return np.abs(r).max()

    e2 = [err(eps, second) for eps in (2e-3, 1e-3, 5e-4)]
    e1 = [err(eps, None) for eps in (2e-3, 1e-3, 5e-4)]
    assert all(0.09 <= b / a <= 0.17 for a, b in zip(e2, e2[1:])), e2
    assert all(0.19 <= b / a <= 0.32 for a, b in zip(e1, e1[1:])), e1
    assert e2[-1] < 0.1 * e1[-1]


@pytest.mark.parametrize("psi0", [math.pi / 4, 3 * math.pi / 8])
def test_order2_map_agrees_with_ode(psi0):
    """Released from rest at 0.95π, 1000 time units, ε = 3e-3, 1e-3, 3e-4: the order-2 map's maximum-by-maximum
    errors in Q, Θ, t and φ fall with log-log slope ≥ 1.8 (order 1: ~1), and at ε = 1e-3 are ≥ 5× below order 1's."""
    errs: dict[int, dict[str, list[float]]] = {1: {}, 2: {}}
    for eps in (3e-3, 1e-3, 3e-4):
        body = Body.paper(eps)
        ref = ode_slow_summary(body, THETA0, psi0, 1000.0)
        for order in (1, 2):
            pred = av.predict_slow_motion(body, THETA0, psi0, 1000.0, order=order)
            assert pred.order == order
            for k, v in sample_errors(pred.series, ref).items():
                errs[order].setdefault(k, []).append(v)
    for k, e2 in errs[2].items():
        assert loglog_slope((3e-3, 1e-3, 3e-4), e2) >= 1.8, (k, e2)
        assert e2[1] <= 0.2 * errs[1][k][1], (k, e2, errs[1][k])


def test_order2_map_is_reversible(table, second):
    """N steps, reverse Q, N steps: back to the reversed start, at order 1 and order 2, within the map's local errors
    added over the 2N steps: the implicit kick solved to 1e-13 of the kick + 4 ulp (compiled_map.iterate_slow_map; the
    kick is bounded by the largest change of the component in a step, D), each value rounded (4 u of its largest size
    along the orbit, S, per step); the two half-orbits are mirror images, so the defects do not grow on the way back
    beyond × 4 (margin).  The time t and Θ are sums over the steps: their S is their final size."""
    eps, N = 3e-3, 25
    Q0 = np.array(table.chart(0.2, 0.1))
    for sec in (None, second):
        fwd = iterate_slow_map(table, eps, 0.7, 1e9, Q0=Q0, n_steps=N, second=sec)
        back = iterate_slow_map(table, eps, 0.5 * fwd.Theta[-1], 1e9, Q0=(-fwd.QR[-1], -fwd.QJ[-1]), n_steps=N,
                                second=sec)
        defect = np.abs([back.QR[-1] + Q0[0], back.QJ[-1] + Q0[1], float(wrap_angle(back.Theta[-1] - 1.4)),
                         back.t[-1] - fwd.t[-1]])
        series = [(fwd.QR, back.QR), (fwd.QJ, back.QJ), (fwd.Theta, back.Theta), (fwd.t, back.t)]
        S = np.array([max(np.max(np.abs(a)), np.max(np.abs(b))) for a, b in series])
        D = np.array([max(np.max(np.abs(np.diff(a))), np.max(np.abs(np.diff(b)))) for a, b in series])
        bound = 4.0 * 2 * N * (1e-13 * D + 4 * U * S + 4 * U * S)
        assert np.all(defect <= bound), (sec is not None, defect, bound)


def test_order_argument(table):
    from rocknroller.analysis.model.equations import EulerState

    with pytest.raises(ValueError, match="order must be 1 or 2"):
        av.predict_slow_motion(Body.paper(1e-3), THETA0, 0.7, 100.0, order=3)
    from rocknroller.analysis.slow.map import region as sr
    from rocknroller.analysis.slow.map.family import first_maximum

    body, start = Body.paper(1e-3), EulerState(THETA0, 0.0, 0.7, 0.0, 0.01, 0.0)
    with warnings.catch_warnings():
        warnings.simplefilter("ignore", av.AveragingValidityWarning)  # coarse
        coarse = sr.build_region_table(body, first_maximum(body, start).E, nu=16, nv=8)
    with pytest.raises(ValueError, match="order=2 uses the second-order tables on the default region tables"):
        av.predict_slow_motion(body, start, None, 100.0, table=coarse, order=2)


def test_slow_order_option(second, capsys):
    """--order: a release in the release tables' range defaults to order 2 (the better validated); --order 1 is the
    first-order map; for a start with velocity order 2 needs the default region tables (refused with --nodes,
    naming the options).  (Here, after the fixture has
    cached the second-order tables, rather than in test_cli_slow.py, whose fresh cache would build them again.)"""
    import json

    from rocknroller.cli import main

    assert main(["slow", "--theta0", "0.95pi", "--json"]) == 0
    assert json.loads(capsys.readouterr().out)["order"] == 2
    assert main(["slow", "--theta0", "0.95pi", "--order", "1", "--json"]) == 0
    assert json.loads(capsys.readouterr().out)["order"] == 1
    assert main(["slow", "--theta0", "0.95pi", "--phi-dot0", "0.01", "--order", "2", "--nodes", "16", "8"]) == 2
    assert "leave out --nodes and --chart" in capsys.readouterr().err


def test_api_and_cli_share_one_default_order(second, capsys):
    """predict_slow_motion and ``rocknroller slow`` default to the same order for the same start (issue 25: the API
    gave order 1, slow period 153.393, where the command gave order 2, 153.426, as the ODE): order 2 for a release
    in THETA0_RANGE, the same numbers bit for bit, and 1 for a release below it and for a start with velocity; both
    say so (the docstring and --help name the other)."""
    import json

    from rocknroller.analysis.model.equations import EulerState
    from rocknroller.cli import main

    body = Body.paper(1e-3)
    assert av.default_order(THETA0) == 2 and av.default_order(np.float64(av.THETA0_RANGE[0])) == 2
    assert av.default_order(0.5 * math.pi) == 1 and av.default_order(EulerState(THETA0, 0.0, 0.7, 0.0, 0.01, 0.0)) == 1
    assert av.default_order(EulerState(THETA0, 0.0, 0.7)) == 1  # a state from rest: the region tables of its energy
    pred = av.predict_slow_motion(body, THETA0, math.pi / 4, 400.0)
    assert pred.order == 2
    explicit = av.predict_slow_motion(body, THETA0, math.pi / 4, 400.0, order=2)
    assert np.array_equal(pred.series.t, explicit.series.t) and np.array_equal(pred.series.QR, explicit.series.QR)
    assert main(["slow", "--theta0", "0.95pi", "--psi0", "pi/4", "--t-end", "400", "--json"]) == 0
    out = json.loads(capsys.readouterr().out)
    assert out["order"] == 2 and out["eps"] == float(body.epsilon_text()) == 1e-3  # eps as given, not its rounding
    assert out["slow_period"] == pred.slow_period and out["QR_extent"] == pred.QR_extent and out["Phi"] == pred.Phi
    # the explicit order is kept: order 1 differs from the default by the map's O(eps^2) (here ~2e-4 of the period)
    first = av.predict_slow_motion(body, THETA0, math.pi / 4, 400.0, order=1)
    assert first.order == 1 and first.slow_period != pred.slow_period
    doc = " ".join(av.predict_slow_motion.__doc__.split())
    assert "Default: :func:`default_order`, the same as ``rocknroller slow``'s" in doc
    with pytest.raises(SystemExit):
        main(["slow", "--help"])
    assert "default, the same as predict_slow_motion's: 2 for releases from rest in [0.75pi, 0.999pi]" in " ".join(
        capsys.readouterr().out.split())


@pytest.mark.parametrize("kind", ["release", "region"])
def test_k2_accuracy_warning_names_options_that_exist(kind, monkeypatch, tmp_path):
    """Above its accuracy a second-order table warns with advice the user can follow (issue 25: the region table's
    default grid warned "use more nodes (nu=16, nv=32)", an option that does not help there and that the command
    refuses with --order 2).  Release tables: more nodes of load_or_build_second_order_table, passed as second=;
    region tables, which more nodes do not improve: the direct ODE (--check) or order 1.  A coarse chart (4 x 4
    first-order nodes, 8 x 2 for k2) makes both warn; the region's default is measured in docs/averaging.md."""
    from rocknroller.analysis.slow.map import region as sr
    from rocknroller.analysis.slow.map import second_order as so
    from rocknroller.analysis.slow.map import table as slow_table
    from rocknroller.analysis.slow.map.family import rest_energy
    from rocknroller.numerics.cache import MemoryCache

    monkeypatch.setenv("ROCKNROLLER_CACHE", str(tmp_path))
    monkeypatch.setattr(slow_table, "_TABLES", MemoryCache(slow_table.TABLE_CACHE_BYTES))
    sym = Body.paper(0.0)
    E = rest_energy(sym, 0.6 * math.pi)
    with warnings.catch_warnings():
        warnings.simplefilter("ignore", av.AveragingValidityWarning)
        first = (av.load_or_build_table(sym, 0.9 * math.pi, nu=4, nv=4) if kind == "release" else
                 sr.load_or_build_region_table(sym, E, axis="spindle", nu=4, nv=4))
    monkeypatch.setattr(so, "_first_table", lambda body, where, k, **run: first)
    build = so.build_second_order_table if kind == "release" else so.build_second_order_region_table
    with pytest.warns(av.AveragingValidityWarning, match="interpolate k2 only to") as caught:
        table = build(sym, 0.9 * math.pi if kind == "release" else E, nu=8, nv=2)
    limit = so.K2_ACCURACY if kind == "release" else so.K2_REGION_ACCURACY
    assert table.interp_error > limit
    msg = str(caught[-1].message)
    assert f"(relative, above {limit:g})" in msg
    if kind == "release":
        assert "use more nodes (nu, nv of load_or_build_second_order_table: now 8, 2" in msg and "second=" in msg
    else:
        assert "more nodes do not bring it down" in msg and "--check" in msg and "--order 1" in msg
        assert "use more nodes" not in msg
