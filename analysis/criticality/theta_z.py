"""cos θ_z, θ_e and the δ^½ bound on θ_X near θ = π.

Paper §criticality and §range_X (eq. range_X).

* cos θ_z (zero of V_φ in Regions I and III).  With q = Q_J/Q_R, V_φ = 0 ⇔ q = ρ f I3, squared a quadratic in
  c = cos θ.  Its root is (derived by :func:`cos_theta_z_sympy`)

      cos θ_z = [a β I3 + sgn(q) √(I1(I3 − β)[β(I3 − I1)(I3 + 1) − a²β I3 + I1 I3(I3 + 1)])] / [β(I3 − I1) + I1 I3],
      β = I3 − q²/I1.

  **Erratum.** The paper prints β = I3 − q² (missing 1/I1) and always the + root; the root of the squared
  equation with the + sign solves q = −ρ f I3 when q < 0 (the sign of f = c − a must be that of q).
  Since I1(I3 − β) = q², the root is evaluated as [a β I3 + q √(…)]/[…], which carries the sign by itself.
* θ_e, the extremum of V_φ (dV_φ/dθ = 0), and the necessary condition for a reversal at a turning point.
* The δ^½ bound (eq. range_X).  Writing Q_J = Q_J,π^crit (1 − δ) (Region I for Q_R > 0, III for Q_R < 0), the
  necessary condition θ_z < θ_X bounds θ_X from below by θ_z(δ), which depends on δ only:

      θ_z = π − C₁ δ^½ − C₃ δ^{3/2} + O(δ^{5/2}).

  The paper's C₁ = √(2(1 + a)[(1 + a)² + I1] I3/(I1(I3 + 1 + a))) is confirmed (:func:`delta_bound_sympy`);
  C₃ is new.  The bound concerns θ_z (the smallest admissible θ_X), not θ_X itself.
"""

from __future__ import annotations

from functools import lru_cache
from typing import TYPE_CHECKING, Callable

import numpy as np
from numpy.typing import ArrayLike, NDArray

from rocknroller.analysis.criticality.lines import REGIONS, QJ_crit_pi, check_finite, region, strict_regions
from rocknroller.analysis.model.body import Body
from rocknroller.analysis.routh.reduction import check_invariants, u_ends

if TYPE_CHECKING:  # sympy (0.3 s to import) is loaded by the symbolic functions only, when called
    import sympy as sp

__all__ = [
    "cos_theta_z", "cos_theta_z_printed", "cos_theta_z_sympy", "theta_z", "theta_e", "necessary_condition", "delta_of",
    "delta_bound_sympy", "delta_bound_coefficients", "theta_z_expansion"
]


