"""Critical Jellett lines, the regions I–IV, cos θ_z, θ_e, the δ^½ bound, and starts on a critical line.

Paper §criticality (eqs. phidotCJQR th=0, th=pi, QJcrit_0, QJcrit_pi), §range_X (eq. range_X) and §Recession.

* The critical lines Q_J = Q_J,0^crit(Q_R) = ρ₀(1 − a) I3 Q_R and Q_J = Q_J,π^crit(Q_R) = −ρ_π(1 + a) I3 Q_R are the
  zeros of the numerator u = Q_J − ρ f I3 Q_R of V_φ (paper eq. phidotCJQR) at θ = 0 and θ = π.  Their signed
  distances u₀ = Q_J − Q_J,0^crit and u_π = Q_J − Q_J,π^crit are evaluated once, in double-double, by
  :func:`rocknroller.analysis.reduction.u_ends`; everything here is built on them.
* Regions (paper §criticality): I: u₀ < 0 < u_π (Q_R > 0); II: u₀, u_π > 0; III: u_π < 0 < u₀ (Q_R < 0); IV: u₀, u_π < 0.
* cos θ_z (zero of V_φ in Regions I and III).  With q = Q_J/Q_R, V_φ = 0 ⇔ q = ρ f I3, squared a quadratic in
  c = cos θ.  Its root is (derived by :func:`cos_theta_z_sympy`)

      cos θ_z = [a β I3 + sgn(q) √(I1(I3 − β)[β(I3 − I1)(I3 + 1) − a²β I3 + I1 I3(I3 + 1)])] / [β(I3 − I1) + I1 I3],
      β = I3 − q²/I1.

  **Erratum.** The paper prints β = I3 − q² (missing 1/I1) and always the + root; the root of the squared
  equation with the + sign solves q = −ρ f I3 when q < 0 (the sign of f = c − a must be that of q).
  Since I1(I3 − β) = q², the root is evaluated as [a β I3 + q √(…)]/[…], which carries the sign by itself.
* The δ^½ bound (eq. range_X).  Writing Q_J = Q_J,π^crit (1 − δ) (Region I for Q_R > 0, III for Q_R < 0), the
  necessary condition θ_z < θ_X bounds θ_X from below by θ_z(δ), which depends on δ only:

      θ_z = π − C₁ δ^½ − C₃ δ^{3/2} + O(δ^{5/2}).

  The paper's C₁ = √(2(1 + a)[(1 + a)² + I1] I3/(I1(I3 + 1 + a))) is confirmed (:func:`delta_bound_sympy`);
  C₃ is new.  The bound concerns θ_z (the smallest admissible θ_X), not θ_X itself.
"""

from __future__ import annotations

from dataclasses import dataclass
from functools import lru_cache
from typing import TYPE_CHECKING, Callable

import numpy as np
import sympy as sp
from numpy.typing import ArrayLike, NDArray
from scipy.optimize import brentq

from rocknroller.analysis.body import Body
from rocknroller.analysis.invariants import V_phi, V_psi, rho
from rocknroller.analysis.kinematics import omega_from_rates, rates_from_omega
from rocknroller.analysis.laurent import SYMBOLS, V_phi_sym
from rocknroller.analysis.reduction import check_invariants, require_open_tilt, u_ends

if TYPE_CHECKING:  # pragma: no cover
    from rocknroller.numerics.trajectory import Trajectory

__all__ = [
    "REGIONS",
    "ON_LINE_0",
    "ON_LINE_PI",
    "ON_BOTH",
    "LINES",
    "QJ_crit_0",
    "region_from_offsets",
    "side_code",
    "QJ_crit_pi",
    "QJ_crit",
    "region",
    "cos_theta_z",
    "cos_theta_z_printed",
    "cos_theta_z_sympy",
    "theta_z",
    "theta_e",
    "necessary_condition",
    "delta_of",
    "delta_bound_sympy",
    "delta_bound_coefficients",
    "theta_z_expansion",
    "CriticalStart",
    "critical_start",
    "TurningPointRegion",
    "Crossing",
    "ReversalAnalysis",
    "reversal_analysis",
]

