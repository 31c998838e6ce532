"""The two integrators of :func:`rocknroller.numerics.integrate.simulate`, advanced stretch by stretch.

``heyoka`` (:class:`_HeyokaRun`)
    heyoka's adaptive Taylor integrator at tolerance = machine epsilon, compiled once per process
    (:func:`heyoka_integrator`, after :func:`check_diskcache`) and copied once per thread; turning points are
    non-terminal events on dγ3/dt = 0.
``scipy`` (:class:`_ScipyRun`)
    scipy's DOP853 on the same right-hand side with a numpy implementation, as an independent check.

Each returns, per stretch, its dense output and the turning points located on it
(:func:`rocknroller.numerics.events._turning_points`); the module docstring of :mod:`rocknroller.numerics.integrate`
describes both.
"""

from __future__ import annotations

import copy
import threading
from typing import Any

import numpy as np
from numpy.typing import NDArray

from rocknroller.analysis.model.body import Body, LoadedSphere
from rocknroller.analysis.model.equations import STATE_SIZE, body_frame_rhs, turning_point_function
from rocknroller.numerics.cache import compiling, probe_writable, warn_unwritable
from rocknroller.numerics.events import DenseOutput, _turning_points, start_turning_point
from rocknroller.numerics.run_limits import MAX_DENSE_STEPS

__all__ = ["heyoka_integrator", "check_diskcache", "check_params", "PARAM_COUNTS"]

_PRECISIONS = ("double", "extended")
#: The integrator compiled once per process, per precision and tolerance; never propagated itself, only copied.
_TEMPLATES: dict[tuple[str, float, int], Any] = {}
_TEMPLATE_LOCK = threading.Lock()
#: Each thread's own copies of the templates (a heyoka integrator must not be propagated by two threads at once).
_PER_THREAD = threading.local()


class _EventLog:
    """Non-terminal event callback: records (time, direction) of each turning point."""

    def __init__(self) -> None:
        self.events: list[tuple[float, int]] = []

    def __call__(self, ta: Any, time: Any, d_sgn: Any) -> None:
        self.events.append((float(time), int(d_sgn)))


def _build_heyoka(fp_type: Any, tol: float, n_par: int) -> Any:
    import heyoka as hy

    names = ["g1", "g2", "g3", "w1", "w2", "w3", "x1", "x2", "x3", "X", "Y"]
    y = hy.make_vars(*names)
    pars = [hy.par[i] for i in range(n_par)]
    rhs = body_frame_rhs(y, pars)
    kwargs = {} if fp_type is float else {"fp_type": fp_type}
    ev = hy.nt_event(turning_point_function(y), _EventLog(), **kwargs)
    return hy.taylor_adaptive(list(zip(y, rhs)), np.zeros(STATE_SIZE, dtype=fp_type),
                              pars=np.zeros(n_par, dtype=fp_type), nt_events=[ev], tol=fp_type(tol), **kwargs)


def check_params(n_par: int) -> int:
    """The number of runtime parameters of form (i): 5 for a :class:`~rocknroller.analysis.model.body.Body` (the mass
    centre on the third axis, (a, I1, I2, I3, g)), 7 for a :class:`~rocknroller.analysis.model.body.LoadedSphere`
    ((c1, c2, c3, I1, I2, I3, g)); each has its own compiled integrator."""
    if n_par not in PARAM_COUNTS:
        raise ValueError(f"n_par must be one of {PARAM_COUNTS} (the on-axis body, the general loaded sphere), "
                         f"got {n_par!r}")
    return n_par


#: The runtime parameter counts of form (i): the on-axis Body, the general LoadedSphere.
PARAM_COUNTS = (5, 7)


