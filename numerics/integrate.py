"""simulate(): integrate the direct equations of motion (form (i)) and locate every turning point of θ.

Backends
--------
``heyoka`` (default)
    heyoka's adaptive Taylor integrator at tolerance = machine epsilon.  The body parameters are
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
* g in ``G_RANGE`` = [1e-12, 1e12]: g only sets the unit of time, but products of g with the rates
  squared must stay far from overflow and underflow;
* E/g ≤ ``MAX_ENERGY_OVER_G`` = 1e12 (the energy in units of m g R), for the same reason;
* the amplitude of θ at least ``THETA_MIN`` (see "Turning points").

Every run's energy error is checked against the tolerance asked for
(:func:`rocknroller.numerics.trajectory.energy_error_bound`): a run that misses it warns
(:class:`AccuracyWarning`), or raises :class:`AccuracyError` with ``strict=True``.
"""

from __future__ import annotations

import copy
import math
import sys
import threading
import warnings
from typing import Any, Callable, Literal, NamedTuple, TypeVar, overload

import numpy as np
from numpy.typing import NDArray

from rocknroller.analysis.model.body import Body
from rocknroller.analysis.model.equations import STATE_SIZE, EulerState, body_frame_rhs, turning_point_function
from rocknroller.analysis.model.invariants import energy
from rocknroller.numerics.budget import (DOP853_SECONDS_PER_RADIAN, HEYOKA_EXTENDED_SECONDS_PER_RADIAN,
                                         HEYOKA_SECONDS_PER_RADIAN, WORK_BUDGET_SECONDS, check_work)
from rocknroller.numerics.cache import (CacheWarning, cache_dir, compiling, probe_writable,  # cache_dir: re-exported
                                        warn_unwritable)
from rocknroller.numerics.events import _U, THETA_MIN, _turning_points, start_turning_point
from rocknroller.numerics.trajectory import (DenseOutput, Trajectory, TurningPointRun, TurningPoints, _Samples,
                                             energy_error_bound, energy_scale)

__all__ = [
    "simulate", "check_run", "finish_run", "check_energy_error", "check_theta_resolved", "check_diskcache", "RunPlan", "heyoka_integrator", "default_dt", "cache_dir", "rate_bound", "AccuracyWarning",
    "AccuracyError", "CacheWarning", "MAX_SAMPLES", "MAX_DENSE_RADIANS", "MAX_DENSE_STEPS", "MAX_RADIANS",
    "MAX_GRID_POINTS", "GRID_CHUNK_POINTS", "UNWRAP_RADIANS", "DT_RADIANS", "GRID_BYTES_PER_POINT", "MOMENT_RANGE",
    "G_RANGE", "MAX_ENERGY_OVER_G"
]

_METHODS = ("heyoka", "scipy")
_PRECISIONS = ("double", "extended")
#: The integrator compiled once per process, per precision; never propagated itself, only copied.
_TEMPLATES: dict[str, Any] = {}
_TEMPLATE_LOCK = threading.Lock()
#: Each thread's own copies of the templates (a heyoka integrator must not be propagated by two threads at once).
_PER_THREAD = threading.local()

MAX_SAMPLES = 2_000_000
MAX_DENSE_RADIANS = 3.0e5
MAX_DENSE_STEPS = 600_000
MAX_RADIANS = 1.0e8
MAX_GRID_POINTS = 2.0e8
MOMENT_RANGE = (1e-3, 1e3)
G_RANGE = (1e-12, 1e12)
MAX_ENERGY_OVER_G = 1e12
#: Default output spacing in radians of Λ (≈ 0.05 time units for the paper's runs).
DT_RADIANS = 0.15
#: Default spacing, in radians of Λ, of the grid on which a run with ``samples=False`` unwraps φ and ψ and checks the
#: energy: ≈ 0.35 time units, ≈ 40 points per rocking period, for the paper's runs.  The unwrapping does not rest on
#: it: an interval over which an angle's rate at either end (φ̇, ψ̇ from the state, unbounded near the pole) would turn
#: it by 2π/3 is bisected down to the output grid's spacing ``DT_RADIANS``/Λ (:mod:`rocknroller.numerics.trajectory`),
#: so wherever the angles turn fast the grid is at least as fine as the one used before (issue 24), and the turning
#: points are the same to the bit (tests/numerics/test_batch.py); elsewhere 6.7× fewer points than ``DT_RADIANS``
#: cut a run's sampling by as much.
UNWRAP_RADIANS = 1.0
#: Radians of Λ integrated per stretch when only the turning points are kept (≈ 5·10³ steps, ≈ 9 MB of dense output).
#: Below glibc's largest mmap threshold (32 MB) a stretch's buffers, freed, are reused by the next: at 2·10⁴ radians
#: (≈ 36 MB) each stretch mapped fresh pages, 10 % of a long run's CPU in page faults (issue 25, item 18;
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
    """A run's energy error exceeds what its integrator's tolerance allows."""


