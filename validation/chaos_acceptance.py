"""Regenerates the acceptance tables of docs/order_and_chaos.md (issue 23): the slow map's chaos indicators against
the direct ODE's, the separatrix layer's width, and the onset of the chaotic sea.

Run:  python validation/chaos_acceptance.py [--t-grid 10000] [--t-layer 20000] [--csv DIR]
(~15 min of CPU with the defaults on 2 shared cores, once the tables of 0.9π and 0.95π are cached; ~2 min per θ0 to
build them otherwise).

Paper body, releases from rest (θ0, φ0 = 0, ψ0), the map of order 2 (the package's default for these releases,
:func:`rocknroller.analysis.slow.prediction.default_order`) against the direct ODE's variational equations
(:func:`rocknroller.numerics.variational.direct_chaos_indicators`), both over the same time span and both called
chaotic when MEGNO > ``MEGNO_CHAOTIC`` = 3 (:mod:`rocknroller.numerics.megno`, one formula for both):

a. the 20 × 20 grid ψ0 = k (π/2)/20 (k = 1..20) × ε log-spaced in [1e-3, 1.5e-2] at θ0 = 0.95π and 0.9π, over
   ``--t-grid`` time units: the agreement of the verdicts, every disagreement with both MEGNO values, the ratio
   λ_map/λ_ODE (per unit time) where both call the start chaotic, and the fraction of chaotic starts per ε (per K);
b. the separatrix layer's width at θ0 = 0.95π for five ε log-spaced in [3e-4, 3e-3], over ``--t-layer`` time
   units (definition: :func:`rocknroller.analysis.slow.dynamics.chaos.layer_width`, on its default grid
   10^(−j/16), j = 0..160, with 2 bisections), for the map and the ODE, their ratio, and the least-squares fits
   ln w = ln C − q ln K − A/√K with q = 0 and 3/4 (K = εκ(θ0), κ from
   :func:`rocknroller.analysis.slow.dynamics.pendulum.pendulum_constants`);
c. the onset of the chaotic sea, from the map alone: the fraction of chaotic releases on the 20 ψ0 of (a) against
   K = εκ for K log-spaced in [0.2, 8] (ε = K/κ) at θ0 = 0.9π and 0.95π, over ``--t-grid`` time units, and how far
   in the standard map's momentum p = κ Q_R/C0_R the layer orbit from ψ0 = 1e-3 reaches (beyond Greene's
   K_c ≈ 0.9716 a standard-map orbit from the layer is no longer bounded by a rotational invariant curve and
   reaches |p| = 2π, the next integer resonance), and the map's twist W(Q) along the kick line against the standard
   map's p (where its next resonance would be); and the releases at the stable rocking ψ0 = π/2 on which the map
   gives no verdict in (a), beside two starts next to it.

Prints Markdown tables; with ``--csv DIR`` also writes the rows of (a), (b) and (c) as CSV files with a header
recording the parameters (papers/output.py).
"""

from __future__ import annotations

import argparse
import math
import warnings
from pathlib import Path

import numpy as np
from tqdm import tqdm

from rocknroller.analysis.model.body import Body
from rocknroller.analysis.model.equations import EulerState
from rocknroller.analysis.slow import prediction as av
from rocknroller.analysis.slow.dynamics.chaos import LayerWidth, layer_width
from rocknroller.analysis.slow.map.chart import TABLE_FUNCTIONS
from rocknroller.analysis.slow.map.limits import AveragingRangeError, AveragingValidityWarning
from rocknroller.analysis.slow.dynamics.pendulum import pendulum_constants
from rocknroller.numerics.megno import MEGNO_CHAOTIC, ChaosIndicators
from rocknroller.numerics.variational import direct_chaos_indicators
from rocknroller.papers.output import write_csv

