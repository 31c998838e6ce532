"""Phase volume along the loaded spheres' flow: its divergence, its time average along a run, and the steady rotations.

The flow f = (γ̇, ω̇) = (γ × ω, K⁻¹P) of :func:`~rocknroller.analysis.model.equations.body_frame_rhs` lives on R⁶ and
keeps |γ| (γ̇ ⟂ γ), so its divergence on R⁶ is the divergence on the state space |γ| = 1 (the spheres |γ| = const
are a fixed distance apart).  As ∂(γ × ω)_i/∂γ_i = 0,

    div f = tr(∂ω̇/∂ω) = n(γ)·ω / det K,

linear in ω (:mod:`rocknroller.analysis.hierarchy.measure` proves it) and so odd under ω → −ω.  Along an orbit, the sum
of the Lyapunov exponents is the time average of div f (Liouville: d/dt log det(∂x(t)/∂x0) = div f(x(t))).  A member
with an invariant density ρ has div f = −d/dt log ρ, so the average is −[log ρ]₀ᵗ/t, bounded by C/t
(:func:`log_density`, :func:`log_density_range`): Chaplygin's ball, Routh's sphere.  Without one (the rock'n'roller,
Chaplygin's top) an orbit may settle where volumes contract on average: an attractor (average < 0).

Reversibility.  (γ(t), ω(t)) solves the equations if and only if (γ(−t), −ω(−t)) does.  So the run backward in time
from (γ0, ω0) over [0, T] is the forward run from (γ0, −ω0) (:func:`reversed_state`), traversed with ω negated, and as
div f is odd in ω, its average of div f is minus the forward run's: ``phase_volume_rate(..., backward=True)`` is
−``phase_volume_rate(body, reversed_state(initial), ...)``.  The involution (γ, ω) → (γ, −ω) maps every attractor
to a repeller, where the forward flow expands volumes (average > 0) and which the backward run approaches.

The steady rotations (:func:`steady_rotation`) are the fixed points of the (γ, ω) flow: the body spins at a rate s
about the vertical, ω = s γ, at the tilt where gravity balances the gyroscopic torque,

    γ × [s² I γ − (s² (1 + c·γ) + g) c] = 0,

the same γ for ±s.  div f there is s n(γ)·γ/det K: opposite for ±s, zero at s = 0 and wherever c ∥ γ, and not zero
for Chaplygin's top (the witness of :mod:`~rocknroller.analysis.hierarchy.measure` at ω ∥ γ is such a state).

Examples
--------
>>> import numpy as np
>>> import rocknroller as rr
>>> from rocknroller.analysis.hierarchy.phase_volume import divergence
>>> top = rr.Body.chaplygin_top(0.35, 0.37, 0.4, offset=(0.03, -0.02, -0.05))
>>> gamma, omega = np.array([0.6, 0.0, 0.8]), np.array([0.3, -1.0, 2.0])
>>> print(float(divergence(top, gamma, omega)) == -float(divergence(top, gamma, -omega)))
True
"""

from __future__ import annotations

import math
from dataclasses import dataclass, field, replace
from typing import Any

import numpy as np
from numpy.typing import ArrayLike, NDArray

from rocknroller.analysis.model.body import MEMBERS, Body, LoadedSphere, float_or_nan
from rocknroller.analysis.model.equations import STATE_SIZE, EulerState, body_frame_rhs, euler_from_state
from rocknroller.numerics.integrate import simulate
from rocknroller.numerics.run_limits import rate_bound
from rocknroller.numerics.trajectory import TurningPoints

__all__ = ["COMPLEX_STEP_EXPONENT", "PANEL_RADIANS", "CHECKPOINTS", "SPIN_MAX", "divergence", "reversed_state",
           "advance", "PhaseVolumeRate", "phase_volume_rate", "log_density", "log_density_range", "SteadyRotation",
           "steady_rotation"]