class AccuracyError(RuntimeError):
    """A run's energy error exceeds what its integrator's tolerance allows (``strict=True``)."""


class _EventLog:
    """Non-terminal event callback: records (time, direction) of each turning point."""

    def __init__(self) -> None:
        self.events: list[tuple[float, int]] = []

    def __call__(self, ta: Any, time: Any, d_sgn: Any) -> None:
        self.events.append((float(time), int(d_sgn)))


def _build_heyoka(fp_type: Any) -> Any:
    import heyoka as hy

    names = ["g1", "g2", "g3", "w1", "w2", "w3", "x1", "x2", "x3", "X", "Y"]
    y = hy.make_vars(*names)
    pars = [hy.par[i] for i in range(5)]
    rhs = body_frame_rhs(y, pars)
    kwargs = {} if fp_type is float else {"fp_type": fp_type}
    ev = hy.nt_event(turning_point_function(y), _EventLog(), **kwargs)
    return hy.taylor_adaptive(list(zip(y, rhs)), np.zeros(STATE_SIZE, dtype=fp_type),
                              pars=np.zeros(5, dtype=fp_type), nt_events=[ev], **kwargs)


def heyoka_integrator(precision: str = "double") -> Any:
    """The compiled heyoka integrator of form (i): compiled once per process, one copy per thread.

    Every thread that calls this gets its own copy (made in about a millisecond), so :func:`simulate` may run in
    several threads at once; a copy runs the same machine code as the original, so a run gives the same result bit
    for bit in whichever thread it runs.  heyoka's on-disk JIT cache (``HEYOKA_CACHE_DIR``; default under the user
    cache directory) keeps the compiled code between processes; it holds machine code, so it must be as trusted as
    the installed packages.  An unwritable cache directory gives one :class:`CacheWarning` (each process then
    compiles for ~6 s).
    """
    if precision not in _PRECISIONS:
        raise ValueError(f"precision must be one of {_PRECISIONS}, got {precision!r}")
    mine = _PER_THREAD.__dict__.setdefault("integrators", {})
    if precision not in mine:
        with _TEMPLATE_LOCK:  # one compilation per process; copies are made from a template no thread propagates
            if precision not in _TEMPLATES:
                _TEMPLATES[precision] = _compile(precision)
            mine[precision] = copy.deepcopy(_TEMPLATES[precision])
    return mine[precision]


def _compile(precision: str) -> Any:
    """Build the integrator of ``precision`` (from heyoka's disk cache when it holds it), after checking that the
    cache can be used (:func:`check_diskcache`)."""
    check_diskcache()
    what, seconds = _COMPILE_NOTES[precision]
    with compiling(what, seconds):
        return _build_heyoka(float if precision == "double" else np.longdouble)


#: What :func:`_compile` compiles at each precision and the CPU seconds it usually takes (measured, one core).
_COMPILE_NOTES = {"double": ("the direct integrator (heyoka, double precision)", 5.0),
                  "extended": ("the direct integrator (heyoka, extended precision)", 18.0)}


