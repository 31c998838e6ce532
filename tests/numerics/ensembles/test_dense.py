"""The batch dense output evaluated point by point (numerics/ensembles/_dense.c, ``batch._LaneOutput``): heyoka's own
evaluation within a derived bound, each lane's states independent of its lane mates, bad buffers refused."""

from __future__ import annotations

import math

import numpy as np
import pytest

import rocknroller as rr
from rocknroller.analysis.model.equations import body_frame_rhs
from rocknroller.numerics.ensembles import _dense
from rocknroller.numerics.ensembles.batch import _LaneOutput, batch_integrator

#: Unit round-off of double precision.
U = float(np.finfo(float).eps) / 2.0


def _stretch(width: int, t0: float, t1: list[float], tol: float) -> tuple[_LaneOutput, object, np.ndarray]:
    """A stretch (t0, t1[j]] of ``width`` lanes released at 0.95π with spin phases 0.1 j, its output, heyoka's, and
    the parameters."""
    body = rr.Body.paper(1e-3)
    ta = batch_integrator(width, tol)
    ta.set_time(0.0)
    ta.state[:] = np.stack([rr.EulerState(0.95 * math.pi, psi=0.1 * k).to_body_state() for k in range(width)], axis=1)
    ta.pars[:] = np.stack([np.asarray(body.params, float)] * width, axis=1)
    ta.propagate_until(np.full(width, t0))
    c_out = ta.propagate_until(np.asarray(t1, float), c_output=True)[0]
    return _LaneOutput(c_out), c_out, np.asarray(body.params, float)


@pytest.mark.parametrize("tol", [float(np.finfo(float).eps), 1e-11])
def test_points_are_heyokas_states_within_the_time_rounding_and_horner(tol):
    """Derived bound: heyoka keeps a step's start as a double-length time, ``_dense`` its leading double, so the two
    evaluate at times up to half an ulp of t apart, ≤ u |t|, which moves the state by ≤ u |t| |dy/dt| (the right-hand
    side bounds the polynomial's derivative to its truncation); each evaluates the step's polynomial by Horner's rule,
    ≤ 2 P u Σ|c_k| |h|^k ≤ 2 P u (|y| + |dy/dt| |h| + ...) — at most 2 P u · 4 max(1, |y|) for steps of a fraction of
    the motion's period (P ≤ 21 coefficients); × 2 (two evaluations) and × 4 margin."""
    out, c_out, params = _stretch(8, 300.0, [700.0 + k for k in range(8)], tol)
    rng = np.random.default_rng(1)
    grid = np.sort(rng.uniform(300.0, 700.0, (2000, 8)), axis=0)
    mine = out.points(grid.ravel(), np.tile(np.arange(8), grid.shape[0])).reshape(-1, 8, 11).transpose(0, 2, 1)
    theirs = np.asarray(c_out(grid))
    rate = np.abs(body_frame_rhs(theirs.transpose(1, 0, 2), tuple(params))).transpose(1, 0, 2)
    P = out.tcs.shape[2]
    bound = 4.0 * 2.0 * (U * np.abs(grid)[:, None, :] * rate + 2.0 * P * U * 4.0 * np.maximum(1.0, np.abs(theirs)))
    assert np.all(np.abs(mine - theirs) <= bound)
    assert np.max(np.abs(mine - theirs)) > 0.0  # the time rounding is seen: the bound is what it guards


def test_a_lanes_states_do_not_depend_on_its_lane_mates():
    """The same lane (spin phase 0, stretch (0, 40]) among lanes that run longer or not: its states at the stretch's
    end and inside it are the same bits (the empty steps after a lane's end are never its own)."""
    t = np.array([0.0, 13.0, 26.5, 40.0])
    alone, _, _ = _stretch(2, 0.0, [40.0, 40.0], float(np.finfo(float).eps))
    among, _, _ = _stretch(4, 0.0, [40.0, 55.0, 60.0, 75.0], float(np.finfo(float).eps))
    zero = np.zeros(t.size, np.intp)
    assert np.array_equal(alone.points(t, zero), among.points(t, zero))


def test_a_points_state_does_not_depend_on_the_order_asked():
    """Each lane's step is looked for from its last one (a few steps forward, else by bisection): times asked in
    time order, shuffled, and far apart give the same bits."""
    out, _, _ = _stretch(4, 0.0, [200.0, 220.0, 240.0, 260.0], float(np.finfo(float).eps))
    rng = np.random.default_rng(2)
    t = np.sort(rng.uniform(0.0, 200.0, 3000))
    col = rng.integers(0, 4, t.size)
    shuffle = rng.permutation(t.size)
    in_order = out.points(t, col)
    assert np.array_equal(out.points(t[shuffle], col[shuffle]), in_order[shuffle])
    assert np.array_equal(out.points(t[::-1], col[::-1]), in_order[::-1])


def test_bad_buffers_are_refused():
    out, _, _ = _stretch(2, 0.0, [1.0, 1.0], float(np.finfo(float).eps))
    with pytest.raises(ValueError, match="col: a lane out of range"):
        out.points(np.array([0.5]), np.array([2]))
    with pytest.raises(ValueError, match="times"):
        _dense.states(out.tcs, out.times[:-1], np.array([0.5]), np.array([0], np.int64), np.empty((1, 11)))
    with pytest.raises(ValueError, match="out"):
        _dense.states(out.tcs, out.times, np.array([0.5]), np.array([0], np.int64), np.empty((1, 11), np.float32))
