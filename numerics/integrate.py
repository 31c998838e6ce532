"""simulate(): integrate the direct equations of motion (form (i)) and locate every turning point of θ.

Backends
--------
``heyoka`` (default)
    heyoka's adaptive Taylor integrator at tolerance ``tol`` (default machine epsilon;
    :mod:`rocknroller.numerics.run_limits`).  The body parameters are
    runtime parameters, so one compiled integrator serves every body.  It is built once per process and
    copied once per thread (the same machine code, so every thread gives the same results bit for bit);
    heyoka's own on-disk JIT cache (heyoka ≥ 7.10, ``HEYOKA_CACHE_DIR``, process-safe) makes a build
    after the first one on a machine take a fraction of a second instead of ~6 s.  Nothing is
    unpickled from disk (a cache heyoka cannot use is switched off for the process, with one
    :class:`CacheWarning`, so that heyoka logs nothing on stdout).  Turning points are non-terminal events on
    dγ3/dt = 0.  ``precision="extended"`` uses 80-bit long double (x86-64), for reference runs.
``scipy``
    scipy's DOP853 on the same right-hand side with a numpy implementation, as an independent check.

Turning points
--------------
The integrator's events are checked against the sign of dγ3/dt on the dense output between them and located
there (a safeguarded Newton method, to the rounding of t); an interval where the check fails is scanned on the
dense output (``_turning_points``: near the pole heyoka's event polynomial misplaces, repeats or drops a root at the
end of a step).  A start that is itself a turning point to its rounding (:func:`start_turning_point`) is not
reported.  Motions whose tilt stays below ``THETA_MIN`` = 2¹⁰ u ≈ 1.1e-13 rad are refused: there the state's
round-off is no longer small against the tilt (before the run when the energy confines the tilt, else after it).

Limits (checked before any work; a ``ValueError`` names the parameter and the limit)
--------------------------------------------------------------------------------------
The work and memory of a run scale with Λ·t_end, where Λ = √(2(E + g a)/I_min) bounds the angular
speed for all time (T ≥ ½ I_min |ω|² and T = E − V ≤ E) and the rocking rate; the integrator takes
about one step per radian of Λ t (0.8 measured on the paper's runs).

* ``MAX_SAMPLES`` output samples t_end/dt (each costs ≈ 0.5 kB with its derived series);
* ``MAX_DENSE_RADIANS`` of Λ·t_end when samples are kept: the trajectory keeps the integrator's dense
  output (≈ 1.8 kB of Taylor coefficients per step) — a hard cap of ``MAX_DENSE_STEPS`` steps is also
  enforced while integrating;
* ``MAX_RADIANS`` of Λ·t_end for any run (``samples=False`` streams the turning points, so only time
  grows: about 3 s per 10⁶ radians here), and with ``samples=False`` at most ``MAX_GRID_POINTS`` points
  t_end/dt of the grid on which the angles are unwrapped (≈ 0.3 µs each; the grid is not kept, but sampled in
  pieces of ``GRID_CHUNK_POINTS``: with ``samples=False`` a run holds one stretch's dense output, ≈ 9 MB, one piece
  of the grid, ≤ ``GRID_CHUNK_POINTS`` × ``GRID_BYTES_PER_POINT`` = 16 MB, and its turning points, whatever dt).

A start without motion is refused: at rest in an equilibrium, or with Λ = 0 (no gravity, a = 0, and rates so
small that the kinetic energy underflows to 0).

Accuracy ranges (dimensionless, unit mass and radius; outside them the run is refused)
--------------------------------------------------------------------------------------
* moments I1, I2, I3 in ``MOMENT_RANGE`` = [1e-3, 1e3]: the mass matrix K = diag(I) + |r|² − r rᵀ has
  condition number ≈ (1 + a)²/I_min, and the energy error grows as 1/I_min (measured over 100 time
  units: 6e-16 at I ~ 0.4, 4e-14 at 4e-4, 3e-11 at 4e-7, 3e-9 at 4e-9);
* g = 0 or g in ``G_RANGE`` = [1e-12, 1e12]: g only sets the unit of time, but products of g with the rates
  squared must stay far from overflow and underflow;
* E/g ≤ ``MAX_ENERGY_OVER_G`` = 1e12 (the energy in units of m g R), for the same reason; without gravity (g = 0)
  the energy alone sets the unit of time, and E must lie in ``ENERGY_RANGE_NO_GRAVITY`` = [1e-12, 1e12] (units of
  m R² per unit time squared: the rates squared, |ω|² ~ 2E/I, stay far from overflow and underflow);
* the amplitude of θ at least ``THETA_MIN`` (see "Turning points").

Every run's energy error is checked against the tolerance asked for
(:func:`rocknroller.numerics.run_limits.energy_error_bound`): a run that misses it warns
(:class:`AccuracyWarning`), or raises :class:`AccuracyError` with ``strict=True``.
"""

