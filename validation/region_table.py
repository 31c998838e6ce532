"""Regenerates docs/slow_validation.md, "Region tables" (spindle chart): accuracy, ODE errors, cost.

Run:  python validation/region_table.py
Prints the tables of docs/slow_validation.md, "Region tables":
* for releases from rest at θ0 (the energy E = U(θ0; 0, 0)), the interpolation error of the spindle chart's region
  table (128 × 32 nodes; from 0.65π the default is the band chart, validation/reversal_starts.py) at its off-grid check points and its build time with 1 and 2 worker processes;
* for starts with velocity (ω2 = 0 in the body frame, so E and the table do not depend on ε), the largest
  maximum-by-maximum errors map − ODE over 1000 time units at ε = 1e-2, 1e-3, 1e-4 and their log-log slopes;
* the cost of one prediction of 1000 time units (tables cached) against the direct ODE with the same diagnostics;
* the table orbits in heyoka's batch mode (one orbit per SIMD lane) against one orbit at a time, side by side on
  the same nodes, and the largest difference of their ε-responses.
"""

from __future__ import annotations

import math
import time
import warnings

import numpy as np

from rocknroller.analysis.slow import prediction as av
from rocknroller.analysis.slow.map import region as sr
from rocknroller.analysis.model.body import Body
from rocknroller.analysis.routh.turning_points import turning_points
from rocknroller.analysis.slow.map.family import first_maximum, rest_energy
from rocknroller.analysis.slow.map.harmonic import harmonic_steps
from rocknroller.analysis.model.equations import EulerState
from rocknroller.papers.averaging_check import loglog_slope, sample_errors, timed_map_and_ode

THETA0 = (0.05, 0.15, 0.3, 0.45, 0.6, 0.7, 0.8, 0.95)
STARTS = {"0.6pi, omega=(0, 0, 0.05)": (0.6, 0.3, (0.0, 0.0, 0.05)),
          "0.45pi, omega=(0.3, 0, -0.08)": (0.45, 1.1, (0.3, 0.0, -0.08)),
          "0.3pi, omega=(-0.2, 0, 0.3)": (0.3, 2.0, (-0.2, 0.0, 0.3))}
EPS = (1e-2, 1e-3, 1e-4)


def batch_against_one_at_a_time(th: float = 0.95, nodes: int = 256) -> None:
    """The first ``nodes`` nodes of the default region table of a release's energy, one orbit with three ε-responses
    each."""
    import heyoka as hy

    sym = Body.paper(0.0)
    E = rest_energy(sym, th * math.pi)
    QR, QJ = (np.ravel(q)[:nodes] for q in sr.region_frame(sym, E).nodes())
    thX = turning_points(E, QR, QJ, sym)[1]
    times, resp = {}, {}
    for lanes in (1, None, 1, None):  # twice each, interleaved: the second of each is timed warm
        t0 = time.perf_counter()
        resp[lanes] = harmonic_steps(sym, E, QR, QJ, thX, lanes=lanes)[1]
        times[lanes] = time.perf_counter() - t0
    scale = np.abs(resp[1]).max(axis=(1, 2), keepdims=True)
    print(f"\ntable orbits at the energy of a release from {th:g}π, {nodes} orbits (three ε-responses each): one at "
          f"a time {times[1] / nodes * 1e3:.2f} ms an orbit, batch mode ({hy.recommended_simd_size()} lanes) "
          f"{times[None] / nodes * 1e3:.2f} ms, ratio {times[1] / times[None]:.1f}x; largest difference of the "
          f"responses {float(np.max(np.abs(resp[None] - resp[1]) / scale)):.1e} of each one's largest")


def main() -> None:
    warnings.simplefilter("ignore", av.AveragingValidityWarning)
    batch_against_one_at_a_time()
    sym = Body.paper(0.0)
    print("| release θ0 | E | interp. error | build, 1 worker [s] | build, 2 workers [s] |")
    print("|---|---|---|---|---|")
    for k, th in enumerate(THETA0):
        E = rest_energy(sym, th * math.pi)
        times = []
        for workers in ((1, 2) if k == 0 else (2,)):
            t0 = time.perf_counter()
            table = sr.build_region_table(sym, E, axis="spindle", workers=workers)
            times.append(time.perf_counter() - t0)
        one = f"{times[0]:.1f}" if len(times) == 2 else "–"
        print(f"| {th:g}π | {E:.6g} | {table.interp_error:.1e} | {one} | {times[-1]:.1f} |", flush=True)
    print()
    print("| start (θ0, ω) | observable | ε = 1e-2 | 1e-3 | 1e-4 | slope |")
    print("|---|---|---|---|---|---|")
    cost = None
    for name, (th, psi0, omega) in STARTS.items():
        start = EulerState.from_omega(th * math.pi, 0.0, psi0, omega)
        errs: dict[str, list[float]] = {}
        table = None
        for eps in EPS:
            body = Body.paper(eps)
            if table is None:
                table = sr.load_or_build_region_table(body, first_maximum(body, start).E, workers=2)
            pred, ode, t_first, t_map, t_ode = timed_map_and_ode(body, start, 1000.0, table)
            cost = cost or (t_first, t_map, t_ode)
            for q, e in sample_errors(pred.series, ode).items():
                errs.setdefault(q, []).append(e)
        for q, e in errs.items():
            print(f"| {name} | {q} | {e[0]:.2e} | {e[1]:.2e} | {e[2]:.2e} | {loglog_slope(EPS, e):.2f} |", flush=True)
    t_first, t_map, t_ode = cost
    print(f"\none prediction of 1000 t.u. (cached tables, first maximum by the ODE included): {t_map * 1e3:.1f} ms "
          f"({t_first:.2f} s the first time in a process: the run-time form of the table); the direct ODE with the "
          f"same diagnostics: {t_ode * 1e3:.0f} ms; ratio {t_ode / t_map:.0f}x")


if __name__ == "__main__":
    main()
