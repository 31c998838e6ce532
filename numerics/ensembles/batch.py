"""Direct runs in the lanes of heyoka's batch integrator: several runs integrated at once by one vectorised Taylor
integrator (heyoka's batch mode), each run with its own body, initial state and final time.

:func:`run_batch` gives what :func:`rocknroller.numerics.integrate.simulate` gives with ``samples=False`` (a
:class:`~rocknroller.numerics.trajectory.TurningPointRun`: every turning point of θ, φ and ψ unwrapped, the largest
energy error), by the same steps after the integrator's: the same check and location of the turning points on the
dense output (:mod:`rocknroller.numerics.events`), the same unwrapping grid and the same energy check
(``integrate._grid_pieces``, ``integrate._RunRecord``).  What differs is the integrator: heyoka's batch integrator
takes the steps of each lane by the scalar integrator's rule, but in SIMD registers, so a lane's results differ from
the scalar integrator's in the last bits, which the motion then amplifies (the bound is derived in
``tests/numerics/ensembles/test_batch.py``); and its dense output is evaluated at the (time, lane) pairs asked, in C
(``_dense.c``), at times within half an ulp of heyoka's own evaluation's (``tests/numerics/ensembles/test_dense.py``).
Every lane's events and turning points are worked on together, one numpy pass per stretch for all lanes
(``BATCH_CHUNK_RADIANS``); the unwrapping's refinement and turns in C too, each lane's points in one pass, the same
turns as the numpy unwrapping's bit for bit (``_dense.c``, ``tests/numerics/ensembles/test_turns.py``).  A lane's
results do not depend on the other lanes (each lane has its own time, step size, events and stretches, and its
stretches are set by its own rate bound, not by the width): the same job
gives the same results bit for bit in any lane, any batch and at any width from 2 to ``MAX_LANES`` (tested at
2, 4, 8 and 16).  Width 1 is not a batch: heyoka compiles it as scalar code, whose results differ in the last bits,
so a batch has at least ``MIN_LANES`` = 2 lanes.

The body's parameters are runtime parameters of the compiled system, so one batch holds jobs with different bodies;
its tolerance (:mod:`rocknroller.numerics.run_limits`) is the integrator's, so one batch holds jobs at one tolerance.
The integrator is compiled once per process, width and tolerance and kept in heyoka's disk cache like the scalar one
(:func:`rocknroller.numerics.integrate.heyoka_integrator`), and copied for each thread.
"""

from __future__ import annotations

import copy
import ctypes
import os
import platform
import threading
from typing import Any, Sequence

import numpy as np
from numpy.typing import NDArray

from rocknroller.analysis.model.body import Body, LoadedSphere
from rocknroller.analysis.model.equations import STATE_SIZE, EulerState, body_frame_rhs, turning_point_function
from rocknroller.numerics.backends import check_params
from rocknroller.numerics.cache import compiling
from rocknroller.numerics.ensembles import _dense
from rocknroller.numerics.events import _turning_points_lanes, start_turning_point
from rocknroller.numerics.integrate import (CHUNK_RADIANS, DT_RADIANS, _grid_pieces, _RunRecord, _stretch_end,
                                            check_diskcache, check_run, finish_run)
from rocknroller.numerics.run_limits import DEFAULT_TOL, check_tol
from rocknroller.numerics.trajectory import TurningPointRun, _Samples

__all__ = ["batch_width", "batch_integrator", "run_batch", "MIN_LANES", "MAX_LANES", "BATCH_CHUNK_RADIANS",
           "MALLOC_MMAP_THRESHOLD", "MALLOC_TRIM_THRESHOLD"]