from __future__ import annotations

import math
import sys
import warnings
from typing import Callable, Literal, TypeVar, overload

import numpy as np
from numpy.typing import NDArray

from rocknroller.analysis.model.body import Body, LoadedSphere
from rocknroller.analysis.model.equations import EulerState
from rocknroller.analysis.model.invariants import energy
from rocknroller.numerics.backends import _PRECISIONS, _HeyokaRun, _ScipyRun, check_diskcache, heyoka_integrator
from rocknroller.numerics.budget import (DOP853_SECONDS_PER_RADIAN, HEYOKA_EXTENDED_SECONDS_PER_RADIAN,
                                         HEYOKA_SECONDS_PER_RADIAN, WORK_BUDGET_SECONDS, check_work)
from rocknroller.numerics.cache import CacheWarning, cache_dir  # re-exported
from rocknroller.numerics.events import THETA_MIN
from rocknroller.numerics.run_limits import (DEFAULT_TOL, DT_RADIANS, ENERGY_RANGE_NO_GRAVITY,  # re-exported
                                             G_RANGE, MAX_DENSE_RADIANS, MAX_DENSE_STEPS, MAX_ENERGY_OVER_G,
                                             MAX_GRID_POINTS, MAX_RADIANS, MAX_SAMPLES, MOMENT_RANGE, UNWRAP_RADIANS,
                                             RunPlan, _theta_min_name, check_run, check_tol, default_dt, rate_bound,
                                             theta_min)
from rocknroller.numerics.run_limits import ENERGY_BOUND_MAX, energy_error_bound, energy_scale
from rocknroller.numerics.trajectory import Trajectory, TurningPointRun, TurningPoints, _Samples

__all__ = [
    "simulate", "check_run", "finish_run", "check_energy_error", "check_theta_resolved", "check_diskcache", "RunPlan", "heyoka_integrator", "default_dt", "cache_dir", "rate_bound", "AccuracyWarning",
    "AccuracyError", "CacheWarning", "MAX_SAMPLES", "MAX_DENSE_RADIANS", "MAX_DENSE_STEPS", "MAX_RADIANS",
    "MAX_GRID_POINTS", "GRID_CHUNK_POINTS", "UNWRAP_RADIANS", "DT_RADIANS", "GRID_BYTES_PER_POINT", "MOMENT_RANGE",
    "G_RANGE", "MAX_ENERGY_OVER_G", "ENERGY_RANGE_NO_GRAVITY"
]

_METHODS = ("heyoka", "scipy")

#: Radians of Λ integrated per stretch when only the turning points are kept (≈ 5·10³ steps, ≈ 9 MB of dense output).
#: Below glibc's largest mmap threshold (32 MB) a stretch's buffers, freed, are reused by the next: at 2·10⁴ radians
#: (≈ 36 MB) each stretch mapped fresh pages, 10 % of a long run's CPU in page faults (measured;
#: benchmarks/bench_long_run.py counts them).
CHUNK_RADIANS = 5.0e3
#: Most points of the unwrapping grid sampled at once with ``samples=False`` (pieces of a stretch's grid): at most
#: ``GRID_CHUNK_POINTS`` × ``GRID_BYTES_PER_POINT`` = 16 MB of arrays, whatever dt (its largest array, the states,
#: 1.4 MB: reused from the heap, as the stretch's).
GRID_CHUNK_POINTS = 2**14
#: Bound on the bytes of numpy arrays alive per point of a piece of the grid: the states (88 bytes), their angles,
#: the unwrapping steps and the temporaries of E, measured at a peak of 0.47 kB per point (tracemalloc); × 2 for
#: the points the unwrapping inserts near passages through the pole.
GRID_BYTES_PER_POINT = 1024