#: The complex step is h = 2^(e + COMPLEX_STEP_EXPONENT), 2^e the binary order of 1 + ‖ω‖∞ (h ≈ 1e-30 relative to ω).
#: ω̇ = K(γ)⁻¹ P(γ, ω) with K free of ω and P quadratic in ω, so Im ω̇(ω + i h e_k) = h ∂ω̇/∂ω_k exactly: the h² term
#: of each product of two perturbed factors is real, and no product of two complex factors has a real part that carries
#: an earlier h² term (P's terms are ω × Iω, r × (ω × γ̇), r × (ω × (ω × r)) with r, K real).  So any h is exact up to
#: the rounding of the formula, with no cancellation; h only keeps the imaginary parts in the normal range and h²
#: (1e-60 relative) away from the real parts' digits.  A power of two makes the division by h exact.
COMPLEX_STEP_EXPONENT = -100
#: Width of a quadrature panel in radians of Λ (:func:`~rocknroller.numerics.run_limits.rate_bound`).  heyoka takes
#: 0.8-2 steps per radian (order 20 at tol = ε), so div f(t), analytic along the orbit, is analytic in a strip about a
#: panel's width wide; there the 8-point Gauss–Legendre rule's error is below the 6-point rule's by a factor ρ⁴ (ρ the
#: Bernstein ellipse's parameter, > 1), and |Q8 − Q6| bounds Q8's error once ρ⁴ ≥ 2.  Measured on the torus attractor of
#: validation/hierarchy/chaplygin_top.py (Λ ≈ 15, 2.1 steps per radian) over 2000 time units: Σ|Q8 − Q6| = 1e-5, while Q8 is
#: within 3e-8 of the 12-point rule: the bound is conservative by ~400 there.
PANEL_RADIANS = 1.0
#: Fractions of the run at which :class:`PhaseVolumeRate` reports the running average (panels come in multiples of 8).
CHECKPOINTS = (0.125, 0.25, 0.5, 1.0)
#: Panels evaluated at once: ≤ 4096 states per rule, whose complex step's arrays (11 × 3 × 4096 complex, 1.4 MB) stay in
#: the cache: 0.7 µs a state, against 2 µs at 6·10⁴ states (measured).
_PANEL_CHUNK = 2**9
#: Largest |spin| of :func:`steady_rotation`, whose continuation from rest takes |s|/_SPIN_STEP steps.
SPIN_MAX = 100.0
_SPIN_STEP = 0.25
_NEWTON_ITERATIONS = 50
_U = 0.5 * np.finfo(float).eps
_GAUSS = tuple(np.polynomial.legendre.leggauss(n) for n in (8, 6))


def _real(value: Any) -> float:
    """``float(value)`` for a real number, NaN for anything else (a string or a bool is not a number here)."""
    return math.nan if isinstance(value, (str, bytes, bool)) else float_or_nan(value)


def _sphere(body: Body | LoadedSphere) -> LoadedSphere:
    if isinstance(body, Body):
        return body.as_loaded_sphere()
    if not isinstance(body, LoadedSphere):
        raise ValueError(f"body must be a rocknroller Body or LoadedSphere, got {type(body).__name__}")
    return body


def divergence(body: Body | LoadedSphere, gamma: ArrayLike, omega: ArrayLike) -> NDArray[np.float64]:
    """div f = tr(∂ω̇/∂ω) of the flow at states (γ, ω), by the complex step (exact up to rounding, see
    ``COMPLEX_STEP_EXPONENT``).

    Parameters
    ----------
    body : Body or LoadedSphere
    gamma, omega : array_like, shape (3, ...)
        The upward vertical and the angular velocity in body components, finite, of one shape.

    Returns
    -------
    ndarray, shape (...)

    Examples
    --------
    >>> import numpy as np
    >>> import rocknroller as rr
    >>> from rocknroller.analysis.hierarchy.phase_volume import divergence
    >>> ball = rr.Body.chaplygin_ball(0.35, 0.37, 0.4)
    >>> print(float(divergence(ball, [0.0, 0.0, 1.0], [0.0, 0.0, 5.0])))  # spinning about a principal vertical
    0.0
    """
    params = _sphere(body).params
    g, w = np.asarray(gamma, float), np.asarray(omega, float)
    if g.shape[:1] != (3,) or w.shape != g.shape:
        raise ValueError(f"gamma and omega must be arrays of one shape (3, ...), got shapes {g.shape} and {w.shape}")
    if not (np.all(np.isfinite(g)) and np.all(np.isfinite(w))):
        raise ValueError("gamma and omega must be finite")
    h = np.ldexp(1.0, np.frexp(1.0 + np.max(np.abs(w), axis=0))[1] + COMPLEX_STEP_EXPONENT)
    y = np.zeros((STATE_SIZE, 3) + g.shape[1:], complex)  # e_X = 0: it drives only its own derivative
    y[0:3], y[3:6] = g[:, None], w[:, None]
    for k in range(3):
        y[3 + k, k] += 1j * h
    rhs = body_frame_rhs(y, params)
    return (rhs[3][0].imag + rhs[4][1].imag + rhs[5][2].imag) / h


