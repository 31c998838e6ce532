"""The slow map's tables over energy (``analysis/slow/map/tables_at_once.py``: :class:`EnergyTables`): the
interpolation in s = log(π − θ0), a small build against per-θ0 tables, the cache, the choice of tables for a release,
and the refusal of bad input."""

from __future__ import annotations

import math
import os
import warnings

import numpy as np
import pytest

from rocknroller.analysis.model.body import Body
from rocknroller.analysis.slow.map import tables_at_once as ta
from rocknroller.analysis.slow.map.chart import cheb_nodes
from rocknroller.analysis.slow.map.limits import AveragingValidityWarning
from rocknroller.analysis.slow.map.table import build_table, fit_reduced, fit_table, reduce_responses, release_frame

SYM = Body.paper()
LO, HI = 0.9 * math.pi, 0.91 * math.pi
SMALL = dict(theta0_hi=HI, n_first=6, n_second=2, k2_nu=8)


@pytest.fixture(scope="module")
def span(tmp_path_factory):
    """A small build over [0.9π, 0.91π] in an empty cache of its own (~10 s)."""
    saved = os.environ.get("ROCKNROLLER_CACHE")
    os.environ["ROCKNROLLER_CACHE"] = str(tmp_path_factory.mktemp("energy-cache"))
    try:
        with warnings.catch_warnings():
            warnings.simplefilter("ignore", AveragingValidityWarning)  # k₂ on 8 nodes along: coarse on purpose
            yield ta.load_energy_tables(SYM, theta0_lo=LO, progress=False, **SMALL)
    finally:
        if saved is None:
            os.environ.pop("ROCKNROLLER_CACHE")
        else:
            os.environ["ROCKNROLLER_CACHE"] = saved


