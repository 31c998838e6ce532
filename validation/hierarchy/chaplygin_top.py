"""Chaplygin's top: reversal, attractors and repellers (after Borisov, Kazakov & Sataev, Regul. Chaotic Dyn. 19 (2014)
718-733), with our own parameters.  Regenerates the tables and the figures of docs/theory/chaplygin_top.md:

    python validation/hierarchy/chaplygin_top.py

1. Controls: the time average of div f for the four members of the family (representative bodies, forward and
   backward); Chaplygin's ball and Routh's sphere must stay within C/t (the range of log ρ).
2. The steady rotations about the vertical of five tops: div f there and the stability of ±s.
3. Reversal: from near the unstable rotation (the spin whose div f > 0), the vertical spin ω·γ over 10⁴ time units.
4. Attracting sets of the two strongest tops: the phase-volume rate forward and backward from starts on or near
   them, with MEGNO and the largest Lyapunov exponent (rr.direct_chaos_indicators) of both directions.
5. Figures docs/figures/chaplygin_top_reversal.png and docs/figures/chaplygin_top_attractor.png.

Every run is at most 10⁴ time units; the whole script takes about 2 minutes of CPU (121-135 s measured).
"""

from __future__ import annotations

import math
import sys
import time
from pathlib import Path

import numpy as np
from matplotlib.figure import Figure
from tqdm import tqdm

import rocknroller as rr
from rocknroller.analysis.hierarchy import phase_volume as pv
from rocknroller.analysis.hierarchy.members import MEMBER_BODIES, member_start
from rocknroller.analysis.model.body import MEMBERS

#: Length of every run (time units).
T_RUN = 1.0e4
#: Window of the running mean of the vertical spin (about 10 rocking periods of the tops below).
WINDOW = 20.0
#: Tilt of the starts away from the unstable rotation (radians).
TILT = 0.05
FIGURES = Path(__file__).resolve().parents[2] / "docs" / "figures"
#: The starts of table 4 drawn in the attractor figure.
REVERSAL, SETTLED = "T5, x0 = 0.05 from +3", "T5, 6000 after x0"
TORUS, CHAOTIC = "T4, A: 3000 after 0.1 from +7", "T4, C: 2000 after 0.1 from +6"

#: The tops scanned: the suggested start, larger offsets, more unequal moments (|c| from 0.06 to 0.52).
TOPS = {
    "T1": rr.Body.chaplygin_top(0.35, 0.37, 0.4, offset=(0.03, -0.02, -0.05)),
    "T2": rr.Body.chaplygin_top(0.35, 0.37, 0.4, offset=(0.1, 0.05, -0.2)),
    "T3": rr.Body.chaplygin_top(0.2, 0.4, 0.5, offset=(0.1, 0.05, -0.2)),
    "T4": rr.Body.chaplygin_top(0.15, 0.4, 0.5, offset=(0.3, 0.3, -0.3)),
    "T5": rr.Body.chaplygin_top(0.15, 0.4, 0.5, offset=(0.4, 0.2, -0.2)),
}


def _bar(items, what: str):
    return tqdm(items, desc=what, file=sys.stderr, leave=False)


def _fmt(x: float) -> str:
    return f"{x:+.3e}"


def controls() -> None:
    """Table 1: forward and backward averages for the members; t·average against C for the two with a density."""
    print(f"\n## 1. Controls: (1/t)∫div f along the members' runs from member_start(), t = {T_RUN:g}\n")
    print("| member | t·average at T/8, T/4, T/2, T (forward) | forward rate | backward rate | C = range of log ρ |")
    print("|---|---|---|---|---|")
    bodies = {**MEMBER_BODIES, "T1 (suggested top)": TOPS["T1"]}
    for name in _bar(bodies, "controls"):
        body = bodies[name]
        fwd = pv.phase_volume_rate(body, member_start(), T_RUN)
        bwd = pv.phase_volume_rate(body, member_start(), T_RUN, backward=True)
        C = f"{pv.log_density_range(body):.4f}" if name in (MEMBERS[0], MEMBERS[2]) else "no density of γ"
        t_avg = ", ".join(f"{t * a:+.4f}" for t, a in fwd.checkpoints)
        print(f"| {name} | {t_avg} | {_fmt(fwd.rate)} | {_fmt(bwd.rate)} | {C} |")


