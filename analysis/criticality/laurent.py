"""Laurent expansions of V_φ and V_ψ about θ = 0 and θ = π (paper §criticality, eqs. phidotCJQR th=0 and th=pi).

The exact rates of Routh's sphere (paper eqs. phidotCJQR, psidotCJQR) are

    V_φ = [Q_J − ρ f I3 Q_R]/(I1 s²),    V_ψ = −[c Q_J − ρ(c f I3 + I1 s²) Q_R]/(I1 s²),

with ρ = [I3 + s² + (I3/I1) f²]^(−1/2), f = c − a.  Both are functions of c = cos θ only, so about either end
the expansion in the distance x (x = θ about 0, x = π − θ about π) contains only **even** powers of x:

    V = A₋₂ x⁻² + A₀ + A₂ x² + A₄ x⁴ + …,     A₋₁ = A₁ = A₃ = … = 0 identically.

The derivation here is exact polynomial algebra (no numerical fitting): with w = 1 − cos x one has
c = ±(1 − w), 1 − c² = w (2 − w) and ρ⁻² = D₀ (1 + u(w)) with u a quadratic polynomial in w, so ρ is a binomial
series in u; finally w = 2 sin²(x/2) is substituted and the result truncated in x.  The leading terms reproduce
the paper:

    V_φ ≈ (Q_J − Q_J,0^crit)/(I1 θ²)          about θ = 0,   Q_J,0^crit = ρ₀ (1 − a) I3 Q_R   (eq. QJcrit_0),
    V_φ ≈ (Q_J − Q_J,π^crit)/(I1 (π − θ)²)    about θ = π,   Q_J,π^crit = −ρ_π (1 + a) I3 Q_R (eq. QJcrit_pi),

and V_ψ ≈ −(Q_J − Q_J,0^crit)/(I1 θ²) about 0, V_ψ ≈ +(Q_J − Q_J,π^crit)/(I1 (π − θ)²) about π.

The error of φ̇ at a turning point by the highest order kept, at the paper's high-Q_R case (§numerics
"Recession and Criticality": Q_R = 0.1, θ_X = 0.95π, Q_J on Q_J,π^crit), is computed by
:func:`phidot_turning_point_errors` and checked in ``tests/analysis/criticality/test_laurent.py``.
"""

from __future__ import annotations

from functools import lru_cache
from types import SimpleNamespace
from typing import Callable, Protocol

import numpy as np
import sympy as sp
from numpy.typing import ArrayLike, NDArray

from rocknroller.analysis.model.body import Body
from rocknroller.analysis.model.invariants import V_phi, rho_inv_sq

__all__ = [
    "SYMBOLS",
    "V_phi_sym",
    "V_psi_sym",
    "laurent_coefficients",
    "laurent_series",
    "laurent_function",
    "phidot_turning_point_errors",
]

a, I1, I3 = sp.symbols("a I1 I3", positive=True)
QJ, QR = sp.symbols("Q_J Q_R", real=True)
theta, x = sp.symbols("theta x", positive=True)
_w = sp.Symbol("w", positive=True)

#: The sympy symbols used by every expression of this module.
SYMBOLS = {"a": a, "I1": I1, "I3": I3, "QJ": QJ, "QR": QR, "theta": theta, "x": x}

_QUANTITIES = ("phi", "psi")


def _rho_inv_sq(c: sp.Expr) -> sp.Expr:
    """ρ⁻² (paper eq. measure, rocknroller.analysis.model.invariants.rho_inv_sq) as a polynomial in c = cos θ."""
    return rho_inv_sq(SimpleNamespace(I1=I1, I3=I3), 1 - c**2, c - a)


def _numerators(c: sp.Expr, rho: sp.Expr) -> dict[str, sp.Expr]:
    """I1 s² V_φ and I1 s² V_ψ (paper eqs. phidotCJQR, psidotCJQR) in terms of c and ρ."""
    f = c - a
    return {
        "phi": QJ - rho * f * I3 * QR,
        "psi": -(c * QJ - rho * (c * f * I3 + I1 * (1 - c**2)) * QR),
    }


def V_phi_sym(th: sp.Expr = theta) -> sp.Expr:
    """Exact V_φ(θ; Q_J, Q_R) as a sympy expression (paper eq. phidotCJQR)."""
    c = sp.cos(th)
    return _numerators(c, 1 / sp.sqrt(_rho_inv_sq(c)))["phi"] / (I1 * sp.sin(th) ** 2)


def V_psi_sym(th: sp.Expr = theta) -> sp.Expr:
    """Exact V_ψ(θ; Q_J, Q_R) as a sympy expression (paper eq. psidotCJQR)."""
    c = sp.cos(th)
    return _numerators(c, 1 / sp.sqrt(_rho_inv_sq(c)))["psi"] / (I1 * sp.sin(th) ** 2)


def _about_sign(about: str | float) -> int:
    if isinstance(about, str):
        key = about.strip().lower()
        if key in ("0", "zero"):
            return 1
        if key in ("pi", "π"):
            return -1
    elif about == 0:
        return 1
    elif about == float(np.pi):
        return -1
    raise ValueError(f"about must be 0 or 'pi' (the two ends of 0 <= theta <= pi), got about={about!r}")


