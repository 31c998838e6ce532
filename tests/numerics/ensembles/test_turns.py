"""The unwrapping of the batch lanes in C (``_dense.c``'s ``turns``, ``batch._LaneOutput.unwrap``) against the numpy
one (``trajectory._unwrapped_angles``) on the same dense output: the same unwrapped angles and states, bit for bit,
on coarse grids that need refining, through the pole itself, from given branches; an unresolvable interval and bad
buffers refused."""

from __future__ import annotations

import math

import numpy as np
import pytest
from hypothesis import given, settings
from hypothesis import strategies as st

import rocknroller as rr
from rocknroller.numerics.ensembles import _dense
from rocknroller.numerics.ensembles.batch import _LaneOutput, batch_integrator
from rocknroller.numerics.run_limits import rate_bound
from rocknroller.numerics.trajectory import (_MAX_BISECTIONS, _SHORTEST, _UNWRAP_LIMIT, _branches, _Samples,
                                             _turns)

WIDTH = 8
T_END = 60.0


def _stretch(body: rr.Body, starts: list[rr.EulerState]) -> tuple[_LaneOutput, np.ndarray]:
    """The stretch (0, T_END + j] of lanes started at ``starts``, its output, and each lane's rate bound Λ."""
    ta = batch_integrator(WIDTH)
    ta.set_time(0.0)
    y0 = [s.to_body_state() for s in starts]
    ta.state[:] = np.stack(y0, axis=1)
    ta.pars[:] = np.stack([np.asarray(body.params, float)] * WIDTH, axis=1)
    c_out = ta.propagate_until(T_END + np.arange(WIDTH, dtype=float), c_output=True)[0]
    return _LaneOutput(c_out), np.array([rate_bound(body, y) for y in y0])


def _as_grid_callable(out: _LaneOutput):
    """The same output as a plain lane dense output (times (rows, W) to states (rows, 11, W)): the numpy path."""
    def dense(grid: np.ndarray) -> np.ndarray:
        rows = grid.shape[0]
        return out.points(grid.ravel(), np.tile(np.arange(WIDTH), rows)).reshape(rows, WIDTH, 11).transpose(0, 2, 1)
    return dense


def _both(out: _LaneOutput, rate: np.ndarray, columns: list[int], radians: float, fine_radians: float,
          branches: list[np.ndarray | None]) -> tuple[list[_Samples], list[_Samples]]:
    pieces = [(np.linspace(0.0, T_END, int(T_END * rate[j] / radians) + 2), np.empty(0), np.empty(0))
              for j in columns]
    fill = T_END + np.arange(WIDTH, dtype=float)
    fine = [fine_radians / rate[j] for j in columns]
    in_c = _Samples.take_lanes(out, pieces, columns, fill, branches, fine)
    in_numpy = _Samples.take_lanes(_as_grid_callable(out), pieces, columns, fill, branches, fine)
    return in_c, in_numpy


def _assert_same(in_c: list[_Samples], in_numpy: list[_Samples]) -> None:
    for a, b in zip(in_c, in_numpy, strict=True):
        assert np.array_equal(a.t, b.t) and np.array_equal(a.y, b.y)
        assert np.array_equal(a.angles, b.angles)


def _refinement_matters(samples: list[_Samples]) -> bool:
    """Whether some lane's turns on its grid alone, unrefined, differ from the refined ones."""
    for s in samples:
        ends = np.array([0, s.t.size])
        raw = s.angles.copy()
        raw[1:] = np.arctan2(np.sin(raw[1:]), np.cos(raw[1:]))
        if not np.allclose(_branches(raw, _turns(raw, ends), ends, [s.angles[1:, 0]]), s.angles, atol=1e-9):
            return True
    return False


_start = st.builds(lambda theta, psi, rates: rr.EulerState(theta, 0.0, psi, *rates), st.floats(0.05, 3.0),
                   st.floats(0.0, 2 * math.pi), st.tuples(*[st.floats(-2.0, 2.0)] * 3))


@settings(max_examples=6, deadline=None, derandomize=True)
@given(st.lists(_start, min_size=WIDTH, max_size=WIDTH), st.floats(1.0, 6.0),
       st.sampled_from([0.15, 1.0, math.inf]))
