"""Round-off bounds for the tests, derived from an error analysis of what is compared.

A comparison of two floating-point computations of the same quantity may only use a bound of the form

    (number of rounded operations, or of steps)  ×  (amplification of an error by what follows)  ×  u  ×  margin,

with u = 2⁻⁵³ the unit round-off of IEEE double precision, the amplification computed from the problem
(a condition number, or the growth of the tangent map of an iterated map along the run) and a stated
safety margin for the first-order (linearised) analysis.  Never the value one machine happened to give:
the order of a sum (SIMD kernels, BLAS, compiler) is not fixed, only its error bound is.

The constants follow Higham, *Accuracy and Stability of Numerical Algorithms* (2nd ed., SIAM 2002):
a sum or dot product of n terms, in any order, errs by at most γ_n Σ|aᵢ bᵢ| with γ_n = n u/(1 − n u)
(§3.1, eq. 3.5); a product of n rounded factors by γ_n relative (Lemma 3.1).

Helpers: ``u`` and :func:`gamma`; :func:`formula_bound` (operations × condition × u for a formula);
:func:`relative_condition` (amplification of componentwise relative errors of a state into a function of it);
:func:`fd_jacobian`, :func:`propagated_bound` and :func:`amplification` (an iterated map's own amplification,
from its Jacobians along a run); :func:`integration_bound` (steps × tolerance × amplification for an ODE run);
:func:`energy_condition` (the energy's amplification, from the body alone); :func:`assert_within` (the check,
with the worst ratio in its message).  With ROUNDOFF_LOG=<file> set, every check appends its error, bound,
their ratio and the smallest relative error the bound detects (an audit of how tight each bound is).
"""

from __future__ import annotations

from typing import Callable

import numpy as np
from numpy.typing import ArrayLike, NDArray

#: Unit round-off of IEEE-754 double precision, u = 2⁻⁵³ (half the machine epsilon).
UNIT_ROUNDOFF = float(np.finfo(float).eps) / 2.0
u = UNIT_ROUNDOFF


def gamma(n: float) -> float:
    """Higham's γ_n = n u / (1 − n u): the relative error bound of n rounded operations in a chain.

    Parameters
    ----------
    n : float
        Number of rounded operations (n u < 1).

    Returns
    -------
    float
        γ_n.
    """
    if not 0 <= n * u < 1:
        raise ValueError(f"gamma needs 0 <= n u < 1, got n={n!r}")
    return n * u / (1.0 - n * u)


def fd_jacobian(fun: Callable[[NDArray[np.float64]], ArrayLike], x: ArrayLike, h: ArrayLike) -> NDArray[np.float64]:
    """Jacobian of ``fun`` at ``x`` by central differences, column j with the step ``h[j]``.

    Used to measure how a map amplifies a perturbation; its O(h²) truncation and O(u/h) round-off
    change the amplification by a relative amount far below any safety margin.

    Parameters
    ----------
    fun : callable
        x (1-D array) ↦ values (1-D array).
    x : array_like
        The point.
    h : array_like
        One step per component of x (absolute).

    Returns
    -------
    ndarray, shape (len(fun(x)), len(x))
    """
    x = np.asarray(x, float)
    h = np.broadcast_to(np.asarray(h, float), x.shape)
    cols = []
    for j in range(x.size):
        e = np.zeros_like(x)
        e[j] = h[j]
        cols.append((np.asarray(fun(x + e), float) - np.asarray(fun(x - e), float)) / (2.0 * h[j]))
    return np.stack(cols, axis=1)


def propagated_bound(jacobians: ArrayLike, local: ArrayLike) -> NDArray[np.float64]:
    """Componentwise first-order bound on the error of an iterated map from bounds on its local errors.

    If step n (n = 1 … N) maps x_{n−1} ↦ x_n with Jacobian J_n = ∂x_n/∂x_{n−1} and the two computations
    compared differ by at most δ_n (componentwise) in one step started from the same x_{n−1}, their
    difference after step n is, to first order in the errors,

        |e_n| ≤ B_n = Σ_{m=1}^{n} |J_n J_{n−1} ⋯ J_{m+1}| δ_m      (|·| of a matrix: entrywise).

    The products of Jacobians are the map's own amplification of an error made at step m, taken along
    the run; the bound uses their entries (not norms), so it needs no choice of scales.

    Parameters
    ----------
    jacobians : array_like, shape (N, d, d)
        J_1 … J_N along the run.
    local : array_like, shape (N, d)
        δ_1 … δ_N, nonnegative.

    Returns
    -------
    ndarray, shape (N, d)
        B_1 … B_N.
    """
    J = np.asarray(jacobians, float)
    delta = np.asarray(local, float)
    N, d = delta.shape
    if J.shape != (N, d, d) or np.any(delta < 0):
        raise ValueError(f"need N Jacobians (N, d, d) and N nonnegative local bounds (N, d), "
                         f"got {J.shape}, {delta.shape}")
    out = np.empty((N, d))
    P = np.zeros((0, d, d))  # P[m] = J_n ⋯ J_{m+1} for m < n, the products up to the current step
    for n in range(N):
        P = np.concatenate([np.einsum("ij,mjk->mik", J[n], P), np.eye(d)[None]], axis=0)
        out[n] = np.einsum("mij,mj->i", np.abs(P), delta[: n + 1])
    return out


