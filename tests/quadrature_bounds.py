"""Derived bounds on the double-precision quadrature's error, shared by the quadrature tests and the table command's
tests (tests/analysis/routh/test_quadrature.py, tests/api/cli/test_table.py): a module of its own beside
``roundoff.py``, so that no test file imports another."""

from __future__ import annotations

import numpy as np
import roundoff as ro

from rocknroller.analysis.model.body import Body

#: Safety margin of the quadrature's rounding bound (``quadrature_bound``).
MARGIN = 4.0
#: Rounded operations in one evaluation of an integrand at a node (x, y, P, D, √, u, the residues, ω3).
N_OPS_NODE = 40
#: The body of the quadrature tests (the paper's, symmetric).
BODY = Body.paper()


def _root_error(tp, i: int, end: str) -> float:
    """Relative rounding bound of a turning point in its exact end variable z (x near θ = 0, y near π): P's
    operations (γ_16) × the amplification (|2 s² K| + |N|)/|z ∂P/∂z| of the rounding of P's terms into the root
    (∂P/∂z by central differences), + u."""
    from rocknroller.analysis.routh.reduction import _P_and_terms

    x, y = (float(np.ravel(getattr(tp, f"{c}_{end}"))[i]) for c in ("x", "y"))
    E, QR, QJ = (float(np.ravel(getattr(tp, k))[i]) for k in ("E", "QR", "QJ"))
    use_x = x <= y
    z = x if use_x else y
    xy = (lambda z: (z, 2.0 - z)) if use_x else (lambda z: (2.0 - z, z))
    h = 1e-6
    P = lambda z: _P_and_terms(*xy(z), E, QR, QJ, BODY)[0]  # noqa: E731
    zdP = abs(P(z * (1 + h)) - P(z * (1 - h))) / (2 * h)
    terms = float(_P_and_terms(x, y, E, QR, QJ, BODY)[1])
    return ro.gamma(16) * terms / zdP + ro.u


def quadrature_bound(tp, n_nodes) -> tuple[np.ndarray, np.ndarray]:
    """Per point, bounds on the double quadrature's error: relative for T_θ, in radians for Δφ, Δψ (per T_θ).

    (a) The library's estimate of P's rounding at the nodes (``rounding_error``'s two parts); (b) the rule itself:
    numpy's leggauss takes the nodes from the eigenvalues of the n×n Jacobi matrix and the weights from one Newton
    step on the n-term Legendre recurrence, each within γ_{2n} (numpy documents it as tested to degree 100 only),
    then each integrand value (N_OPS_NODE operations) and the sums (n/2 terms per half): γ_{2n + n/2 + ops} × Σ|w f|
    (T_θ's integrand is positive; for the angles the L1 norm of their integrands); (c) the turning points'
    rounding (``_root_error``), carried into the integrals by the rule's response to moving each end inward,
    measured by a one-sided difference (the substitution stretches a root's rounding over the nodes near it by
    ~1/e, e a node's distance from the end: more nodes, larger response; ``rounding_error`` leaves this out).
    (d) Δφ = kπ + 2 I_φ and the wrap of the visible angle round (3u max(|Δφ|, |Δψ|, π)).  T_θ = 2 T_half.
    × MARGIN.  Private functions of rocknroller.analysis.routh.quadrature: the same rule.
    """
    from rocknroller.analysis.routh import quadrature as q

    names = ("x_N", "y_N", "x_X", "y_X", "E", "QR", "QJ", "u0", "upi")
    bT, bA = [], []
    for i, n in enumerate(np.ravel(n_nodes)):
        n = int(n)
        f0 = [np.array([float(np.ravel(getattr(tp, k))[i])]) for k in names]
        T, Iphi, Ipsi, L1, _, eT, eA = (float(v[0]) for v in q._half_integrals(*f0, BODY, n))
        sums = ro.gamma(2 * n + n // 2 + N_OPS_NODE)
        dT = dA = 0.0
        eta = 1e-9
        for end, (ix, iy) in (("N", (0, 1)), ("X", (2, 3))):
            f1 = [a.copy() for a in f0]
            x, y = f0[ix][0], f0[iy][0]
            inward = 1.0 if end == "N" else -1.0  # θ_N up, θ_X down
            if x <= y:
                f1[ix][0] = x * (1 + inward * eta)
                f1[iy][0] = 2.0 - f1[ix][0]
            else:
                f1[iy][0] = y * (1 - inward * eta)
                f1[ix][0] = 2.0 - f1[iy][0]
            T1, Iphi1, Ipsi1 = (float(v[0]) for v in q._half_integrals(*f1, BODY, n)[:3])
            err = _root_error(tp, i, end)
            dT += abs(T1 - T) / eta * err
            dA += max(abs(Iphi1 - Iphi), abs(Ipsi1 - Ipsi)) / eta * err
        bT.append(MARGIN * (eT / T + sums + dT / T))
        kphi = abs(float(np.ravel(np.sign(tp.u0))[i]) + float(np.ravel(np.sign(tp.upi))[i])) * np.pi
        assemble = 3 * ro.u * max(kphi + 2 * abs(Iphi), 2 * abs(Ipsi) + 2 * np.pi, np.pi)
        bA.append(MARGIN * (2 * (eA + sums * L1 + dA) + assemble))
    return np.array(bT), np.array(bA)


def _bound_at(E, QR, QJ, n_nodes):
    """``quadrature_bound`` at one point (E, Q_R, Q_J) with the node count the quadrature used."""
    from rocknroller.analysis.routh.turning_points import solve_turning_points

    bT, bA = quadrature_bound(solve_turning_points(np.atleast_1d(E), np.atleast_1d(QR), np.atleast_1d(QJ), BODY),
                              np.atleast_1d(n_nodes))
    return float(bT[0]), float(bA[0])