def _check(quantity: str, order: int) -> None:
    if quantity not in _QUANTITIES:
        raise ValueError(f"quantity must be one of {_QUANTITIES}, got quantity={quantity!r}")
    if not isinstance(order, (int, np.integer)) or order < -2:
        raise ValueError(f"order (highest power of x kept) must be an integer >= -2, got order={order!r}")


def _mul(p: list[sp.Expr], q: list[sp.Expr], n: int) -> list[sp.Expr]:
    """Product of two truncated power series (coefficient lists), kept to degree n."""
    return [sp.expand(sum((p[i] * q[k - i] for i in range(k + 1) if i < len(p) and k - i < len(q)),
                          sp.Integer(0))) for k in range(n + 1)]


def _poly_in(expr: sp.Expr, var: sp.Symbol, n: int) -> list[sp.Expr]:
    """Coefficient list of the polynomial ``expr`` in ``var`` up to degree n."""
    poly = sp.Poly(sp.expand(expr), var)
    return [poly.coeff_monomial(var**k) for k in range(n + 1)]


def _compose(outer: list[sp.Expr], inner: list[sp.Expr], n: int) -> list[sp.Expr]:
    """outer(inner(x)) for inner(0) = 0, truncated at degree n (Horner)."""
    out = [outer[-1]] + [sp.Integer(0)] * n
    for cf in reversed(outer[:-1]):
        out = _mul(out, inner, n)
        out[0] = out[0] + cf
    return out