def amplification(jacobians: ArrayLike, scale: ArrayLike) -> float:
    """Largest growth of an error along an iterated map: max over m ≤ n of ‖D⁻¹ J_n ⋯ J_{m+1} D‖_∞.

    D = diag(scale) puts the components in comparable units (a relative perturbation of each).  This is
    the summary number quoted in docstrings; the bounds themselves use :func:`propagated_bound`.

    Parameters
    ----------
    jacobians : array_like, shape (N, d, d)
    scale : array_like, shape (d,)

    Returns
    -------
    float
    """
    J = np.asarray(jacobians, float)
    s = np.asarray(scale, float)
    Js = J * s[None, None, :] / s[None, :, None]
    best, P = 1.0, np.zeros((0,) + Js.shape[1:])
    for Jn in Js:
        P = np.concatenate([np.einsum("ij,mjk->mik", Jn, P), np.eye(Js.shape[1])[None]], axis=0)
        best = max(best, float(np.abs(P).sum(axis=2).max()))
    return best


def integration_bound(n_steps: int, tolerance: float, amplification: float = 1.0) -> float:
    """Error of an adaptive integration run, to first order: n_steps × tolerance × amplification.

    Error model: heyoka runs at tolerance ε (machine epsilon = 2u), which holds each step's truncation at
    the level of the rounding of the state, so every step perturbs each component by ≲ ε of itself
    (Jorba & Zou, Exp. Math. 14, 2005; heyoka's "tolerance" documentation).  In the worst case these add up
    linearly over the steps, each carried to the compared quantity by ``amplification``: for a conserved
    quantity q its :func:`relative_condition` (a perturbation changes q once, the flow then keeps it), for
    anything else the growth of a perturbation along the flow, measured by the caller.

    Parameters
    ----------
    n_steps : int
        Steps taken (the run objects report it: ``Trajectory.n_steps``).
    tolerance : float
        The integrator's tolerance (``Trajectory.tolerance``; machine epsilon for heyoka in double).
    amplification : float
        Change of the compared quantity per unit relative error of every state component.

    Returns
    -------
    float
    """
    return float(max(int(n_steps), 1)) * float(tolerance) * float(amplification)


def assert_within(err: ArrayLike, bound: ArrayLike, what: str = "", value: ArrayLike | None = None) -> float:
    """Assert |err| ≤ bound elementwise, naming the worst element; return max(|err| / bound).

    Parameters
    ----------
    err : array_like
        Observed differences.
    bound : array_like
        Their derived bounds (same shape, or broadcastable).
    what : str
        Label for the message.
    value : array_like, optional
        The compared values: with $ROUNDOFF_LOG set, the smallest relative error the bound still detects,
        min(bound / |value|), is logged with the ratio (an audit of how tight each bound is).

    Returns
    -------
    float
        The largest ratio |err|/bound (≤ 1 when the assertion holds): how much of the bound was used.
    """
    e, b = np.broadcast_arrays(np.abs(np.asarray(err, float)), np.asarray(bound, float))
    with np.errstate(divide="ignore", invalid="ignore"):
        ratio = np.where(e == 0.0, 0.0, e / b)
        detect = float("nan") if value is None else float(np.min(b / np.abs(np.asarray(value, float))))
    i = int(np.argmax(ratio)) if ratio.size else 0
    worst = float(ratio.reshape(-1)[i]) if ratio.size else 0.0
    ei, bi = (float(x.reshape(-1)[i]) if x.size else 0.0 for x in (e, b))
    _log(what, ei, bi, worst, detect)
    assert worst <= 1.0, (f"{what}: round-off difference {ei:.3g} exceeds its derived bound {bi:.3g} "
                          f"(ratio {worst:.3g}) at element {np.unravel_index(i, e.shape) if e.ndim else ()}")
    return worst


def _log(what: str, err: float, bound: float, ratio: float, detect: float) -> None:
    """Append (test, label, error, bound, ratio, detectable relative error) to $ROUNDOFF_LOG, if set."""
    import os

    path = os.environ.get("ROUNDOFF_LOG")
    if path:
        test = os.environ.get("PYTEST_CURRENT_TEST", "?").split(" ")[0]
        with open(path, "a", encoding="utf-8") as fh:
            fh.write(f"{test}\t{what}\t{err:.3e}\t{bound:.3e}\t{ratio:.3g}\t{detect:.3g}\n")