def reversed_state(initial: EulerState) -> EulerState:
    """The state (γ0, −ω0): the same angles, every rate negated (exactly: ω is linear in the rates).

    Examples
    --------
    >>> import rocknroller as rr
    >>> from rocknroller.analysis.hierarchy.phase_volume import reversed_state
    >>> start = rr.EulerState.from_omega(2.0, 0.0, 0.4, (0.7, -0.5, 1.3))
    >>> print(reversed_state(start).omega, reversed_state(reversed_state(start)) == start)
    (-0.7, 0.5, -1.3) True
    """
    return replace(initial, theta_dot=-initial.theta_dot, phi_dot=-initial.phi_dot, psi_dot=-initial.psi_dot,
                   omega=None if initial.omega is None else (-initial.omega[0], -initial.omega[1], -initial.omega[2]))


def advance(body: Body | LoadedSphere, initial: EulerState, t: float) -> EulerState:
    """The state reached from ``initial`` after time ``t`` (:func:`~rocknroller.numerics.integrate.simulate`'s limits
    on t), as an :class:`EulerState` with its body-frame ω: to measure on an attractor after a transient, or to run
    back.  γ is rebuilt from the Euler angles, to a few u.

    Examples
    --------
    >>> import rocknroller as rr
    >>> from rocknroller.analysis.hierarchy.phase_volume import advance, reversed_state
    >>> top = rr.Body.chaplygin_top(0.35, 0.37, 0.4, offset=(0.03, -0.02, -0.05))
    >>> start = rr.EulerState.from_omega(2.0, 0.0, 0.4, (0.7, -0.5, 1.3))
    >>> back = advance(top, reversed_state(advance(top, start, 5.0)), 5.0)
    >>> print(max(abs(a + b) for a, b in zip(back.omega, start.omega)) < 1e-12)
    True
    """
    y = simulate(body, initial, t, dt=t).states[-1]
    theta, phi, psi = euler_from_state(y)[:3]
    return EulerState.from_omega(theta, phi, psi, y[3:6], X=y[9], Y=y[10])


@dataclass(frozen=True)
class PhaseVolumeRate:
    """The time average of div f along one run (:func:`phase_volume_rate`).

    Attributes
    ----------
    rate : float
        (1/T)∫₀ᵀ div f dt along the run, the sum of its finite-time Lyapunov exponents; backward, along the backward
        orbit x(−t), t ∈ [0, T].
    error : float
        Bound on the quadrature's error in ``rate`` (Σ|Q8 − Q6| over the panels, over T; the orbit's own integration
        error is not in it: the average is that of the computed orbit).
    t_end : float
    backward : bool
    checkpoints : tuple of tuple
        (time, average): the running average at the fractions ``CHECKPOINTS`` of the run.
    energy_rel_error : float
        The run's (:attr:`~rocknroller.numerics.trajectory.Trajectory.energy_rel_error`).
    n_steps : int
        The run's integration steps.
    t, running : ndarray
        The ends of the quadrature panels and the running average there (np.cumsum: for plots).
    maxima : rocknroller.numerics.trajectory.TurningPoints
        The θ-maxima of the run integrated (backward: the forward run from :func:`reversed_state`, whose ω are the
        backward orbit's negated, at times −t).
    """

    rate: float
    error: float
    t_end: float
    backward: bool
    checkpoints: tuple[tuple[float, float], ...]
    energy_rel_error: float
    n_steps: int
    t: NDArray[np.float64] = field(repr=False, compare=False)
    running: NDArray[np.float64] = field(repr=False, compare=False)
    maxima: TurningPoints = field(repr=False, compare=False)

    @property
    def drift(self) -> float:
        """How much the running average still moved over the second half: its change from half-time to the end."""
        return abs(self.checkpoints[-1][1] - self.checkpoints[-2][1])


