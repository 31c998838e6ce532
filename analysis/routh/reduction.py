"""Reduction of Routh's sphere (I1 = I2) to one degree of freedom: θ̇² = F(θ).

Paper §2.4 (eq. thetadotsq).  With ω1' = θ̇, Routh's quantity gives ω3' = ρ Q_R
(eq. routh) and Jellett's quantity gives s ω2' = u/I1 with

    u(θ) = Q_J − I3 f ρ Q_R = I1 s² V_φ                      (eqs. jellett, phidotCJQR).

In the intermediate frame r = (0, s, f) and v = ω × r = (f ω2' − s ω3', −f θ̇, s θ̇),
so the energy (eq. energy) splits without cross terms,

    E = ½ D(θ) θ̇² + U(θ),   D = I1 + s² + f² = I1 + (1 − a)² + 2a(1 − c),
    U = g a (1 − c) + N/(2 s²),
    N = (f u/I1 − s² ρ Q_R)² + u²/I1 + I3 s² ρ² Q_R²        (= 2 s² T at θ̇ = 0),

and F = 2(E − U)/D = P/(s² D) with P = 2 s² (E − g a (1 − c)) − N regular on [0, π].

Precision.  Everything is written in x = 1 − c = 2 sin²(θ/2) and y = 1 + c = 2 cos²(θ/2)
(x + y = 2, s² = x y), each of which keeps full relative precision at its own end,
and u is evaluated near θ = 0 (θ = π) as u₀ + I3 Q_R (f₀ρ₀ − fρ) (u_π + ...) with the
difference written without cancellation; u₀ = Q_J − Q_J,0^crit and u_π = Q_J − Q_J,π^crit are
evaluated in double-double (their signs decide the ±π jumps of φ), and E − V near θ = π as
(E − 2ga) + g a y with 2ga split exactly.

Here: F, U, u and P in those variables, the signed distances to the critical lines (:func:`u_ends`), the checks of
(E, Q_R, Q_J), and the conversions between Euler rates and (E, Q_R, Q_J) (:func:`invariants_from_euler`,
:func:`state_from_turning_point`).  The turning points, searched in w = log(x/y) = log tan²(θ/2) (which resolves θ_N
and π − θ_X down to ~1e-60), are in :mod:`rocknroller.analysis.routh.turning_points`.
"""

from __future__ import annotations

from dataclasses import dataclass
from fractions import Fraction
from functools import lru_cache
from types import SimpleNamespace
from typing import Any, Protocol

import mpmath
import numpy as np
from numpy.typing import ArrayLike, NDArray

from rocknroller.analysis.model.body import Body
from rocknroller.analysis.model.invariants import V_phi, V_psi, invariants, rho_inv, rho_inv_sq
from rocknroller.analysis.model.kinematics import omega_from_rates, vertical_in_body

__all__ = [
    "OK", "NO_MOTION", "STEADY", "STATUS_TEXT", "NoMotionError", "SteadyRollingError", "where_defined",
    "TurningPointState", "tilt_xy", "theta_from_xy", "u_numerator", "reduced_N", "reduced_P", "potential", "u_ends",
    "D_coefficient", "effective_potential", "F", "invariants_from_euler", "state_from_turning_point", "Q_RANGE",
    "TILT_MIN", "E_MAX", "check_invariants", "require_open_tilt"
]

#: Magnitudes of Q_R and Q_J that the closed forms resolve: 0, or |Q| in Q_RANGE.  Above, U = … + Q²/(2 I1 s²)
#: overflows inside the turning-point search (which reaches sin²θ ≈ 4 e^(−300) ≈ 2e-130 near the poles); below,
#: the double-double products that decide the side of a critical line (:func:`u_ends`) lose their low part to
#: underflow.
Q_RANGE = (1e-150, 1e80)
#: Largest |E| accepted (2 s² E must not overflow).
E_MAX = 1e300