THETA0S = (0.95 * math.pi, 0.9 * math.pi)
PSI_GRID = np.arange(1, 21) * (0.5 * math.pi / 20)
EPS_GRID = np.geomspace(1e-3, 1.5e-2, 20)
#: The offset in ψ0 of a second direct run at the starts both call chaotic: the spread of λ_ODE(ψ0 + NEARBY)/λ_ODE(ψ0)
#: is that of the finite-time exponent itself, against which λ_map/λ_ODE is judged.
NEARBY = 1e-9
LAYER_THETA0 = 0.95 * math.pi
LAYER_EPS = np.geomspace(3e-4, 3e-3, 5)
#: Bisection steps in ln ψ0 between the largest chaotic grid point and the grid point above it (a factor 10^(1/16)):
#: 2 steps leave a bracket of 10^(1/64), 3.7 %.
LAYER_BISECTIONS = 2
ONSET_K = np.geomspace(0.2, 8.0, 25)
#: The release in the separatrix layer whose excursion in p part (c) follows.
LAYER_PSI0 = 1e-3
#: Header and rule of part (c)'s table (docs/order_and_chaos.md shows it; tests/test_docs_examples.py checks them).
ONSET_HEADER = ("| K | 2√K/2π | " + " | ".join(f"ε at {t / math.pi:.2f}π | chaotic | left the tables | kick did not "
                                               "converge | max abs(p)/2π" for t in THETA0S) + " |")
ONSET_RULE = "|---|---|" + "---|---|---|---|---|" * len(THETA0S)
#: p/2π at which the twist table evaluates W, its header and rule.
TWIST_FRACTIONS = (0.1, 0.25, 0.5, 0.75, 1.0, 1.25)
TWIST_HEADER = "| θ0 | " + " | ".join(f"p/2π = {f:g}" for f in TWIST_FRACTIONS) + " |"
TWIST_RULE = "|---|" + "---|" * len(TWIST_FRACTIONS)
#: Header and rule of part (a)'s table of chaotic starts per ε (a column group per θ0 of ``THETA0S``).
PER_EPS_HEADER = "| ε | " + " | ".join(f"K at {t / math.pi:.2f}π | map | ODE" for t in THETA0S) + " |"
PER_EPS_RULE = "|---|" + "---|---|---|" * len(THETA0S)


def map_chaos(body: Body, theta0: float, psi0: float, t_end: float) -> ChaosIndicators:
    """The map's indicators (order: the package's default, 2 for these releases) over [0, t_end] (``span=t_end``, the
    ODE's span); raises :class:`~rocknroller.analysis.slow.map.limits.AveragingRangeError` where the orbit leaves the
    tables."""
    chaos = av.predict_slow_motion(body, theta0, psi0, t_end, span=t_end).chaos
    assert chaos is not None
    return chaos


def map_megno(body: Body, theta0: float, psi0: float, t_end: float) -> tuple[float, float, str]:
    """(MEGNO, λ, "") of the map, or (nan, nan, why) where it gives no verdict: its orbit leaves the tables, or its
    implicit kick does not converge (both AveragingRangeError; reported as such, never dropped)."""
    try:
        c = map_chaos(body, theta0, psi0, t_end)
    except AveragingRangeError as exc:
        return math.nan, math.nan, "kick did not converge" if "did not converge" in str(exc) else "left the tables"
    return c.megno, c.lyapunov, ""


def ode_chaos(body: Body, theta0: float, psi0: float, t_end: float) -> ChaosIndicators:
    """The direct ODE's indicators over [0, t_end] (variational equations, sampled at the θ-maxima)."""
    return direct_chaos_indicators(body, EulerState(theta0, 0.0, psi0), t_end, budget=None).indicators


def fit_exponent(K: np.ndarray, width: np.ndarray, power: float = 0.0) -> tuple[float, float, float]:
    """Least squares ln w = ln C − power ln K − A/√K: (A, C, the rms residual in ln w)."""
    x = 1.0 / np.sqrt(K)
    y = np.log(width) + power * np.log(K)
    slope, intercept = np.polyfit(x, y, 1)
    resid = y - (slope * x + intercept)
    return float(-slope), float(math.exp(intercept)), float(np.sqrt(np.mean(resid ** 2)))


def _fmt(x: float) -> str:
    return f"{x:.3g}"


#: Why the map gave no verdict, per (θ0, i, j) of the grid.
NO_VERDICT: dict[tuple[float, int, int], str] = {}