REGIONS = ("I", "II", "III", "IV")
#: Labels of :func:`region` for points on a critical line within the tolerance.
ON_LINE_0, ON_LINE_PI, ON_BOTH = "on QJ0crit", "on QJpicrit", "origin"
#: Names of the two critical lines, as accepted by :func:`QJ_crit` and :func:`critical_start`.
LINES = ("0", "pi")
#: Default relative tolerance of :func:`region` for "on a line": |u_e| <= tol * max(|Q_J|, |Q_J,e^crit|).
REGION_TOL = 1e-12

_REGION_OF_SIGNS = {(-1, 1): "I", (1, 1): "II", (1, -1): "III", (-1, -1): "IV"}
#: The same table indexed by side_code(u0, uπ) = 2 [u0 ≥ 0] + [uπ ≥ 0].
_REGION_BY_CODE = np.array([_REGION_OF_SIGNS[(2 * (c // 2) - 1, 2 * (c % 2) - 1)] for c in range(4)], dtype="<U11")


# ----------------------------------------------------------------------------- critical lines
def QJ_crit_0(QR: ArrayLike, body: Body) -> NDArray[np.float64]:
    """Critical Jellett quantity at θ = 0, Q_J,0^crit = ρ₀ (1 − a) I3 Q_R (paper eq. QJcrit_0).

    ρ₀ = [I3 + (I3/I1)(1 − a)²]^(−1/2).  Correctly rounded (from :func:`rocknroller.analysis.reduction.u_ends`).
    """
    (QR,) = check_invariants(QR=QR)
    return -u_ends(QR, 0.0, body)[0]


def QJ_crit_pi(QR: ArrayLike, body: Body) -> NDArray[np.float64]:
    """Critical Jellett quantity at θ = π, Q_J,π^crit = −ρ_π (1 + a) I3 Q_R (paper eq. QJcrit_pi).

    ρ_π = [I3 + (I3/I1)(1 + a)²]^(−1/2).  Correctly rounded (from :func:`rocknroller.analysis.reduction.u_ends`).
    """
    (QR,) = check_invariants(QR=QR)
    return -u_ends(QR, 0.0, body)[1]


def QJ_crit(line: str, QR: ArrayLike, body: Body) -> NDArray[np.float64]:
    """Q_J,0^crit (``line="0"``) or Q_J,π^crit (``line="pi"``)."""
    if line == "0":
        return QJ_crit_0(QR, body)
    if line == "pi":
        return QJ_crit_pi(QR, body)
    raise ValueError(f"line must be one of {LINES} (Q_J,0^crit or Q_J,pi^crit), got line={line!r}")


def _finite(name: str, v: ArrayLike) -> NDArray[np.float64]:
    arr = np.asarray(v, float)
    if not np.all(np.isfinite(arr)):
        raise ValueError(f"{name} must be finite, got {v!r}")
    return arr


def region_from_offsets(u0: ArrayLike, upi: ArrayLike) -> NDArray[np.str_]:
    """Region I–IV from the signs of u0 = Q_J − Q_J,0^crit and uπ = Q_J − Q_J,π^crit (paper §criticality).

    A zero offset counts as above its line; :func:`region` reports points near a line separately.
    """
    return np.asarray(_REGION_BY_CODE[side_code(u0, upi)], dtype=_REGION_BY_CODE.dtype)  # an array also for scalars


def side_code(u0: ArrayLike, upi: ArrayLike) -> NDArray[np.int64]:
    """The sides of both critical lines as one integer 2 [u0 ≥ 0] + [uπ ≥ 0]: bit 1 is the side of
    Q_J,0^crit, bit 0 that of Q_J,π^crit (so the XOR of two codes names the lines crossed)."""
    return 2 * (np.asarray(u0) >= 0).astype(np.int64) + (np.asarray(upi) >= 0)


def _on_line(u: NDArray, QJ: NDArray, tol: float) -> NDArray[np.bool_]:
    """|Q_J − Q_J,e^crit| = |u_e| ≤ tol · max(|Q_J|, |Q_J,e^crit|): on the critical line e within tol."""
    return np.abs(u) <= tol * np.maximum(np.abs(QJ), np.abs(QJ - u))


def region(QR: ArrayLike, QJ: ArrayLike, body: Body, tol: float = REGION_TOL) -> NDArray[np.str_] | str:
    """Critical region I–IV of (Q_R, Q_J) (paper §criticality), vectorised.

    A point with |Q_J − Q_J,e^crit| ≤ tol · max(|Q_J|, |Q_J,e^crit|) is reported as on that line:
    ``ON_LINE_0`` ("on QJ0crit"), ``ON_LINE_PI`` ("on QJpicrit"), or ``ON_BOTH`` ("origin", only Q_R = Q_J = 0
    for tol < 1).  The default tol = 1e-12 is about 4500 rounding units (2⁻⁵²): the side of a line is then
    decided by the sign of the double-double distance u_e, which is exact for the given doubles.

    Returns
    -------
    numpy array of str (a plain str for scalar input).
    """
    QR, QJ = check_invariants(QR=QR, QJ=QJ)
    tol = float(tol)
    if not 0.0 <= tol < 1.0:
        raise ValueError(f"tol must satisfy 0 <= tol < 1, got tol={tol!r}")
    u0, upi = u_ends(QR, QJ, body)
    on0, onpi = _on_line(u0, QJ, tol), _on_line(upi, QJ, tol)
    out = np.broadcast_to(region_from_offsets(u0, upi), np.broadcast(QR, QJ).shape).copy()
    out[on0] = ON_LINE_0
    out[onpi] = ON_LINE_PI
    out[on0 & onpi] = ON_BOTH
    return str(out) if out.ndim == 0 else out


def _strict_regions(QR: NDArray, QJ: NDArray, body: Body, allowed: tuple[str, ...], what: str) -> NDArray:
    reg = np.asarray(region(QR, QJ, body, tol=0.0))
    bad = ~np.isin(reg, allowed)
    if np.any(bad):
        i = np.flatnonzero(bad.ravel())[0]
        raise ValueError(f"{what} exists only in Regions {'/'.join(allowed)}; (QR, QJ) = "
                         f"({np.ravel(QR * np.ones_like(QJ))[i]!r}, {np.ravel(QJ * np.ones_like(QR))[i]!r}) "
                         f"is in {reg.ravel()[i]}")
    return reg


def _ratio(QR: NDArray, QJ: NDArray) -> NDArray:
    if np.any(QR == 0.0):
        raise ValueError("QR must be nonzero: the ratio q = QJ/QR is undefined at QR = 0")
    return QJ / QR


# ----------------------------------------------------------------------------- cos θ_z
def cos_theta_z(QR: ArrayLike, QJ: ArrayLike, body: Body) -> NDArray[np.float64]:
    """cos θ_z, the single zero of V_φ(θ) in Regions I and III, in closed form (corrected paper §range_X).

    cos θ_z = [a β I3 + q √(β(I3 − I1)(I3 + 1) − a² β I3 + I1 I3 (I3 + 1))]/[β(I3 − I1) + I1 I3],
    q = Q_J/Q_R, β = I3 − q²/I1; equal to the form with sgn(q) √(I1(I3 − β)[…]) (module docstring).

    Raises
    ------
    ValueError
        Q_R = 0, or a point outside Regions I and III (no zero there).
    """
    QR, QJ = check_invariants(QR=QR, QJ=QJ)
    q = _ratio(QR, QJ)
    _strict_regions(QR, QJ, body, ("I", "III"), "the zero theta_z of V_phi")
    a, I1, I3 = body.a, body.I1, body.I3
    beta = I3 - q * q / I1
    root = np.sqrt(beta * (I3 - I1) * (I3 + 1.0) - a * a * beta * I3 + I1 * I3 * (I3 + 1.0))
    return (a * beta * I3 + q * root) / (beta * (I3 - I1) + I1 * I3)


def cos_theta_z_printed(QR: ArrayLike, QJ: ArrayLike, body: Body) -> NDArray[np.float64]:
    """The paper's printed formula for cos θ_z (§range_X), with β = I3 − (Q_J/Q_R)² and the + root. WRONG.

    Kept only to document the erratum (tests show it misses the zero of V_φ).  Returns NaN where the printed
    square root is of a negative number.
    """
    QR, QJ = check_invariants(QR=QR, QJ=QJ)
    q = _ratio(QR, QJ)
    a, I1, I3 = body.a, body.I1, body.I3
    beta = I3 - q * q
    with np.errstate(invalid="ignore"):
        root = np.sqrt(I1 * (I3 - beta) * (beta * (I3 - I1) * (I3 + 1.0) - a * a * beta * I3 + I1 * I3 * (I3 + 1.0)))
    return (a * beta * I3 + root) / (beta * (I3 - I1) + I1 * I3)


@lru_cache(maxsize=1)
def cos_theta_z_sympy() -> dict[str, sp.Expr]:
    """Sympy derivation of cos θ_z from V_φ = 0 (paper eq. phidotCJQR).

    Returns
    -------
    dict
        ``quadratic``: the squared condition q² ρ⁻² − I3² f² as a polynomial in c (times I1);
        ``roots``: its two roots in terms of β = I3 − q²/I1 (symbol ``beta``), ``q``;
        ``closed_form``: the root selected by sgn(q), written as in :func:`cos_theta_z`;
        ``symbols``: the symbols c, q, beta.
    """
    a, I1, I3 = SYMBOLS["a"], SYMBOLS["I1"], SYMBOLS["I3"]
    c, q, beta = sp.symbols("c q beta", real=True)
    th = SYMBOLS["theta"]
    # numerator of V_φ with Q_J = q Q_R, divided by Q_R: q − ρ f I3; the zero needs q² = ρ² f² I3²
    numer = sp.expand(V_phi_sym(th) * I1 * sp.sin(th) ** 2)
    rho_f_I3 = (-numer.coeff(SYMBOLS["QR"])).subs(sp.cos(th), c).subs(sp.sin(th) ** 2, 1 - c**2)
    rho_sq_f_sq_I3_sq = sp.simplify(rho_f_I3**2)
    quad = sp.expand(sp.cancel((q**2 - rho_sq_f_sq_I3_sq) * I1 / rho_sq_f_sq_I3_sq * (c - a) ** 2 * I3**2))
    poly = sp.Poly(quad, c)
    A, B, C = poly.all_coeffs()
    sub = {q**2: I1 * (I3 - beta)}
    A, B, C = (sp.expand(sp.expand(v).subs(sub)) for v in (A, B, C))
    disc = sp.factor(sp.expand(B**2 - 4 * A * C))
    roots = [sp.simplify((-B + s * sp.sqrt(disc)) / (2 * A)) for s in (1, -1)]
    closed = (a * beta * I3 + q * sp.sqrt(beta * (I3 - I1) * (I3 + 1) - a**2 * beta * I3 + I1 * I3 * (I3 + 1))) / (
        beta * (I3 - I1) + I1 * I3)
    return {"quadratic": quad, "roots": roots, "discriminant": disc, "closed_form": closed,
            "symbols": {"c": c, "q": q, "beta": beta}}


def theta_z(QR: ArrayLike, QJ: ArrayLike, body: Body) -> NDArray[np.float64]:
    """θ_z = arccos(cos θ_z), the zero of V_φ in Regions I and III (:func:`cos_theta_z`).

    Near θ = π the arccos costs precision: the absolute error is ~ε/sin θ_z (1e-14 at π − θ_z = 0.01).
    """
    return np.arccos(np.clip(cos_theta_z(QR, QJ, body), -1.0, 1.0))


# ----------------------------------------------------------------------------- θ_e
@lru_cache(maxsize=1)
def _dV_phi_dtheta() -> Callable:
    s = SYMBOLS
    expr = sp.diff(V_phi_sym(s["theta"]), s["theta"])
    return sp.lambdify((s["theta"], s["QJ"], s["QR"], s["a"], s["I1"], s["I3"]), expr, modules="math")


def _theta_e_one(QR: float, QJ: float, body: Body) -> float:
    d = _dV_phi_dtheta()

    def dv(t: float) -> float:
        return d(t, QJ, QR, body.a, body.I1, body.I3)

    # V_φ has a single extremum; near the ends dV_φ/dθ ≈ −2u₀/(I1 θ³) and +2u_π/(I1 (π − θ)³).
    u0, upi = (float(v) for v in u_ends(QR, QJ, body))
    lo = next((np.pi * 10.0**-k for k in range(1, 17) if np.sign(dv(np.pi * 10.0**-k)) == -np.sign(u0)), None)
    hi = next((np.pi * (1 - 10.0**-k) for k in range(1, 16) if np.sign(dv(np.pi * (1 - 10.0**-k))) == np.sign(upi)),
              None)
    if lo is None or hi is None or dv(lo) * dv(hi) >= 0:
        raise ValueError(f"no extremum of V_phi found for (QR, QJ) = ({QR!r}, {QJ!r})")
    return brentq(dv, lo, hi, xtol=1e-15, rtol=4 * np.finfo(float).eps, maxiter=200)


def theta_e(QR: ArrayLike, QJ: ArrayLike, body: Body) -> NDArray[np.float64]:
    """θ_e, the extremum of V_φ(θ) in Regions II (minimum) and IV (maximum), found numerically (paper §range_X).

    Root of dV_φ/dθ (differentiated by sympy from paper eq. phidotCJQR) by Brent's method, to round-off.

    Raises
    ------
    ValueError
        A point outside Regions II and IV.
    """
    QR, QJ = np.broadcast_arrays(*check_invariants(QR=QR, QJ=QJ))
    _strict_regions(QR, QJ, body, ("II", "IV"), "the extremum theta_e of V_phi")
    out = np.array([_theta_e_one(float(r), float(j), body) for r, j in zip(QR.ravel(), QJ.ravel())])
    return out.reshape(QR.shape) if QR.ndim else out[0]


def necessary_condition(theta_X: ArrayLike, QR: ArrayLike, QJ: ArrayLike, body: Body) -> NDArray[np.bool_]:
    """The paper's necessary condition (§range_X) for the Laurent expansion about π to decide φ̇(θ_X).

    Regions I and III: θ_z < θ_X; Regions II and IV: θ_e < θ_X.  Vectorised.

    Raises
    ------
    ValueError
        θ_X outside (0, π], or a point exactly on a critical line (no region); Q_R = 0 in Regions I/III
        cannot occur (there Q_J,π^crit < Q_J < Q_J,0^crit forces Q_R ≠ 0).
    """
    theta_X, QR, QJ = np.broadcast_arrays(_finite("theta_X", theta_X), *check_invariants(QR=QR, QJ=QJ))
    if np.any((theta_X <= 0.0) | (theta_X > np.pi)):
        raise ValueError(f"theta_X must lie in (0, pi], got {theta_X!r}")
    reg = np.asarray(region(QR, QJ, body, tol=0.0))
    if np.any(~np.isin(reg, REGIONS)):
        raise ValueError("necessary_condition: a point lies exactly on a critical line (no region I-IV)")
    out = np.zeros(theta_X.shape, bool)
    zi = np.isin(reg, ("I", "III"))
    if np.any(zi):
        out[zi] = theta_z(QR[zi], QJ[zi], body) < theta_X[zi]
    ei = ~zi
    if np.any(ei):
        out[ei] = theta_e(QR[ei], QJ[ei], body) < theta_X[ei]
    return out


# ----------------------------------------------------------------------------- δ^½ bound
def delta_of(QR: ArrayLike, QJ: ArrayLike, body: Body) -> NDArray[np.float64]:
    """δ = 1 − Q_J/Q_J,π^crit (paper eq. range_X: Q_J/Q_J,π^crit = 1 − δ).

    Raises
    ------
    ValueError
        Q_R = 0 (then Q_J,π^crit = 0).
    """
    QR, QJ = check_invariants(QR=QR, QJ=QJ)
    if np.any(QR == 0.0):
        raise ValueError("QR must be nonzero: delta = 1 - QJ/QJ_pi^crit needs QJ_pi^crit = k QR != 0")
    return 1.0 - QJ / QJ_crit_pi(QR, body)


@lru_cache(maxsize=1)
def delta_bound_sympy() -> dict[str, sp.Expr]:
    """Sympy derivation of θ_z(δ) = π − C₁ δ^½ − C₃ δ^{3/2} + O(δ^{5/2}) (paper eq. range_X).

    With x = π − θ, the zero of V_φ solves ρ f I3 |_{π−x} = (1 − δ) ρ_π f_π I3, whose left side is
    1 + k₂ x² + k₄ x⁴ + … times the right side's value at δ = 0; reverting the series gives
    x = C₁ δ^½ + C₃ δ^{3/2} with C₁ = (−1/k₂)^½ and C₃ = C₁ k₄/(2 k₂²).

    Returns
    -------
    dict with ``C1``, ``C3``, ``k2``, ``k4`` (sympy expressions in a, I1, I3) and ``C1_paper`` (the printed form).
    """
    a, I1, I3 = SYMBOLS["a"], SYMBOLS["I1"], SYMBOLS["I3"]
    th, x = SYMBOLS["theta"], SYMBOLS["x"]
    numer = sp.expand(V_phi_sym(th) * I1 * sp.sin(th) ** 2)
    g = -numer.coeff(SYMBOLS["QR"])  # ρ f I3
    ratio = g.subs(th, sp.pi - x) / g.subs(th, sp.pi)
    ser = sp.expand(sp.series(ratio, x, 0, 6).removeO())
    k2, k4 = sp.factor(ser.coeff(x, 2)), sp.factor(ser.coeff(x, 4))
    C1 = sp.sqrt(sp.factor(-1 / k2))
    C3 = sp.factor(C1 * k4 / (2 * k2**2))
    C1_paper = sp.sqrt(2 * (1 + a) * ((1 + a) ** 2 + I1) * I3 / (I1 * (I3 + 1 + a)))
    return {"C1": C1, "C3": C3, "k2": k2, "k4": k4, "C1_paper": C1_paper}


@lru_cache(maxsize=64)
def delta_bound_coefficients(body: Body) -> tuple[float, float]:
    """Numeric (C₁, C₃) of :func:`delta_bound_sympy` for ``body``."""
    d = delta_bound_sympy()
    vals = {SYMBOLS["a"]: body.a, SYMBOLS["I1"]: body.I1, SYMBOLS["I3"]: body.I3}
    return float(d["C1"].evalf(30, subs=vals)), float(d["C3"].evalf(30, subs=vals))


def _check_delta(delta: ArrayLike) -> NDArray[np.float64]:
    d = _finite("delta", delta)
    if np.any((d <= 0.0) | (d >= 1.0)):
        raise ValueError(f"delta must lie in the open interval (0, 1) (QJ = QJ_pi^crit (1 - delta)), got {delta!r}")
    return d


def theta_z_expansion(delta: ArrayLike, body: Body, terms: int = 2) -> NDArray[np.float64]:
    """θ_z(δ) from the δ-expansion: π − C₁ δ^½ (terms=1, the paper's eq. range_X) or − C₃ δ^{3/2} too (terms=2).

    This is the lower bound θ_X ≥ θ_z of the necessary condition near Q_J = Q_J,π^crit(1 − δ).

    Raises
    ------
    ValueError
        δ outside (0, 1) or terms not 1 or 2.
    """
    d = _check_delta(delta)
    if terms not in (1, 2):
        raise ValueError(f"terms must be 1 or 2, got terms={terms!r}")
    C1, C3 = delta_bound_coefficients(body)
    x = C1 * np.sqrt(d)
    if terms == 2:
        x = x + C3 * d * np.sqrt(d)
    return np.pi - x


# ----------------------------------------------------------------------------- starts on a critical line
@dataclass(frozen=True)
class CriticalStart:
    """A turning-point start (θ̇0 = 0) at a prescribed signed distance from a critical line.

    ``offset`` = Q_J − Q_J,e^crit(Q_R) (vertical distance in the (Q_R, Q_J) plane).  The authoritative state
    is (θ0, ψ0, ``omega``), the body-frame angular velocity, whose (Q_R, Q_J) lie on the target to round-off;
    the Euler rates reproduce it only to ~ε|ψ̇0|/|ω3'| relative, because ω3' = c φ̇0 + ψ̇0 cancels when the body
    spins and rolls with ψ̇ ≈ −c φ̇ (the usual case near θ = π).
    """

    line: str
    theta0: NDArray[np.float64]
    psi0: NDArray[np.float64]
    phi_dot0: NDArray[np.float64]
    psi_dot0: NDArray[np.float64]
    omega: NDArray[np.float64]
    QR: NDArray[np.float64]
    QJ: NDArray[np.float64]
    offset: NDArray[np.float64]


def _check_theta_range(theta0: NDArray) -> None:
    require_open_tilt(theta0, why=" to be a turning point (phi_dot is undefined at sin(theta0) = 0)")


def _check_turning_theta(theta0: NDArray, body: Body, QR: NDArray, QJ: NDArray) -> None:
    _check_theta_range(theta0)
    if body.is_symmetric:
        from rocknroller.analysis.reduction import STEADY, solve_turning_points, state_from_turning_point

        E = state_from_turning_point(body, theta0, QR, QJ).E
        if np.any(solve_turning_points(E, QR, QJ, body).status == STEADY):
            raise ValueError("theta0 cannot be a turning point here: with these (QR, QJ) it is the tilt of "
                             "steady circular rolling (double root of F, theta_ddot = 0)")


def critical_start(body: Body, theta0: ArrayLike, psi0: ArrayLike = 0.0, line: str = "pi", *,
                   QR: ArrayLike | None = None, psi_dot0: ArrayLike | None = None,
                   offset: ArrayLike = 0.0) -> CriticalStart:
    """Initial rates that put (Q_R, Q_J) on a critical line, or at a signed distance from it (paper §numerics, figs. 8, 9).

    The start is a turning point, θ̇0 = 0, at θ0.  With the paper's definitions (eq. JelletandRouth_Qtys,
    valid for I1 ≠ I2 too) Q_J = I1 s² φ̇ + I3 f ω3' and Q_R = ω3'/ρ with ω3' = c φ̇ + ψ̇, independent of ψ0:

    * given Q_R: Q_J = Q_J,e^crit(Q_R) + offset, φ̇0 = V_φ(θ0), ψ̇0 = V_ψ(θ0) (eqs. phidotCJQR, psidotCJQR), and
      the body-frame ω = Σ(θ0, ψ0)(0, φ̇0, ·) (:func:`rocknroller.analysis.kinematics.omega_from_rates`) with ω3 = ω3' = ρ Q_R;
    * given ψ̇0: φ̇0 solves the linear equation Q_J(φ̇0) = k Q_R(φ̇0) + offset (k the line's slope), which fixes
      Q_R; then as above (the returned ψ̇0 equals the given one to rounding, see :class:`CriticalStart`).

    Vectorised (broadcasting) to generate many states.

    Parameters
    ----------
    body : Body
    theta0 : array_like
        Turning-point tilt, 0 < θ0 < π.
    psi0 : array_like
        Spin angle (enters ω only, not Q_R, Q_J).
    line : {"pi", "0"}
        Q_J,π^crit (visible-angle reversals) or Q_J,0^crit (full-angle reversals).
    QR, psi_dot0 : array_like
        Exactly one of them.
    offset : array_like
        Signed distance Q_J − Q_J,e^crit(Q_R).

    Raises
    ------
    ValueError
        θ0 outside (0, π) or (symmetric body) a steady-rolling tilt; neither or both of QR, psi_dot0; a ψ̇0 for
        which the line cannot be reached; non-finite input.
    """
    if (QR is None) == (psi_dot0 is None):
        raise ValueError("give exactly one of QR and psi_dot0")
    theta0 = _finite("theta0", theta0)
    psi0 = _finite("psi0", psi0)
    offset = _finite("offset", offset)
    _check_theta_range(theta0)
    slope = QJ_crit(line, 1.0, body)
    r = rho(theta0, body)
    if QR is not None:
        (QRv,) = check_invariants(QR=QR)
    else:
        pd = _finite("psi_dot0", psi_dot0)
        c, s2 = np.cos(theta0), np.sin(theta0) ** 2
        f = c - body.a
        # I1 s² φ̇ + I3 f (c φ̇ + ψ̇) = k (c φ̇ + ψ̇)/ρ + offset
        den = body.I1 * s2 + body.I3 * f * c - slope * c / r
        scale = body.I1 * s2 + np.abs(body.I3 * f * c) + np.abs(slope * c / r)
        if np.any(np.abs(den) <= 64 * np.finfo(float).eps * scale):
            raise ValueError("with this psi_dot0 and theta0 no phi_dot0 reaches the critical line "
                             "(the line is parallel to the family of states); give QR instead")
        phi_dot = (slope * pd / r + offset - body.I3 * f * pd) / den
        QRv = (c * phi_dot + pd) / r
        try:
            check_invariants(QR=QRv)
        except ValueError as exc:
            raise ValueError(f"psi_dot0 with this theta0 puts the start outside the resolved range: {exc}") from None
    (offset,) = check_invariants(offset=offset)
    QJv = QJ_crit(line, QRv, body) + offset
    _check_turning_theta(theta0, body, QRv, QJv)
    z = np.zeros(np.broadcast(theta0, psi0, QRv, QJv).shape)
    phi_dot0 = V_phi(theta0, QR=QRv, QJ=QJv, body=body) + z
    omega = omega_from_rates(theta0 + z, psi0 + z, z, phi_dot0, z)
    omega[2] = r * QRv + z
    return CriticalStart(line=line, theta0=theta0 + z, psi0=psi0 + z, phi_dot0=phi_dot0,
                         psi_dot0=V_psi(theta0, QR=QRv, QJ=QJv, body=body) + z, omega=omega, QR=QRv + z, QJ=QJv + z,
                         offset=offset + z)


# ----------------------------------------------------------------------------- reversal analysis
@dataclass(frozen=True)
class TurningPointRegion:
    """Turning points of a trajectory in time order with their region and the sign of φ̇ there."""

    t: NDArray[np.float64]
    kind: NDArray[np.str_]          # "max" (θ_X) or "min" (θ_N)
    theta: NDArray[np.float64]
    QR: NDArray[np.float64]
    QJ: NDArray[np.float64]
    region: NDArray[np.str_]
    phi_dot: NDArray[np.float64]
    phi_dot_sign: NDArray[np.int64]


@dataclass(frozen=True)
class Crossing:
    """A critical crossing between two consecutive turning points of the relevant kind (paper §Recession).

    ``line`` "0": Q_J,0^crit judged at the θ-minima (full-angle reversal); "pi": Q_J,π^crit judged at
    the θ-maxima (visible-angle reversal).
    """

    line: str
    kind: str
    t_before: float
    t_after: float
    region_before: str
    region_after: str


@dataclass(frozen=True)
class ReversalAnalysis:
    turning_points: TurningPointRegion
    crossings: list[Crossing]

    def count(self, line: str) -> int:
        """Number of crossings of one line ("0" or "pi")."""
        return sum(1 for c in self.crossings if c.line == line)


def reversal_analysis(traj: "Trajectory", tol: float = 0.0) -> ReversalAnalysis:
    """Regions and φ̇ signs at every turning point of a direct-ODE trajectory, and its critical crossings.

    Paper §Recession: the full angle reverses when Q_J − Q_J,0^crit changes sign between passages near θ_N
    (checked at consecutive θ-minima); the visible angle reverses when Q_J − Q_J,π^crit changes sign between
    passages near θ_X (checked at consecutive θ-maxima).  φ̇ at a turning point comes from the body-frame state
    (φ̇ = (γ1 ω1 + γ2 ω2)/s², :func:`rocknroller.analysis.kinematics.rates_from_omega`), not from V_φ.

    Parameters
    ----------
    traj : rocknroller.numerics.trajectory.Trajectory
    tol : float
        Passed to :func:`region`; a sample within tol of a line does not count as a side.
    """
    body = traj.body
    parts = []
    for kind, tp in (("max", traj.maxima), ("min", traj.minima)):
        omega = tp.states[:, 3:6].T
        phi_dot = rates_from_omega(tp.theta, tp.psi, omega)[1] if len(tp) else np.zeros(0)
        parts.append((np.full(len(tp), kind), tp.t, tp.theta, tp.QR, tp.QJ, phi_dot))
    kind, t, th, QR, QJ, pd = (np.concatenate(v) for v in zip(*parts))
    order = np.argsort(t, kind="stable")
    kind, t, th, QR, QJ, pd = (v[order] for v in (kind, t, th, QR, QJ, pd))
    reg = np.asarray(region(QR, QJ, body, tol=tol)) if t.size else np.zeros(0, "<U11")
    tpr = TurningPointRegion(t=t, kind=kind, theta=th, QR=QR, QJ=QJ, region=np.atleast_1d(reg), phi_dot=pd,
                             phi_dot_sign=np.sign(pd).astype(np.int64))
    crossings: list[Crossing] = []
    for line, judged_at, name in (("0", "min", "full-angle reversal"), ("pi", "max", "visible-angle reversal")):
        idx = np.flatnonzero(kind == judged_at)
        if idx.size < 2:
            continue
        u = u_ends(QR[idx], QJ[idx], body)[0 if line == "0" else 1]
        side = np.where(_on_line(u, QJ[idx], tol), 0, np.sign(u))
        prev = None
        for j, sgn in zip(idx, side):
            if sgn == 0:
                continue
            if prev is not None and sgn != prev[1]:
                crossings.append(Crossing(line=line, kind=name, t_before=float(t[prev[0]]), t_after=float(t[j]),
                                          region_before=str(tpr.region[prev[0]]),
                                          region_after=str(tpr.region[j])))
            prev = (j, sgn)
    crossings.sort(key=lambda c: c.t_after)
    return ReversalAnalysis(turning_points=tpr, crossings=crossings)