def check_invariants(**values: ArrayLike) -> list[NDArray[np.float64]]:
    """The given invariants (keywords ``E``, ``QR``, ``QJ``) as float arrays, or a ValueError naming the first one
    that is not finite or lies outside its range (:data:`Q_RANGE` for Q_R, Q_J; :data:`E_MAX` for E)."""
    out = []
    lo, hi = Q_RANGE
    for name, value in values.items():
        try:
            v = np.asarray(value, float)
        except (TypeError, ValueError, OverflowError):  # not numbers, or an int beyond the floats (10**400)
            raise ValueError(f"{name} must be finite real numbers, got {name}={value!r}") from None
        a = np.abs(v)
        if name == "E":
            bad, allowed = ~(a <= E_MAX), f"finite with |E| <= {E_MAX:g}"
        else:
            bad, allowed = ~((a == 0.0) | ((a >= lo) & (a <= hi))), f"0 or finite with {lo:g} <= |{name}| <= {hi:g}"
        if np.any(bad):
            raise ValueError(f"{name} must be {allowed}, got {name}={float(v[bad].flat[0])!r}")
        out.append(v)
    return out

#: Status codes of :func:`solve_turning_points` (and of the quadratures built on it).
OK, NO_MOTION, STEADY = 0, 1, 2
STATUS_TEXT = {
    OK: "ok",
    NO_MOTION: "no_motion: E < min U(theta), F(theta) < 0 on all of (0, pi)",
    STEADY: "steady_rolling: double root theta_N = theta_X (E = min U), not integrated",
}


class NoMotionError(ValueError):
    """(E, Q_R, Q_J) admits no motion: E < U(θ) (F(θ) < 0) for every θ in (0, π).

    Examples
    --------
    >>> import rocknroller as rr
    >>> body = rr.Body.paper()
    >>> try:
    ...     rr.turning_points(-1.0, 0.01, 0.0, body)
    ... except rr.NoMotionError as err:
    ...     print(isinstance(err, ValueError))
    ...
    True
    """


class SteadyRollingError(ValueError):
    """(E, Q_R, Q_J) is steady circular rolling (double root θ_N = θ_X); ``theta`` holds that tilt
    (a masked array, masked where the point is not steady).

    Examples
    --------
    >>> import rocknroller as rr
    >>> from scipy.optimize import minimize_scalar
    >>> body = rr.Body.paper()
    >>> QR, QJ = 0.5, 0.1
    >>> lowest = minimize_scalar(lambda t: rr.effective_potential(t, QR, QJ, body), bounds=(0.1, 3.0), method="bounded",
    ...                          options={"xatol": 1e-10})
    >>> try:
    ...     rr.turning_points(lowest.fun, QR, QJ, body)
    ... except rr.SteadyRollingError as err:
    ...     print(f"steady rolling at theta = {float(err.theta):.6f}")
    ...
    steady rolling at theta = 0.510542
    """

    def __init__(self, message: str, theta: np.ma.MaskedArray):
        super().__init__(message)
        self.theta = theta


def where_defined(values: ArrayLike, defined: ArrayLike) -> np.ma.MaskedArray:
    """``values`` where ``defined``, masked elsewhere (data 0 there).

    The package's form of a vectorised result that does not exist at some points (no motion, steady
    rolling, unresolved): a numpy masked array with the point's status alongside, never NaN.
    ``result.mask`` marks the missing points; ``result.filled(np.nan)`` gives the NaN convention if wanted.
    """
    defined = np.asarray(defined, bool)
    return np.ma.MaskedArray(np.where(defined, values, 0.0), mask=~defined)


# ----------------------------------------------------------------------------- precise variables
def tilt_xy(theta: ArrayLike) -> tuple[NDArray[np.float64], NDArray[np.float64]]:
    """x = 1 − cos θ = 2 sin²(θ/2) and y = 1 + cos θ = 2 cos²(θ/2), each exact to round-off.

    Raises
    ------
    ValueError
        If some θ is non-finite or outside [0, π].
    """
    try:
        theta = np.asarray(theta, float)
    except (TypeError, ValueError, OverflowError):  # not numbers, or an int beyond the floats (10**400)
        raise ValueError(f"theta must be finite and in [0, pi], got {theta!r}") from None
    if not np.all(np.isfinite(theta)) or np.any((theta < 0.0) | (theta > np.pi)):
        raise ValueError(f"theta must be finite and in [0, pi], got {theta!r}")
    return 2.0 * np.sin(0.5 * theta) ** 2, 2.0 * np.cos(0.5 * theta) ** 2