def rotations() -> None:
    """Table 2: div f at the steady rotations and the stability of ±s."""
    print("\n## 2. Steady rotations ω = s γ: div f at +s (−div f at −s) and the stability of +s / −s\n")
    print("| top | I | c | s = 1 | s = 3 | s = 6 |")
    print("|---|---|---|---|---|---|")
    for name, top in TOPS.items():
        cells = []
        for s in (1.0, 3.0, 6.0):
            up, down = pv.steady_rotation(top, s), pv.steady_rotation(top, -s)
            cells.append(f"{_fmt(up.divergence)} {up.stability}/{down.stability}")
        print(f"| {name} | {(top.I1, top.I2, top.I3)} | {top.offset} | " + " | ".join(cells) + " |")


def _spin_series(top: rr.LoadedSphere, start: rr.EulerState) -> tuple[np.ndarray, np.ndarray, np.ndarray, np.ndarray]:
    """t, ω·γ on a grid of 0.25 time units, and the running mean over WINDOW (its centres and values)."""
    run = rr.simulate(top, start, T_RUN, dt=0.25)
    spin = np.sum(run.gamma * run.omega, axis=0)
    cumulative = np.concatenate([[0.0], np.cumsum(0.5 * (spin[1:] + spin[:-1]) * np.diff(run.t))])
    left = np.arange(0.0, T_RUN - WINDOW, 1.0)
    mean = (np.interp(left + WINDOW, run.t, cumulative) - np.interp(left, run.t, cumulative)) / WINDOW
    return run.t, spin, left + 0.5 * WINDOW, mean


def reversals() -> dict[str, tuple]:
    """Table 3: from near the unstable rotation, the first time the spin's running mean has turned to at least half its
    start's size the other way (a reversal), and where it ends."""
    print(f"\n## 3. Reversal: from the unstable rotation tilted by {TILT} rad, running mean of ω·γ over {WINDOW:g}\n")
    print("| top | start spin s | that rotation | first reversal (mean ≤ −s/2) | mean spin: min, max, at the end |")
    print("|---|---|---|---|---|")
    series = {}
    for name, s in _bar([(n, s) for n in TOPS for s in (3.0, 6.0)], "reversals"):
        rot = pv.steady_rotation(TOPS[name], s)
        if rot.divergence < 0.0:  # start on the unstable side: the rotation whose div f > 0
            rot = pv.steady_rotation(TOPS[name], -s)
        t, spin, centres, mean = _spin_series(TOPS[name], rot.nearby(TILT))
        turned = np.flatnonzero(mean * math.copysign(1.0, rot.spin) <= -0.5 * abs(rot.spin))
        first = centres[turned[0]] if turned.size else None
        series[f"{name} s={rot.spin:+g}"] = (t, spin, centres, mean, rot.spin, first)
        print(f"| {name} | {rot.spin:+g} | {rot.stability}, div f {_fmt(rot.divergence)} | "
              f"{'none' if first is None else f't = {first:.0f}'} | "
              f"{mean.min():+.2f}, {mean.max():+.2f}, {mean[-1]:+.2f} |")
    return series


def _landing(top: rr.LoadedSphere, state: np.ndarray, sign: float) -> str:
    """Where a run ended, from its last θ-maximum: at a steady rotation (|ω − s γ| < 1e-3) or not (its spin)."""
    gamma, omega = state[0:3], sign * state[3:6]
    s = float(gamma @ omega)
    if np.max(np.abs(omega - s * gamma)) < 1e-3:
        return f"rotation s = {s:+.3f} (div f {_fmt(pv.steady_rotation(top, s).divergence)})"
    return f"spin at the last max {s:+.2f}"