def part_a(t_end: float, csv_dir: Path | None) -> dict[float, dict[str, np.ndarray]]:
    results: dict[float, dict[str, np.ndarray]] = {}
    bar = tqdm(total=len(THETA0S) * EPS_GRID.size * PSI_GRID.size, desc="grid: map and ODE", unit="start")
    for theta0 in THETA0S:
        kappa = pendulum_constants(Body.paper(EPS_GRID[0]), theta0).kappa
        shape = (EPS_GRID.size, PSI_GRID.size)
        r = {name: np.zeros(shape) for name in ("megno_map", "megno_ode", "lam_map", "lam_ode", "rocks_ode")}
        for i, eps in enumerate(EPS_GRID):
            body = Body.paper(float(eps))
            for j, psi in enumerate(PSI_GRID):
                r["megno_map"][i, j], r["lam_map"][i, j], why = map_megno(body, theta0, float(psi), t_end)
                if why:
                    NO_VERDICT[theta0, i, j] = why
                co = ode_chaos(body, theta0, float(psi), t_end)
                r["megno_ode"][i, j], r["lam_ode"][i, j], r["rocks_ode"][i, j] = co.megno, co.lyapunov, co.t.size
                bar.update()
        # the finite-time λ's own spread: the ODE against itself from ψ0 + NEARBY, where both call the start chaotic
        r["lam_ode_nearby"] = np.full(shape, math.nan)
        for i, j in zip(*np.nonzero((r["megno_map"] > MEGNO_CHAOTIC) & (r["megno_ode"] > MEGNO_CHAOTIC))):
            r["lam_ode_nearby"][i, j] = ode_chaos(Body.paper(float(EPS_GRID[i])), theta0, float(PSI_GRID[j]) + NEARBY,
                                                  t_end).lyapunov
        r["kappa"] = np.array(kappa)
        results[theta0] = r
        if csv_dir is not None:
            E, P = np.meshgrid(EPS_GRID, PSI_GRID, indexing="ij")
            write_csv(csv_dir / f"chaos_acceptance_grid_{theta0 / math.pi:.2f}pi.csv",
                      {"eps": E.ravel(), "K": kappa * E.ravel(), "psi0": P.ravel(),
                       **{k: v.ravel() for k, v in r.items() if k != "kappa"}},
                      [f"paper body, release from rest, theta0 = {theta0 / math.pi:.2f} pi, kappa = {kappa!r}",
                       f"t_end = {t_end!r} for the map (order 2) and the ODE; chaotic: MEGNO > {MEGNO_CHAOTIC}",
                       "lam_*: finite-time Lyapunov exponent per unit time; rocks_ode: theta-maxima sampled; "
                       f"lam_ode_nearby: the ODE's from psi0 + {NEARBY!r} where both call the start chaotic; "
                       "megno_map empty: the map gives no verdict (its orbit left its tables, or its implicit kick "
                       "did not converge)"])
    bar.close()
    return results


