"""Chaos indicators of the direct motion: a tangent vector integrated along the ODE, sampled at the θ-maxima.

The reference for the slow map's indicators: MEGNO and the finite-time maximal Lyapunov exponent of a
direct run, in the units the slow map reports them (per unit time and per rock), from the package's one formula,
:func:`rocknroller.numerics.megno.chaos_indicators`.

Variational system
------------------
The body-frame equations of form (i) (:func:`rocknroller.analysis.model.equations.body_frame_rhs`) for the vertical
γ and the angular velocity ω are closed: the azimuth (the space axis e_X) and the contact point (X, Y) are driven by
(γ, ω) and do not act back.  The tangent vector w = (δγ, δω) therefore lives in the 6-dimensional (γ, ω) system,
whose first-order variational equations ẇ = ∂f/∂(γ, ω) · w heyoka builds by automatic differentiation
(``heyoka.var_ode_sys`` with respect to the initial value of one variable: one column of the Jacobian of the flow,
6 equations, whose initial value is then set to w0).  The body's parameters (a, I1, I2, I3, g) are runtime
parameters, so one compiled integrator (12 equations, with the θ-maxima as terminal events) serves every body; it is
built once per process, copied once per thread, and kept between processes by heyoka's disk cache, as
:func:`rocknroller.numerics.integrate.heyoka_integrator`'s integrator is (whose cache check runs first).
(e_X, X, Y) are left out on purpose: δφ grows linearly on every orbit (φ is cyclic) and the contact point's
perturbation quadratically (it integrates δφ), which would make MEGNO tend to 4, not 2, on regular motion.

Norm
----
‖w‖² = |δγ|² + |δω|²/Λ², Λ = :func:`rocknroller.numerics.integrate.rate_bound` (√(2(E + g a)/I_min), a bound on
|ω| for all time): δγ is an angle (|δγ| = the change of direction of the vertical, radians) and δω/Λ an angle per
radian of Λ t, so both parts count alike.  λ does not depend on the norm (any two norms are equivalent); MEGNO does
only through the transient.  The slow map's indicators (state (u, v, Θ)) are comparable per unit time and per rock:
λ is a property of the orbit, not of the coordinates.

Initial tangent vector
----------------------
Fixed and generic: in the scaled coordinates (δγ, δω/Λ), the vector (1, 1, 1, 1, 1, 1) with the component of δγ
along γ0 removed (the tangent plane of |γ| = 1, which the flow preserves), normalised to ‖w0‖ = 1.  It has a
component along the energy (action) direction, so on a regular orbit ‖w‖ grows linearly (the frequency shear of
neighbouring tori: MEGNO → 2, also on pure rocking, whose period depends on its amplitude), and along the most
unstable direction of a chaotic one (MEGNO ≈ λ t/2).  The time-shift direction (the flow itself) only stays bounded.

Samples
-------
At every θ-maximum (dγ3/dt rising through 0, :func:`~rocknroller.analysis.model.equations.turning_point_function`,
a terminal event of the integrator, as heyoka locates it on its Taylor polynomial) the run records t_k and
ℓ_k = ln ‖w(t_k)‖ and renormalises w to 1 (adding up the logarithms: nothing overflows on long chaotic runs); w is
also renormalised, without a sample, at the end of every stretch of ``CHUNK_RADIANS`` radians of Λ t.  A start that
is itself a maximum (release from rest) is not a sample
(:func:`~rocknroller.numerics.events.start_turning_point`).  The maxima are those of this run's own orbit, which on
a chaotic orbit leaves :func:`~rocknroller.numerics.integrate.simulate`'s (integrated with other steps) after a few
dozen Lyapunov times; both are numerical orbits of the same accuracy, and their indicators agree statistically.

Checks (tests/numerics/test_variational.py)
-------------------------------------------
The tangent against central differences of two runs (the h² law, to its estimated truncation); λ per rock of pure
rocking about the unstable axis (ψ0 = 0) against ln μ of the exact one-step map's Jacobian
(:func:`rocknroller.analysis.slow.dynamics.period_doubling.rocking_jacobian`), to 1e-11; MEGNO → 2 (1.91-1.92 after 3000
rocks) on stable pure rocking and on a regular release; λ of chaotic releases against the growth rate of two runs
1e-10 apart, over the same window, to 0.1-5 %.  Rocking about the stable axis is itself unstable past the period
doubling: at θ0 = 0.95π, ε = 1e-2 lies past ε_pd ≈ 4/κ = 0.0094, and its MEGNO grows (25 after 300 rocks).
"""