def heyoka_integrator(precision: str = "double", tol: float | None = None, n_par: int = 5) -> Any:
    """The compiled heyoka integrator of form (i) at tolerance ``tol`` (None: heyoka's default, the machine epsilon
    of ``precision``; checked by the caller, :func:`rocknroller.numerics.run_limits.check_tol`) for ``n_par``
    runtime parameters (:func:`check_params`): compiled once per process, one copy per thread.

    Every thread that calls this gets its own copy (made in about a millisecond), so
    :func:`~rocknroller.numerics.integrate.simulate` may run in several threads at once; a copy runs the same machine
    code as the original, so a run gives the same result bit for bit in whichever thread it runs.  heyoka's on-disk
    JIT cache (``HEYOKA_CACHE_DIR``; default under the user cache directory) keeps the compiled code between
    processes; it holds machine code, so it must be as trusted as the installed packages.  An unwritable cache
    directory gives one :class:`~rocknroller.numerics.cache.CacheWarning` (each process then compiles for ~6 s).
    """
    if precision not in _PRECISIONS:
        raise ValueError(f"precision must be one of {_PRECISIONS}, got {precision!r}")
    mine = _PER_THREAD.__dict__.setdefault("integrators", {})
    key = (precision, float(np.finfo(float if precision == "double" else np.longdouble).eps) if tol is None else tol,
           check_params(n_par))
    if key not in mine:
        with _TEMPLATE_LOCK:  # one compilation per process; copies are made from a template no thread propagates
            if key not in _TEMPLATES:
                _TEMPLATES[key] = _compile(*key)
            mine[key] = copy.deepcopy(_TEMPLATES[key])
    return mine[key]


def _compile(precision: str, tol: float, n_par: int) -> Any:
    """Build the integrator of ``precision`` at ``tol`` (from heyoka's disk cache when it holds it), after checking
    that the cache can be used (:func:`check_diskcache`); a build that takes long says so on stderr
    (:func:`~rocknroller.numerics.cache.compiling`)."""
    check_diskcache()
    what, seconds = _COMPILE_NOTES[precision]
    if n_par != PARAM_COUNTS[0]:
        what = what.replace("direct integrator", "direct integrator of the general loaded sphere")
    with compiling(what, seconds):
        return _build_heyoka(float if precision == "double" else np.longdouble, tol, n_par)


#: What :func:`_compile` compiles at each precision and the CPU seconds it usually takes (measured, one core).
_COMPILE_NOTES = {"double": ("the direct integrator (heyoka, double precision)", 5.0),
                  "extended": ("the direct integrator (heyoka, extended precision)", 18.0)}


def check_diskcache() -> None:
    """Check that heyoka's disk cache can be used before anything is compiled.

    A cache heyoka cannot use (a directory that cannot be written or created, a ``cache.db`` that is not a database)
    makes heyoka log a ``[warning]`` line on stdout at every lookup and insertion, where it would corrupt the
    JSON of ``rocknroller ... --json``.  Such a cache is switched off for this process instead (its warnings are then
    never logged), and one :class:`~rocknroller.numerics.cache.CacheWarning` says so.  heyoka's own logger is left
    as the user set it.
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



class _HeyokaRun:
    """heyoka integrator advanced stretch by stretch, with the dense output of each stretch."""

    def __init__(self, body: Body | LoadedSphere, y0: NDArray[np.float64], precision: str, bar: Any,
                 max_steps: int | None, tol: float | None = None):
        self.fp = float if precision == "double" else np.longdouble
        self.ta = ta = heyoka_integrator(precision, tol, len(body.params))
        ta.time = self.fp(0.0)
        ta.state[:] = np.asarray(y0, dtype=self.fp)
        ta.pars[:] = np.asarray(body.params, dtype=self.fp)
        self.log = ta.nt_events[0].callback
        self.log.events.clear()
        self.bar, self.max_steps, self.n_steps = bar, max_steps, 0
        self.tolerance = float(ta.tol)
        self.params, self.start = body.params, start_turning_point(body, y0)

    def advance(self, t_b: float) -> tuple[DenseOutput, list[tuple[float, int]]]:
        ta, fp = self.ta, self.fp
        t_a = float(ta.time)
        steps_before = self.n_steps

        def step_callback(ta_: Any) -> bool:
            self.bar.update(float(ta_.time) - self.bar.n)
            return True

        # the step cap is heyoka's own (max_steps: one past the cap, to tell reaching it from needing more); a Python
        # call per step only to move a bar that is shown (it cost 7 % of a run that shows none):
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

    def __init__(self, body: Body | LoadedSphere, y0: NDArray[np.float64], rtol: float, atol: float, bar: Any):
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