def report_a(results: dict[float, dict[str, np.ndarray]], t_end: float) -> None:
    print(f"\n## (a) Verdicts on the 20 × 20 grid, {t_end:g} time units, map (order 2) vs direct ODE\n")
    print("| θ0 | κ | K range | starts | agree | map: no verdict | map chaotic | ODE chaotic | both chaotic | "
          "λ_map/λ_ODE median | quartiles | min–max | maxima sampled |")
    print("|---|---|---|---|---|---|---|---|---|---|---|---|---|")
    all_agree, all_n, all_ratio, all_none, all_self = 0, 0, [], 0, []
    disagreements = []
    for theta0, r in results.items():
        kappa = float(r["kappa"])
        cm, co = r["megno_map"] > MEGNO_CHAOTIC, r["megno_ode"] > MEGNO_CHAOTIC
        none = np.isnan(r["megno_map"])
        agree = int(np.sum((cm == co) & ~none))
        all_none += int(none.sum())
        both = cm & co
        ratio = r["lam_map"][both] / r["lam_ode"][both]
        all_agree, all_n = all_agree + agree, all_n + cm.size
        all_ratio.extend(ratio.tolist())
        all_self.extend((r["lam_ode_nearby"][both] / r["lam_ode"][both]).tolist())
        q1, med, q3 = np.percentile(ratio, [25, 50, 75]) if ratio.size else (math.nan,) * 3
        print(f"| {theta0 / math.pi:.2f}π | {kappa:.4g} | {kappa * EPS_GRID[0]:.3g}–{kappa * EPS_GRID[-1]:.3g} | "
              f"{cm.size} | {agree} ({100 * agree / cm.size:.1f} %) | {int(none.sum())} | {int(cm.sum())} | "
              f"{int(co.sum())} | "
              f"{int(both.sum())} | {_fmt(med)} | {_fmt(q1)}–{_fmt(q3)} | "
              f"{_fmt(ratio.min()) if ratio.size else '–'}–{_fmt(ratio.max()) if ratio.size else '–'} | "
              f"{int(r['rocks_ode'].min())}–{int(r['rocks_ode'].max())} |")
        for i, j in zip(*np.nonzero((cm != co) | none)):
            disagreements.append((theta0, EPS_GRID[i], kappa * EPS_GRID[i], j + 1, PSI_GRID[j], r["megno_map"][i, j],
                                  r["megno_ode"][i, j], r["lam_map"][i, j], r["lam_ode"][i, j]))
    ratio = np.array(all_ratio)
    q1, med, q3 = np.percentile(ratio, [25, 50, 75]) if ratio.size else (math.nan,) * 3
    print(f"| both | | | {all_n} | {all_agree} ({100 * all_agree / all_n:.1f} %) | {all_none} | | | {ratio.size} | "
          f"{_fmt(med)} | "
          f"{_fmt(q1)}–{_fmt(q3)} | {_fmt(ratio.min()) if ratio.size else '–'}–"
          f"{_fmt(ratio.max()) if ratio.size else '–'} | |")
    if all_none < all_n:
        print(f"\nAgreement where the map gives a verdict: {all_agree} of {all_n - all_none} "
              f"({100 * all_agree / (all_n - all_none):.1f} %); a start on which the map gives none counts as a "
              "disagreement above.")
    print(f"\nStarts where both are chaotic with |λ_map/λ_ODE − 1| ≤ 25 %: "
          f"{int(np.sum(np.abs(ratio - 1) <= 0.25))} of {ratio.size}.")
    own = np.array(all_self)
    if own.size:
        q = np.percentile(own, [25, 50, 75])
        print(f"\nThe ODE against itself at the same {own.size} starts, λ_ODE(ψ0 + {NEARBY:g})/λ_ODE(ψ0): median "
              f"{q[1]:.3g}, quartiles {q[0]:.3g}–{q[2]:.3g}, min–max {own.min():.3g}–{own.max():.3g}; within 25 %: "
              f"{int(np.sum(np.abs(own - 1) <= 0.25))} of {own.size}.")
    print(f"\n### Disagreements ({len(disagreements)})\n")
    print("| θ0 | ε | K | k | ψ0 | MEGNO map | MEGNO ODE | λ map | λ ODE | map: no verdict because |")
    print("|---|---|---|---|---|---|---|---|---|---|")
    for theta0, eps, K, k, psi, mm, mo, lm, lo in disagreements:
        why = NO_VERDICT.get((theta0, int(np.argmin(np.abs(EPS_GRID - eps))), k - 1), "")
        print(f"| {theta0 / math.pi:.2f}π | {eps:.3g} | {K:.3g} | {k} | {psi:.4f} | {mm:.3g} | {mo:.3g} | {lm:.3g} | "
              f"{lo:.3g} | {why} |")
    print("\n### Chaotic starts per ε (of the 20 ψ0), map / ODE\n")
    assert tuple(results) == THETA0S  # the columns of PER_EPS_HEADER
    print(PER_EPS_HEADER)
    print(PER_EPS_RULE)
    for i, eps in enumerate(EPS_GRID):
        cells = []
        for r in results.values():
            none = int(np.sum(np.isnan(r["megno_map"][i])))
            cells.append(f"{float(r['kappa']) * eps:.3g} | {int(np.sum(r['megno_map'][i] > MEGNO_CHAOTIC))}"
                         + (f" (+{none} no verdict)" if none else "")
                         + f" | {int(np.sum(r['megno_ode'][i] > MEGNO_CHAOTIC))}")
        print(f"| {eps:.3g} | " + " | ".join(cells) + " |")