from __future__ import annotations

import copy
import math
import threading
from array import array
from dataclasses import dataclass, field
from typing import TYPE_CHECKING, Any

import numpy as np
from numpy.typing import ArrayLike, NDArray

from rocknroller.analysis.model.body import Body, LoadedSphere
from rocknroller.analysis.model.equations import EulerState, body_frame_rhs, turning_point_function
from rocknroller.analysis.model.invariants import energy
from rocknroller.numerics.budget import WORK_BUDGET_SECONDS, check_work
from rocknroller.numerics.backends import check_params
from rocknroller.numerics.cache import compiling
from rocknroller.numerics.events import start_turning_point
from rocknroller.numerics.integrate import check_energy_error, check_run, check_theta_resolved, heyoka_integrator
from rocknroller.numerics.megno import ChaosIndicators, chaos_indicators
from rocknroller.numerics.run_limits import energy_scale

if TYPE_CHECKING:
    import pandas

__all__ = ["DirectChaos", "direct_chaos_indicators", "initial_tangent", "tangent_flow", "tangent_to_maximum",
           "tangent_norm", "variational_integrator", "VARIATIONAL_SECONDS_PER_RADIAN", "CHUNK_RADIANS"]

#: CPU seconds per radian of Λ t of the variational run (12 equations, a terminal event and a renormalisation at every
#: θ-maximum): 1.5e-5 measured by benchmarks/bench_variational.py (load 1.2), 2.0× plain
#: ``simulate(..., samples=False)`` over the same orbit; rounded up, as the rates of :mod:`rocknroller.numerics.budget`.
VARIATIONAL_SECONDS_PER_RADIAN = 2.0e-5
#: Radians of Λ t after which w is renormalised even without a θ-maximum (slow rocks, steady rolling).  Between two
#: renormalisations ‖w‖ grows at most by e^(c · CHUNK_RADIANS), c the largest growth rate of the linearised flow per
#: radian of Λ t, of order 1 (the Jacobian's entries in the scaled norm are ω ≲ Λ and g a/(I Λ) ≲ Λ): far below the
#: overflow at e^709.
CHUNK_RADIANS = 100.0
#: Most integration steps per stretch: 20 per radian (about one is taken); an integrator that stalls is stopped.
_STEPS_PER_STRETCH = int(20 * CHUNK_RADIANS)

_NAMES = ("g1", "g2", "g3", "w1", "w2", "w3", "x1", "x2", "x3", "X", "Y")
_N = 6  # the (γ, ω) system
_TEMPLATE: dict[int, Any] = {}
_LOCK = threading.Lock()
_PER_THREAD = threading.local()


def _build(n_par: int) -> Any:
    import heyoka as hy

    y = hy.make_vars(*_NAMES)
    pars = [hy.par[i] for i in range(n_par)]
    rhs = body_frame_rhs(y, pars)[:_N]  # (γ̇, ω̇) involve only γ, ω and the parameters
    vsys = hy.var_ode_sys(list(zip(y[:_N], rhs)), [y[0]], order=1)
    maxima = hy.t_event(turning_point_function(y), direction=hy.event_direction.positive)
    what = "the chaos indicators' variational integrator" + ("" if n_par == 5 else " (general loaded sphere)")
    with compiling(what, 24.0):
        return hy.taylor_adaptive(vsys, np.zeros(_N), pars=np.zeros(n_par), t_events=[maxima])


def variational_integrator(n_par: int = 5) -> Any:
    """heyoka's integrator of the (γ, ω) system and one tangent vector (state: 6 + 6 components), with the θ-maxima
    as its one terminal event, for ``n_par`` runtime parameters (5 for a Body, 7 for a LoadedSphere,
    :func:`~rocknroller.numerics.backends.check_params`): compiled once per process (from heyoka's disk cache when it
    holds it), one copy per thread (module docstring)."""
    mine = _PER_THREAD.__dict__.setdefault("integrators", {})
    key = check_params(n_par)
    if key not in mine:
        with _LOCK:
            if key not in _TEMPLATE:
                heyoka_integrator("double")  # its check of heyoka's disk cache (switched off if unusable), first
                _TEMPLATE[key] = _build(key)
            mine[key] = copy.deepcopy(_TEMPLATE[key])
    return mine[key]