# ----------------------------------------------------------------------------- cos θ_z
def cos_theta_z(QR: ArrayLike, QJ: ArrayLike, body: Body) -> NDArray[np.float64]:
    """cos θ_z, the single zero of V_φ(θ) in Regions I and III, in closed form (corrected paper §range_X).

    cos θ_z = [a β I3 + q √(β(I3 − I1)(I3 + 1) − a² β I3 + I1 I3 (I3 + 1))]/[β(I3 − I1) + I1 I3],
    q = Q_J/Q_R, β = I3 − q²/I1; equal to the form with sgn(q) √(I1(I3 − β)[…]) (module docstring).

    Raises
    ------
    ValueError
        Q_R = 0, or a point outside Regions I and III (no zero there).

    Examples
    --------
    >>> import math
    >>> import rocknroller as rr
    >>> body = rr.Body.paper()
    >>> QR = 0.01
    >>> QJ = 0.99 * rr.QJ_crit_pi(QR, body)
    >>> print(rr.region(QR, QJ, body))
    I
    >>> c = rr.cos_theta_z(QR, QJ, body)
    >>> print(f"{c:.12f}", abs(rr.V_phi(math.acos(c), QR=QR, QJ=QJ, body=body)) < 1e-12)
    -0.988002821561 True
    """
    QR, QJ = check_invariants(QR=QR, QJ=QJ)
    q = _ratio(QR, QJ)
    strict_regions(QR, QJ, body, ("I", "III"), "the zero theta_z of V_phi")
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
    import sympy as sp

    from rocknroller.analysis.criticality.laurent import SYMBOLS, V_phi_sym

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

    Examples
    --------
    >>> import math
    >>> import rocknroller as rr
    >>> body = rr.Body.paper()
    >>> QR = 0.01
    >>> QJ = 0.99 * rr.QJ_crit_pi(QR, body)
    >>> theta_z = rr.theta_z(QR, QJ, body)
    >>> print(f"{theta_z / math.pi:.10f} pi", abs(rr.V_phi(theta_z, QR=QR, QJ=QJ, body=body)) < 1e-12)
    0.9506440137 pi True
    """
    return np.arccos(np.clip(cos_theta_z(QR, QJ, body), -1.0, 1.0))


# ----------------------------------------------------------------------------- θ_e
@lru_cache(maxsize=1)
def _dV_phi_dtheta() -> Callable:
    import sympy as sp

    from rocknroller.analysis.criticality.laurent import SYMBOLS, V_phi_sym

    s = SYMBOLS
    expr = sp.diff(V_phi_sym(s["theta"]), s["theta"])
    return sp.lambdify((s["theta"], s["QJ"], s["QR"], s["a"], s["I1"], s["I3"]), expr, modules="math")


def _theta_e_one(QR: float, QJ: float, body: Body) -> float:
    from scipy.optimize import brentq

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

    Examples
    --------
    >>> import math
    >>> import rocknroller as rr
    >>> body = rr.Body.paper()
    >>> QR = 0.01
    >>> QJ = 1.01 * rr.QJ_crit_pi(QR, body)
    >>> print(rr.region(QR, QJ, body))
    IV
    >>> print(f"{rr.theta_e(QR, QJ, body) / math.pi:.10f} pi")
    0.8383960905 pi
    """
    QR, QJ = np.broadcast_arrays(*check_invariants(QR=QR, QJ=QJ))
    strict_regions(QR, QJ, body, ("II", "IV"), "the extremum theta_e of V_phi")
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
    theta_X, QR, QJ = np.broadcast_arrays(check_finite("theta_X", theta_X), *check_invariants(QR=QR, QJ=QJ))
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

    Examples
    --------
    >>> import rocknroller as rr
    >>> body = rr.Body.paper()
    >>> QJ = 0.99 * rr.QJ_crit_pi(0.01, body)
    >>> print(f"{rr.delta_of(0.01, QJ, body):.12f}")
    0.010000000000
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
    import sympy as sp

    from rocknroller.analysis.criticality.laurent import SYMBOLS, V_phi_sym

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
    """Numeric (C₁, C₃) of :func:`delta_bound_sympy` for ``body``.

    Examples
    --------
    >>> import rocknroller as rr
    >>> C1, C3 = rr.delta_bound_coefficients(rr.Body.paper())
    >>> print(f"C1 = {C1:.12f}, C3 = {C3:.12f}")
    C1 = 1.550528274826, C3 = 0.002968312155
    """
    from rocknroller.analysis.criticality.laurent import SYMBOLS

    d = delta_bound_sympy()
    vals = {SYMBOLS["a"]: body.a, SYMBOLS["I1"]: body.I1, SYMBOLS["I3"]: body.I3}
    return float(d["C1"].evalf(30, subs=vals)), float(d["C3"].evalf(30, subs=vals))


def _check_delta(delta: ArrayLike) -> NDArray[np.float64]:
    d = check_finite("delta", delta)
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

    Examples
    --------
    >>> import rocknroller as rr
    >>> body = rr.Body.paper()
    >>> QR = 0.01
    >>> QJ = 0.99 * rr.QJ_crit_pi(QR, body)
    >>> exact = rr.theta_z(QR, QJ, body)
    >>> for terms in (1, 2):
    ...     print(f"{abs(rr.theta_z_expansion(0.01, body, terms) - exact):.1e}")
    ...
    3.6e-06
    6.1e-07
    """
    d = _check_delta(delta)
    if terms not in (1, 2):
        raise ValueError(f"terms must be 1 or 2, got terms={terms!r}")
    C1, C3 = delta_bound_coefficients(body)
    x = C1 * np.sqrt(d)
    if terms == 2:
        x = x + C3 * d * np.sqrt(d)
    return np.pi - x


def _ratio(QR: NDArray, QJ: NDArray) -> NDArray:
    if np.any(QR == 0.0):
        raise ValueError("QR must be nonzero: the ratio q = QJ/QR is undefined at QR = 0")
    return QJ / QR
