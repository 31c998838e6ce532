"""The release atlas's MEGNO layer against the direct motion's MEGNO (issue 23, item 6; docs/slow_howto.md, "Atlas").

Run:  python validation/atlas_megno.py [--n-eps 20] [--n-psi 20] [--t-end 1000] [--threads 1]

For ε log-spaced in [1e-3, 1.5e-2] (``--n-eps`` values) the release atlas of the paper body over θ0 ∈ {0.9π, 0.95π}
and ψ0 evenly in (0, π/2] (``--n-psi`` values, π/2 included: issue 23's acceptance grid), by the map of order
``--order`` (default 2) with its chaos layer over ``slow``'s span, max(t_end, 1000 rocks)
(:func:`rocknroller.analysis.slow.atlas.atlas_from_rest`), is confirmed at every point
(:func:`~rocknroller.analysis.slow.atlas_check.confirm_atlas` with ``every=1``: the direct run over t_end and the
variational run over the same span), one start at a time (a start that the map cannot step, past the period
doubling, is listed and left out).  Prints per ε and θ0 how many starts each method calls chaotic (MEGNO > 3) and how many
verdicts agree, the overall agreement, every disagreement with both MEGNO values, the ratio map/ODE of the Lyapunov
exponents where both call a start chaotic (median and range), and the CPU time of each part (the map's atlas with
and without the layer, the plain and the variational runs).
"""

from __future__ import annotations

import argparse
import math
import time
import warnings

import numpy as np

from rocknroller.analysis.model.body import Body
from rocknroller.analysis.slow import atlas as at
from rocknroller.analysis.slow.atlas_check import confirm_atlas
from rocknroller.analysis.slow.map.limits import AveragingRangeError, AveragingValidityWarning
from rocknroller.numerics.megno import MEGNO_CHAOTIC

THETA0 = (0.9 * math.pi, 0.95 * math.pi)


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--n-eps", type=int, default=20, help="values of eps in [1e-3, 1.5e-2] (default 20)")
    parser.add_argument("--n-psi", type=int, default=20, help="values of psi0 in (0, pi/2] (default 20)")
    parser.add_argument("--t-end", type=float, default=1000.0, help="time span of each run (default 1000)")
    parser.add_argument("--threads", type=int, default=1, help="threads of the direct and variational runs")
    parser.add_argument("--order", type=int, choices=(1, 2), default=2, help="the map's order (default 2)")
    args = parser.parse_args()
    warnings.simplefilter("ignore", AveragingValidityWarning)  # K > 4 at the largest eps: stated in the output
    psi0 = np.linspace(0.5 * math.pi / args.n_psi, 0.5 * math.pi, args.n_psi)
    n = agree = 0
    ratios: list[float] = []
    disagreements: list[str] = []
    cpu = {"map": 0.0, "map without the layer": 0.0, "direct and variational runs": 0.0}
    print(f"release atlas, paper body, theta0 in {{0.9, 0.95}} pi, {args.n_psi} psi0 in (0, pi/2], t_end "
          f"{args.t_end:g}, map of order {args.order}, indicators over max(t_end, 1000 rocks); verdict: MEGNO > "
          f"{MEGNO_CHAOTIC:g} chaotic")
    at.atlas_from_rest(Body.paper(1e-3), THETA0, psi0[:1], 100.0, progress=False,
                       order=args.order)  # load the tables, untimed
    print(f"{'eps':>9} {'theta0/pi':>9} {'map chaotic':>11} {'ODE chaotic':>11} {'agree':>7}")
    failed: list[str] = []
    for eps in np.geomspace(1e-3, 1.5e-2, args.n_eps):
        body = Body.paper(float(eps))
        for th in THETA0:
            rows = []  # (map MEGNO, ODE MEGNO, map λ, ODE λ, ψ0) per start the map resolves
            for p0 in psi0:  # one point at a time: a start the map cannot step is listed, not fatal
                t = time.process_time()
                try:
                    at.atlas_from_rest(body, [th], [p0], args.t_end, progress=False, chaos=False, order=args.order)
                except AveragingRangeError as exc:
                    failed.append(f"  eps {eps:.3e}, theta0 {th / math.pi:.3g} pi, psi0 {p0:.4f}: {exc}")
                    continue
                cpu["map without the layer"] += time.process_time() - t
                t = time.process_time()
                atlas = at.atlas_from_rest(body, [th], [p0], args.t_end, progress=False, order=args.order)
                cpu["map"] += time.process_time() - t
                t = time.process_time()
                check = confirm_atlas(atlas, body, every=1, progress=False, threads=args.threads, budget=None)
                cpu["direct and variational runs"] += time.process_time() - t
                rows.append((float(check.map["megno"][0]), float(check.ode["megno"][0]),
                             float(check.map["lyapunov"][0]), float(check.ode["lyapunov"][0]), float(p0)))
            r = np.array(rows, dtype=float).reshape(-1, 5)
            m, o = r[:, 0] > MEGNO_CHAOTIC, r[:, 1] > MEGNO_CHAOTIC
            agrees = m == o
            print(f"{eps:9.3e} {th / math.pi:9.3g} {int(m.sum()):11d} {int(o.sum()):11d} "
                  f"{int(agrees.sum()):3d}/{agrees.size}")
            n += agrees.size
            agree += int(agrees.sum())
            for k in np.flatnonzero(~agrees):
                disagreements.append(f"  eps {eps:.3e}, theta0 {th / math.pi:.3g} pi, psi0 {r[k, 4]:.4f}: "
                                     f"MEGNO map {r[k, 0]:.3f}, ODE {r[k, 1]:.3f}")
            both = m & o & (r[:, 3] > 0.0)
            ratios += list(r[both, 2] / r[both, 3])
    print(f"verdicts agree at {agree} of {n} starts ({agree / n:.1%})")
    print("disagreements:" if disagreements else "disagreements: none")
    for line in disagreements:
        print(line)
    print(f"starts the map cannot step (left out): {len(failed)}")
    for line in failed:
        print(line)
    if ratios:
        r = np.array(ratios)
        print(f"lambda map/ODE where both call a start chaotic: {r.size} starts, median {np.median(r):.3f}, "
              f"range {r.min():.3f}..{r.max():.3f}, within 25 %: {int(np.sum(np.abs(r - 1.0) <= 0.25))}")
    for k, v in cpu.items():
        print(f"CPU {k}: {v:.2f} s")


if __name__ == "__main__":
    main()