def theta_from_xy(x: ArrayLike, y: ArrayLike) -> NDArray[np.float64]:
    """θ = 2 atan(√(x/y)) in [0, π] (relative precision of x kept near θ = 0)."""
    return 2.0 * np.arctan2(np.sqrt(x), np.sqrt(y))


def _f(x, y, body: Body):
    """f = c − a, from whichever of x, y is exact at its end."""
    return np.where(x <= 1.0, (1.0 - body.a) - x, y - (1.0 + body.a))


def _u_direct(f, R, QR, QJ, body: Body):
    """u = Q_J − I3 f ρ Q_R = I1 s² V_φ (numerator of paper eq. phidotCJQR); generic arithmetic."""
    return QJ - body.I3 * QR * f / R


def u_numerator(x: ArrayLike, y: ArrayLike, QR: ArrayLike, QJ: ArrayLike, body: Body) -> NDArray[np.float64]:
    """u = Q_J − I3 f ρ Q_R without cancellation near θ = 0 and θ = π.

    Near θ = 0 (x ≤ 1, f > 0): u = u₀ + I3 Q_R (f₀ρ₀ − fρ) with f₀ = 1 − a and
    f₀ρ₀ − fρ = x [I3 (f₀ + f) + f₀² y] / [R R₀ (f₀ R + f R₀)], R = 1/ρ.
    Near θ = π (y ≤ 1, f < 0) the same with f_π = −(1 + a) and y in place of x (sign flipped).
    Elsewhere u is evaluated directly.  u₀ and u_π (:func:`u_ends`) are the numerators at θ = 0
    and π, whose signs are those of Q_J − Q_J,0^crit and Q_J − Q_J,π^crit (paper eqs. QJcrit_0,
    QJcrit_pi).
    """
    x, y = np.asarray(x, float), np.asarray(y, float)
    s2 = x * y
    f = _f(x, y, body)
    return _u_xy(x, y, f, rho_inv(body, s2, f), np.asarray(QR, float), np.asarray(QJ, float), body)


def _u_xy(x, y, f, R, QR, QJ, body: Body):
    left = x <= 1.0
    end_f = np.where(left, 1.0 - body.a, -(1.0 + body.a))
    small = np.where(left, x, y)
    sign = np.where(left, 1.0, -1.0)
    R_end = rho_inv(body, 0.0, end_f)
    u0, upi = u_ends(QR, QJ, body)
    u_end = np.where(left, u0, upi)
    near = np.where(left, f > 0.0, f < 0.0)
    # end_f² R² − f² R_end² = I3 (end_f² − f²) + end_f² s², with end_f² − f² = ±small (end_f + f)
    num = small * (sign * body.I3 * (end_f + f) + end_f * end_f * (2.0 - small))
    with np.errstate(invalid="ignore", divide="ignore"):
        diff = num / (R * R_end * (end_f * R + f * R_end))  # end_f ρ_end − f ρ
    return np.where(near, u_end + body.I3 * QR * diff, _u_direct(f, R, QR, QJ, body))


def _two_prod(a, b):
    """Dekker's exact product: a b = p + e with p = fl(a b) (no fma needed)."""
    split = 134217729.0  # 2^27 + 1
    p = a * b
    ta = split * a
    ah = ta - (ta - a)
    al = a - ah
    tb = split * b
    bh = tb - (tb - b)
    bl = b - bh
    e = ((ah * bh - p) + ah * bl + al * bh) + al * bl
    return p, e


@lru_cache(maxsize=64)
def _critical_slopes(body: Body) -> tuple[tuple[float, float], tuple[float, float]]:
    """I3 f_e ρ_e at θ = 0 (f_e = 1 − a) and θ = π (f_e = −(1 + a)) as double-double (hi, lo).

    Q_J,e^crit = (I3 f_e ρ_e) Q_R (paper eqs. QJcrit_0, QJcrit_pi); computed at 40 digits from the
    exact binary values of the body parameters.
    """
    out = []
    with mpmath.workdps(40):
        mb = SimpleNamespace(a=mpmath.mpf(body.a), I1=mpmath.mpf(body.I1), I3=mpmath.mpf(body.I3))
        for fe in (1 - mb.a, -(1 + mb.a)):
            c = mb.I3 * fe / mpmath.sqrt(rho_inv_sq(mb, 0, fe))
            hi = float(c)
            out.append((hi, float(c - hi)))
    return out[0], out[1]


