"""Regenerates docs/slow_validation.md, "Band chart" and "Reversal starts of the paper": the map vs the ODE.

Run:  python validation/reversal_starts.py
Prints the tables of docs/slow_validation.md, "Band chart" and "Reversal starts of the paper":
* the interpolation error and build time (2 processes) of the band tables at the energies of releases from rest;
* for the paper's reversal starts (θ0 = 0.95π, ψ0 = π/4: fig. 7 from rest, figs. 8 and 11 on Q_J,π^crit, fig. 9 on
  Q_J,0^crit, computed on their lines; fig. 10 shows 7–9 together), each as an initial state (the region tables of
  its energy, first and second order) at ε = 1e-3 and 5e-4, 1000 time units: whether
  the map's critical-region runs are the ODE's (count, and each run's length within ±1 rock), the largest
  difference of the runs' start times over a rocking period, and the relative errors of the slow period, the Q_R and
  Q_J extents and Φ;
* the cost of one prediction (tables cached) against the direct ODE with the same diagnostics.
"""

from __future__ import annotations

import itertools
import math
import time

import numpy as np

from rocknroller.analysis.slow.map import region as sr
from rocknroller.analysis.model.body import Body
from rocknroller.analysis.slow.map.second_order import load_or_build_second_order_region_table
from rocknroller.analysis.slow.map.family import first_maximum, rest_energy
from rocknroller.analysis.model.equations import EulerState
from rocknroller.papers.averaging_check import relative_errors, timed_map_and_ode
from rocknroller.papers.lynch_bustamante import fig8_visible_reversal, fig9_full_reversal, fig11_high_QR
from rocknroller.analysis.criticality import starts as paper

THETA0 = (0.65, 0.7, 0.8, 0.9, 0.95, 0.97, 0.99)
EPS = (1e-3, 5e-4)


def starts(body: Body) -> dict[str, EulerState]:
    """The paper's starts for this body (the critical starts depend on ε through the energy)."""
    return {"fig. 7 (rest)": EulerState(paper.THETA0, 0.0, paper.PSI0),
            "fig. 8 (on QJpi, psi_dot0 0.002)": paper.start_on_line("pi", fig8_visible_reversal.PSI_DOT0, of=body),
            "fig. 9 (on QJ0, psi_dot0 0.378)": paper.start_on_line("0", fig9_full_reversal.PSI_DOT0, of=body),
            "fig. 11 (on QJpi, Q_R 0.1)": paper.start_on_line("pi", QR=fig11_high_QR.QR0, of=body)}


def main() -> None:
    sym = Body.paper(0.0)
    print("| release θ0 | E | axis | nu × nv | interp. error | build, 2 processes [s] |")
    print("|---|---|---|---|---|---|")
    for th in THETA0:
        E = rest_energy(sym, th * math.pi)
        t0 = time.perf_counter()
        table = sr.build_region_table(sym, E, axis="band", workers=2)
        nu, nv = table.coef.shape[1:]
        print(f"| {th:g}π | {E:.6g} | {sr.region_axis(sym, E)} | {nu} × {nv} | {table.interp_error:.1e} | "
              f"{time.perf_counter() - t0:.1f} |", flush=True)
    print()
    print("| start | ε | order | runs (map, ODE) | same runs | max Δt of a run / T_rock | slow period | Q_R extent | "
          "Q_J extent | Φ |")
    print("|---|---|---|---|---|---|---|---|---|---|")
    cost: dict[int, tuple[float, float]] = {}
    for eps, order in itertools.product(EPS, (1, 2)):
        body = Body.paper(eps)
        for name, start in starts(body).items():
            E = first_maximum(body, start).E
            table = sr.load_or_build_region_table(body, E, workers=2)
            second = load_or_build_second_order_region_table(body, E, workers=2) if order == 2 else None
            pred, ode, _, t_map, t_ode = timed_map_and_ode(body, start, 1000.0, table, order, second)
            cost[order] = (t_map, t_ode)  # the last start of each order: every run warm
            T_rock = 2.0 * float(np.median(np.diff(ode.t)))
            same = len(pred.region_runs) == len(ode.region_runs) and all(
                a[0] == b[0] and abs(a[1] - b[1]) <= 1 for a, b in zip(pred.region_runs, ode.region_runs))
            dt = max((abs(a[2] - b[2]) for a, b in zip(pred.region_runs, ode.region_runs)), default=0.0) / T_rock
            err = relative_errors(pred, ode)
            cells = " | ".join("–" if err[q] is None else f"{err[q]:.1e}"
                               for q in ("slow_period", "QR_extent", "QJ_extent", "Phi"))
            print(f"| {name} | {eps:g} | {order} | {len(pred.region_runs)}, {len(ode.region_runs)} | "
                  f"{'yes' if same else 'no'} | {dt:.1e} | {cells} |", flush=True)
    for order, (t_map, t_ode) in cost.items():
        print(f"\none prediction of order {order}, 1000 t.u. from the last start above (tables cached, first maximum by the "
              f"ODE included): {t_map * 1e3:.2f} ms; the direct ODE with the same diagnostics: {t_ode * 1e3:.0f} ms; "
              f"ratio {t_ode / t_map:.0f}x")


if __name__ == "__main__":
    main()
