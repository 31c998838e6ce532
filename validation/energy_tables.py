"""The tables over energy against the per-θ0 tables (docs/slow_validation.md, "Tables over energy").

Run:  python validation/energy_tables.py
(the tables over energy of the paper body built if not cached, ~5 min of CPU on 2 cores; then each release angle's
per-θ0 release and second-order tables, ~10 s each if not cached).

At release angles between the nodes, across ``THETA0_RANGE``:

* the interpolated release table against the per-θ0 table (``kick_error``: T, W, Δφ and each kick relative to its
  largest value, at the per-θ0 table's nodes) and k₂ against the per-θ0 second-order table (``k2_error``);
* one step of the order-2 map from six points of the chart (three points, two angles Θ) at ε = 1e-3, or half the
  period doubling's ε where that is smaller: the difference between the two tables' steps over the per-θ0 map's own
  error against the exact step (the direct ODE from maximum to maximum: the ε³ truncation), per component (Q, Θ, t,
  φ), and the interpolated map's error against the exact step over the per-θ0 map's;
* the noise floor of the data over energy: the Chebyshev coefficients in s = log(π − θ0) of the ε-responses at a
  node of the chart level off at ~1e-12 of their size for the Q responses and ~1e-6 for the Θ and t responses, the
  rounding of the variational orbits, which the per-θ0 tables carry as well.
"""

from __future__ import annotations

import math
import warnings

import numpy as np

from rocknroller.analysis.model.body import Body
from rocknroller.analysis.model.diagnostics import wrap_angle
from rocknroller.analysis.slow.map import tables_at_once as ta
from rocknroller.analysis.slow.map.chart import cheb_fit_matrix
from rocknroller.analysis.slow.map.compiled_map import iterate_slow_map
from rocknroller.analysis.slow.map.exact_step import exact_step
from rocknroller.analysis.slow.map.limits import AveragingValidityWarning
from rocknroller.analysis.slow.map.second_order import load_or_build_second_order_table
from rocknroller.analysis.slow.map.table import load_or_build_table

BODY = Body.paper()
FRACTIONS = (0.76, 0.8, 0.87, 0.93, 0.97, 0.99, 0.997)
POINTS = ((0.3, 0.3), (0.05, -0.5), (-0.7, 0.2))
ANGLES = (0.9, 4.0)


def _step(table, second, Q, theta, eps):
    r = iterate_slow_map(table, eps, 0.5 * theta, 1e6, Q0=Q, n_steps=1, second=second)
    return np.array([r.QR[0], r.QJ[0], r.Theta[0], r.t[0], r.phi[0]])


def _sizes(d):
    d = d.copy()
    d[2], d[4] = wrap_angle(d[2]), wrap_angle(d[4], math.pi)
    return np.array([np.hypot(d[0], d[1]), *np.abs(d[2:])])


def main() -> None:
    warnings.simplefilter("ignore", AveragingValidityWarning)
    span = ta.load_energy_tables(BODY, workers=2)
    print(f"tables over energy: {span.resp.shape[0]} nodes (first order), {span.k2.shape[0]} (k2) in s = log(pi - theta0)"
          f" over [{span.theta0_lo / math.pi:.4g}pi, {span.theta0_hi / math.pi:.4g}pi]; the build's own checks: "
          f"{span.first_error:.1e} (first order), {span.second_error:.1e} (k2)")
    print("| θ0 | ε | first order | k₂ | step: interp − per-θ0 over per-θ0 − exact (Q, Θ, t, φ) "
          "| interp − exact over per-θ0 − exact (Q, Θ, t, φ) |")
    print("|---|---|---|---|---|---|")
    for f in FRACTIONS:
        t0 = f * math.pi
        per, per2 = load_or_build_table(BODY, t0), load_or_build_second_order_table(BODY, t0)
        got, got2 = span.release_table(t0), span.second_order_table(t0)
        eps = min(1e-3, 0.5 * 4.0 / abs(per.kappa))
        ratio, rel = np.zeros(4), np.zeros(4)
        for x, y in POINTS:
            Q = np.array([float(c) for c in per.chart(x, y)])
            for th in ANGLES:
                exact = exact_step(BODY, eps, per.E0, Q[0], Q[1], 0.5 * th)
                p, q = _step(per, per2, Q, th, eps), _step(got, got2, Q, th, eps)
                own = _sizes(p - exact)
                ratio = np.maximum(ratio, _sizes(q - p) / own)
                rel = np.maximum(rel, _sizes(q - exact) / own)
        print(f"| {f:g}π | {eps:.2g} | {ta.kick_error(got, per):.1e} | {ta.k2_error(got, got2, per, per2):.1e} | "
              + ", ".join(f"{r:.2g}" for r in ratio) + " | " + ", ".join(f"{r:.3f}" for r in rel) + " |")
    A = cheb_fit_matrix(span.resp.shape[0])
    print("noise floor: the largest of the last ten Chebyshev coefficients in s of the reduced responses at chart node "
          "(64, 3), harmonic c1, over the largest value:")
    for k, name in enumerate(("Q_R", "Q_J", "Theta", "t", "phi")):
        v = span.resp[:, k, 64, 3, 1]
        print(f"  {name}: {np.abs(A @ v)[-10:].max() / np.abs(v).max():.1e}")


if __name__ == "__main__":
    main()