class AccuracyWarning(UserWarning):
    """A run's energy error exceeds what its integrator's tolerance allows.

    Examples
    --------
    >>> import math
    >>> import rocknroller as rr
    >>> body = rr.Body.paper(epsilon=1e-3)
    >>> start = rr.EulerState.from_omega(0.95 * math.pi, 0.0, 0.0, (0.0, 1e-3, -1e-3))
    >>> import warnings
    >>> with warnings.catch_warnings():
    ...     warnings.simplefilter("error", rr.AccuracyWarning)
    ...     run = rr.simulate(body, start, 60.0, samples=False)
    ...
    >>> issubclass(rr.AccuracyWarning, UserWarning)
    True
    """


class AccuracyError(RuntimeError):
    """A run's energy error exceeds what its integrator's tolerance allows (``strict=True``).

    Examples
    --------
    >>> import math
    >>> import rocknroller as rr
    >>> body = rr.Body.paper(epsilon=1e-3)
    >>> start = rr.EulerState.from_omega(0.95 * math.pi, 0.0, 0.0, (0.0, 1e-3, -1e-3))
    >>> run = rr.simulate(body, start, 60.0, samples=False, strict=True)
    >>> issubclass(rr.AccuracyError, RuntimeError)
    True
    """



def _progress(total: float, enabled: bool | None):
    from tqdm import tqdm

    if enabled is None:
        enabled = sys.stderr.isatty()
    return tqdm(total=total, disable=not enabled, unit="t.u.", leave=False, file=sys.stderr,
                bar_format="{l_bar}{bar}| {n:.4g}/{total:.4g} time units [{elapsed}<{remaining}]")



def check_energy_error(err: float, n_steps: int, tolerance: float, strict: bool, what: str = "",
                       stacklevel: int = 2) -> None:
    """Warn (:class:`AccuracyWarning`), or raise :class:`AccuracyError` with ``strict``, if a run's relative energy
    error ``err`` exceeds what ``n_steps`` steps at ``tolerance`` allow (:func:`energy_error_bound`), or if that bound
    exceeds ``ENERGY_BOUND_MAX``, where the check can no longer tell an accurate run from a wrong one; ``what`` names
    where it was measured; ``stacklevel`` counts from the caller of this function."""
    bound = energy_error_bound(tolerance, n_steps)
    if bound > ENERGY_BOUND_MAX:
        msg = (f"the energy check cannot vouch for this run: {n_steps} steps at tolerance {tolerance:.3g} allow a "
               f"relative energy error of {bound:.3g}, over {ENERGY_BOUND_MAX:g} (measured {err:.3g}{what}); lower "
               "the tolerance or shorten the run")
        if strict:
            raise AccuracyError(msg)
        warnings.warn(msg, AccuracyWarning, stacklevel=stacklevel + 1)
    elif err > bound:
        msg = (f"the relative energy error {err:.3g}{what} exceeds {bound:.3g}, the most that {n_steps} steps at "
               f"tolerance {tolerance:.3g} allow: the run is not accurate")
        if strict:
            raise AccuracyError(msg)
        warnings.warn(msg, AccuracyWarning, stacklevel=stacklevel + 1)


def check_theta_resolved(theta_maxima: NDArray[np.float64], initial: EulerState, tol: float = DEFAULT_TOL) -> None:
    """Refuse a motion near the pole that the energy did not confine there: θ-maxima below ``THETA_MIN`` (at
    tolerance ``tol``, :func:`rocknroller.numerics.run_limits.theta_min`), where the integrator does not resolve the
    turning points (:mod:`rocknroller.numerics.events`)."""
    lowest = theta_min(tol)
    if np.any(theta_maxima < lowest):
        raise ValueError(f"theta0={initial.theta!r}: theta has maxima as small as {theta_maxima.min():.3g} "
                         f"rad, below {_theta_min_name(lowest)} = {lowest:.3g} rad, the smallest amplitude at which "
                         f"the integrator resolves the turning points of theta; give theta0 >= {lowest:.3g}")


#: The ``on_turning_points`` callback of :func:`simulate`.
_TurningPointsCallback = Callable[[TurningPoints, TurningPoints], None]


# The result's type follows ``samples`` (a Trajectory with samples, a TurningPointRun without), for type checkers.
@overload
def simulate(body: Body | LoadedSphere, initial: EulerState, t_end: float, *, method: str = ..., dt: float | None = ...,
             precision: str = ..., tol: float | None = ..., rtol: float = ..., atol: float = ...,
             progress: bool | None = ...,
             samples: Literal[True] = ..., on_turning_points: _TurningPointsCallback | None = ...,
             strict: bool = ...) -> Trajectory: ...
