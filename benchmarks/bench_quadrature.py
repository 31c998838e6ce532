"""Precession quadratures side by side: the vectorised rule, scipy.integrate.quad point by point, mpmath.

Run:  python benchmarks/bench_quadrature.py [--n-table 10000] [--n-acc 60] [--dps 40]

* Speed: a 10^4-point table (paper body, θ_X = θ0 = 0.95π, Q_R, Q_J ∈ [−0.01, 0.01]) with the vectorised
  double-precision rule (rocknroller.analysis.routh.quadrature.precession_from_turning_point).
* Accuracy and time per point on ``n_acc`` points spread over the plane (a third with θ_N < 1e-3, a
  sixth with θ_X > π − 1e-3), against the mpmath reference (rocknroller.analysis.routh.quadrature_mp.precession_mp):
  - the vectorised rule;
  - scipy.integrate.quad with the algebraic end-point weight (QUADPACK QAWS, weight='alg',
    wvar=(−½, −½)) in θ, i.e. the standard way to integrate dθ/√F between simple roots,
    f(θ) = √((θ − θ_N)(θ_X − θ)/F(θ)) and V_φ f, V_ψ f, with the same turning points;
  - mpmath itself (time only).
Errors: T_θ relative; Δφ, Δψ per T_θ relative to max(|Δ|, 1 rad).
"""

from __future__ import annotations

import argparse
import time
import warnings

import numpy as np
from scipy import integrate

from rocknroller.analysis.model.body import Body
from rocknroller.analysis.model.invariants import V_phi, V_psi
from rocknroller.analysis.routh.quadrature import precession, precession_from_turning_point
from rocknroller.analysis.routh.quadrature_mp import precession_mp
from rocknroller.analysis.routh.reduction import F, state_from_turning_point, u_ends
from rocknroller.analysis.routh.turning_points import turning_points


def points(rng: np.random.Generator, n: int, body: Body) -> tuple[np.ndarray, np.ndarray, np.ndarray]:
    """(E, Q_R, Q_J): half generic, a third with θ_N small, a sixth with θ_X near π."""
    theta0, QR, QJ = [], [], []
    for i in range(n):
        q = rng.uniform(-0.02, 0.02)
        kind = i % 6
        if kind < 3:
            t0, qj = rng.uniform(0.55, 0.99) * np.pi, rng.uniform(-0.02, 0.02)
        elif kind < 5:
            t0 = rng.uniform(0.55, 0.99) * np.pi
            qj = -float(u_ends(q, 0.0, body)[0]) + rng.choice([-1, 1]) * 10 ** rng.uniform(-10, -4)
        else:
            t0 = np.pi - 10 ** rng.uniform(-7, -3)
            qj = -float(u_ends(q, 0.0, body)[1]) + rng.choice([-1, 1]) * 10 ** rng.uniform(-8, -2)
        theta0.append(t0)
        QR.append(q)
        QJ.append(qj)
    E = state_from_turning_point(body, np.array(theta0), np.array(QR), np.array(QJ)).E
    return E, np.array(QR), np.array(QJ)


def scipy_point(E: float, QR: float, QJ: float, body: Body) -> tuple[float, float, float]:
    """T_θ, Δφ, Δψ per T_θ with scipy.integrate.quad (QAWS algebraic weight at both turning points)."""
    tN, tX = (float(v) for v in turning_points(E, QR, QJ, body))

    lo, hi = np.nextafter(tN, tX), np.nextafter(tX, tN)

    def f(th):
        # QAWS may sample the end points, and within round-off of a turning point F may come out ≤ 0:
        # keep θ strictly inside and use |F| (the integrand must be finite)
        th = min(max(th, lo), hi)
        val = np.sqrt(np.abs((th - tN) * (tX - th) / F(th, E, QR, QJ, body)))
        return float(val) if np.isfinite(val) else 0.0

    opts = dict(weight="alg", wvar=(-0.5, -0.5), epsabs=0.0, epsrel=1e-13, limit=200)
    with warnings.catch_warnings():
        warnings.simplefilter("ignore")
        T = integrate.quad(f, tN, tX, **opts)[0]
        ph = integrate.quad(lambda th: V_phi(th, QR=QR, QJ=QJ, body=body) * f(th), tN, tX, **opts)[0]
        ps = integrate.quad(lambda th: V_psi(th, QR=QR, QJ=QJ, body=body) * f(th), tN, tX, **opts)[0]
    return 2 * T, 2 * ph, 2 * ps


