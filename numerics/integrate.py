"""simulate(): integrate the direct equations of motion (form (i)) and locate every turning point of θ.

Backends
--------
``heyoka`` (default)
    heyoka's adaptive Taylor integrator at tolerance = machine epsilon.  The body parameters are
    runtime parameters, so one compiled integrator serves every body.  It is compiled once per
    process, and pickled (object code included) to a per-user cache directory so that later
    processes load it in milliseconds instead of compiling (about 3 s).  Turning points are
    non-terminal events on dγ3/dt = 0, located by heyoka on the Taylor polynomials to round-off.
    ``precision="extended"`` uses 80-bit long double (x86-64), for reference runs.
``scipy``
    scipy's DOP853 on the same right-hand side with a numpy implementation, as an independent check.
"""

from __future__ import annotations

import hashlib
import inspect
import math
import os
import pickle
import sys
import tempfile
from pathlib import Path
from typing import Any

import numpy as np
from numpy.typing import NDArray

from analysis.body import Body
from numerics import equations
from numerics.cache import cache_dir  # re-exported: numerics.integrate.cache_dir
from numerics.equations import STATE_SIZE, EulerState, body_frame_rhs, turning_point_function
from numerics.trajectory import Trajectory

__all__ = ["simulate", "heyoka_integrator", "default_dt", "cache_dir"]

_METHODS = ("heyoka", "scipy")
_PRECISIONS = ("double", "extended")
_INTEGRATORS: dict[str, Any] = {}


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
    """The compiled heyoka integrator of form (i) (memoised in-process and cached on disk)."""
    if precision not in _PRECISIONS:
        raise ValueError(f"precision must be one of {_PRECISIONS}, got {precision!r}")
    if precision in _INTEGRATORS:
        return _INTEGRATORS[precision]
    import heyoka as hy

    fp_type = float if precision == "double" else np.longdouble
    source = inspect.getsource(equations) + inspect.getsource(_EventLog)
    key = hashlib.sha256(f"{hy.__version__}|{sys.version}|{precision}|{source}".encode()).hexdigest()[:16]
    path = cache_dir() / f"taylor-{precision}-{key}.pickle"
    ta = None
    if path.exists():
        try:
            with path.open("rb") as fh:
                ta = pickle.load(fh)
        except Exception:  # a stale or truncated cache entry is rebuilt
            ta = None
    if ta is None:
        ta = _build_heyoka(fp_type)
        try:
            path.parent.mkdir(parents=True, exist_ok=True)
            with tempfile.NamedTemporaryFile(dir=path.parent, delete=False) as fh:
                pickle.dump(ta, fh)
            os.replace(fh.name, path)
        except OSError:  # a read-only cache is not an error
            pass
    _INTEGRATORS[precision] = ta
    return ta


def default_dt(t_end: float) -> float:
    """Default sample spacing: 0.05 time units (≈ 400 samples per rocking period), at least 200 samples."""
    return min(0.05, t_end / 200.0)


def _validate(body: Body, initial: EulerState, t_end: float) -> NDArray[np.float64]:
    if not isinstance(body, Body):
        raise ValueError(f"body must be an analysis.body.Body, got {type(body).__name__}")
    if not isinstance(initial, EulerState):
        raise ValueError(f"initial must be a numerics.equations.EulerState, got {type(initial).__name__}")
    t_end = float(t_end)
    if not math.isfinite(t_end) or t_end <= 0.0:
        raise ValueError(f"t_end must be a finite number > 0, got t_end={t_end!r}")
    at_pole = initial.theta in (0.0, math.pi)
    if at_pole and initial.theta_dot == 0.0 and initial.phi_dot + initial.psi_dot == 0.0:
        raise ValueError(
            "the initial state has no motion: theta0 is an equilibrium (0 or pi) and the body is at rest; "
            "give theta0 in (0, pi) or a non-zero rate"
        )
    return initial.to_body_state()


def _progress(total: float, enabled: bool | None):
    from tqdm import tqdm

    if enabled is None:
        enabled = sys.stderr.isatty()
    return tqdm(total=total, disable=not enabled, unit="t.u.", leave=False, file=sys.stderr,
                bar_format="{l_bar}{bar}| {n:.0f}/{total:.0f} time units [{elapsed}<{remaining}]")