@overload
def simulate(body: Body | LoadedSphere, initial: EulerState, t_end: float, *, method: str = ..., dt: float | None = ...,
             precision: str = ..., tol: float | None = ..., rtol: float = ..., atol: float = ...,
             progress: bool | None = ...,
             samples: Literal[False], on_turning_points: _TurningPointsCallback | None = ...,
             strict: bool = ...) -> TurningPointRun: ...
@overload
def simulate(body: Body | LoadedSphere, initial: EulerState, t_end: float, *, method: str = ..., dt: float | None = ...,
             precision: str = ..., tol: float | None = ..., rtol: float = ..., atol: float = ...,
             progress: bool | None = ...,
             samples: bool = ..., on_turning_points: _TurningPointsCallback | None = ...,
             strict: bool = ...) -> Trajectory | TurningPointRun: ...


def simulate(body: Body | LoadedSphere, initial: EulerState, t_end: float, *, method: str = "heyoka", dt: float | None = None,
             precision: str = "double", tol: float | None = None, rtol: float = 3e-14, atol: float = 1e-15,
             progress: bool | None = False, samples: bool = True,
             on_turning_points: Callable[[TurningPoints, TurningPoints], None] | None = None,
             strict: bool = False, budget: float | None = WORK_BUDGET_SECONDS) -> Trajectory | TurningPointRun:
    """Integrate the rock'n'roller from ``initial`` over [0, t_end] and find every turning point of θ.

    Parameters
    ----------
    body : Body
        Moments in ``MOMENT_RANGE``, g in ``G_RANGE`` (see the module docstring).
    initial : EulerState
        Initial Euler angles and rates (``EulerState.from_omega`` for a body-frame ω); energy at most
        ``MAX_ENERGY_OVER_G`` · g.  A body at rest in an equilibrium is refused (no motion).
    t_end : float
        Final time, > 0, with Λ·t_end ≤ ``MAX_RADIANS`` (≤ ``MAX_DENSE_RADIANS`` when samples are kept).
    method : {"heyoka", "scipy"}
        Taylor integrator (default) or DOP853 (independent check).
    dt : float, optional
        Spacing of the output grid (default :func:`default_dt`), at most ``MAX_SAMPLES`` samples; turning
        points are always added.  With ``samples=False``, the spacing of the grid on which φ and ψ are
        unwrapped and the energy is checked (default ``UNWRAP_RADIANS``/Λ).
    precision : {"double", "extended"}
        heyoka only: 64-bit or 80-bit floating point.
    tol : float, optional
        heyoka only: the integrator's tolerance, in [ε, ``TOL_MAX`` = 1e-6] with ε the machine epsilon of
        ``precision`` (default None: ε, heyoka's default).  It sets the Taylor order, the energy check and the
        smallest tilt resolved (:mod:`rocknroller.numerics.run_limits`); 1e-11 gives DOP853's best energy error.
    rtol, atol : float
        scipy only: DOP853 tolerances.
    progress : bool or None
        Show a tqdm bar on stderr (None: only if stderr is a terminal).
    samples : bool
        True: return a :class:`Trajectory` with every sample.  False: integrate stretch by stretch and
        keep only the turning points (a :class:`TurningPointRun`); memory then does not grow with t_end
        beyond the turning points themselves (≈ 0.2 kB each).
    on_turning_points : callable, optional
        With ``samples=False``: called with (maxima, minima) of each stretch as it is finished (to stream them).
    strict : bool
        Raise :class:`AccuracyError` instead of warning when the energy error exceeds
        :func:`rocknroller.numerics.run_limits.energy_error_bound`.
    budget : float or None
        CPU seconds the run may take (:mod:`rocknroller.numerics.budget`; None: no limit), estimated before it starts
        from Λ·t_end and the method's measured cost per radian: heyoka's longest run (``MAX_RADIANS``) stays within
        the default hour in double precision, not in extended (5.6× slower); DOP853 (~100× slower) past ~3.6e6
        radians does not.

    Returns
    -------
    Trajectory or TurningPointRun
        Turning points: maxima (dγ3/dt rising through 0) and minima (falling), none reported at t = 0 (a start with
        θ̇0 = 0 to its rounding is itself a turning point, :func:`start_turning_point`, and is not reported).

    Raises
    ------
    ValueError
        Naming the parameter: a limit or an accuracy range exceeded (:func:`check_run`), no motion, a tilt that stays
        below ``THETA_MIN``.

    Examples
    --------
    >>> import math
    >>> import rocknroller as rr
    >>> body = rr.Body.paper(epsilon=1e-3)
    >>> start = rr.EulerState.from_omega(0.95 * math.pi, 0.0, 0.0, (0.0, 1e-3, -1e-3))
    >>> traj = rr.simulate(body, start, 60.0)
    >>> print(len(traj.maxima.t), len(traj.minima.t), traj.energy_rel_error < 1e-12)
    4 5 True
    >>> print(f"{traj.maxima.theta[0] / math.pi:.6f} pi")
    0.949999 pi
    """
    if method not in _METHODS:
        raise ValueError(f"method must be one of {_METHODS}, got {method!r}")
    if precision not in _PRECISIONS:
        raise ValueError(f"precision must be one of {_PRECISIONS}, got {precision!r}")
    if method == "scipy" and precision != "double":
        raise ValueError("precision='extended' is available with method='heyoka' only")
    if tol is not None:
        if method == "scipy":
            raise ValueError(f"tol is heyoka's tolerance; method='scipy' takes rtol and atol, got tol={tol!r}")
        tol = check_tol(tol, "tol", float(np.finfo(float if precision == "double" else np.longdouble).eps))
    if method == "scipy" and not (0.0 < rtol < 1.0 and math.isfinite(atol) and atol > 0.0):
        raise ValueError(f"rtol must lie in (0, 1) and atol be > 0, got rtol={rtol!r}, atol={atol!r}")
    t_end, dt, n_grid, y0, rate = check_run(body, initial, t_end, dt=dt, samples=samples,
                                            tol=DEFAULT_TOL if tol is None else tol)
    per_radian = (DOP853_SECONDS_PER_RADIAN if method == "scipy" else HEYOKA_SECONDS_PER_RADIAN
                  if precision == "double" else HEYOKA_EXTENDED_SECONDS_PER_RADIAN)
    check_work(rate * t_end * per_radian, f"this run ({method}, {precision} precision, Λ t_end = {rate * t_end:.3g} "
               "radians)", budget)
    if on_turning_points is not None and samples:
        raise ValueError("on_turning_points streams the turning points of a run with samples=False")
    with _progress(t_end, progress) as bar:
        run: _HeyokaRun | _ScipyRun
        if method == "heyoka":
            run = _HeyokaRun(body, y0, precision, bar, MAX_DENSE_STEPS if samples else None, tol)
        else:
            run = _ScipyRun(body, y0, rtol, atol, bar)
        if samples:
            dense, events = run.advance(t_end)
            result: Trajectory | TurningPointRun = Trajectory.from_dense(
                body, method, dense, np.linspace(0.0, t_end, n_grid), [t for t, d in events if d > 0],
                [t for t, d in events if d < 0], n_steps=run.n_steps, tolerance=run.tolerance)
        else:
            result = _turning_points_only(body, method, run, y0, t_end, dt, rate, on_turning_points)
    return finish_run(result, initial, strict, DEFAULT_TOL if tol is None else tol)