def attracting_sets() -> dict[tuple[str, bool], pv.PhaseVolumeRate]:
    """Table 4: forward and backward rates and MEGNO from starts on or near the attracting sets of T4 and T5."""
    T4, T5 = TOPS["T4"], TOPS["T5"]
    near = pv.steady_rotation(T5, 3.0).nearby(TILT)
    starts = {
        REVERSAL: (T5, lambda: near),
        SETTLED: (T5, lambda: pv.advance(T5, near, 6000.0)),
        TORUS: (T4, lambda: pv.advance(T4, pv.steady_rotation(T4, 7.0).nearby(0.1), 3000.0)),
        **{f"T4, C: {t0:g} after {tilt:g} from +{s:g}":
           (T4, lambda s=s, tilt=tilt, t0=t0: pv.advance(T4, pv.steady_rotation(T4, s).nearby(tilt), t0))
           for s, tilt, t0 in ((6.0, 0.1, 2000.0), (6.0, 0.3, 2000.0), (5.0, 0.1, 2000.0), (5.0, 0.3, 2000.0))},
    }
    print(f"\n## 4. Attracting sets: averages of div f over [0, {T_RUN:g}] forward and backward, MEGNO, λ_max\n")
    print("| start | forward: average at T/8, T/4, T/2, T | ends | MEGNO, λ_max | backward: average at T/8, T/4, "
          "T/2, T | ends | MEGNO, λ_max (reversed) |")
    print("|---|---|---|---|---|---|---|")
    kept = {}
    for label in _bar(starts, "attracting sets"):
        top, make = starts[label]
        x = make()
        cols = []
        for backward in (False, True):
            r = pv.phase_volume_rate(top, x, T_RUN, backward=backward)
            chaos = rr.direct_chaos_indicators(top, pv.reversed_state(x) if backward else x, T_RUN).indicators
            verdict = "regular" if chaos.regular else "chaotic"
            ends = _landing(top, r.maxima.states[-1], -1.0 if backward else 1.0)
            cols += [", ".join(_fmt(a) for _, a in r.checkpoints), ends, f"{chaos.megno:.1f}, {chaos.lyapunov:.3f} "
                     f"({verdict})"]
            kept[(label, backward)] = r
        print(f"| {label} | " + " | ".join(cols) + " |")
    chaotic = [kept[(label, False)].rate for label in starts if label.startswith("T4, C")]
    print(f"\nC, forward rate at T over its {len(chaotic)} starts: mean {_fmt(float(np.mean(chaotic)))}, "
          f"from {_fmt(min(chaotic))} to {_fmt(max(chaotic))}; the largest quadrature bound of the table's rates: "
          f"{max(r.error for r in kept.values()):.1e}")
    return kept


def _spin_at_maxima(r: pv.PhaseVolumeRate) -> np.ndarray:
    """ω·γ of the orbit (backward: the reversed run's, negated) at its θ-maxima."""
    states = r.maxima.states
    return (-1.0 if r.backward else 1.0) * np.sum(states[:, 0:3] * states[:, 3:6], axis=1)