def check_diskcache() -> None:
    """Check that heyoka's disk cache can be used before anything is compiled.

    A cache heyoka cannot use (a directory that cannot be written or created, a ``cache.db`` that is not a database)
    makes heyoka log a ``[warning]`` line on stdout at every lookup and insertion, where it would corrupt the
    JSON of ``rocknroller ... --json``.  Such a cache is switched off for this process instead (its warnings are then
    never logged), and one :class:`CacheWarning` says so.  heyoka's own logger is left as the user set it.
    """
    import heyoka as hy

    if hy.llvm_state.get_diskcache_enabled():
        path = hy.llvm_state.get_diskcache_path()
        error: BaseException | None = probe_writable(path)
        if error is None:
            try:
                hy.llvm_state.get_diskcache_size()  # opens the cache's database: raises if heyoka cannot use it
            except RuntimeError as exc:
                error = exc
        if error is not None:
            hy.llvm_state.set_diskcache_enabled(False)
            warn_unwritable(path, error, "heyoka's compilation cache is switched off, and every process compiles the "
                            "integrator (~6 s)",
                            fix="point HEYOKA_CACHE_DIR at a writable folder to keep heyoka's compilation cache")


def rate_bound(body: Body, y0: NDArray[np.float64]) -> float:
    """Λ = √(2(E + g a)/I_min): a bound on |ω(t)| for all t (½ I_min |ω|² ≤ T ≤ E) that also covers the
    rocking rate √(g a/I) of motions near rest.  Work and memory of a run scale with Λ·t_end."""
    E = float(energy(body, y0[0:3], y0[3:6]))
    return math.sqrt(2.0 * (E + body.g * body.a) / min(body.I1, body.I2, body.I3))


def default_dt(t_end: float, rate: float, samples: bool = True) -> float:
    """Default sample spacing: ``DT_RADIANS``/Λ (≈ 0.05 time units, ≈ 200 samples per rocking period, for
    the paper's runs), and at least 200 samples over the run (a t_end so small that t_end/200 underflows to 0
    gets the two samples 0 and t_end).  With ``samples=False``, the unwrapping grid's: ``UNWRAP_RADIANS``/Λ, at least
    200 points."""
    return min((DT_RADIANS if samples else UNWRAP_RADIANS) / rate, t_end / 200.0) or t_end


def _validate(body: Body, initial: EulerState, t_end: float) -> tuple[NDArray[np.float64], float]:
    if not isinstance(body, Body):
        raise ValueError(f"body must be a rocknroller.analysis.model.body.Body, got {type(body).__name__}")
    if not isinstance(initial, EulerState):
        raise ValueError(f"initial must be a rocknroller.analysis.model.equations.EulerState, got {type(initial).__name__}")
    if not math.isfinite(t_end) or t_end <= 0.0:
        raise ValueError(f"t_end must be a finite number > 0, got t_end={t_end!r}")
    lo, hi = MOMENT_RANGE
    for name in ("I3", "I1", "I2"):  # I3 first: the CLI derives I1 (and I2) from it by default
        if not lo <= getattr(body, name) <= hi:
            raise ValueError(f"{name} must lie in [{lo:g}, {hi:g}] (units of m R^2) for the integrator to be "
                             f"accurate (the energy error grows as 1/I_min), got {name}={getattr(body, name)!r}")
    if not G_RANGE[0] <= body.g <= G_RANGE[1]:
        raise ValueError(f"g must lie in [{G_RANGE[0]:g}, {G_RANGE[1]:g}] (g only sets the unit of time; "
                         f"rescale time to bring it there), got g={body.g!r}")
    y0 = initial.to_body_state()
    with np.errstate(over="ignore", invalid="ignore"):  # rates of 1e200 overflow E to inf: refused below
        E = float(energy(body, y0[0:3], y0[3:6]))
    if not E <= MAX_ENERGY_OVER_G * body.g:
        raise ValueError(f"the initial rates are too large: the energy E = {E:.3g} exceeds {MAX_ENERGY_OVER_G:g} g "
                         f"(units m g R); reduce the rates (theta_dot, phi_dot, psi_dot or omega)")
    if not np.any(y0[3:6]) and (body.a == 0.0 or initial.theta in (0.0, math.pi) or not np.any(y0[0:2])):
        raise ValueError(
            "the initial state has no motion: the body is at rest in an equilibrium (theta0 = 0 or pi, or any "
            "theta0 when a = 0); give theta0 in (0, pi) with a > 0, or a non-zero rate")
    if not E + body.g * body.a > 0.0:
        # Λ = 0: T = ½ ωᵀKω ≥ ½ I_min |ω|² (K ≥ I_min) underflows to 0 when ½ I_min |ω|² is below half the smallest
        # subnormal number, i.e. |ω| < √(2⁻¹⁰⁷⁴/I_min); with g a = 0 nothing else moves the body
        w_min = math.sqrt(math.ulp(0.0) / min(body.I1, body.I2, body.I3))
        raise ValueError(
            f"the initial state has no motion to resolve: {initial} has the kinetic energy E = {E!r} in double "
            f"precision (its rates, max |omega_i| = {float(np.max(np.abs(y0[3:6]))):.3g}, are below about {w_min:.2g}, "
            f"where (1/2) I_min |omega|^2 underflows) and g a = {body.g * body.a!r}; give a > 0 or larger rates")
    _check_tilt_resolved(body, initial, y0, E)
    return y0, rate_bound(body, y0)