_Run = TypeVar("_Run", bound=Trajectory | TurningPointRun)


def finish_run(result: _Run, initial: EulerState, strict: bool, tol: float = DEFAULT_TOL) -> _Run:
    """The checks after a run at heyoka's tolerance ``tol`` (default for scipy's): θ-maxima resolved
    (:func:`check_theta_resolved`), the energy error within its bound (:func:`check_energy_error`)."""
    check_theta_resolved(result.maxima.theta, initial, tol)
    check_energy_error(result.energy_rel_error, result.n_steps, result.tolerance, strict, stacklevel=3)
    return result


def _stretch_end(t_a: float, t_end: float, stretch: float) -> float:
    """The end of the stretch that starts at ``t_a``: ``stretch`` on, or ``t_end`` if that is within 1.5 stretches."""
    return t_end if t_end - t_a <= 1.5 * stretch else t_a + stretch


def _grid_pieces(t_a: float, t_b: float, dt: float,
                 events: list[tuple[float, int]]) -> list[tuple[NDArray, NDArray, NDArray]]:
    """The unwrapping grid of the stretch (t_a, t_b] (spacing ``dt``, as ``np.linspace`` computes it) in pieces of at
    most ``GRID_CHUNK_POINTS`` points that share their end points, each with its maxima and minima among ``events``
    (one on a shared end point is the earlier piece's)."""
    n = int(math.ceil((t_b - t_a) / dt - 1e-9)) + 1  # the points of np.linspace(t_a, t_b, n), piece by piece
    step = (t_b - t_a) / (n - 1)
    ev_t, ev_d = np.array([t for t, _ in events], float), np.array([d for _, d in events], int)
    pieces = []
    for k0 in range(0, n - 1, GRID_CHUNK_POINTS - 1):
        k1 = min(k0 + GRID_CHUNK_POINTS - 1, n - 1)
        grid = np.arange(k0, k1 + 1) * step + t_a  # as np.linspace computes it, its last point t_b exactly
        if k1 == n - 1:
            grid[-1] = t_b
        mine = slice(0 if k0 == 0 else np.searchsorted(ev_t, grid[0], "right"),
                     np.searchsorted(ev_t, grid[-1], "right"))
        t_ev, d_ev = ev_t[mine], ev_d[mine]
        pieces.append((grid, t_ev[d_ev > 0], t_ev[d_ev < 0]))
    return pieces