def figures(series: dict[str, tuple], kept: dict[tuple[str, bool], pv.PhaseVolumeRate]) -> None:
    fig = Figure(figsize=(10, 7.5))
    axes = fig.subplots(3, 1, sharex=True)
    for ax, key in zip(axes, ("T5 s=+3", "T4 s=+3", "T1 s=-3")):
        t, spin, centres, mean, s, when = series[key]
        ax.plot(t, spin, lw=0.2, color="0.6", label=r"$\omega\cdot\gamma$")
        ax.plot(centres, mean, lw=1.0, color="tab:red", label=f"running mean over {WINDOW:g}")
        for level in (s, -s):
            ax.axhline(level, lw=0.6, ls="--", color="k")
        if when is not None:
            ax.axvline(when, lw=0.8, color="tab:blue", label=f"first reversal, t = {when:.0f}")
        top = TOPS[key[:2]]
        ax.set_title(f"{key[:2]}: I = {(top.I1, top.I2, top.I3)}, c = {top.offset}, from the unstable rotation "
                     f"s = {s:+g} tilted by {TILT}", fontsize=8)
        ax.set_ylabel("vertical spin")
        ax.legend(fontsize=7, loc="upper right")
    axes[-1].set_xlabel("t")
    fig.tight_layout()
    fig.savefig(FIGURES / "chaplygin_top_reversal.png", dpi=120)

    fig = Figure(figsize=(13, 4.4))
    ax1, ax2, ax3 = fig.subplots(1, 3)
    late = {key: r.maxima.t >= 0.5 * r.t_end for key, r in kept.items()}
    for label, color, name in ((CHAOTIC, "tab:red", "C (chaotic)"), (TORUS, "tab:blue", "A (torus)")):
        r = kept[(label, False)]
        ax1.plot(r.maxima.theta[late[(label, False)]], _spin_at_maxima(r)[late[(label, False)]], ".", ms=1.0,
                 color=color, label=name)
    r = kept[(CHAOTIC, False)]
    ax2.plot(r.maxima.theta[late[(CHAOTIC, False)]], -_spin_at_maxima(r)[late[(CHAOTIC, False)]], ".", ms=1.0,
             color="0.75", label="C mirrored: ω → −ω")
    for label, color, name in ((CHAOTIC, "tab:red", "backward from C's start"),
                               (TORUS, "tab:blue", "backward from A's start")):
        r = kept[(label, True)]
        ax2.plot(r.maxima.theta[late[(label, True)]], _spin_at_maxima(r)[late[(label, True)]], ".", ms=1.0,
                 color=color, label=name)
    for ax, title in ((ax1, "forward, t > T/2: attractors"), (ax2, "backward, t > T/2: repellers")):
        ax.set_xlabel(r"$\theta$ at the $\theta$-maxima")
        ax.set_ylabel(r"$\omega\cdot\gamma$ there")
        ax.set_title(f"T4, {title}", fontsize=9)
        ax.legend(fontsize=7, markerscale=8)
    for (label, backward), color, ls, name in (
            ((CHAOTIC, False), "tab:red", "-", "C forward"), ((CHAOTIC, True), "tab:red", "--", "C backward"),
            ((TORUS, False), "tab:blue", "-", "A forward"), ((TORUS, True), "tab:blue", "--", "A backward"),
            ((SETTLED, False), "tab:green", "-", "T5 at the rotation s = −2.98, forward")):
        r = kept[(label, backward)]
        ax3.plot(r.t, r.running, ls=ls, color=color, lw=1.0, label=name)
    ax3.axhline(0.0, color="k", lw=0.5)
    ax3.set_xscale("log")
    ax3.set_xlim(50.0, T_RUN)
    ax3.set_ylim(-0.03, 0.03)
    ax3.set_xlabel("t")
    ax3.set_ylabel(r"$(1/t)\int_0^t \mathrm{div}\, f\, dt$")
    ax3.set_title("running average of div f", fontsize=9)
    ax3.legend(fontsize=7)
    fig.tight_layout()
    fig.savefig(FIGURES / "chaplygin_top_attractor.png", dpi=120)


def main() -> None:
    cpu, wall = time.process_time(), time.perf_counter()
    controls()
    rotations()
    series = reversals()
    kept = attracting_sets()
    figures(series, kept)
    print(f"\nCPU {time.process_time() - cpu:.0f} s, wall {time.perf_counter() - wall:.0f} s; figures in {FIGURES}")


if __name__ == "__main__":
    main()