def tangent_norm(w: ArrayLike, rate: float) -> NDArray[np.float64]:
    """‖w‖ = √(|δγ|² + |δω|²/Λ²) of tangent vectors w (components along the first axis: δγ, δω) with Λ = ``rate``."""
    w = np.asarray(w, float)
    return np.sqrt(np.sum(w[0:3] ** 2, axis=0) + np.sum((w[3:6] / rate) ** 2, axis=0))


def initial_tangent(y0: ArrayLike, rate: float) -> NDArray[np.float64]:
    """The fixed initial tangent vector w0 = (δγ, δω) at the body-frame state ``y0`` (module docstring), ‖w0‖ = 1."""
    gamma = np.asarray(y0, float)[0:3]
    dg = np.ones(3) - gamma * (np.sum(gamma) / float(gamma @ gamma))
    w = np.concatenate([dg, rate * np.ones(3)])
    return w / float(tangent_norm(w, rate))


def _start(ta: Any, body: Body | LoadedSphere, y0: NDArray[np.float64], w0: NDArray[np.float64]) -> None:
    ta.time = 0.0
    ta.state[:_N] = y0[:_N]
    ta.state[_N:] = w0
    ta.pars[:] = body.params
    ta.reset_cooldowns()


def tangent_flow(body: Body | LoadedSphere, initial: EulerState, times: ArrayLike,
                 w0: ArrayLike | None = None) -> tuple[NDArray[np.float64], NDArray[np.float64]]:
    """The (γ, ω) state and the tangent vector, not renormalised, at ``times`` (a check of the variational system).

    Parameters
    ----------
    body, initial : as for :func:`direct_chaos_indicators`.
    times : increasing times ≥ 0, the last within the limits of :func:`~rocknroller.numerics.integrate.check_run`.
    w0 : the initial tangent (δγ, δω), 6 numbers (default :func:`initial_tangent`).

    Returns
    -------
    states, tangents : arrays (len(times), 6).
    """
    times = np.asarray(times, float)
    if times.ndim != 1 or times.size == 0 or not (np.all(np.isfinite(times)) and times[0] >= 0.0
                                                    and np.all(np.diff(times) > 0.0)):
        raise ValueError("times must be a non-empty 1-d array of finite, increasing times >= 0")
    plan = check_run(body, initial, max(float(times[-1]), math.ulp(0.0)), samples=False)
    w = initial_tangent(plan.y0, plan.rate) if w0 is None else np.asarray(w0, float)
    if w.shape != (_N,) or not np.all(np.isfinite(w)):
        raise ValueError(f"w0 must be 6 finite numbers (dgamma, domega), got {w0!r}")
    ta = variational_integrator(len(body.params))
    _start(ta, body, plan.y0, w)
    out = np.empty((times.size, 2 * _N))
    stretch = CHUNK_RADIANS / plan.rate
    for k, t in enumerate(times):
        while float(ta.time) < t:  # in stretches, through the maxima (which stop the integrator)
            _check_outcome(ta, ta.propagate_until(min(float(t), float(ta.time) + stretch),
                                                  max_steps=_STEPS_PER_STRETCH)[0])
        out[k] = ta.state
    return out[:, :_N], out[:, _N:]