class _RunRecord:
    """The turning points and the largest energy error of a run with ``samples=False``, taken piece by piece of its
    unwrapping grid (:func:`_grid_pieces`), the angles unwrapped from one piece into the next."""

    def __init__(self, body: Body | LoadedSphere, y0: NDArray[np.float64]) -> None:
        self.body, self.E0 = body, float(energy(body, y0[0:3], y0[3:6]))
        self.worst = 0.0
        self.start: NDArray[np.float64] | None = None  # (φ, ψ) at the end of the last piece: its branch continues
        self.maxima: list[TurningPoints] = []
        self.minima: list[TurningPoints] = []
        self._parts: tuple[list[TurningPoints], list[TurningPoints]] = ([], [])

    def add(self, smp: _Samples) -> None:
        """One piece sampled (``_Samples.take`` or ``take_lanes``, from ``self.start``)."""
        self.start = smp.angles[1:, -1]
        self.worst = max(self.worst, float(np.max(np.abs(energy(self.body, smp.y[:, 0:3].T, smp.y[:, 3:6].T)
                                                         - self.E0))))
        self._parts[0].append(smp.turning(self.body, smp.i_max))
        self._parts[1].append(smp.turning(self.body, smp.i_min))

    def end_stretch(self) -> tuple[TurningPoints, TurningPoints]:
        """The maxima and minima of the pieces added since the last call."""
        mx, mn = (TurningPoints.concatenate(parts, self.body) for parts in self._parts)
        self._parts = ([], [])
        self.maxima.append(mx)
        self.minima.append(mn)
        return mx, mn

    def result(self, method: str, t_end: float, n_steps: int, tolerance: float) -> TurningPointRun:
        return TurningPointRun(body=self.body, method=method, t_end=t_end,
                               maxima=TurningPoints.concatenate(self.maxima, self.body),
                               minima=TurningPoints.concatenate(self.minima, self.body),
                               energy_rel_error=self.worst / energy_scale(self.body, self.E0), n_steps=n_steps,
                               tolerance=tolerance)


def _turning_points_only(body: Body | LoadedSphere, method: str, run: _HeyokaRun | _ScipyRun, y0: NDArray[np.float64],
                         t_end: float, dt: float, rate: float,
                         on_turning_points: Callable[[TurningPoints, TurningPoints], None] | None) -> TurningPointRun:
    """Integrate stretch by stretch (``CHUNK_RADIANS`` of Λ each), keep the turning points, drop the rest.

    Each stretch's grid (spacing ``dt``) is sampled in pieces of at most ``GRID_CHUNK_POINTS`` points that share
    their end points, the angles unwrapped from one piece into the next: the grid is never held whole.
    """
    record = _RunRecord(body, y0)
    stretch = max(CHUNK_RADIANS / rate, dt)
    t_a = 0.0
    while t_a < t_end:
        t_b = _stretch_end(t_a, t_end, stretch)
        dense, events = run.advance(t_b)
        for grid, t_max, t_min in _grid_pieces(t_a, t_b, dt, events):
            record.add(_Samples.take(dense, grid, t_max, t_min, record.start, DT_RADIANS / rate))
        mx, mn = record.end_stretch()
        if on_turning_points is not None:
            on_turning_points(mx, mn)
        t_a = t_b
    return record.result(method, t_end, run.n_steps, run.tolerance)