def test_c_unwraps_as_numpy_on_random_lanes(starts, radians, fine_radians):
    """Random starts (tilts down to 0.05 rad, fast spins), grids of 1-6 radians of Λ (coarser than the 2π/3 limit:
    refined), the rate test applied down to 0.15 or 1 radian or not at all; lanes taken out of order and from branches 2π·k
    away: the same bits."""
    out, rate = _stretch(rr.Body.paper(1e-3), starts)
    columns = [5, 0, 3, 7, 1]
    branches = [None, np.array([4 * math.pi, -2 * math.pi]), None, np.array([-6 * math.pi, 0.0]), None]
    # a branch continues the lane's first angles: start + wrap(angle0 − start) picks the turn nearest to them
    in_c, in_numpy = _both(out, rate, columns, radians, fine_radians, branches)
    _assert_same(in_c, in_numpy)


def test_c_unwraps_as_numpy_through_the_pole_and_where_refinement_matters():
    """Planar rocking with ψ0 = 0 passes through θ = 0 itself (φ and ψ each jump by π there, only φ + ψ is
    continuous: bisection down to round-off), beside releases near the pole: the same bits, and refining changed
    the turns of some lane (the test would see a path that skips it)."""
    body = rr.Body.paper(1e-3)
    starts = [rr.EulerState(0.4), rr.EulerState(0.4, psi=0.0, theta_dot=0.1), rr.EulerState(0.95 * math.pi, psi=0.3),
              rr.EulerState(0.02, psi=1.0, phi_dot=3.0), rr.EulerState(2.0, psi=2.0, psi_dot=-4.0),
              rr.EulerState(0.9 * math.pi), rr.EulerState(0.1, psi=0.5), rr.EulerState(1.5, psi=0.7)]
    out, rate = _stretch(body, starts)
    in_c, in_numpy = _both(out, rate, list(range(WIDTH)), 3.0, 1.0, [None] * WIDTH)
    _assert_same(in_c, in_numpy)
    assert np.min(in_c[0].y[:, 0] ** 2 + in_c[0].y[:, 1] ** 2) < 1e-3  # lane 0 passes the pole
    assert _refinement_matters(in_c)


def test_an_unresolvable_interval_and_bad_buffers_are_refused():
    out, rate = _stretch(rr.Body.paper(1e-3), [rr.EulerState(0.95 * math.pi, psi=0.1 * k) for k in range(WIDTH)])
    t = np.linspace(0.0, T_END, 5)  # 15 time units apart: φ and ψ turn by far more than 2π/3
    col, fine = np.zeros(t.size, np.intp), np.full(t.size, math.inf)
    with pytest.raises(RuntimeError, match="could not resolve"):
        out.unwrap(t, col, fine, _UNWRAP_LIMIT, 0, _SHORTEST)
    y, turns = out.unwrap(t, col, fine, _UNWRAP_LIMIT, _MAX_BISECTIONS, _SHORTEST)
    assert np.array_equal(y, out.points(t, col)) and np.all(np.isfinite(turns))
    y0, turns0 = out.unwrap(t[:0], col[:0], fine[:0], _UNWRAP_LIMIT, _MAX_BISECTIONS, _SHORTEST)
    assert y0.shape == (0, 11) and turns0.shape == (2, 0)  # no points: nothing read, nothing written
    with pytest.raises(ValueError, match="col: a lane out of range"):
        out.unwrap(t, col + WIDTH, fine, _UNWRAP_LIMIT, _MAX_BISECTIONS, _SHORTEST)
    with pytest.raises(ValueError, match="fine"):
        out.unwrap(t, col, fine[:-1], _UNWRAP_LIMIT, _MAX_BISECTIONS, _SHORTEST)
    with pytest.raises(ValueError, match="max_bisections"):
        out.unwrap(t, col, fine, _UNWRAP_LIMIT, -1, _SHORTEST)
    with pytest.raises(ValueError, match="out"):
        _dense.turns(out.tcs, out.times, t, col.astype(np.int64), y, fine, _UNWRAP_LIMIT, 4, _SHORTEST,
                     np.empty((2, t.size), np.float32))