def tangent_to_maximum(body: Body | LoadedSphere, y0: ArrayLike, w0: ArrayLike, t_after: float,
                       t_before: float) -> tuple[float, NDArray[np.float64], NDArray[np.float64]]:
    """The first θ-maximum of the run from the (γ, ω) state ``y0`` after the time ``t_after`` (the integrator's
    terminal event, located by heyoka on its Taylor polynomial): its time t₁, the state there and the tangent vector
    Φ(t₁) w0 (the flow's derivative at the fixed time t₁, not renormalised; the event's own dependence on the start
    is the caller's: −f ∇h·w/∇h·f, h = dγ3/dt).  Maxima before ``t_after`` are passed over (a start at a maximum is
    one).

    Raises
    ------
    ValueError
        y0 or w0 not 6 finite numbers, or not 0 ≤ t_after < t_before.
    RuntimeError
        No θ-maximum in (t_after, t_before].
    """
    y0, w0 = np.asarray(y0, float), np.asarray(w0, float)
    if y0.shape != (_N,) or w0.shape != (_N,) or not (np.all(np.isfinite(y0)) and np.all(np.isfinite(w0))):
        raise ValueError(f"y0 and w0 must be 6 finite numbers (gamma, omega) and (dgamma, domega), got {y0!r}, {w0!r}")
    if not (math.isfinite(t_before) and 0.0 <= t_after < t_before):
        raise ValueError(f"need 0 <= t_after < t_before (finite), got t_after={t_after!r}, t_before={t_before!r}")
    ta = variational_integrator(len(body.params))
    _start(ta, body, y0, w0)
    while float(ta.time) < t_after:  # through the maxima before t_after (heyoka's cooldown: each stops it once)
        _check_outcome(ta, ta.propagate_until(t_after, max_steps=_STEPS_PER_STRETCH)[0])
    if not _check_outcome(ta, ta.propagate_until(t_before, max_steps=_STEPS_PER_STRETCH)[0]):
        raise RuntimeError(f"no maximum of theta between t={t_after!r} and t={t_before!r}")
    state = np.array(ta.state)
    return float(ta.time), state[:_N], state[_N:]


def _check_outcome(ta: Any, outcome: Any) -> bool:
    """True when the integrator stopped at a θ-maximum (its terminal event), False at the time asked; else raise."""
    import heyoka as hy

    if outcome == hy.taylor_outcome.time_limit:
        return False
    if int(outcome.value) == -1:  # terminal event 0 (heyoka reports event i as −i − 1)
        return True
    raise RuntimeError(f"heyoka stopped the variational run at t={float(ta.time)!r}: {outcome}")


@dataclass(frozen=True)
class DirectChaos:
    """The chaos indicators of one direct run (:func:`direct_chaos_indicators`).

    Attributes
    ----------
    indicators : MEGNO and λ (per unit time and per rock) from the samples at the θ-maxima
        (:class:`~rocknroller.numerics.megno.ChaosIndicators`; its ``t`` are the times of the maxima).
    theta_maxima : θ at the maxima.
    rate : Λ, the scale of δω in the tangent norm (module docstring).
    w0 : the initial tangent vector (δγ, δω).
    energy_rel_error : largest |E − E0|/(E0 + g a) at the maxima.
    n_steps : integration steps.

    Examples
    --------
    >>> import math
    >>> import rocknroller as rr
    >>> body = rr.Body.paper(epsilon=1e-3)
    >>> dc = rr.direct_chaos_indicators(body, rr.EulerState(theta=0.95 * math.pi, psi=math.pi / 4), 300.0)
    >>> print(dc.theta_maxima.size >= 8, dc.energy_rel_error < 1e-12)
    True True
    """

    indicators: ChaosIndicators
    theta_maxima: NDArray[np.float64] = field(repr=False)
    rate: float
    w0: NDArray[np.float64] = field(repr=False)
    energy_rel_error: float
    n_steps: int

    @property
    def t_maxima(self) -> NDArray[np.float64]:
        """Times of the θ-maxima (the samples)."""
        return self.indicators.t

    def to_dataframe(self) -> "pandas.DataFrame":
        """One row per θ-maximum: t, θ, the tangent vector's log-growth ℓ and the running MEGNO ⟨Y⟩ (needs pandas)."""
        from rocknroller.analysis.model.frames import dataframe

        ind = self.indicators
        return dataframe({"t": ind.t, "theta": self.theta_maxima, "log_growth": ind.log_growth,
                          "mean_megno": ind.mean_megno})

    def plot(self, ax: Any = None) -> Any:
        """Draw the running MEGNO ⟨Y⟩ at the θ-maxima against t on ``ax`` (a new pyplot figure without one), with the
        line MEGNO = ``MEGNO_CHAOTIC`` between regular and chaotic.  Returns the axes."""
        from rocknroller.numerics.trajectory_plots import plot_megno

        return plot_megno(self.indicators, ax=ax)