#: Fewest lanes of a batch integrator (module docstring).
MIN_LANES = 2
#: Most lanes of a batch integrator (its stretches hold width × ``BATCH_CHUNK_RADIANS`` steps of dense output,
#: ≈ 1.8 kB per step and lane: 36 MB at 16 lanes).
MAX_LANES = 16
#: Radians of Λ integrated per stretch of each lane: a quarter of the scalar path's ``CHUNK_RADIANS``, so that the
#: dense output of a stretch of 8 lanes (the widest heyoka recommends), ≈ 18 MB and at most 1.5 × that, stays below
#: glibc's largest mmap threshold (32 MB) and is reused from the heap (``CHUNK_RADIANS``).  Measured on
#: benchmarks/bench_ensemble.py's 64 jobs (1000 time units, 8 lanes), with the unwrapping in C: 1.2× faster per
#: trajectory than an eighth (twice the stretches, each with its fixed cost of heyoka's dense output and of the
#: bookkeeping), 1.3× faster than a half (mapped fresh).  Fixed, not divided by the width: a lane's stretches, and so
#: its steps, are the same at every width.
BATCH_CHUNK_RADIANS = CHUNK_RADIANS / 4
#: glibc's malloc thresholds fixed at the first batch run of a process (:func:`_steady_malloc`): allocations below
#: 32 MiB come from the heap (glibc's largest dynamic mmap threshold on 64 bits, DEFAULT_MMAP_THRESHOLD_MAX), and
#: its top is returned to the system only past 128 MiB free: twice the most a stretch's dense output takes on the heap
#: while it grows (a doubling series of blocks below 32 MiB sums to under 64 MiB).
MALLOC_MMAP_THRESHOLD = 32 * 2**20
MALLOC_TRIM_THRESHOLD = 128 * 2**20
_MALLOPT = {"M_TRIM_THRESHOLD": -1, "M_MMAP_THRESHOLD": -3}  # glibc's malloc.h
_MALLOC_ENVIRONMENT = ("MALLOC_MMAP_THRESHOLD_", "MALLOC_TRIM_THRESHOLD_")
_MALLOC_DONE = threading.Event()
_TEMPLATES: dict[tuple[int, float, int], Any] = {}
_TEMPLATE_LOCK = threading.Lock()
_PER_THREAD = threading.local()


def batch_width() -> int:
    """The batch width heyoka recommends for this CPU (``heyoka.recommended_simd_size()``: 8 with AVX-512, 4 with
    AVX2), within [``MIN_LANES``, ``MAX_LANES``]."""
    import heyoka as hy

    return max(MIN_LANES, min(int(hy.recommended_simd_size()), MAX_LANES))


def _steady_malloc() -> None:
    """Fix glibc's malloc thresholds at ``MALLOC_MMAP_THRESHOLD`` and ``MALLOC_TRIM_THRESHOLD``, once per process,
    unless the environment sets them (``MALLOC_MMAP_THRESHOLD_``, ``MALLOC_TRIM_THRESHOLD_``, or ``GLIBC_TUNABLES``'s
    ``glibc.malloc.mmap_threshold``, ``glibc.malloc.trim_threshold``) or the C library is not glibc.

    A stretch's dense output is heyoka's: a vector grown by doubling to ≈ 30 MB at 8 lanes (``BATCH_CHUNK_RADIANS``),
    freed when the stretch is done.  With glibc's dynamic thresholds the heap's top is returned to the system when
    more than twice the last freed mapping is free, which such a series reaches or not depending on what else the
    process holds, and the next stretch then maps its memory afresh, a page fault per 4 kB: measured on
    benchmarks/bench_ensemble.py's 64 jobs, the same lanes took 4.8-5.2 ms of CPU per trajectory in one process and
    7.6-8.1 ms in another, the difference all system time, ≈ 1600 page faults per trajectory against ≈ 50.  With the
    thresholds fixed every stretch after the first reuses the heap (tests/numerics/ensembles/test_malloc.py).  The
    cost: a process keeps up to ``MALLOC_TRIM_THRESHOLD`` of freed heap instead of returning it."""
    if _MALLOC_DONE.is_set():
        return
    _MALLOC_DONE.set()
    tunables = os.environ.get("GLIBC_TUNABLES", "")
    if platform.libc_ver()[0] != "glibc" or any(name in os.environ for name in _MALLOC_ENVIRONMENT) or \
            any(f"glibc.malloc.{name}=" in tunables for name in ("mmap_threshold", "trim_threshold")):
        return
    mallopt = ctypes.CDLL(None).mallopt
    mallopt(_MALLOPT["M_TRIM_THRESHOLD"], MALLOC_TRIM_THRESHOLD)
    mallopt(_MALLOPT["M_MMAP_THRESHOLD"], MALLOC_MMAP_THRESHOLD)


class _BatchLog:
    """Non-terminal batch event callback: records (time, direction, lane) of each turning point."""

    def __init__(self) -> None:
        self.events: list[tuple[float, int, int]] = []

    def __call__(self, ta: Any, time: float, d_sgn: int, lane: int) -> None:
        self.events.append((time, d_sgn, lane))  # heyoka passes a float and two ints


def _check_width(width: Any) -> int:
    if isinstance(width, bool) or not isinstance(width, (int, np.integer)) or not MIN_LANES <= width <= MAX_LANES:
        raise ValueError(f"width must be a whole number in [{MIN_LANES}, {MAX_LANES}] (MIN_LANES, MAX_LANES), got "
                         f"width={width!r}")
    return int(width)