@pytest.mark.parametrize("n", [5, 12])
def test_interpolation_reproduces_power_laws_and_polynomials(n):
    """Two cases the construction is exact on, to rounding at an off-node x: a pure power law of π − θ0 (an
    exponential in the node coordinate, times any pattern over the trailing axes: its size is fitted exactly and
    divided out, leaving constants), and a polynomial of degree < n that vanishes at a node (not scaled; the
    barycentric formula is exact on it).  Bound 1e-13 relative: a sum of n terms, the Lebesgue constant ~log n, the
    fit's exp and log, each a few units of round-off."""
    xs = cheb_nodes(n)
    pattern = np.array([[1.0, -0.5, 0.25], [2.0, 0.0, -3.0]])  # (functions, trailing)
    law = np.exp(-3.0 * xs + 0.7)[:, None, None] * pattern
    poly = np.polynomial.Polynomial([0.0, 1.0, 0.5, -0.2, 0.1][:n])  # poly(0) = 0: a node of odd n
    vanishing = np.stack([poly(xs) - poly(xs[n // 2]), 2.0 * (poly(xs) - poly(xs[n // 2]))], axis=1)[..., None]
    for x in (0.123, -0.77):
        got, want = ta._interpolate(law, x), math.exp(-3.0 * x + 0.7) * pattern
        assert np.abs(got - want).max() <= 1e-13 * np.abs(want).max()
        got = ta._interpolate(vanishing, x)[:, 0]
        want = np.array([1.0, 2.0]) * (poly(x) - poly(xs[n // 2]))
        assert np.abs(got - want).max() <= 1e-13 * np.abs(vanishing).max()
    assert np.array_equal(ta._interpolate(law, xs[2]), law[2])  # at a node: the node's values


def test_reduced_fit_is_the_fit():
    """The table fitted from reduced responses (what the tables over energy interpolate) is the table fitted from the
    responses, to rounding: the half-drift's part taken out and added back is the same linear operation."""
    frame, T, W, dphi, thX = release_frame(SYM, 0.93 * math.pi, nu=16)
    rng = np.random.default_rng(1)
    resp = rng.standard_normal((5,) + T.shape + (3,))
    a = fit_table(frame, T, W, dphi, resp)
    b = fit_reduced(frame, T, W, dphi, reduce_responses(frame, T, W, dphi, resp))
    assert np.array_equal(a.coef, b.coef)


def test_off_node_tables_match_per_theta0_tables(span):
    """At release angles between the nodes the tables agree with the per-θ0 tables within ten times the error the
    build measured at its own checks (an interpolant's error varies by a small factor between neighbouring gaps);
    the chart's orientation, interpolated, to 1e-9 of the per-θ0 one."""
    assert span.first_error > 0.0
    for t in (0.9013 * math.pi, 0.9071 * math.pi):
        got, ref = span.release_table(t), build_table(SYM, t, progress=False)
        assert np.abs(got.e - ref.e).max() <= 1e-9 and abs(got.U / ref.U - 1.0) <= 1e-9
        assert ta.kick_error(got, ref) <= 10.0 * span.first_error
        assert got.interp_error == span.first_error
        second = span.second_order_table(t)
        assert second.coef.shape == (25, 8, 6) and second.E0 == got.E0 and second.interp_error == span.second_error


def test_a_new_angle_runs_no_orbit(span, monkeypatch):
    """A release table from the tables over energy runs no orbit (the kick at rest is interpolated too): the
    variational orbits' entry point is not called."""
    from rocknroller.analysis.slow.map import table as tb

    def refuse(*args, **kwargs):
        raise AssertionError("an orbit was run")

    monkeypatch.setattr(tb, "kick_at_rest", refuse)
    ta._ENERGY_CACHE.clear()
    span.release_table(0.9042 * math.pi)


def test_cache_round_trip(span):
    """A second load reads the file: the same arrays, without building (build=False)."""
    from rocknroller.analysis.slow.map.table import _TABLES

    _TABLES.clear()
    again = ta.load_energy_tables(SYM, theta0_lo=LO, build=False, **SMALL)
    assert np.array_equal(again.resp, span.resp) and np.array_equal(again.k2, span.k2)
    assert (again.first_error, again.second_error) == (span.first_error, span.second_error)


def test_release_tables_prefer_the_tables_over_energy(span, monkeypatch):
    """``release_tables`` serves a release from the tables over energy when they are cached for the body, else from
    the per-θ0 tables."""
    t = 0.9037 * math.pi
    monkeypatch.setattr(ta, "energy_tables_cached", lambda body: False)
    per = ta.release_tables(SYM, t, 1)[0]
    assert np.array_equal(per.coef, build_table(SYM, t, progress=False).coef)
    monkeypatch.setattr(ta, "energy_tables_cached", lambda body: True)
    monkeypatch.setattr(ta, "load_energy_tables", lambda body, build=True: span)
    first, second = ta.release_tables(SYM, t, 2)
    assert np.array_equal(first.coef, span.release_table(t).coef) and second is not None


@pytest.mark.parametrize("kwargs, name", [
    (dict(theta0_hi=0.5 * math.pi), "theta0_hi"),
    (dict(theta0_hi=0.85 * math.pi), "theta0_hi must exceed"),
    (dict(n_first=1), "n_first"),
    (dict(n_second=129), "n_second"),
    (dict(k2_nu=7), "nu"),
])
def test_bad_options_are_refused(kwargs, name):
    with pytest.raises(ValueError, match=name):
        ta.build_energy_tables(SYM, 0.9 * math.pi, **kwargs)


def test_angles_outside_the_span_are_refused(span):
    with pytest.raises(ValueError, match="theta0 must lie in"):
        span.release_table(0.95 * math.pi)


def test_a_bad_file_falls_back_to_per_theta0_tables(monkeypatch):
    """Tables over energy whose file fails its checks (``load_energy_tables(build=False)`` then raises, after its
    CacheWarning) leave the release to the per-θ0 tables, not to an error."""
    def unusable(body, build=True):
        raise ta.TableNotCachedError("the file failed its checks")

    monkeypatch.setattr(ta, "energy_tables_cached", lambda body: True)
    monkeypatch.setattr(ta, "load_energy_tables", unusable)
    t = 0.9037 * math.pi
    assert np.array_equal(ta.release_tables(SYM, t, 1)[0].coef, build_table(SYM, t, progress=False).coef)


@pytest.mark.slow
@pytest.mark.validation
@pytest.mark.parametrize("fraction", [0.7891, 0.8123, 0.8777, 0.9137, 0.9543])
def test_predictions_on_the_tables_over_energy_match_the_ode(fraction):
    """The acceptance: order-2 predictions at release angles kept outside the build (no node of either table) are
    within 5e-4 of the direct ODE at ε = 1e-3, 1000 time units (slow period, extents, Φ; largest measured 4.5e-4, the
    Q_J extent at 0.9543π, as on the per-θ0 tables: docs/slow_validation.md).  Builds the default tables over energy
    if they are not cached (~5 min)."""
    from rocknroller.analysis.slow.prediction import predict_slow_motion
    from rocknroller.papers.averaging_check import check_prediction

    body = Body.paper(1e-3)
    span = ta.load_energy_tables(body, workers=2)
    t0 = fraction * math.pi
    table, second = span.release_table(t0), span.second_order_table(t0)
    pred = predict_slow_motion(body, t0, 0.5, 1000.0, table=table, second=second, order=2)
    check = check_prediction(body, pred)
    for name in ("slow_period", "QR_extent", "QJ_extent", "Phi"):
        assert abs(check.rel_errors[name]) < 5e-4, (name, check.rel_errors[name])


def test_the_environment_can_set_them_aside(span, monkeypatch):
    """``ROCKNROLLER_ENERGY_TABLES=off`` sets cached tables over energy aside: a release is on its per-θ0 tables (to
    reproduce a result made without them; the docs' examples run so)."""
    from rocknroller.analysis.slow.map import table as tb

    key, _, path, _, _ = tb._table_location(ta.build_energy_tables, SYM, ta.THETA0_RANGE[0], {})
    monkeypatch.setattr(ta, "is_cached", lambda builder, body, where, **grid: True)  # as if they were cached
    assert ta.energy_tables_cached(SYM)
    monkeypatch.setenv("ROCKNROLLER_ENERGY_TABLES", "off")
    assert not ta.energy_tables_cached(SYM)
    t = 0.9037 * math.pi
    assert np.array_equal(ta.release_tables(SYM, t, 1)[0].coef, build_table(SYM, t, progress=False).coef)