def _check_tilt_resolved(body: Body, initial: EulerState, y0: NDArray[np.float64], E: float) -> None:
    """Refuse a motion whose energy keeps its tilt below ``THETA_MIN`` (see there).

    V = g a (1 − cos θ) ≤ E bounds the tilt by θ_E, 2 g a sin²(θ_E/2) = E = T + V; in the upper hemisphere V is taken
    as g a (γ1² + γ2²)/(1 + γ3), which keeps its digits where 1 − γ3 rounds to 0 (θ < 1.5e-8), and T = E − g a (1 − γ3)
    exactly as ``energy`` adds it up.  Without gravity (a = 0) the energy bounds no tilt.
    """
    if body.a == 0.0:
        return
    ga = body.g * body.a
    one_minus_c = (y0[0] ** 2 + y0[1] ** 2) / (1.0 + y0[2]) if y0[2] > 0.0 else 1.0 - y0[2]
    s2 = ((E - ga * (1.0 - y0[2])) + ga * one_minus_c) / (2.0 * ga)  # sin²(θ_E/2)
    if s2 < math.sin(0.5 * THETA_MIN) ** 2:
        theta_E = 2.0 * math.asin(math.sqrt(max(s2, 0.0)))
        raise ValueError(
            f"theta0={initial.theta!r}: the start's energy keeps its tilt within theta_E = {theta_E:.3g} rad of the "
            f"pole, below THETA_MIN = {THETA_MIN:.3g} rad, the smallest amplitude at which the integrator resolves "
            f"the turning points of theta (its state carries an absolute round-off of u = {_U:.3g}); give "
            f"theta0 >= {THETA_MIN:.3g} or larger rates")


def _progress(total: float, enabled: bool | None):
    from tqdm import tqdm

    if enabled is None:
        enabled = sys.stderr.isatty()
    return tqdm(total=total, disable=not enabled, unit="t.u.", leave=False, file=sys.stderr,
                bar_format="{l_bar}{bar}| {n:.4g}/{total:.4g} time units [{elapsed}<{remaining}]")


class _HeyokaRun:
    """heyoka integrator advanced stretch by stretch, with the dense output of each stretch."""

    def __init__(self, body: Body, y0: NDArray[np.float64], precision: str, bar: Any, max_steps: int | None):
        self.fp = float if precision == "double" else np.longdouble
        self.ta = ta = heyoka_integrator(precision)
        ta.time = self.fp(0.0)
        ta.state[:] = np.asarray(y0, dtype=self.fp)
        ta.pars[:] = np.asarray(body.params, dtype=self.fp)
        self.log = ta.nt_events[0].callback
        self.log.events.clear()
        self.bar, self.max_steps, self.n_steps = bar, max_steps, 0
        self.tolerance = float(np.finfo(self.fp).eps)
        self.params, self.start = body.params, start_turning_point(body, y0)

    def advance(self, t_b: float) -> tuple[DenseOutput, list[tuple[float, int]]]:
        ta, fp = self.ta, self.fp
        t_a = float(ta.time)
        steps_before = self.n_steps

        def step_callback(ta_: Any) -> bool:
            self.bar.update(float(ta_.time) - self.bar.n)
            return True

        # the step cap is heyoka's own (max_steps: one past the cap, to tell reaching it from needing more); a Python
        # call per step only to move a bar that is shown (it cost 7 % of a run that shows none, issue 25, item 18):
        # without one, heyoka keeps the GIL released for the whole stretch (threads run in parallel).  The steps
        # themselves are the same either way.
        cap = 0 if self.max_steps is None else self.max_steps - self.n_steps + 1
        self.log.events.clear()
        result = ta.propagate_until(fp(t_b), c_output=True, max_steps=cap,
                                    callback=None if self.bar.disable else step_callback)
        outcome, c_out = result[0], result[4]
        self.n_steps += int(result[3])
        if outcome.name == "step_limit" or (self.max_steps is not None and self.n_steps > self.max_steps):
            raise ValueError(f"t_end: the run needs more than MAX_DENSE_STEPS = {MAX_DENSE_STEPS} integration steps "
                             f"to keep its samples (stopped at t = {float(ta.time):.6g} after "
                             f"{self.n_steps - steps_before} steps); use samples=False (turning points only) or a "
                             "shorter t_end")
        if outcome.name != "time_limit":
            raise RuntimeError(f"heyoka stopped early at t={float(ta.time)!r}: {outcome}")

        def dense(t: NDArray[np.float64]) -> NDArray[np.float64]:
            return np.asarray(c_out(np.asarray(t, dtype=fp)), dtype=float).reshape(-1, STATE_SIZE)

        events = _turning_points(list(self.log.events), t_a, t_b, dense, self.params,
                                 self.start if t_a == 0.0 else None)
        self.log.events.clear()
        return dense, events