def relative_condition(fun: Callable[[NDArray[np.float64]], ArrayLike], Y: ArrayLike,
                       rel: float = 1e-6) -> NDArray[np.float64]:
    """Σᵢ |yᵢ ∂f/∂yᵢ| for each row y of ``Y``: the change of f when every component of y is perturbed by
    one unit of relative error (to first order).  It is the amplification of componentwise relative errors
    of the state (rounding, or an integrator's error held at that level) into f.

    Central differences with relative steps ``rel``: exact to rounding for polynomials of degree ≤ 2 and
    accurate to O(rel²) otherwise, far below any safety margin.

    Parameters
    ----------
    fun : callable
        Y (shape (N, d)) ↦ values (shape (N,)), vectorised over rows.
    Y : array_like, shape (N, d)
    rel : float

    Returns
    -------
    ndarray, shape (N,)
    """
    Y = np.atleast_2d(np.asarray(Y, float))
    out = np.zeros(Y.shape[0])
    for i in range(Y.shape[1]):
        h = rel * Y[:, i]
        if not np.any(h):
            continue
        Yp, Ym = Y.copy(), Y.copy()
        Yp[:, i] += h
        Ym[:, i] -= h
        d = (np.asarray(fun(Yp), float) - np.asarray(fun(Ym), float)) / 2.0  # = h ∂f/∂yᵢ = rel yᵢ ∂f/∂yᵢ
        out += np.abs(d) / rel
    return out


def energy_condition(body) -> float:
    """c with Σᵢ |yᵢ ∂E/∂yᵢ| ≤ c (E + g a) for every state of ``body``: the amplification of componentwise relative
    errors of the state (γ, ω) into E, relative to the energy scale E + g a (``rocknroller.numerics.run_limits.energy_scale``).

    E = ½ ωᵀK ω + g a (1 − γ3), K = diag(I) + |r|² − r rᵀ, r = γ − a e3, λ_min(K) ≥ min I, λ_max(K) ≤ max I + (1 + a)².
    Σ|ωᵢ (Kω)ᵢ| ≤ |ω| |Kω| ≤ λ_max |ω|²; |∂T/∂r| = ||ω|² r − (ω·r) ω| ≤ 2 |ω|² |r|, |r| ≤ 1 + a, so
    Σ|γᵢ ∂T/∂γᵢ| ≤ 2 (1 + a) |ω|²; |γ3 ∂V/∂γ3| ≤ g a; and |ω|² ≤ 2T/λ_min, T ≤ E (V ≥ 0).  Hence
    c = max(2 (λ_max + 2 (1 + a))/λ_min, 1).

    Parameters
    ----------
    body : rocknroller.analysis.model.body.Body

    Returns
    -------
    float
    """
    lam_min = min(body.I1, body.I2, body.I3)
    lam_max = max(body.I1, body.I2, body.I3) + (1.0 + body.a) ** 2
    return max(2.0 * (lam_max + 2.0 * (1.0 + body.a)) / lam_min, 1.0)


def formula_bound(fun: Callable[..., ArrayLike], inputs: dict, n_ops: int, rel: float = 1e-8) -> NDArray[np.float64]:
    """Rounding bound of a formula evaluated in n_ops rounded operations: γ_{n_ops} × Σᵢ |xᵢ ∂f/∂xᵢ|.

    Σᵢ |xᵢ ∂f/∂xᵢ| is the formula's absolute condition number with respect to relative perturbations of all
    its inputs (the numeric constants and parameters included); it measures the cancellation among the
    terms, and the n_ops roundings act like relative perturbations of that size (each by ≤ u).  This is
    the "operations × amplification × u" bound; callers multiply it by a stated safety margin.

    Parameters
    ----------
    fun : callable
        fun(**inputs) ↦ values, vectorised over array inputs.
    inputs : dict
        Name ↦ value (scalars or arrays broadcast together); zero inputs contribute nothing.
    n_ops : int
        Rounded operations in one evaluation (count them in the code evaluated).
    rel : float
        Relative step of the central differences.

    Returns
    -------
    ndarray
        γ_{n_ops} × Σᵢ |xᵢ ∂f/∂xᵢ|, one value per output element.
    """
    base = {k: np.asarray(v, float) for k, v in inputs.items()}
    kappa = 0.0
    for name, x in base.items():
        if not np.any(x):
            continue
        up, down = dict(base), dict(base)
        up[name], down[name] = x * (1 + rel), x * (1 - rel)
        kappa = kappa + np.abs(np.asarray(fun(**up), float) - np.asarray(fun(**down), float)) / (2 * rel)
    return gamma(n_ops) * np.asarray(kappa, float)