def phase_volume_rate(body: Body | LoadedSphere, initial: EulerState, t_end: float, backward: bool = False, *,
                      progress: bool | None = False) -> PhaseVolumeRate:
    """The time average of div f along the run from ``initial`` over [0, t_end], forward or backward in time.

    The run is :func:`~rocknroller.numerics.integrate.simulate`'s (heyoka at ε); ∫ div f dt is the 8-point
    Gauss–Legendre rule on panels of ``PANEL_RADIANS``/Λ of its dense output, with the 6-point rule beside it for the
    error bound.  Backward: the forward run from :func:`reversed_state` with the sign of div f flipped (module
    docstring).

    Parameters
    ----------
    body, initial, t_end : as for :func:`~rocknroller.numerics.integrate.simulate`, whose limits apply (Λ t_end ≤
        ``MAX_DENSE_RADIANS``: at most that many panels, each 14 evaluations of div f, ≈ 0.7 µs each).
    backward : bool
        Average along the orbit backward in time.
    progress : bool or None
        ``simulate``'s progress bar.

    Returns
    -------
    PhaseVolumeRate

    Examples
    --------
    >>> import rocknroller as rr
    >>> from rocknroller.analysis.hierarchy.phase_volume import phase_volume_rate
    >>> ball = rr.Body.chaplygin_ball(0.35, 0.37, 0.4)
    >>> start = rr.EulerState.from_omega(2.0, 0.0, 0.4, (0.7, -0.5, 1.3))
    >>> fwd, bwd = phase_volume_rate(ball, start, 100.0), phase_volume_rate(ball, start, 100.0, backward=True)
    >>> print(abs(fwd.rate) < 0.05 / 100, abs(bwd.rate) < 0.05 / 100, fwd.error < 1e-13)
    True True True
    """
    run = simulate(body, reversed_state(initial) if backward else initial, t_end, dt=t_end / 8, progress=progress)
    t_end = float(run.t[-1])
    sign = -1.0 if backward else 1.0
    n = 8 * math.ceil(rate_bound(body, run.states[0]) * t_end / (8 * PANEL_RADIANS))
    width = t_end / n
    sums = np.empty((2, n))
    for a in range(0, n, _PANEL_CHUNK):
        b = min(n, a + _PANEL_CHUNK)
        mid = (np.arange(a, b) + 0.5) * width
        for k, (nodes, weights) in enumerate(_GAUSS):
            y = run.state_at((mid[:, None] + 0.5 * width * nodes).ravel())
            d = divergence(body, y[:, 0:3].T, y[:, 3:6].T).reshape(b - a, nodes.size)
            sums[k, a:b] = 0.5 * width * (d @ weights)
    q = sign * sums[0]
    ends = np.arange(1, n + 1, dtype=np.float64) * width
    marks = tuple((f * t_end, math.fsum(q[:round(f * n)]) / (f * t_end)) for f in CHECKPOINTS)
    return PhaseVolumeRate(rate=marks[-1][1], error=math.fsum(np.abs(sums[0] - sums[1])) / t_end, t_end=t_end,
                           backward=bool(backward), checkpoints=marks, energy_rel_error=run.energy_rel_error,
                           n_steps=run.n_steps, t=ends, running=np.asarray(np.cumsum(q) / ends, np.float64),
                           maxima=run.maxima)


