"""The limits of a run of :func:`rocknroller.numerics.integrate.simulate`, checked before any work.

The work and memory of a run scale with Λ·t_end (:func:`rate_bound`); :func:`check_run` refuses a run past
``MAX_SAMPLES``, ``MAX_DENSE_RADIANS``, ``MAX_RADIANS`` or ``MAX_GRID_POINTS``, a body outside the accuracy ranges
``MOMENT_RANGE``, ``G_RANGE``, ``MAX_ENERGY_OVER_G`` and ``ENERGY_RANGE_NO_GRAVITY``, a start without motion and one whose energy keeps its tilt
below ``THETA_MIN``, with a ``ValueError`` that names the parameter and the limit.  The module docstring of
:mod:`rocknroller.numerics.integrate` derives each limit.

The tolerance
-------------
The accuracy knob of the direct runs is heyoka's tolerance ``tol``; its range and what follows from it:

heyoka's Taylor integrator takes one tolerance, relative and absolute at once: each step keeps its local error within
``tol`` · max(1, ‖y‖∞).  It sets the Taylor order, p = ⌈−ln(tol)/2⌉ + 1 (20 at tol = ε = 2u, the default; 14 at 1e-11,
12 at 1e-9, 8 at 1e-6), and the step follows from the series' radius of convergence, so the energy error comes in
levels, one per order, rather than in proportion to ``tol``.

What scales with ``tol``
------------------------
* The energy check (:func:`rocknroller.numerics.run_limits.energy_error_bound`): ``ENERGY_SLACK`` × (tol · n_steps + u).
  Its derivation holds at any tolerance: each step errs by at most tol of max(1, ‖y‖∞) (the unit vectors γ and e_X
  make ‖y‖∞ ≥ 1), the errors add at most linearly over n steps, and the energy, evaluated in double precision from
  the states, adds a few u relative to its scale.
* The smallest tilt resolved (:func:`theta_min`): ``THETA_MIN`` = 2¹⁰ u rests on the state's absolute error of u per
  step (:mod:`rocknroller.numerics.events`); at tolerance tol that error is tol/2 per step, so the smallest tilt at
  which the turning points keep a relative error ≤ 2⁻¹⁰ is 2¹⁰ · tol/2, ``THETA_MIN`` · tol/ε.
* The turning points: each run's are within n_steps · tol · max(1, ‖y‖∞) · S of the exact ones (S the amplification
  of an error by the flow), as at the default with tol for 2u (tests/numerics/test_batch.py derives the bound).

What does not: the location of the turning points on the dense output (to the rounding of t), the unwrapping grid,
the limits on a run's size, and the work estimate (a looser tolerance takes about as many steps of a lower order,
so :data:`rocknroller.numerics.budget.HEYOKA_SECONDS_PER_RADIAN`, measured at ε, bounds it).

Range
-----
``TOL_RANGE`` = [ε, 1e-6] in double precision (the unit round-off 2u of the precision run, and 1e-6).  Below ε heyoka
would ask its steps for more than their arithmetic holds; above 1e-6 the order drops below 8 and the energy bound,
10 tol per step, allows 1 % of the energy within 10³ steps: a run no longer worth its turning points.

Compilation
-----------
The compiled code depends on the order only, not on ``tol`` itself: heyoka's caches (in memory, and on disk in
``HEYOKA_CACHE_DIR``, both keyed by the generated code) hold one integrator per order.  A tolerance of an order not
yet compiled on the machine compiles once (measured: 0.4-0.9 s CPU for the scalar or the 8-lane batch integrator at
orders 9-10, 1.6 s for the batch one at order 14; the default order 20 ≈ 3 s, docs/performance.md), after which every
process loads it from the disk cache in ≈ 0.02 s CPU, and another tolerance of the same order is a hit in memory.
Each tolerance used keeps its own integrator per process and thread (≈ the default's memory).
"""

from __future__ import annotations

import math
from typing import Any, NamedTuple

import numpy as np
from numpy.typing import NDArray

from rocknroller.analysis.model.body import Body, LoadedSphere
from rocknroller.analysis.model.equations import EulerState
from rocknroller.analysis.model.invariants import energy
from rocknroller.numerics.events import _U, THETA_MIN

__all__ = ["check_run", "RunPlan", "rate_bound", "default_dt", "MAX_SAMPLES", "MAX_DENSE_RADIANS", "MAX_DENSE_STEPS",
           "MAX_RADIANS", "MAX_GRID_POINTS", "MOMENT_RANGE", "G_RANGE", "MAX_ENERGY_OVER_G",
           "ENERGY_RANGE_NO_GRAVITY", "DT_RADIANS", "UNWRAP_RADIANS", "DEFAULT_TOL", "TOL_MAX", "check_tol", "theta_min",
           "energy_scale", "energy_error_bound", "ENERGY_SLACK", "ENERGY_BOUND_MAX"]