def u_ends(QR: ArrayLike, QJ: ArrayLike, body: Body) -> tuple[NDArray[np.float64], NDArray[np.float64]]:
    """(u₀, u_π) = (Q_J − Q_J,0^crit, Q_J − Q_J,π^crit): the numerator u at θ = 0 and θ = π.

    Evaluated in double-double, so each is correctly rounded to ~ε |u_e| (not ε |Q_J|): its sign,
    the side of the critical line, is exact for the given doubles (|Q| in :data:`Q_RANGE`, or 0).
    """
    QR, QJ = np.asarray(QR, float), np.asarray(QJ, float)
    res = []
    for hi, lo in _critical_slopes(body):
        p, e = _two_prod(QR, hi)
        res.append(((QJ - p) - e) - QR * lo)
    return res[0], res[1]


def reduced_N(s2: Any, f: Any, R: Any, u: Any, QR: Any, body: Body) -> Any:
    """N = 2 s² T(θ̇ = 0) = (f u/I1 − s² Q_R/R)² + u²/I1 + I3 s² Q_R²/R² (generic arithmetic).

    From v = ω × r in the intermediate frame with s ω2' = u/I1 and ω3' = ρ Q_R (module docstring).
    Works on numpy arrays, mpmath numbers and sympy expressions.
    """
    a1 = f * u / body.I1 - s2 * QR / R
    return a1 * a1 + u * u / body.I1 + body.I3 * s2 * QR * QR / (R * R)


def potential(x: Any, body: Body) -> Any:
    """V = g a (1 − cos θ) = g a x (paper §2.4); generic arithmetic."""
    return body.g * body.a * x


def reduced_P(s2: Any, K: Any, N: Any) -> Any:
    """P = s² D F = 2 s² K − N with K = E − V, regular on [0, π]; its roots are the turning points."""
    return 2 * s2 * K - N


class _Coefficients(Protocol):
    """What the generic-arithmetic functions read of a body: a :class:`Body`, or the same parameters as other numbers
    (quadrature_mp's mpmath copy of a body)."""

    @property
    def a(self) -> Any: ...
    @property
    def I1(self) -> Any: ...


def D_coefficient(x: Any, body: _Coefficients) -> Any:
    """D = I1 + s² + f² = I1 + (1 − a)² + 2 a x, the coefficient of θ̇²/2 in the energy."""
    return body.I1 + (1 - body.a) ** 2 + 2 * body.a * x


def _N_xy(x, y, QR, QJ, body: Body):
    s2 = x * y
    f = _f(x, y, body)
    R = rho_inv(body, s2, f)
    return reduced_N(s2, f, R, _u_xy(x, y, f, R, QR, QJ, body), QR, body)


def _U_xy(x, y, QR, QJ, body: Body):
    with np.errstate(divide="ignore", invalid="ignore", over="ignore"):  # U → +inf at the poles
        return potential(x, body) + _N_xy(x, y, QR, QJ, body) / (2.0 * x * y)


@lru_cache(maxsize=64)
def _two_ga(body: Body) -> tuple[float, float]:
    """2 g a as an unevaluated sum hi + lo of doubles (exact to ~1e-32 relative)."""
    exact = 2 * Fraction(body.g) * Fraction(body.a)
    hi = float(exact)
    return hi, float(exact - Fraction(hi))


def _kinetic(x, y, E, body: Body):
    """E − V = E − g a x; near θ = π as ((E − 2ga)_hi − lo) + g a y, so that the small kinetic
    energy at a turning point close to π keeps its relative precision."""
    hi, lo = _two_ga(body)
    return np.where(x <= y, E - potential(x, body), ((E - hi) - lo) + potential(y, body))


def _P_xy(x, y, E, QR, QJ, body: Body):
    """P = 2 s² (E − V) − N (= reduced_P, with E − V evaluated by _kinetic)."""
    return reduced_P(x * y, _kinetic(x, y, E, body), _N_xy(x, y, QR, QJ, body))