class _ScipyRun:
    """scipy DOP853 advanced stretch by stretch (numpy right-hand side), with the dense output of each stretch."""

    def __init__(self, body: Body, y0: NDArray[np.float64], rtol: float, atol: float, bar: Any):
        self.body, self.y, self.t = body, np.asarray(y0, float), 0.0
        self.rtol, self.atol, self.bar, self.n_steps, self.tolerance = rtol, atol, bar, 0, rtol
        self.start = start_turning_point(body, y0)

    def advance(self, t_b: float) -> tuple[DenseOutput, list[tuple[float, int]]]:
        from scipy.integrate import solve_ivp

        params, bar = self.body.params, self.bar

        def fun(t: float, y: NDArray[np.float64]) -> NDArray[np.float64]:
            if t - bar.n >= 1.0:
                bar.update(t - bar.n)
            return np.array(body_frame_rhs(y, params))

        def rising(t: float, y: NDArray[np.float64]) -> float:
            return turning_point_function(y)

        def falling(t: float, y: NDArray[np.float64]) -> float:
            return turning_point_function(y)

        # solve_ivp reads an event's crossing direction from its attribute ``direction`` (a function declares none)
        setattr(rising, "direction", 1.0)
        setattr(falling, "direction", -1.0)
        t_a = self.t
        sol = solve_ivp(fun, (t_a, t_b), self.y, method="DOP853", rtol=self.rtol, atol=self.atol, dense_output=True,
                        events=[rising, falling])
        if sol.status != 0:
            raise RuntimeError(f"scipy DOP853 failed: {sol.message}")
        self.n_steps += sol.t.size - 1
        self.t, self.y = t_b, sol.y[:, -1]
        bar.update(t_b - bar.n)
        raw = [(float(t), 1) for t in sol.t_events[0]] + [(float(t), -1) for t in sol.t_events[1]]

        def dense(t: NDArray[np.float64]) -> NDArray[np.float64]:
            return np.asarray(sol.sol(np.asarray(t, float))).T.reshape(-1, STATE_SIZE)

        return dense, _turning_points(raw, t_a, t_b, dense, params, self.start if t_a == 0.0 else None)


def check_energy_error(err: float, n_steps: int, tolerance: float, strict: bool, what: str = "",
                       stacklevel: int = 2) -> None:
    """Warn (:class:`AccuracyWarning`), or raise :class:`AccuracyError` with ``strict``, if a run's relative energy
    error ``err`` exceeds what ``n_steps`` steps at ``tolerance`` allow (:func:`energy_error_bound`); ``what`` names
    where it was measured; ``stacklevel`` counts from the caller of this function."""
    bound = energy_error_bound(tolerance, n_steps)
    if err > bound:
        msg = (f"the relative energy error {err:.3g}{what} exceeds {bound:.3g}, the most that {n_steps} steps at "
               f"tolerance {tolerance:.3g} allow: the run is not accurate")
        if strict:
            raise AccuracyError(msg)
        warnings.warn(msg, AccuracyWarning, stacklevel=stacklevel + 1)