def batch_integrator(width: int, tol: float = DEFAULT_TOL, n_par: int = 5) -> Any:
    """The compiled batch integrator of form (i) with ``width`` lanes at tolerance ``tol``
    (:func:`rocknroller.numerics.run_limits.check_tol`) for ``n_par`` runtime parameters (5 for a Body, 7 for a
    LoadedSphere, :func:`~rocknroller.numerics.backends.check_params`): compiled once per process, width, tolerance
    and parameter count (from heyoka's disk cache when it holds it), one copy per thread (as
    :func:`rocknroller.numerics.integrate.heyoka_integrator`)."""
    key = (_check_width(width), check_tol(tol), check_params(n_par))
    mine = _PER_THREAD.__dict__.setdefault("integrators", {})
    if key not in mine:
        with _TEMPLATE_LOCK:
            if key not in _TEMPLATES:
                _TEMPLATES[key] = _build(*key)
            mine[key] = copy.deepcopy(_TEMPLATES[key])
    return mine[key]


def _build(width: int, tol: float, n_par: int) -> Any:
    import heyoka as hy

    check_diskcache()
    y = hy.make_vars("g1", "g2", "g3", "w1", "w2", "w3", "x1", "x2", "x3", "X", "Y")
    pars = [hy.par[i] for i in range(n_par)]
    ev = hy.nt_event_batch(turning_point_function(y), _BatchLog())
    general = "" if n_par == 5 else ", general loaded sphere"
    with compiling(f"the ensembles' batch integrator ({width} lanes{general})", 6.0):
        return hy.taylor_adaptive_batch(list(zip(y, body_frame_rhs(y, pars))), np.zeros((STATE_SIZE, width)),
                                        pars=np.zeros((n_par, width)), nt_events=[ev], tol=tol)


class _Lane:
    """One run in a lane: its plan, its turning points so far, its own stretch."""

    def __init__(self, body: Body | LoadedSphere, initial: EulerState, t_end: float, tol: float) -> None:
        plan = check_run(body, initial, t_end, samples=False, tol=tol)
        self.body, self.initial, self.t_end, self.dt = body, initial, plan.t_end, plan.dt
        self.y0 = plan.y0
        self.stretch = max(BATCH_CHUNK_RADIANS / plan.rate, plan.dt)
        self.fine = DT_RADIANS / plan.rate  # where the unwrapping's rate test stops, as simulate's
        self.start = start_turning_point(body, plan.y0)
        self.record = _RunRecord(body, plan.y0)
        self.t_a, self.n_steps = 0.0, 0


def run_batch(runs: Sequence[tuple[Body | LoadedSphere, EulerState, float]], width: int | None = None, *,
              tol: float = DEFAULT_TOL) -> list[TurningPointRun]:
    """Integrate up to ``width`` runs at once in the lanes of heyoka's batch integrator, turning points only.

    Parameters
    ----------
    runs : sequence of tuple
        (body, initial state, final time) of each run, at most ``width`` of them, each within the limits of
        ``simulate(..., samples=False)`` (checked first).
    width : int, optional
        Lanes of the integrator, in [``MIN_LANES``, ``MAX_LANES``] (default :func:`batch_width`); lanes beyond the
        runs idle.
    tol : float
        The integrator's tolerance, in [ε, ``TOL_MAX``] (default ε, heyoka's; :mod:`rocknroller.numerics.run_limits`).

    Returns
    -------
    list of TurningPointRun
        One per run, in order: what ``simulate(body, initial, t_end, samples=False, tol=tol)`` returns, to the batch
        integrator's rounding (module docstring); an :class:`~rocknroller.numerics.integrate.AccuracyWarning` for a
        run whose energy error exceeds its bound.

    Raises
    ------
    ValueError
        A run outside ``simulate``'s limits, more runs than lanes, a width or ``tol`` out of range (before any
        work); a run whose θ-maxima fall below ``THETA_MIN`` (at ``tol``, ``theta_min(tol)``; after it).
    """
    width = batch_width() if width is None else _check_width(width)
    tol = check_tol(tol)
    if not 1 <= len(runs) <= width:
        raise ValueError(f"runs: between 1 and width = {width} runs per batch, got {len(runs)}")
    lanes = [_Lane(body, initial, t_end, tol) for body, initial, t_end in runs]
    n_par = {len(lane.body.params) for lane in lanes}
    if len(n_par) != 1:
        raise ValueError("runs: one batch holds bodies of one kind only, all Body (the mass centre on the third axis) "
                         "or all LoadedSphere (run_ensemble groups them)")
    _steady_malloc()
    ta = batch_integrator(width, tol, n_par.pop())
    ta.set_time(0.0)
    idle = lanes[0]  # lanes beyond the runs hold a copy of the first and never move
    ta.state[:] = np.stack([(lanes[j] if j < len(lanes) else idle).y0 for j in range(width)], axis=1)
    ta.pars[:] = np.stack([np.asarray((lanes[j] if j < len(lanes) else idle).body.params, float)
                           for j in range(width)], axis=1)
    log = ta.nt_events[0].callback
    t_now = np.zeros(width)
    while any(lane.t_a < lane.t_end for lane in lanes):
        moving = [j for j, lane in enumerate(lanes) if lane.t_a < lane.t_end]
        t_b = t_now.copy()
        for j in moving:
            t_b[j] = _stretch_end(lanes[j].t_a, lanes[j].t_end, lanes[j].stretch)
        log.events.clear()
        c_out = _LaneOutput(ta.propagate_until(t_b, c_output=True)[0])
        for j in moving:
            outcome, _, _, n = ta.propagate_res[j]
            if outcome.name != "time_limit":
                raise RuntimeError(f"heyoka stopped early at t={float(ta.time[j])!r} in lane {j}: {outcome}")
            lanes[j].n_steps += int(n)
        _stretch_samples(lanes, moving, c_out, t_b, log.events)
        del c_out  # freed before the next stretch's is allocated, so that its memory is reused (CHUNK_RADIANS)
        for j in moving:
            lanes[j].record.end_stretch()
            lanes[j].t_a = float(t_b[j])
        t_now = t_b
    return [finish_run(lane.record.result("heyoka", lane.t_end, lane.n_steps, tol), lane.initial, strict=False,
                       tol=tol) for lane in lanes]


