"""The maps on arrays of points (issue item "Arrays"): ``SlowMap``/``ExactMap`` take x of shape (..., 3) and keep its
leading shape (``__call__``, ``inverse`` (..., 3), ``jacobian`` (..., 3, 3), ``iterate`` (..., n + 1, 3)), each row
the one-point call's bit for bit; one point (3,) gives what it always gave; a row whose step fails is reported alone
(``failed="raise"``: its own error, noting every failed row; ``failed="nan"``: NaN rows); bad rows are named; the
periodic orbits' scan runs the slow map on the whole line at once.

Paper body, releases from rest at θ0 = 0.95π, ε = 1e-2 (tests/analysis/slow/map/test_maps.py's cases).
"""

from __future__ import annotations

import math
import sys

import numpy as np
import pytest

from rocknroller.analysis.model.body import Body
from rocknroller.analysis.model.diagnostics import wrap_angle
from rocknroller.analysis.routh.reduction import NoMotionError
from rocknroller.analysis.slow.dynamics import periodic_orbits as po
from rocknroller.analysis.slow.map.compiled_map import _CHUNK, _fast, _FastTable
from rocknroller.analysis.slow.map.limits import AveragingRangeError
from rocknroller.analysis.slow.map.maps import ExactMap, SlowMap

BODY = Body.paper(0.0)
THETA0 = 0.95 * math.pi
EPS = 1e-2


@pytest.fixture(scope="module")
def slow1() -> SlowMap:
    return SlowMap(BODY, THETA0, EPS, 1)  # order 1 given: the default is 2 (default_order)


@pytest.fixture(scope="module")
def slow2() -> SlowMap:
    """Order 2: the second-order table is built once per cache (~60 s on 2 cores), then read."""
    return SlowMap(BODY, THETA0, EPS, 2, workers=2)


@pytest.fixture(scope="module")
def exact() -> ExactMap:
    return ExactMap(BODY, THETA0, EPS)


def inside(F: SlowMap, n: int, seed: int = 0) -> np.ndarray:
    """n maxima inside F's release table: |u| ≤ 0.1 U along the kick direction, |v| ≤ 2e-5 across, Θ in [−6, 6]."""
    rng = np.random.default_rng(seed)
    u, v = rng.uniform(-0.1, 0.1, n) * F.table.U, rng.uniform(-2e-5, 2e-5, n)
    return np.column_stack([np.outer(u, F.table.e) + np.outer(v, F.table.n), rng.uniform(-6.0, 6.0, n)])


def leaving(F: SlowMap) -> np.ndarray:
    """A maximum near the table's end (u = 0.7 U, Θ = 5) whose orbit leaves the table at its fourth step."""
    return np.array([*(0.7 * F.table.U * F.table.e), 5.0])


def rows(method, X: np.ndarray, *args) -> np.ndarray:
    """``method`` called on each row of X (..., 3) alone, stacked back to X's leading shape."""
    flat = [method(x, *args) for x in X.reshape(-1, 3)]
    return np.array(flat).reshape(X.shape[:-1] + flat[0].shape)


@pytest.mark.parametrize("order", [1, 2])
def test_slow_map_on_an_array_is_its_rows_bit_for_bit(slow1, slow2, order):
    """F, inverse, jacobian and iterate of a stack (N, 3) and of an array (2, 3, 4, 3) keep the leading shape and
    equal the one-point calls row by row, bit for bit (each row's kernel call and arithmetic are the one point's)."""
    F = slow1 if order == 1 else slow2
    X = inside(F, 60)
    for A in (X, X[:24].reshape(2, 3, 4, 3)):
        lead = A.shape[:-1]
        for method, tail in ((F, (3,)), (F.inverse, (3,)), (F.jacobian, (3, 3))):
            out = method(A)
            assert out.shape == lead + tail
            np.testing.assert_array_equal(out, rows(method, A))
        orbit = F.iterate(A, 5)
        assert orbit.shape == lead + (6, 3)
        np.testing.assert_array_equal(orbit, rows(F.iterate, A, 5))
        np.testing.assert_array_equal(orbit[..., 0, :], A)
    assert F(X[:0]).shape == (0, 3) and F.jacobian(X[:0]).shape == (0, 3, 3) and F.iterate(X[:0], 2).shape == (0, 3, 3)
    assert F.iterate(X, 0).shape == (60, 1, 3)