def _density_member(body: Body | LoadedSphere) -> tuple[LoadedSphere, str]:
    """The body as a LoadedSphere and its member, for the members with a density of γ alone written here."""
    sphere = _sphere(body)
    kind = sphere.kind
    if kind == MEMBERS[0] or (kind == MEMBERS[2] and sphere.offset[:2] == (0.0, 0.0) and sphere.I1 == sphere.I2):
        return sphere, kind
    raise ValueError(f"the invariant density is written here for Chaplygin's ball (c = 0) and Routh's sphere with c on "
                     f"the third axis (c1 = c2 = 0, I1 = I2); got {sphere.describe()} (rotate the axes with "
                     f"body.relabelled for Routh's sphere about another axis)")


def log_density(body: Body | LoadedSphere, gamma: ArrayLike) -> NDArray[np.float64]:
    """log ρ(γ) of the invariant density in (γ, ω) of Chaplygin's ball, ρ = √det K, or of Routh's sphere,
    ρ = det K (I3 + s² + (I3/I1) f²)^(−1/2), s² = γ1² + γ2², f = γ3 + c3
    (:mod:`~rocknroller.analysis.hierarchy.measure`); div f = −d/dt log ρ along the flow.

    Examples
    --------
    >>> import math
    >>> import rocknroller as rr
    >>> from rocknroller.analysis.hierarchy.phase_volume import log_density
    >>> ball = rr.Body.chaplygin_ball(0.35, 0.37, 0.4)  # det K = (1 + I1)(1 + I2) I3 at γ = e3
    >>> print(f"{float(log_density(ball, [0.0, 0.0, 1.0])):.15f}", f"{0.5 * math.log(1.35 * 1.37 * 0.4):.15f}")
    -0.150687699791892 -0.150687699791892
    """
    sphere, kind = _density_member(body)
    g = np.asarray(gamma, float)
    if g.shape[:1] != (3,) or not np.all(np.isfinite(g)):
        raise ValueError(f"gamma must be a finite array of shape (3, ...), got shape {g.shape}")
    r = g + np.reshape(sphere.offset, (3,) + (1,) * (g.ndim - 1))
    K = np.diag((sphere.I1, sphere.I2, sphere.I3)) + np.einsum("i...,i...->...", r, r)[..., None, None] * np.eye(3) \
        - np.einsum("i...,j...->...ij", r, r)
    log_det = np.log(np.linalg.det(K))
    if kind == MEMBERS[0]:
        return 0.5 * log_det
    return log_det - 0.5 * np.log(sphere.I3 + g[0] ** 2 + g[1] ** 2 + sphere.I3 / sphere.I1 * r[2] ** 2)


def log_density_range(body: Body | LoadedSphere) -> float:
    """A bound C on max log ρ − min log ρ over the sphere |γ| = 1, so that |(1/t)∫₀ᵗ div f| ≤ C/t on every orbit.

    Chaplygin's ball: det K = Π(1 + I_j) Σ γ_i² q_i, q_i = I_i/(1 + I_i) (the determinant lemma on
    diag(I) + 1 − γγᵀ), so C = ½ log(max q / min q), exactly.  Routh's sphere: with x = γ3,
    ρ = √I1 (I1 + r·r) √(I1 I3 + I1 (1 − x²) + I3 (x + c3)²) (det K = (I1 + r·r)(I1 I3 + I1 s² + I3 f²)),
    r·r = 1 + 2 c3 x + c3² monotone in x and the last root's argument a quadratic in x: C is the sum of the two
    factors' log-ranges over x ∈ [−1, 1] (endpoints and the quadratic's vertex), an upper bound.

    Examples
    --------
    >>> import rocknroller as rr
    >>> from rocknroller.analysis.hierarchy.phase_volume import log_density_range
    >>> print(f"{log_density_range(rr.Body.chaplygin_ball(0.35, 0.37, 0.4)):.4f}")
    0.0486
    """
    sphere, kind = _density_member(body)
    I1, I3 = sphere.I1, sphere.I3
    if kind == MEMBERS[0]:
        q = [m / (1.0 + m) for m in (sphere.I1, sphere.I2, sphere.I3)]
        return 0.5 * math.log(max(q) / min(q))
    c3 = sphere.offset[2]
    linear = abs(math.log((I1 + (1.0 + c3) ** 2) / (I1 + (1.0 - c3) ** 2)))
    xs = [-1.0, 1.0] + ([-I3 * c3 / (I3 - I1)] if I3 != I1 and abs(I3 * c3 / (I3 - I1)) <= 1.0 else [])
    quad = [I1 * I3 + I1 * (1.0 - x * x) + I3 * (x + c3) ** 2 for x in xs]
    return linear + 0.5 * math.log(max(quad) / min(quad))