def _run_heyoka(body: Body, y0: NDArray[np.float64], t_end: float, precision: str, progress: bool | None):
    ta = heyoka_integrator(precision)
    fp_type = float if precision == "double" else np.longdouble
    ta.time = fp_type(0.0)
    ta.state[:] = np.asarray(y0, dtype=fp_type)
    ta.pars[:] = np.asarray(body.params, dtype=fp_type)
    ta.reset_cooldowns()
    log = ta.nt_events[0].callback
    log.events.clear()
    with _progress(t_end, progress) as bar:
        def step_callback(ta_: Any) -> bool:
            bar.update(float(ta_.time) - bar.n)
            return True

        result = ta.propagate_until(fp_type(t_end), c_output=True, callback=step_callback)
    outcome, c_out = result[0], result[4]
    if outcome.name not in ("time_limit",):
        raise RuntimeError(f"heyoka stopped early at t={float(ta.time)!r}: {outcome}")
    events = sorted(e for e in log.events if e[0] > 0.0)
    log.events.clear()

    def dense(t: NDArray[np.float64]) -> NDArray[np.float64]:
        return np.asarray(c_out(np.asarray(t, dtype=fp_type)), dtype=float).reshape(-1, STATE_SIZE)

    return dense, events


def _run_scipy(body: Body, y0: NDArray[np.float64], t_end: float, rtol: float, atol: float,
               progress: bool | None):
    from scipy.integrate import solve_ivp

    params = body.params
    with _progress(t_end, progress) as bar:
        def fun(t: float, y: NDArray[np.float64]) -> NDArray[np.float64]:
            if t - bar.n >= 1.0:
                bar.update(t - bar.n)
            return np.array(body_frame_rhs(y, params))

        def rising(t: float, y: NDArray[np.float64]) -> float:
            return turning_point_function(y)

        def falling(t: float, y: NDArray[np.float64]) -> float:
            return turning_point_function(y)

        rising.direction, falling.direction = 1.0, -1.0
        sol = solve_ivp(fun, (0.0, t_end), y0, method="DOP853", rtol=rtol, atol=atol, dense_output=True,
                        events=[rising, falling])
    if sol.status != 0:
        raise RuntimeError(f"scipy DOP853 failed: {sol.message}")
    events = sorted([(float(t), 1) for t in sol.t_events[0] if t > 0.0]
                    + [(float(t), -1) for t in sol.t_events[1] if t > 0.0])

    def dense(t: NDArray[np.float64]) -> NDArray[np.float64]:
        return np.asarray(sol.sol(np.asarray(t, float))).T.reshape(-1, STATE_SIZE)

    return dense, events


def simulate(body: Body, initial: EulerState, t_end: float, *, method: str = "heyoka", dt: float | None = None,
             precision: str = "double", rtol: float = 3e-14, atol: float = 1e-15,
             progress: bool | None = False) -> Trajectory:
    """Integrate the rock'n'roller from ``initial`` over [0, t_end] and find every turning point of θ.

    Parameters
    ----------
    body : Body
    initial : EulerState
        Initial Euler angles and rates (``EulerState.from_omega`` for a body-frame ω).
    t_end : float
        Final time, > 0.
    method : {"heyoka", "scipy"}
        Taylor integrator (default) or DOP853 (independent check).
    dt : float, optional
        Spacing of the output grid (default :func:`default_dt`); turning points are always added.
    precision : {"double", "extended"}
        heyoka only: 64-bit or 80-bit floating point.
    rtol, atol : float
        scipy only: DOP853 tolerances.
    progress : bool or None
        Show a tqdm bar on stderr (None: only if stderr is a terminal).

    Returns
    -------
    Trajectory
        Samples, unwrapped angles, invariants, contact track, and the turning points
        (maxima: dγ3/dt rising through 0; minima: falling), none reported at t = 0.
    """
    y0 = _validate(body, initial, t_end)
    t_end = float(t_end)
    if method not in _METHODS:
        raise ValueError(f"method must be one of {_METHODS}, got {method!r}")
    if dt is None:
        dt = default_dt(t_end)
    if not math.isfinite(dt) or dt <= 0.0:
        raise ValueError(f"dt must be a finite number > 0, got dt={dt!r}")
    if method == "heyoka":
        dense, events = _run_heyoka(body, y0, t_end, precision, progress)
    else:
        if precision != "double":
            raise ValueError("precision='extended' is available with method='heyoka' only")
        dense, events = _run_scipy(body, y0, t_end, rtol, atol, progress)
    n = int(math.ceil(t_end / dt - 1e-9))
    grid = np.linspace(0.0, t_end, n + 1)
    t_max = [t for t, d in events if d > 0]
    t_min = [t for t, d in events if d < 0]
    return Trajectory.from_dense(body, method, dense, grid, t_max, t_min)