def check_theta_resolved(theta_maxima: NDArray[np.float64], initial: EulerState) -> None:
    """Refuse a motion near the pole that the energy did not confine there: θ-maxima below ``THETA_MIN``, where the
    integrator does not resolve the turning points (:mod:`rocknroller.numerics.events`)."""
    if np.any(theta_maxima < THETA_MIN):
        raise ValueError(f"theta0={initial.theta!r}: theta has maxima as small as {theta_maxima.min():.3g} "
                         f"rad, below THETA_MIN = {THETA_MIN:.3g} rad, the smallest amplitude at which the integrator "
                         f"resolves the turning points of theta; give theta0 >= {THETA_MIN:.3g}")


class RunPlan(NamedTuple):
    """A run of :func:`simulate` checked by :func:`check_run`."""

    t_end: float
    """Final time."""
    dt: float
    """Spacing of the output grid (with ``samples=False``, of the grid on which the angles are unwrapped)."""
    n_grid: int
    """Points of that grid, both ends included."""
    y0: NDArray[np.float64]
    """Initial body-frame state."""
    rate: float
    """The rate bound Λ (:func:`rate_bound`)."""


def check_run(body: Body, initial: EulerState, t_end: float, *, dt: float | None = None,
              samples: bool = True) -> RunPlan:
    """Check a run of :func:`simulate` against its limits before any work: every check ``simulate`` makes on the
    body, the initial state, ``t_end`` and ``dt``.

    Parameters
    ----------
    body, initial, t_end, dt, samples : as for :func:`simulate`.

    Returns
    -------
    RunPlan
        ``t_end`` and ``dt`` (default :func:`default_dt`) as floats, the grid size, the initial body-frame state and Λ.

    Raises
    ------
    ValueError
        Naming the parameter and the limit it exceeds (see the module docstring).
    """
    try:
        t_end = float(t_end)
    except (TypeError, ValueError, OverflowError):  # OverflowError: an int beyond the floats, like 10**400
        raise ValueError(f"t_end must be a finite number > 0, got t_end={t_end!r}") from None
    y0, rate = _validate(body, initial, t_end)
    radians = rate * t_end
    limit, limit_name = (MAX_DENSE_RADIANS, "MAX_DENSE_RADIANS") if samples else (MAX_RADIANS, "MAX_RADIANS")
    if radians > limit:
        hint = "; use samples=False (turning points only) or a shorter t_end" if samples else ""
        raise ValueError(f"t_end={t_end!r} is too long: the run spans Λ t_end = {radians:.3g} radians of its rate bound "
                         f"Λ = {rate:.3g} (about as many integration steps), over the limit {limit_name} = {limit:g}{hint}")
    if dt is None:
        dt = default_dt(t_end, rate, samples)
    dt = float(dt)
    if not math.isfinite(dt) or dt <= 0.0:
        raise ValueError(f"dt must be a finite number > 0, got dt={dt!r}")
    intervals = t_end / dt  # inf for a subnormal dt: refused below, never converted to an integer
    n_grid = max(2, int(math.ceil(intervals - 1e-9)) + 1) if intervals < 1e18 else math.inf  # both ends
    if n_grid > (MAX_SAMPLES if samples else MAX_GRID_POINTS):
        what = (f"MAX_SAMPLES = {MAX_SAMPLES} (≈ 0.5 kB each); give a larger dt or samples=False" if samples else
                f"MAX_GRID_POINTS = {MAX_GRID_POINTS:g} (≈ 1 µs each); give a larger dt")
        raise ValueError(f"dt={dt!r} gives {n_grid:.3g} samples over t_end={t_end!r}, over the limit {what}")
    return RunPlan(t_end, dt, int(n_grid), y0, rate)


#: The ``on_turning_points`` callback of :func:`simulate`.
_TurningPointsCallback = Callable[[TurningPoints, TurningPoints], None]


# The result's type follows ``samples`` (a Trajectory with samples, a TurningPointRun without), for type checkers.
@overload
def simulate(body: Body, initial: EulerState, t_end: float, *, method: str = ..., dt: float | None = ...,
             precision: str = ..., rtol: float = ..., atol: float = ..., progress: bool | None = ...,
             samples: Literal[True] = ..., on_turning_points: _TurningPointsCallback | None = ...,
             strict: bool = ...) -> Trajectory: ...