class _LaneOutput:
    """A stretch's batch dense output (heyoka's ``continuous_output_batch``), evaluated at the (time, lane) pairs
    asked and only those (:meth:`points`, C source ``_dense.c``; a
    ``events._PointDense``)."""

    def __init__(self, c_out: Any) -> None:
        self._c_out = c_out  # owns the arrays below
        self.tcs, self.times = c_out.tcs, c_out.times

    def points(self, t: NDArray[np.float64], col: NDArray[np.intp]) -> NDArray[np.float64]:
        """The states (m, 11) at times ``t`` (m,) of lanes ``col`` (m,)."""
        out = np.empty((np.size(t), STATE_SIZE))
        _dense.states(self.tcs, self.times, np.ascontiguousarray(t, float), np.ascontiguousarray(col, np.int64), out)
        return out

    def unwrap(self, t: NDArray[np.float64], col: NDArray[np.intp], fine: NDArray[np.float64], limit: float,
               max_bisections: int, shortest: float) -> tuple[NDArray[np.float64], NDArray[np.float64]]:
        """The states (m, 11) at times ``t`` (m,) of lanes ``col`` (m,) and the whole turns (2, m) of φ and ψ since
        each lane's first point (``events._PointDense.unwrap``)."""
        t, col = np.ascontiguousarray(t, float), np.ascontiguousarray(col, np.int64)
        y, out = self.points(t, col), np.empty((2, t.size))
        _dense.turns(self.tcs, self.times, t, col, y, np.ascontiguousarray(fine, float), float(limit),
                     int(max_bisections), float(shortest), out)
        return y, out


def _stretch_samples(lanes: list[_Lane], moving: list[int], c_out: _LaneOutput, t_b: NDArray[np.float64],
                     raw: list[tuple[float, int, int]]) -> None:
    """Locate the turning points of each moving lane's stretch and sample its unwrapping grid, all lanes evaluated
    together on the batch dense output."""
    logged = np.array(raw, float).reshape(-1, 3)  # (time, direction, lane)
    logged = logged[np.argsort(logged[:, 2], kind="stable")]
    ends = np.searchsorted(logged[:, 2], moving, "left"), np.searchsorted(logged[:, 2], moving, "right")
    found = _turning_points_lanes([logged[a:b, :2] for a, b in zip(*ends)],
                                  [lanes[j].t_a for j in moving], [float(t_b[j]) for j in moving], c_out, moving,
                                  t_b, [lanes[j].body.params for j in moving],
                                  [lanes[j].start if lanes[j].t_a == 0.0 else None for j in moving])
    pieces = {j: _grid_pieces(lanes[j].t_a, float(t_b[j]), lanes[j].dt, events) for j, events in zip(moving, found)}
    for k in range(max(len(p) for p in pieces.values())):
        here = [j for j in moving if k < len(pieces[j])]
        samples = _Samples.take_lanes(c_out, [pieces[j][k] for j in here], here, t_b,
                                      [lanes[j].record.start for j in here], [lanes[j].fine for j in here])
        for j, smp in zip(here, samples):
            lanes[j].record.add(smp)