MAX_SAMPLES = 2_000_000
MAX_DENSE_RADIANS = 3.0e5
MAX_DENSE_STEPS = 600_000
MAX_RADIANS = 1.0e8
MAX_GRID_POINTS = 2.0e8
MOMENT_RANGE = (1e-3, 1e3)
G_RANGE = (1e-12, 1e12)
MAX_ENERGY_OVER_G = 1e12
ENERGY_RANGE_NO_GRAVITY = (1e-12, 1e12)
#: Default output spacing in radians of Λ (≈ 0.05 time units for the paper's runs).
DT_RADIANS = 0.15
#: Default spacing, in radians of Λ, of the grid on which a run with ``samples=False`` unwraps φ and ψ and checks the
#: energy: ≈ 0.35 time units, ≈ 40 points per rocking period, for the paper's runs.  The unwrapping does not rest on
#: it: an interval over which an angle's rate at either end (φ̇, ψ̇ from the state, unbounded near the pole) would turn
#: it by 2π/3 is bisected down to the output grid's spacing ``DT_RADIANS``/Λ (:mod:`rocknroller.numerics.trajectory`),
#: so wherever the angles turn fast the grid is at least as fine as the output grid, and the turning
#: points are the same to the bit (tests/numerics/ensembles/test_batch.py); elsewhere 6.7× fewer points than ``DT_RADIANS``
#: cut a run's sampling by as much.
UNWRAP_RADIANS = 1.0



#: heyoka's default tolerance in double precision: the machine epsilon ε = 2u = 2⁻⁵².
DEFAULT_TOL = float(np.finfo(float).eps)
#: The loosest tolerance accepted (module docstring, "Range").
TOL_MAX = 1e-6


def check_tol(tol: Any, name: str = "tol", lowest: float = DEFAULT_TOL) -> float:
    """``tol`` as a float, checked to lie in [``lowest``, ``TOL_MAX``].

    Parameters
    ----------
    tol : float
        The tolerance asked for.
    name : str
        The parameter as the user typed it (``"tol"``, or ``"--tol"`` on the command line).
    lowest : float
        The machine epsilon of the precision run (default double's, ``DEFAULT_TOL``).

    Raises
    ------
    ValueError
        Naming ``name`` and the range, for anything but a real number in the range.
    """
    try:
        value = float(tol) if not isinstance(tol, (bool, str, bytes)) else math.nan
    except (TypeError, ValueError, OverflowError):
        value = math.nan
    if not lowest <= value <= TOL_MAX:  # False for NaN
        raise ValueError(f"{name} must be a number in [{lowest!r}, {TOL_MAX:g}] (from the machine epsilon of the "
                         f"precision to {TOL_MAX:g}), got {name}={tol!r}")
    return value


def theta_min(tol: float) -> float:
    """The smallest amplitude of θ whose turning points a run at tolerance ``tol`` resolves: ``THETA_MIN`` at the
    default tolerance and below it (extended precision: the state is rounded to double), ``THETA_MIN`` · tol/ε above
    (module docstring)."""
    return THETA_MIN * max(1.0, tol / DEFAULT_TOL)


def _theta_min_name(lowest: float) -> str:
    """How the error messages name the smallest tilt resolved: ``THETA_MIN``, or ``theta_min(tol)`` above it."""
    return "THETA_MIN" if lowest == THETA_MIN else "theta_min(tol)"

def rate_bound(body: Body | LoadedSphere, y0: NDArray[np.float64]) -> float:
    """Λ = √(2(E + g a)/I_min): a bound on |ω(t)| for all t (½ I_min |ω|² ≤ T ≤ E) that also covers the
    rocking rate √(g a/I) of motions near rest (a = |c| for a LoadedSphere).  Work and memory of a run scale with
    Λ·t_end."""
    E = float(energy(body, y0[0:3], y0[3:6]))
    return math.sqrt(2.0 * (E + body.g * body.offset_norm) / min(body.I1, body.I2, body.I3))


def default_dt(t_end: float, rate: float, samples: bool = True) -> float:
    """Default sample spacing: ``DT_RADIANS``/Λ (≈ 0.05 time units, ≈ 200 samples per rocking period, for
    the paper's runs), and at least 200 samples over the run (a t_end so small that t_end/200 underflows to 0
    gets the two samples 0 and t_end).  With ``samples=False``, the unwrapping grid's: ``UNWRAP_RADIANS``/Λ, at least
    200 points."""
    return min((DT_RADIANS if samples else UNWRAP_RADIANS) / rate, t_end / 200.0) or t_end