def test_one_point_keeps_its_shapes_and_values(slow1, exact):
    """One point (3,) gives (3,), (3, 3) and (n + 1, 3) as before, the same numbers as the one-row array (1, 3); a 0-d
    x is refused as before."""
    x = np.array([1e-3, -2e-5, 1.0])
    for F in (slow1, exact):
        assert F(x).shape == (3,) and F.inverse(x).shape == (3,) and F.iterate(x, 2).shape == (3, 3)
        np.testing.assert_array_equal(F(x[None])[0], F(x))
        np.testing.assert_array_equal(F.iterate(x[None], 2)[0], F.iterate(x, 2))
        with pytest.raises(ValueError, match=r"x must be three finite numbers \(Q_R, Q_J, Theta\)"):
            F(1.0)
    assert slow1.jacobian(x).shape == (3, 3)
    np.testing.assert_array_equal(slow1.jacobian(x[None])[0], slow1.jacobian(x))


def test_slow_iterate_in_one_kernel_call_is_the_chunked_run(slow1):
    """``iterate`` now runs each orbit in one kernel call; ``iterate_slow_map`` runs it in chunks of ``_CHUNK`` rows,
    each restarting the kernel from the last row.  Past a chunk boundary the two are the same orbit, bit for bit (the
    one-point iterate's arithmetic on the chunked rows: the chart's rotation and the Θ continuation)."""
    x = np.array([0.0, 0.0, math.pi / 2 + 0.3])  # regular: stays in the table
    n = _CHUNK + 100
    orbit = slow1.iterate(x[None], n)[0]
    ft = _fast(slow1.table)
    chunked, _ = ft.iterate(slow1.eps, float(ft.e @ x[:2]), float(ft.n @ x[:2]), float(x[2]), 0.0,
                            sys.float_info.max, n)
    assert len(chunked) == n
    np.testing.assert_array_equal(orbit[1:, :2], (chunked[:, 1:4] @ slow1.chart.T)[:, :2])
    raw = np.concatenate([[x[2]], chunked[:, 3]])
    np.testing.assert_array_equal(orbit[:, 2], np.cumsum(np.concatenate([[x[2]], wrap_angle(np.diff(raw))])))


def test_the_second_order_run_time_form_shares_the_first_orders_rows(slow2):
    """A prediction asks for the run-time form without and with the second-order rows (``centre_period``, then the
    run): the second shares the first's arrays, and both are bit for bit what a build of their own gives."""
    one, two = _fast(slow2.table), _fast(slow2.table, slow2.second)
    assert two.rows is one.rows and two.rows_jac is one.rows_jac and two.geom is one.geom
    assert one.rows2 is None and two.second is slow2.second
    own = _FastTable(slow2.table, slow2.second)
    for name in ("rows", "rows_jac", "geom", "rows2"):
        assert np.array_equal(getattr(two, name), getattr(own, name)), name


def test_exact_map_on_an_array_is_its_rows_bit_for_bit(exact):
    """One direct run per row: the same numbers as the one-point calls (two points, one step; the Jacobian at one)."""
    X = np.array([[1e-3, -2e-5, 1.0], [-4e-3, 1e-4, 4.0]])
    for method in (exact, exact.inverse):
        assert method(X).shape == (2, 3)
        np.testing.assert_array_equal(method(X), rows(method, X))
    orbit = exact.iterate(X, 1)
    assert orbit.shape == (2, 2, 3)
    np.testing.assert_array_equal(orbit, rows(exact.iterate, X, 1))
    J = exact.jacobian(X[None, :1])
    assert J.shape == (1, 1, 3, 3)
    np.testing.assert_array_equal(J[0, 0], exact.jacobian(X[0]))


def test_a_slow_point_that_leaves_the_tables_fails_alone(slow1):
    """One row off the tables: ``failed="nan"`` gives it NaN (its Jacobian a NaN block) and the other rows as they are
    alone; ``failed="raise"`` (the default) raises that row's own AveragingRangeError with a note naming the failed
    rows; an orbit that leaves keeps its maxima inside the tables (NaN after); one point with ``failed="nan"`` is a
    NaN row."""
    X = inside(slow1, 6)
    X[[1, 4]] = [0.5, 0.0, 1.0]  # Q_R = 0.5: far outside (|u| ≤ 0.04)
    ok = [0, 2, 3, 5]
    for method in (slow1, slow1.inverse, slow1.jacobian):
        out = method(X, failed="nan")
        assert np.isnan(out[[1, 4]]).all() and np.isfinite(out[ok]).all()
        np.testing.assert_array_equal(out[ok], method(X[ok]))
        with pytest.raises(AveragingRangeError, match="left the tabulated region") as info:
            method(X)
        assert any("at x[1], the first of rows [1, 4] (2 of 6)" in note for note in info.value.__notes__)
    with pytest.raises(AveragingRangeError) as info:
        slow1(X[1])  # one point: its error as ever, no note
    assert not getattr(info.value, "__notes__", None)
    assert np.isnan(slow1(X[1], failed="nan")).all()
    x = leaving(slow1)
    orbits = slow1.iterate(np.array([x, X[0]]), 6, failed="nan")
    np.testing.assert_array_equal(orbits[0, :4], slow1.iterate(x, 3))
    assert np.isnan(orbits[0, 4:]).all()
    np.testing.assert_array_equal(orbits[1], slow1.iterate(X[0], 6))
    with pytest.raises(AveragingRangeError):
        slow1.iterate(x, 6)