@overload
def simulate(body: Body, initial: EulerState, t_end: float, *, method: str = ..., dt: float | None = ...,
             precision: str = ..., rtol: float = ..., atol: float = ..., progress: bool | None = ...,
             samples: Literal[False], on_turning_points: _TurningPointsCallback | None = ...,
             strict: bool = ...) -> TurningPointRun: ...
@overload
def simulate(body: Body, initial: EulerState, t_end: float, *, method: str = ..., dt: float | None = ...,
             precision: str = ..., rtol: float = ..., atol: float = ..., progress: bool | None = ...,
             samples: bool = ..., on_turning_points: _TurningPointsCallback | None = ...,
             strict: bool = ...) -> Trajectory | TurningPointRun: ...


def simulate(body: Body, initial: EulerState, t_end: float, *, method: str = "heyoka", dt: float | None = None,
             precision: str = "double", rtol: float = 3e-14, atol: float = 1e-15,
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
        :func:`rocknroller.numerics.trajectory.energy_error_bound`.
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
    """
    if method not in _METHODS:
        raise ValueError(f"method must be one of {_METHODS}, got {method!r}")
    if precision not in _PRECISIONS:
        raise ValueError(f"precision must be one of {_PRECISIONS}, got {precision!r}")
    if method == "scipy" and precision != "double":
        raise ValueError("precision='extended' is available with method='heyoka' only")
    if method == "scipy" and not (0.0 < rtol < 1.0 and math.isfinite(atol) and atol > 0.0):
        raise ValueError(f"rtol must lie in (0, 1) and atol be > 0, got rtol={rtol!r}, atol={atol!r}")
    t_end, dt, n_grid, y0, rate = check_run(body, initial, t_end, dt=dt, samples=samples)
    per_radian = (DOP853_SECONDS_PER_RADIAN if method == "scipy" else HEYOKA_SECONDS_PER_RADIAN
                  if precision == "double" else HEYOKA_EXTENDED_SECONDS_PER_RADIAN)
    check_work(rate * t_end * per_radian, f"this run ({method}, {precision} precision, Λ t_end = {rate * t_end:.3g} "
               "radians)", budget)
    if on_turning_points is not None and samples:
        raise ValueError("on_turning_points streams the turning points of a run with samples=False")
    with _progress(t_end, progress) as bar:
        run: _HeyokaRun | _ScipyRun
        if method == "heyoka":
            run = _HeyokaRun(body, y0, precision, bar, MAX_DENSE_STEPS if samples else None)
        else:
            run = _ScipyRun(body, y0, rtol, atol, bar)
        if samples:
            dense, events = run.advance(t_end)
            result: Trajectory | TurningPointRun = Trajectory.from_dense(
                body, method, dense, np.linspace(0.0, t_end, n_grid), [t for t, d in events if d > 0],
                [t for t, d in events if d < 0], n_steps=run.n_steps, tolerance=run.tolerance)
        else:
            result = _turning_points_only(body, method, run, y0, t_end, dt, rate, on_turning_points)
    return finish_run(result, initial, strict)


_Run = TypeVar("_Run", bound=Trajectory | TurningPointRun)


def finish_run(result: _Run, initial: EulerState, strict: bool) -> _Run:
    """The checks after a run: θ-maxima resolved (:func:`check_theta_resolved`), the energy error within its bound
    (:func:`check_energy_error`)."""
    check_theta_resolved(result.maxima.theta, initial)
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

    def __init__(self, body: Body, y0: NDArray[np.float64]) -> None:
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
        mx, mn = (TurningPoints.concatenate(parts) for parts in self._parts)
        self._parts = ([], [])
        self.maxima.append(mx)
        self.minima.append(mn)
        return mx, mn

    def result(self, method: str, t_end: float, n_steps: int, tolerance: float) -> TurningPointRun:
        return TurningPointRun(body=self.body, method=method, t_end=t_end,
                               maxima=TurningPoints.concatenate(self.maxima),
                               minima=TurningPoints.concatenate(self.minima),
                               energy_rel_error=self.worst / energy_scale(self.body, self.E0), n_steps=n_steps,
                               tolerance=tolerance)


def _turning_points_only(body: Body, method: str, run: _HeyokaRun | _ScipyRun, y0: NDArray[np.float64],
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