def _validate(body: Body | LoadedSphere, initial: EulerState, t_end: float,
              tol: float = DEFAULT_TOL) -> tuple[NDArray[np.float64], float]:
    if not isinstance(body, (Body, LoadedSphere)):
        raise ValueError(f"body must be a rocknroller Body or LoadedSphere, got {type(body).__name__}")
    if not isinstance(initial, EulerState):
        raise ValueError(f"initial must be a rocknroller.analysis.model.equations.EulerState, got {type(initial).__name__}")
    if not math.isfinite(t_end) or t_end <= 0.0:
        raise ValueError(f"t_end must be a finite number > 0, got t_end={t_end!r}")
    lo, hi = MOMENT_RANGE
    for name in ("I3", "I1", "I2"):  # I3 first: the CLI derives I1 (and I2) from it by default
        if not lo <= getattr(body, name) <= hi:
            raise ValueError(f"{name} must lie in [{lo:g}, {hi:g}] (units of m R^2) for the integrator to be "
                             f"accurate (the energy error grows as 1/I_min), got {name}={getattr(body, name)!r}")
    if not (body.g == 0.0 or G_RANGE[0] <= body.g <= G_RANGE[1]):
        raise ValueError(f"g must be 0 or lie in [{G_RANGE[0]:g}, {G_RANGE[1]:g}] (g only sets the unit of time; "
                         f"rescale time to bring it there), got g={body.g!r}")
    y0 = initial.to_body_state()
    with np.errstate(over="ignore", invalid="ignore"):  # rates of 1e200 overflow E to inf: refused below
        E = float(energy(body, y0[0:3], y0[3:6]))
    if body.g > 0.0 and not E <= MAX_ENERGY_OVER_G * body.g:
        raise ValueError(f"the initial rates are too large: the energy E = {E:.3g} exceeds {MAX_ENERGY_OVER_G:g} g "
                         f"(units m g R); reduce the rates (theta_dot, phi_dot, psi_dot or omega)")
    lo_E, hi_E = ENERGY_RANGE_NO_GRAVITY
    if body.g == 0.0 and np.any(y0[3:6]) and not lo_E <= E <= hi_E:
        raise ValueError(f"without gravity (g = 0) the energy sets the unit of time and must lie in [{lo_E:g}, "
                         f"{hi_E:g}], got E = {E:.3g}; scale the rates (theta_dot, phi_dot, psi_dot or omega)")
    if not np.any(y0[3:6]) and _at_equilibrium(body, initial, y0):
        raise ValueError(
            "the initial state has no motion: the body is at rest in an equilibrium (theta0 = 0 or pi, or any "
            "theta0 when a = 0 or g = 0; for a LoadedSphere, the vertical along its offset c, or c = 0 or g = 0); "
            "give a tilted start with a > 0 and g > 0, or a non-zero rate")
    if not E + body.g * body.offset_norm > 0.0:
        # Λ = 0: T = ½ ωᵀKω ≥ ½ I_min |ω|² (K ≥ I_min) underflows to 0 when ½ I_min |ω|² is below half the smallest
        # subnormal number, i.e. |ω| < √(2⁻¹⁰⁷⁴/I_min); with g a = 0 nothing else moves the body
        w_min = math.sqrt(math.ulp(0.0) / min(body.I1, body.I2, body.I3))
        raise ValueError(
            f"the initial state has no motion to resolve: {initial} has the kinetic energy E = {E!r} in double "
            f"precision (its rates, max |omega_i| = {float(np.max(np.abs(y0[3:6]))):.3g}, are below about {w_min:.2g}, "
            f"where (1/2) I_min |omega|^2 underflows) and g a = {body.g * body.offset_norm!r}; give a > 0 or larger "
            "rates")
    if isinstance(body, Body):  # the tilt bound below is the on-axis potential's g a (1 - cos θ)
        _check_tilt_resolved(body, initial, y0, E, theta_min(tol))
    return y0, rate_bound(body, y0)


def _at_equilibrium(body: Body | LoadedSphere, initial: EulerState, y0: NDArray[np.float64]) -> bool:
    """Whether a start at rest is an equilibrium: no gravity or no offset, or the vertical along the offset (for a
    Body, θ0 = 0 or π, as γ1 = γ2 = 0).  For a LoadedSphere, to the rounding of γ0: |γ0 × c| ≤ 4 u |c| (γ0's
    components carry a rounding of a few u each, from the Euler angles' sines and cosines)."""
    if isinstance(body, Body):
        return body.a == 0.0 or body.g == 0.0 or initial.theta in (0.0, math.pi) or not np.any(y0[0:2])
    c1, c2, c3 = body.offset
    g1, g2, g3 = y0[0:3]
    torque = math.hypot(g2 * c3 - g3 * c2, g3 * c1 - g1 * c3, g1 * c2 - g2 * c1)
    return body.g == 0.0 or body.offset_norm == 0.0 or torque <= 4.0 * _U * body.offset_norm