def _P_and_terms(x, y, E, QR, QJ, body: Body):
    """P and the size |2 s² (E − V)| + N of the terms it is the difference of (its rounding scale)."""
    two_s2K = 2.0 * x * y * _kinetic(x, y, E, body)
    N = _N_xy(x, y, QR, QJ, body)
    return reduced_P(1.0, 0.5 * two_s2K, N), np.abs(two_s2K) + np.abs(N)


def _xy_from_w(w: NDArray[np.float64]) -> tuple[NDArray[np.float64], NDArray[np.float64]]:
    """x = 2/(1 + e^{−w}), y = 2/(1 + e^{w}) for w = log(x/y)."""
    return 2.0 / (1.0 + np.exp(-w)), 2.0 / (1.0 + np.exp(w))


# ----------------------------------------------------------------------------- public reduction
def effective_potential(theta: ArrayLike, QR: ArrayLike, QJ: ArrayLike, body: Body) -> NDArray[np.float64]:
    """U(θ; Q_R, Q_J) = E at θ̇ = 0, so that E = ½ D θ̇² + U (module docstring). Vectorised.

    Raises
    ------
    ValueError
        If the body is not symmetric or θ is outside (0, π).

    Examples
    --------
    >>> import math
    >>> import rocknroller as rr
    >>> body = rr.Body.paper()
    >>> E, QR, QJ = rr.invariants_from_euler(body, 0.95 * math.pi, 0.0, 0.15, 0.15)
    >>> U = rr.effective_potential(0.95 * math.pi, QR, QJ, body)
    >>> print(f"E = {E:.10f}, U = {U:.10f}")
    E = 0.9813247617, U = 0.9813247617
    """
    body.require_symmetric("the effective potential U(theta) of the reduction theta_dot^2 = F(theta)")
    x, y = tilt_xy(theta)
    _require_open(x, y, "theta")
    return _U_xy(x, y, QR, QJ, body)


def F(theta: ArrayLike, E: ArrayLike, QR: ArrayLike, QJ: ArrayLike, body: Body) -> NDArray[np.float64]:
    """F(θ; E, Q_R, Q_J) with θ̇² = F(θ) (paper eq. thetadotsq), explicit and vectorised.

    F = P/(s² D) with P = 2 s² (E − g a (1 − c)) − N and D = I1 + s² + f²; see the module
    docstring for N.  F has poles at θ = 0 and π (unless Q_J is critical there); s² F is regular.

    Parameters
    ----------
    theta : array_like
        Tilt angle(s) in (0, π).
    E, QR, QJ : array_like
        Energy, Routh's and Jellett's quantities (paper eqs. energy, routh, jellett); broadcast.
    body : Body
        A symmetric body (I1 == I2).

    Raises
    ------
    ValueError
        If the body is asymmetric or θ is outside (0, π).

    Examples
    --------
    >>> import math
    >>> import rocknroller as rr
    >>> body = rr.Body.paper()
    >>> E, QR, QJ = rr.invariants_from_euler(body, 0.95 * math.pi, 0.0, 0.15, 0.15)
    >>> print(f"{rr.F(0.9 * math.pi, E, QR, QJ, body):.10f}")
    0.0253921920
    >>> print(abs(rr.F(0.95 * math.pi, E, QR, QJ, body)) < 1e-12)
    True
    """
    body.require_symmetric("F(theta) of the reduction theta_dot^2 = F(theta) (paper eq. thetadotsq)")
    x, y = tilt_xy(theta)
    _require_open(x, y, "theta")
    return _P_xy(x, y, E, QR, QJ, body) / (x * y * D_coefficient(x, body))


#: Smallest tilt from the vertical of a start: closer, 1 − cos θ = 2 sin²(θ/2) underflows and sin θ = 0 is a pole.
TILT_MIN = 1e-150


def require_open_tilt(theta: ArrayLike, name: str = "theta0", why: str = "") -> NDArray[np.float64]:
    """``theta`` as a float array, or a ValueError naming ``name`` unless every value is finite and in
    [TILT_MIN, π) (the open interval (0, π) as far as double precision resolves it near θ = 0)."""
    t = np.asarray(theta, float)
    bad = ~(np.isfinite(t) & (t >= TILT_MIN) & (t < np.pi))
    if np.any(bad):
        raise ValueError(f"{name} must lie in the open interval (0, pi), at least {TILT_MIN:g}{why}, "
                         f"got {name}={float(t[bad].flat[0])!r}")
    return t