def test_an_exact_point_without_motion_fails_alone(exact):
    """(E, Q) without motion (Q_R = 5) in one row: NaN there with ``failed="nan"``, its NoMotionError (a ValueError)
    noting the row with ``failed="raise"``; the other row as it is alone."""
    X = np.array([[1e-3, -2e-5, 1.0], [5.0, 0.0, 1.0]])
    y = exact(X, failed="nan")
    assert np.isnan(y[1]).all()
    np.testing.assert_array_equal(y[0], exact(X[0]))
    with pytest.raises(NoMotionError) as info:
        exact(X)
    assert any("at x[1], the first of rows [1] (1 of 2)" in note for note in info.value.__notes__)
    assert np.isnan(exact.iterate(X[1:], 2, failed="nan")[0, 1:]).all()


def test_bad_rows_are_named(slow1, exact):
    """Each row is checked as one point is (finite, |Θ| ≤ ANGLE_MAX, real): the ValueError names the rows; a
    complex array is refused, not cast; the last axis must be 3; ``failed`` must be "raise" or "nan"; ``run`` takes one
    start."""
    X = inside(slow1, 5)
    for F in (slow1, exact):
        bad = X.copy()
        bad[[2, 3], 1] = [math.nan, math.inf]
        for method in (F, F.inverse, F.jacobian, lambda x: F.iterate(x, 2)):
            with pytest.raises(ValueError, match=r"in every row, and rows \[2, 3\] \(2 of 5\) of x \(shape \(5, 3\)\)"):
                method(bad)
        far = X.reshape(5, 1, 3).copy()
        far[4, 0, 2] = 1e17
        with pytest.raises(ValueError, match=r"Theta must be a finite angle within .*got Theta=1e\+17, the first of "
                                             r"rows \[\(4, 0\)\] \(1 of 5\)"):
            F(far)
        with pytest.raises(ValueError, match=r"x must be three finite numbers \(Q_R, Q_J, Theta\), or an array"):
            F(X.astype(complex))
        with pytest.raises(ValueError, match=r"or an array \(\.\.\., 3\) of them, got an array of shape \(3, 2, 2\)"):
            F(np.zeros((3, 2, 2)))
        with pytest.raises(ValueError, match=r"failed must be one of \('raise', 'nan'\), got failed='skip'"):
            F(X, failed="skip")
    with pytest.raises(ValueError, match=r"run takes one maximum x = \(Q_R, Q_J, Theta\), got an array of shape"):
        slow1.run(X, 10.0)


def test_the_period_two_scan_runs_the_slow_map_on_the_whole_line(monkeypatch):
    """periodic_orbit's scan for the period-2 start evaluates the slow map once on its 64 points (an array call,
    benchmarks/bench_map_arrays.py: ~6x faster than a call each) and finds the start that the point-by-point scan
    finds, bit for bit; G on an array is G on each row."""
    problem = po._Problem(BODY, THETA0, 1.2 * 4.0 / abs(SlowMap(BODY, THETA0, EPS).kappa), "slow", 1, 1)
    calls: list[tuple[int, ...]] = []
    F = problem.F

    def counted(x, *, failed="raise"):
        calls.append(np.shape(x))
        return SlowMap.__call__(F, x, failed=failed)

    monkeypatch.setattr(problem, "F", type("Counted", (), {"__call__": staticmethod(counted)})())
    start = problem.start(2, problem.theta_star)
    assert calls[0] == (po._SCAN[2], 3) and all(s == (3,) for s in calls[1:])  # then Brent's method, point by point
    us = float(problem.table.U) * np.geomspace(*po._SCAN)
    line = np.column_stack([us, np.zeros_like(us), np.full_like(us, problem.theta_star)])
    G = problem.G(line, failed="nan")
    np.testing.assert_array_equal(G, np.array([problem.G(x, failed="nan") for x in line]))
    k = int(np.nonzero(G[:-1, 0] * G[1:, 0] <= 0.0)[0][0])  # the first sign change of u' + u: the scan's bracket
    assert us[k] <= start[0] <= us[k + 1]