def _check_tilt_resolved(body: Body, initial: EulerState, y0: NDArray[np.float64], E: float,
                         lowest: float = THETA_MIN) -> None:
    """Refuse a motion whose energy keeps its tilt below ``lowest`` (``THETA_MIN`` at the default tolerance, see
    there; :func:`theta_min`).

    V = g a (1 − cos θ) ≤ E bounds the tilt by θ_E, 2 g a sin²(θ_E/2) = E = T + V; in the upper hemisphere V is taken
    as g a (γ1² + γ2²)/(1 + γ3), which keeps its digits where 1 − γ3 rounds to 0 (θ < 1.5e-8), and T = E − g a (1 − γ3)
    exactly as ``energy`` adds it up.  Without a potential (a = 0 or g = 0) the energy bounds no tilt.
    """
    if body.a == 0.0 or body.g == 0.0:
        return
    ga = body.g * body.a
    one_minus_c = (y0[0] ** 2 + y0[1] ** 2) / (1.0 + y0[2]) if y0[2] > 0.0 else 1.0 - y0[2]
    s2 = ((E - ga * (1.0 - y0[2])) + ga * one_minus_c) / (2.0 * ga)  # sin²(θ_E/2)
    if s2 < math.sin(0.5 * lowest) ** 2:
        theta_E = 2.0 * math.asin(math.sqrt(max(s2, 0.0)))
        raise ValueError(
            f"theta0={initial.theta!r}: the start's energy keeps its tilt within theta_E = {theta_E:.3g} rad of the "
            f"pole, below {_theta_min_name(lowest)} = {lowest:.3g} rad, the smallest amplitude at which the "
            f"integrator resolves the turning points of theta (its state carries an absolute error of "
            f"{lowest / THETA_MIN * _U:.3g} per step); give theta0 >= {lowest:.3g} or larger rates")



class RunPlan(NamedTuple):
    """A run of :func:`~rocknroller.numerics.integrate.simulate` checked by :func:`check_run`."""

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


def check_run(body: Body | LoadedSphere, initial: EulerState, t_end: float, *, dt: float | None = None,
              samples: bool = True, tol: float = DEFAULT_TOL) -> RunPlan:
    """Check a run of :func:`~rocknroller.numerics.integrate.simulate` against its limits before any work: every
    check ``simulate`` makes on the body, the initial state, ``t_end`` and ``dt``.

    Parameters
    ----------
    body, initial, t_end, dt, samples : as for :func:`~rocknroller.numerics.integrate.simulate`.
    tol : float
        The integrator's tolerance, already checked (:func:`check_tol`): it sets the smallest tilt resolved
        (:func:`theta_min`).

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
    y0, rate = _validate(body, initial, t_end, tol)
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


def energy_scale(body: Body | LoadedSphere, E0: float) -> float:
    """Scale of the energy error: E(0) + g a (g|c| for a LoadedSphere, whose 0 ≤ V ≤ 2 g|c| likewise).

    Every term of E = T + V is bounded by it within a factor 3 (T ≤ E, 0 ≤ V = g a (1 − cos θ) ≤ 2 g a),
    so the round-off of one evaluation of E is a few units of u·(E + g a), and the scale never vanishes:
    g a > 0 for a > 0, and for a = 0 a state with motion has E = T > 0 (rest is refused by ``simulate``).
    Relative to E alone the error of a body released from rest at θ0 → 0 would be measured against
    E ≈ g a θ0²/2 → 0, which the round-off of g a (1 − cos θ) does not follow.
    """
    return abs(float(E0)) + body.g * body.offset_norm


def energy_error_bound(tolerance: float, n_steps: int) -> float:
    """The relative energy error a run may reach: ``ENERGY_SLACK`` × (tolerance × steps + u).

    Each step of an integrator run at relative tolerance ``tolerance`` commits a local error of at most
    about ``tolerance`` of the state, and in the worst case these add up linearly in the number of steps;
    the energy is evaluated in double precision from states rounded to double, which adds a few units of
    u = 2⁻⁵³·2 (``np.finfo(float).eps``) relative to :func:`energy_scale` whatever the integrator's precision.
    A run whose energy error exceeds this bound has missed the asked tolerance by far (the paper's runs
    stay 10²–10⁴ below it).
    """
    return ENERGY_SLACK * (float(tolerance) * max(int(n_steps), 1) + float(np.finfo(float).eps))


#: Factor of :func:`energy_error_bound` over the linear accumulation of the per-step tolerance.
ENERGY_SLACK = 10.0
#: Largest :func:`energy_error_bound` with which the energy check still vouches for a run: past a tenth of the energy
#: scale, an error the bound allows is one that has left the energy surface (at ``TOL_MAX`` over 10⁵ time units of
#: the paper's runs it was 2.6, 261 %, and ``--strict`` could never fail).
ENERGY_BOUND_MAX = 0.1