def direct_chaos_indicators(body: Body | LoadedSphere, initial: EulerState, t_end: float, *,
                            budget: float | None = WORK_BUDGET_SECONDS, strict: bool = False) -> DirectChaos:
    """MEGNO and the finite-time maximal Lyapunov exponent of the direct motion from ``initial`` over [0, t_end].

    A tangent vector is integrated along the orbit by heyoka's variational equations and sampled, and renormalised,
    at every θ-maximum (module docstring: the system, the norm, the initial vector); the indicators are
    :func:`rocknroller.numerics.megno.chaos_indicators` of those samples.

    Parameters
    ----------
    body, initial, t_end : as for :func:`~rocknroller.numerics.integrate.simulate` (the same checks and limits,
        :func:`~rocknroller.numerics.integrate.check_run` with ``samples=False``).
    budget : CPU seconds the run may take (None: no limit), estimated from Λ t_end and
        ``VARIATIONAL_SECONDS_PER_RADIAN``.
    strict : raise :class:`~rocknroller.numerics.integrate.AccuracyError` instead of warning
        (:class:`~rocknroller.numerics.integrate.AccuracyWarning`) when the energy error at the maxima exceeds
        :func:`~rocknroller.numerics.run_limits.energy_error_bound`.

    Returns
    -------
    DirectChaos

    Raises
    ------
    ValueError
        As ``simulate`` for the body, the state and t_end; a run over the budget; fewer than
        :data:`~rocknroller.numerics.megno.MIN_SAMPLES` θ-maxima in [0, t_end] (t_end too short, or no rocking).

    Examples
    --------
    >>> import math
    >>> import rocknroller as rr
    >>> body = rr.Body.paper(epsilon=1e-3)
    >>> start = rr.EulerState(theta=0.95 * math.pi, psi=math.pi / 4)
    >>> dc = rr.direct_chaos_indicators(body, start, 300.0)
    >>> print(dc.indicators.regular, dc.theta_maxima.size)
    True 22
    """
    t_end, _, _, y0, rate = check_run(body, initial, t_end, samples=False)
    check_work(rate * t_end * VARIATIONAL_SECONDS_PER_RADIAN,
               f"the variational run (Λ t_end = {rate * t_end:.3g} radians)", budget)
    w0 = initial_tangent(y0, rate)
    ta = variational_integrator(len(body.params))
    _start(ta, body, y0, w0)
    own = start_turning_point(body, y0)
    window = own.window if own is not None and own.kind > 0 else -1.0
    stretch = CHUNK_RADIANS / rate
    times, logs, thetas, energies = array("d"), array("d"), array("d"), array("d")
    log_sum, n_steps = 0.0, 0
    while float(ta.time) < t_end:
        result = ta.propagate_until(min(t_end, float(ta.time) + stretch), max_steps=_STEPS_PER_STRETCH)
        n_steps += int(result[3])
        at_maximum = _check_outcome(ta, result[0])
        state = ta.state
        size = float(tangent_norm(state[_N:], rate))
        if at_maximum and float(ta.time) > window:
            times.append(float(ta.time))
            logs.append(log_sum + math.log(size))
            thetas.append(math.atan2(math.hypot(state[0], state[1]), state[2]))
            energies.append(float(energy(body, state[0:3], state[3:6])))
        log_sum += math.log(size)
        state[_N:] /= size
    theta_max = np.frombuffer(thetas, dtype=float).copy()
    check_theta_resolved(theta_max, initial)
    E0 = float(energy(body, y0[0:3], y0[3:6]))
    err = float(np.max(np.abs(np.frombuffer(energies, dtype=float) - E0), initial=0.0)) / energy_scale(body, E0)
    check_energy_error(err, n_steps, float(np.finfo(float).eps), strict,
                       " at the theta-maxima of the variational run")
    try:
        indicators = chaos_indicators(np.frombuffer(times, dtype=float).copy(), np.frombuffer(logs, dtype=float).copy())
    except ValueError as exc:
        raise ValueError(f"t_end={t_end!r}: {exc}") from None
    return DirectChaos(indicators=indicators, theta_maxima=theta_max, rate=rate, w0=w0, energy_rel_error=err,
                       n_steps=n_steps)