@dataclass(frozen=True)
class SteadyRotation:
    """A steady rotation about the vertical (:func:`steady_rotation`): a fixed point of the (γ, ω) flow.

    Attributes
    ----------
    spin : float
        The vertical spin s = ω·γ.
    gamma, omega : tuple of 3 floats
        The vertical in body components and ω = s γ.
    divergence : float
        div f there: the sum of the Lyapunov exponents of every orbit that tends to it.
    eigenvalues : tuple of complex
        Of the 6 × 6 Jacobian J of (γ̇, ω̇) (complex step), by decreasing real part.  Two vanish: |γ| (kept by the
        flow) and the family of rotations (s, or the energy); the other four decide :attr:`stability`.
    resolution : float
        2¹⁰ u ‖J‖_F: a real part within it is not told from 0 (an eigenvalue's rounding is about κ u ‖J‖, κ its
        condition number, here ≲ 10², and J's entries are within a few u).
    """

    spin: float
    gamma: tuple[float, float, float]
    omega: tuple[float, float, float]
    divergence: float
    eigenvalues: tuple[complex, ...] = field(repr=False)
    resolution: float = field(repr=False)

    @property
    def stability(self) -> str:
        """"attracting" or "repelling" (the four eigenvalues that are not the two zeros, those nearest 0, all to the
        left or all to the right of the imaginary axis), "saddle" (on both sides), or "neutral" (a real part within
        :attr:`resolution` of 0, and none on the other side: the rest state, whose rocking is undamped)."""
        real = [e.real for e in sorted(self.eigenvalues, key=abs)[2:]]
        left, right = any(x < -self.resolution for x in real), any(x > self.resolution for x in real)
        if left and right:
            return "saddle"
        if all(abs(x) > self.resolution for x in real):
            return "attracting" if left else "repelling"
        return "neutral"

    def nearby(self, tilt: float) -> EulerState:
        """A start near the rotation: the vertical turned by ``tilt`` radians (|tilt| ≤ π/2) towards the body axis
        e1 × γ (e2 × γ if γ is within 26° of e1), spinning at s about it (ω = s γ'), with φ0 = 0."""
        t = _real(tilt)
        if not abs(t) <= 0.5 * math.pi:
            raise ValueError(f"tilt must be a real number with |tilt| <= pi/2, got tilt={tilt!r}")
        g = np.array(self.gamma)
        axis = np.cross((1.0, 0.0, 0.0) if abs(g[0]) < 0.9 else (0.0, 1.0, 0.0), g)
        g = math.cos(t) * g + math.sin(t) * axis / np.linalg.norm(axis)
        return EulerState.from_omega(math.acos(max(-1.0, min(1.0, g[2]))), 0.0, math.atan2(g[0], g[1]), self.spin * g)