def part_b(t_end: float, csv_dir: Path | None) -> None:
    kappa = pendulum_constants(Body.paper(float(LAYER_EPS[0])), LAYER_THETA0).kappa
    K = kappa * LAYER_EPS
    widths: dict[str, list[LayerWidth]] = {"map": [], "ODE": []}
    for eps in tqdm(LAYER_EPS, desc="layer widths", unit="ε"):
        body = Body.paper(float(eps))
        for name, method in (("map", map_chaos), ("ODE", ode_chaos)):
            widths[name].append(layer_width(lambda p: method(body, LAYER_THETA0, p, t_end),
                                            bisections=LAYER_BISECTIONS))
    print(f"\n## (b) Separatrix layer width at θ0 = 0.95π (κ = {kappa:.4g}), {t_end:g} time units\n")
    print("| ε | K = εκ | width map | bracket map | width ODE | bracket ODE | map/ODE | MEGNO in/out map | "
          "MEGNO in/out ODE |")
    print("|---|---|---|---|---|---|---|---|---|")
    for i, eps in enumerate(LAYER_EPS):
        m, o = widths["map"][i], widths["ODE"][i]
        print(f"| {eps:.3g} | {K[i]:.3g} | {m.width:.3g} | {m.bracket[0]:.3g}–{m.bracket[1]:.3g} | {o.width:.3g} | "
              f"{o.bracket[0]:.3g}–{o.bracket[1]:.3g} | {m.width / o.width:.3g} | {m.megno_in:.3g}/{m.megno_out:.3g} | "
              f"{o.megno_in:.3g}/{o.megno_out:.3g} |")
    print("\nFits w = C K^(−q) exp(−A/√K), least squares on ln w over the five ε: q = 0 (the law as stated), and "
          "q = 3/4 (the separatrix map's prefactor: relative energy width ∝ K^(−3/2) exp(−π²/√K), and the width in "
          "ψ0 is its square root, A = π²/2 = 4.93)\n")
    print("| method | q | A | C | rms residual of ln w |")
    print("|---|---|---|---|---|")
    for q in (0.0, 0.75):
        for name, ws in widths.items():
            A, C, rms = fit_exponent(K, np.array([w.width for w in ws]), q)
            print(f"| {name} | {q:g} | {A:.3g} | {C:.3g} | {rms:.3g} |")
    if csv_dir is not None:
        write_csv(csv_dir / "chaos_acceptance_layer.csv",
                  {"eps": LAYER_EPS, "K": K,
                   **{f"width_{n.lower()}": [w.width for w in ws] for n, ws in widths.items()},
                   **{f"lo_{n.lower()}": [w.bracket[0] for w in ws] for n, ws in widths.items()},
                   **{f"hi_{n.lower()}": [w.bracket[1] for w in ws] for n, ws in widths.items()}},
                  [f"paper body, release from rest, theta0 = 0.95 pi, kappa = {kappa!r}, t_end = {t_end!r}",
                   "width: largest chaotic psi0 (MEGNO > 3) scanning down 10^(-j/16) from 1, then "
                   f"{LAYER_BISECTIONS} bisections in ln psi0; geometric mean of the bracket [lo, hi]"])


def _p_excursion(body: Body, theta0: float, t_end: float, kappa: float, C0R: float) -> float:
    """max |p|/(2π) along the map's orbit of the release at ``LAYER_PSI0`` (in the layer), p = κ Q_R/C0_R the
    standard map's momentum on the line Q = (p/κ) C0 (docs/averaging.md); nan where the orbit leaves the tables."""
    try:
        series = av.predict_slow_motion(body, theta0, LAYER_PSI0, t_end).series
    except AveragingRangeError:
        return math.nan
    return float(kappa * np.max(np.abs(series.QR)) / C0R / (2.0 * math.pi))


def twist_table() -> None:
    """The map's twist W(Q)/2π along the kick line Q = (p/κ) C0 against the standard map's p/2π (their linear term
    is the same, docs/averaging.md): the standard map's resonances sit at p = 2πm, the map's where W = 2πm."""
    fractions = TWIST_FRACTIONS
    print("\nThe twist W(Q)/2π of a step along the kick line Q = (p/κ) C0 (the release tables), against p/2π:\n")
    print(TWIST_HEADER)
    print(TWIST_RULE)
    for theta0 in THETA0S:
        table = av.load_or_build_table(Body.paper(0.0), theta0)
        c = pendulum_constants(Body.paper(1e-3), theta0)
        W = [float(table.evaluate(2.0 * math.pi * f / c.kappa * c.C0)[TABLE_FUNCTIONS.index("W")]) for f in fractions]
        print(f"| {theta0 / math.pi:.2f}π | " + " | ".join(f"{w / (2.0 * math.pi):.4f}" for w in W) + " |")


def fixed_point_check(t_end: float) -> None:
    """The releases at the stable rocking ψ0 = π/2 on the ε of (a) where the map gives no verdict, beside
    ψ0 = π/2 − 1e-8 and π/2 − 1e-4: MEGNO, or why there is none."""
    print(f"\nThe stable rocking ψ0 = π/2 on the ε of (a) where the map gives no verdict, {t_end:g} time units "
          "(MEGNO of the map, or why none):\n")
    print("| θ0 | ε | K | ψ0 = π/2 | π/2 − 1e-8 | π/2 − 1e-4 |")
    print("|---|---|---|---|---|---|")
    for theta0 in THETA0S:
        kappa = pendulum_constants(Body.paper(1e-3), theta0).kappa
        for eps in EPS_GRID:
            body = Body.paper(float(eps))
            cells = [map_megno(body, theta0, 0.5 * math.pi - d, t_end) for d in (0.0, 1e-8, 1e-4)]
            if cells[0][2]:
                print(f"| {theta0 / math.pi:.2f}π | {eps:.3g} | {kappa * eps:.3g} | "
                      + " | ".join(why or f"{m:.3g}" for m, _, why in cells) + " |")