def _require_open(x, y, name: str) -> None:
    if np.any((x <= 0.0) | (y <= 0.0)):
        raise ValueError(f"{name} must lie in the open interval (0, pi) (sin(theta) = 0 is a pole of F)")


# ----------------------------------------------------------------------------- conversions
def invariants_from_euler(body: Body, theta: ArrayLike, theta_dot: ArrayLike, phi_dot: ArrayLike,
                          psi_dot: ArrayLike, psi: ArrayLike = 0.0) -> tuple[NDArray, NDArray, NDArray]:
    """(E, Q_R, Q_J) of an Euler-angle state (paper eqs. energy, routh, jellett).

    Valid for any body (the paper's definitions); ψ matters only if I1 ≠ I2.

    Raises
    ------
    ValueError
        If θ is outside [0, π] or a rate is non-finite.

    Examples
    --------
    >>> import math
    >>> import rocknroller as rr
    >>> body = rr.Body.paper()
    >>> E, QR, QJ = rr.invariants_from_euler(body, 0.95 * math.pi, 0.0, 0.15, 0.15)
    >>> print(f"E = {E:.10f}, Q_R = {QR:.10f}, Q_J = {QJ:.10f}")
    E = 0.9813247617, Q_R = 0.0023758531, Q_J = 0.0005182265
    """
    tilt_xy(theta)  # validates θ
    for name, v in (("theta_dot", theta_dot), ("phi_dot", phi_dot), ("psi_dot", psi_dot), ("psi", psi)):
        if not np.all(np.isfinite(np.asarray(v, float))):
            raise ValueError(f"{name} must be finite, got {v!r}")
    gamma = vertical_in_body(theta, psi)
    omega = omega_from_rates(theta, psi, theta_dot, phi_dot, psi_dot)
    return invariants(body, gamma, omega)


@dataclass(frozen=True)
class TurningPointState:
    """A state at a turning point θ0 (θ̇ = 0) with given (Q_R, Q_J), and its energy."""

    theta: NDArray[np.float64]
    E: NDArray[np.float64]
    theta_dot: NDArray[np.float64]
    phi_dot: NDArray[np.float64]
    psi_dot: NDArray[np.float64]


def state_from_turning_point(body: Body, theta0: ArrayLike, QR: ArrayLike, QJ: ArrayLike) -> TurningPointState:
    """E and the rates (θ̇ = 0, φ̇ = V_φ(θ0), ψ̇ = V_ψ(θ0)) of the state at the turning point θ0.

    E = U(θ0; Q_R, Q_J) (paper eqs. phidotCJQR, psidotCJQR, energy).  Whether θ0 is the upper
    or the lower turning point follows from the sign of U'(θ0); see quadrature.

    Raises
    ------
    ValueError
        If θ0 is outside the open interval (0, π), or the body is asymmetric.

    Examples
    --------
    >>> import math
    >>> import rocknroller as rr
    >>> body = rr.Body.paper()
    >>> s = rr.state_from_turning_point(body, 0.95 * math.pi, 0.01, -0.002)
    >>> print(f"E = {s.E:.10f}, phi_dot = {s.phi_dot:.10f}, psi_dot = {s.psi_dot:.10f}")
    E = 0.9813231967, phi_dot = 0.1431829510, psi_dot = 0.1491931243
    >>> E, QR, QJ = rr.invariants_from_euler(body, s.theta, 0.0, s.phi_dot, s.psi_dot)
    >>> print(f"{QR:.12f} {QJ:.12f}")
    0.010000000000 -0.002000000000
    """
    body.require_symmetric("a turning-point state of Routh's sphere")
    theta0 = require_open_tilt(theta0)
    x, y = tilt_xy(theta0)
    E = _U_xy(x, y, QR, QJ, body)
    zero = np.zeros(np.broadcast(theta0, QR, QJ).shape)
    return TurningPointState(theta=theta0 + zero, E=E, theta_dot=zero,
                             phi_dot=V_phi(theta0, QR=QR, QJ=QJ, body=body) + zero, psi_dot=V_psi(theta0, QR=QR, QJ=QJ, body=body) + zero)