@lru_cache(maxsize=None)
def _coefficients(quantity: str, sign: int, order: int) -> tuple[sp.Expr, ...]:
    """Coefficients A₋₂, A₋₁, …, A_order (index k + 2) of the expansion in x, exact sympy expressions.

    All arithmetic is on truncated coefficient lists, so the cost grows only polynomially with the order.
    """
    nx = order + 2            # degree kept in x of the regular factor x² V
    m = nx // 2               # degree kept in w (w = O(x²))
    c = sign * (1 - _w)
    D = _poly_in(_rho_inv_sq(c), _w, 2)          # ρ⁻² = D0 + D1 w + D2 w² exactly
    D0 = D[0]
    # Work with placeholders R = D0^(-1/2), d1 = D1/D0, d2 = D2/D0 (pure polynomial algebra, fast),
    # substituted at the end.
    R, d1, d2 = sp.symbols("R_ d1_ d2_")
    u = [sp.Integer(0), d1, d2] + [sp.Integer(0)] * max(m - 2, 0)
    # ρ = D0^(-1/2) (1 + u)^(-1/2):  binomial series composed with u(w)
    binom = [sp.binomial(sp.Rational(-1, 2), k) for k in range(m + 1)]
    rho = [R * cf for cf in _compose(binom, u[: m + 1], m)] if m >= 1 else [R]
    rho_sym = sp.Symbol("rho_w")
    num = sp.expand(_numerators(c, rho_sym)[quantity])
    # num is linear in ρ: num = P(w) + ρ Q(w)
    P = _poly_in(num.coeff(rho_sym, 0), _w, m)
    Q = _poly_in(num.coeff(rho_sym, 1), _w, m)
    numer = [P[k] + sum(Q[i] * rho[k - i] for i in range(k + 1)) for k in range(m + 1)]
    # I1 s² = I1 w (2 − w):  V = G(w)/w with G = numer/(2 I1) Σ (w/2)^k
    geom = [sp.Rational(1, 2) ** k / (2 * I1) for k in range(m + 1)]
    G = _mul(numer, geom, m)
    # w = 1 − cos x = (x²/2)(1 + r(x));  x² V = G(w(x)) · 2/(1 + r(x))
    w_x = [sp.Integer(0)] * (nx + 3)
    for k in range(1, nx // 2 + 2):
        w_x[2 * k] = sp.Integer(-1) ** (k + 1) / sp.factorial(2 * k)
    r = [sp.Integer(0)] + [2 * w_x[k + 2] for k in range(1, nx + 1)]
    w_x = w_x[: nx + 1]
    inv = _compose([2 * sp.Integer(-1) ** k for k in range(nx + 1)], r, nx)  # 2/(1 + r)
    G_x = _compose(G, w_x, nx) if m >= 1 else [G[0]] + [sp.Integer(0)] * nx
    subs = {R: 1 / sp.sqrt(D0), d1: sp.cancel(D[1] / D0), d2: sp.cancel(D[2] / D0)}
    return tuple(sp.expand(cf).subs(subs) for cf in _mul(G_x, inv, nx))


def laurent_coefficients(quantity: str, about: str | float, order: int) -> dict[int, sp.Expr]:
    """Exact Laurent coefficients of V_φ or V_ψ about θ = 0 or θ = π.

    Parameters
    ----------
    quantity : {"phi", "psi"}
        V_φ (paper eq. phidotCJQR) or V_ψ (paper eq. psidotCJQR).
    about : {0, "pi"}
        Expansion point; the variable is x = θ about 0 and x = π − θ about π.
    order : int
        Highest power of x kept, ``>= -2``.

    Returns
    -------
    dict
        ``{k: A_k}`` for k = −2, …, order; sympy expressions in the symbols of :data:`SYMBOLS`.  Odd k are exactly 0.

    Examples
    --------
    >>> import rocknroller as rr
    >>> A = rr.laurent_coefficients("phi", "pi", 0)
    >>> print(sorted(A))
    [-2, -1, 0]
    >>> print(A[-1])
    0
    """
    _check(quantity, order)
    coeffs = _coefficients(quantity, _about_sign(about), int(order))
    return {k - 2: cf for k, cf in enumerate(coeffs)}


def laurent_series(quantity: str, about: str | float, order: int) -> sp.Expr:
    """The truncated Laurent series Σ_{k=−2}^{order} A_k x^k as one sympy expression (see :func:`laurent_coefficients`).

    Examples
    --------
    >>> import rocknroller as rr
    >>> series = rr.laurent_series("phi", 0, 0)
    >>> sorted(str(s) for s in series.free_symbols)
    ['I1', 'I3', 'Q_J', 'Q_R', 'a', 'x']
    """
    return sum((cf * x**k for k, cf in laurent_coefficients(quantity, about, order).items()), sp.Integer(0))


@lru_cache(maxsize=None)
def _lambdified(quantity: str, sign: int, order: int) -> Callable:
    coeffs = _coefficients(quantity, sign, order)
    args = (x, QJ, QR, a, I1, I3)
    return sp.lambdify(args, sum(cf * x ** (k - 2) for k, cf in enumerate(coeffs)), modules="numpy")


class _SeriesFunction(Protocol):
    """What :func:`laurent_function` returns: ``fn(x, *, QR, QJ)``."""

    def __call__(self, xv: ArrayLike, *, QR: ArrayLike, QJ: ArrayLike) -> NDArray[np.float64]: ...


def laurent_function(quantity: str, about: str | float, order: int, body: Body) -> _SeriesFunction:
    """Fast numeric form of the truncated series (sympy ``lambdify``), vectorised over numpy arrays.

    Parameters
    ----------
    quantity, about, order
        As in :func:`laurent_coefficients`.
    body : Body
        Routh's sphere (I1 = I2 required; the paper's definitions use I1).

    Returns
    -------
    callable
        ``fn(x, *, QR, QJ)`` with x = θ (about 0) or x = π − θ (about π), ``x > 0`` (Q_R and Q_J keyword-only,
        as in :func:`rocknroller.analysis.model.invariants.V_phi`).

    Examples
    --------
    >>> import math
    >>> import rocknroller as rr
    >>> body = rr.Body.paper()
    >>> QR = 0.01
    >>> QJ = 0.99 * rr.QJ_crit_pi(QR, body)
    >>> fn = rr.laurent_function("phi", "pi", 4, body)
    >>> x = 1e-2
    >>> print(abs(fn(x, QR=QR, QJ=QJ) / rr.V_phi(math.pi - x, QR=QR, QJ=QJ, body=body) - 1) < 1e-10)
    True
    """
    _check(quantity, order)
    body.require_symmetric("the Laurent expansion of V_phi, V_psi")
    fn = _lambdified(quantity, _about_sign(about), int(order))

    def evaluate(xv: ArrayLike, *, QR: ArrayLike, QJ: ArrayLike) -> NDArray[np.float64]:
        QRv, QJv = QR, QJ
        xv = np.asarray(xv, float)
        if np.any(~(xv > 0)):
            raise ValueError("x (distance from the expansion point) must be > 0 and finite")
        out = fn(xv, np.asarray(QJv, float), np.asarray(QRv, float), body.a, body.I1, body.I3)
        return np.broadcast_to(np.asarray(out, float), np.broadcast_shapes(xv.shape, np.shape(QJv), np.shape(QRv))).copy()

    return evaluate


def phidot_turning_point_errors(body: Body, theta_X: float, QR: float, QJ: float,
                                orders: tuple[int, ...] = (-2, 0, 2, 4, 6)) -> dict[int, dict[str, float]]:
    """How well the series about π predicts φ̇ at the turning point θ_X, order by order (paper §numerics "Recession and Criticality").

    The exact value is V_φ(θ_X; Q_J, Q_R) (paper eq. phidotCJQR); the prediction is the series about θ = π
    truncated after x^order, x = π − θ_X.

    Returns
    -------
    dict
        ``{order: {"exact", "predicted", "abs_error", "rel_error"}}``.
    """
    if not 0.0 < theta_X < np.pi:
        raise ValueError(f"theta_X must satisfy 0 < theta_X < pi, got theta_X={theta_X!r}")
    exact = float(V_phi(theta_X, QR=QR, QJ=QJ, body=body))
    xv = np.pi - theta_X
    out: dict[int, dict[str, float]] = {}
    for n in orders:
        pred = float(laurent_function("phi", "pi", n, body)(xv, QR=QR, QJ=QJ))
        err = abs(pred - exact)
        out[n] = {"exact": exact, "predicted": pred, "abs_error": err,
                  "rel_error": err / abs(exact) if exact != 0.0 else float("inf")}
    return out