def main() -> None:
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--n-table", type=int, default=10_000)
    ap.add_argument("--n-acc", type=int, default=60)
    ap.add_argument("--dps", type=int, default=40)
    args = ap.parse_args()
    body = Body.paper()

    # --- speed: the 10^4-point table -----------------------------------------------------------------
    side = int(round(np.sqrt(args.n_table)))
    QR, QJ = (a.ravel() for a in np.meshgrid(np.linspace(-0.01, 0.01, side), np.linspace(-0.01, 0.01, side)))
    precession_from_turning_point(0.95 * np.pi, QR[:10], QJ[:10], body)  # warm-up
    t = time.perf_counter()
    pr, _ = precession_from_turning_point(0.95 * np.pi, QR, QJ, body)
    t_table = time.perf_counter() - t
    print(f"vectorised rule, {QR.size}-point table (theta_X = 0.95 pi): {t_table:.3f} s "
          f"({1e6 * t_table / QR.size:.1f} us/point), nodes used: {sorted(set(pr.n_nodes.ravel().tolist()))}")

    # --- accuracy and time per point on points spread over the plane ----------------------------------
    E, QR, QJ = points(np.random.default_rng(2024), args.n_acc, body)
    t = time.perf_counter()
    vec = precession(E, QR, QJ, body)
    t_vec = (time.perf_counter() - t) / E.size
    t = time.perf_counter()
    sp = np.array([scipy_point(E[i], QR[i], QJ[i], body) for i in range(E.size)])
    t_sp = (time.perf_counter() - t) / E.size
    t = time.perf_counter()
    ref = [precession_mp(E[i], QR[i], QJ[i], body, dps=args.dps) for i in range(E.size)]
    t_mp = (time.perf_counter() - t) / E.size
    R = np.array([[float(r.T_theta), float(r.delta_phi), float(r.delta_psi)] for r in ref])
    V = np.stack([vec.T_theta, vec.delta_phi, vec.delta_psi], axis=1)
    scale = np.concatenate([np.abs(R[:, :1]), np.maximum(np.abs(R[:, 1:]), 1.0)], axis=1)
    err_vec = np.abs(V - R) / scale
    err_sp = np.abs(sp - R) / scale
    n_small, n_pi = int(np.sum(vec.theta_N < 1e-3)), int(np.sum(vec.theta_X > np.pi - 1e-3))
    print(f"\n{E.size} points over the plane ({n_small} with theta_N < 1e-3, {n_pi} with theta_X > pi - 1e-3), "
          f"reference mpmath dps={args.dps}")
    print(f"{'method':28s} {'time/point':>12s} {'max err T':>11s} {'max err dphi':>13s} {'max err dpsi':>13s} "
          f"{'median err':>11s}")
    for name, tp, err in (("vectorised rule (double)", t_vec, err_vec), ("scipy.integrate.quad (QAWS)", t_sp, err_sp)):
        print(f"{name:28s} {1e6 * tp:10.1f}us {err[:, 0].max():11.2e} {err[:, 1].max():13.2e} "
              f"{err[:, 2].max():13.2e} {np.median(err):11.2e}")
    print(f"{'mpmath (reference)':28s} {1e6 * t_mp:10.1f}us")
    print(f"\nratios: scipy.quad / vectorised time = {t_sp / t_vec:.0f}x;  mpmath / vectorised time = "
          f"{t_mp / t_vec:.0f}x;  scipy.quad / vectorised max error = {err_sp.max() / max(err_vec.max(), 1e-17):.0f}x "
          f"(median {np.median(err_sp) / max(np.median(err_vec), 1e-17):.0f}x)")
    worst = np.argmax(err_sp.max(axis=1))
    print(f"scipy's worst point: theta_N={vec.theta_N[worst]:.3g}, pi-theta_X={np.pi - vec.theta_X[worst]:.3g}")


if __name__ == "__main__":
    main()