def part_c(t_end: float, csv_dir: Path | None) -> None:
    print(f"\n## (c) Onset of the chaotic sea (map, order 2), {t_end:g} time units: chaotic releases of the 20 ψ0 "
          f"of (a), and the largest |p|/2π reached from ψ0 = {LAYER_PSI0:g} (in the layer), against the separatrix's "
          "2√K/2π\n")
    counts: dict[float, list[int]] = {}
    left: dict[float, list[int]] = {}
    stuck: dict[float, list[int]] = {}
    reach: dict[float, list[float]] = {}
    consts = {t: pendulum_constants(Body.paper(1e-3), t) for t in THETA0S}
    for theta0 in THETA0S:
        kappa, C0R = consts[theta0].kappa, float(consts[theta0].C0[0])
        counts[theta0], left[theta0], stuck[theta0], reach[theta0] = [], [], [], []
        for K in tqdm(ONSET_K, desc=f"onset {theta0 / math.pi:.2f}π", unit="K"):
            body = Body.paper(float(K / kappa))
            runs = [map_megno(body, theta0, float(p), t_end) for p in PSI_GRID]
            counts[theta0].append(sum(m > MEGNO_CHAOTIC for m, _, _ in runs))
            left[theta0].append(sum(why == "left the tables" for _, _, why in runs))
            stuck[theta0].append(sum(why == "kick did not converge" for _, _, why in runs))
            reach[theta0].append(_p_excursion(body, theta0, t_end, kappa, C0R))
    print(ONSET_HEADER)
    print(ONSET_RULE)
    for i, K in enumerate(ONSET_K):
        print(f"| {K:.3g} | {math.sqrt(K) / math.pi:.3f} | "
              + " | ".join(f"{K / consts[t].kappa:.3g} | {counts[t][i]}/20 | {left[t][i]} | {stuck[t][i]} | "
                           f"{reach[t][i]:.3f}" for t in THETA0S) + " |")
    twist_table()
    fixed_point_check(t_end)
    if csv_dir is not None:
        write_csv(csv_dir / "chaos_acceptance_onset.csv",
                  {"K": ONSET_K, **{f"chaotic_{t / math.pi:.2f}pi": counts[t] for t in THETA0S},
                   **{f"left_tables_{t / math.pi:.2f}pi": left[t] for t in THETA0S},
                   **{f"kick_not_converged_{t / math.pi:.2f}pi": stuck[t] for t in THETA0S},
                   **{f"max_p_over_2pi_{t / math.pi:.2f}pi": reach[t] for t in THETA0S}},
                  [f"paper body, releases from rest at psi0 = k (pi/2)/20, k = 1..20, map of order 2, "
                   f"t_end = {t_end!r}",
                   "chaotic_*: releases with MEGNO > 3 of the 20; eps = K / kappa(theta0), kappa = "
                   + ", ".join(f"{consts[t].kappa!r} at {t / math.pi:.2f} pi" for t in THETA0S),
                   f"max_p_over_2pi: max |p|/(2 pi), p = kappa Q_R / C0_R, of the release at psi0 = {LAYER_PSI0!r}"])


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--t-grid", type=float, default=10000.0, help="time span of (a) and (c)")
    parser.add_argument("--t-layer", type=float, default=20000.0, help="time span of (b)")
    parser.add_argument("--csv", type=Path, default=None, help="directory for the CSV files")
    parser.add_argument("--parts", default="abc", help="which parts to run (default abc)")
    args = parser.parse_args()
    warnings.simplefilter("ignore", AveragingValidityWarning)  # K > 4 on part of the grid: measured, not predicted
    if "a" in args.parts:
        report_a(part_a(args.t_grid, args.csv), args.t_grid)
    if "b" in args.parts:
        part_b(args.t_layer, args.csv)
    if "c" in args.parts:
        part_c(args.t_grid, args.csv)


if __name__ == "__main__":
    main()