def steady_rotation(body: Body | LoadedSphere, spin: float) -> SteadyRotation:
    """The steady rotation about the vertical at vertical spin ``spin``, continued from rest with the mass centre
    lowest (γ = −c/|c|) in steps of s of at most 0.25, each solved by Newton's method on
    γ × [s² I γ − (s² (1 + c·γ) + g) c] + (γ·γ − 1) γ = 0 to the rounding of its terms.

    Parameters
    ----------
    body : Body or LoadedSphere
        With c ≠ 0 and g > 0 (else every vertical is an equilibrium at rest).
    spin : float
        |spin| ≤ ``SPIN_MAX``.

    Examples
    --------
    >>> import rocknroller as rr
    >>> from rocknroller.analysis.hierarchy.phase_volume import steady_rotation
    >>> top = rr.Body.chaplygin_top(0.15, 0.4, 0.5, offset=(0.3, 0.3, -0.3))
    >>> fwd, bwd = steady_rotation(top, 6.0), steady_rotation(top, -6.0)
    >>> print(fwd.stability, bwd.stability, f"{fwd.divergence:.4f} {bwd.divergence:.4f}")
    repelling attracting 0.0257 -0.0257
    """
    sphere = _sphere(body)
    s = _real(spin)
    if not abs(s) <= SPIN_MAX:
        raise ValueError(f"spin must be a real number with |spin| <= SPIN_MAX = {SPIN_MAX:g}, got spin={spin!r}")
    if not (sphere.offset_norm > 0.0 and sphere.g > 0.0):
        raise ValueError(f"a steady rotation from rest needs c != 0 and g > 0, got c={sphere.offset!r}, g={sphere.g!r}")
    c, inertia = np.array(sphere.offset), np.array((sphere.I1, sphere.I2, sphere.I3))
    gamma = -c / sphere.offset_norm
    for step in np.linspace(0.0, s, max(2, math.ceil(abs(s) / _SPIN_STEP) + 1))[1:]:
        gamma = _newton(gamma, step * step * inertia, step * step, c, sphere.g)
    omega = s * gamma
    jac = _jacobian(sphere, np.concatenate([gamma, omega]))
    ev = np.linalg.eigvals(jac)
    return SteadyRotation(spin=s, gamma=(float(gamma[0]), float(gamma[1]), float(gamma[2])),
                          omega=(float(omega[0]), float(omega[1]), float(omega[2])),
                          divergence=float(np.trace(jac)),
                          eigenvalues=tuple(complex(e) for e in ev[np.argsort(-ev.real, kind="stable")]),
                          resolution=2.0**10 * _U * float(np.linalg.norm(jac)))


def _newton(gamma: NDArray[np.float64], s2_inertia: NDArray[np.float64], s2: float, c: NDArray[np.float64],
            g: float) -> NDArray[np.float64]:
    """One continuation step of :func:`steady_rotation`: Newton from ``gamma`` until the residual is within 64 u of
    the size of its terms (a few roundings of each of the ≲ 10 products; the Jacobian is exact)."""
    def cross_matrix(a: NDArray[np.float64]) -> NDArray[np.float64]:
        return np.array([[0.0, -a[2], a[1]], [a[2], 0.0, -a[0]], [-a[1], a[0], 0.0]])

    for _ in range(_NEWTON_ITERATIONS):
        lever = s2 * (1.0 + c @ gamma) + g
        v = s2_inertia * gamma - lever * c
        residual = np.cross(gamma, v) + (gamma @ gamma - 1.0) * gamma
        if np.max(np.abs(residual)) <= 64.0 * _U * (np.max(np.abs(s2_inertia)) + abs(lever) * np.max(np.abs(c)) + 1.0):
            return gamma
        dv = np.diag(s2_inertia) - s2 * np.outer(c, c)
        jac = -cross_matrix(v) + cross_matrix(gamma) @ dv + 2.0 * np.outer(gamma, gamma)  # |γ| = 1: (γ·γ − 1) 1 drops
        gamma = gamma - np.linalg.solve(jac, residual)
        gamma /= np.linalg.norm(gamma)
    raise ValueError(f"the steady rotation was not found by Newton's method at s^2 = {s2!r} (the branch continued from "
                     "rest may turn back there)")


def _jacobian(sphere: LoadedSphere, y6: NDArray[np.float64]) -> NDArray[np.float64]:
    """∂(γ̇, ω̇)/∂(γ, ω) at y6 by the complex step (h as :func:`divergence`'s; in γ its error is O(h²): 1e-60)."""
    h = math.ldexp(1.0, math.frexp(1.0 + float(np.max(np.abs(y6))))[1] + COMPLEX_STEP_EXPONENT)
    y = np.zeros((STATE_SIZE, 6), complex)
    y[:6] = y6[:, None] + 1j * h * np.eye(6)
    return np.array(body_frame_rhs(y, sphere.params)[:6]).imag / h
