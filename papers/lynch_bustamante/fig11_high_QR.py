"""Paper fig. 11: visible-angle reversal at high Q_R = 0.1, started slightly above Q_J,π^crit.

The paper gives no offset.  At Q_R = 0.1 the leading Laurent term no longer fixes the sign of φ̇(θ_X), and an
orbit started on the line crosses into Region IV.  Starts 2.5 % of |Q_J,π^crit| above the line stay in Region I
and recede steadily (Δφ(t_j) < 0), 3.5 % above they precess steadily (Δφ(t_j) > 0).  The offset is solved
between these so that the mean of the visible precession angle Δφ(t_j) = φ(t_j) − φ(t_{j−2}) mod 2π over the
run vanishes: the orbit stays in Region I while Δφ(t_j) takes both signs, as the paper describes.
"""

from __future__ import annotations

import math
from pathlib import Path

import numpy as np

from rocknroller.analysis.criticality.lines import QJ_crit_pi, region
from rocknroller.analysis.criticality.starts import FIG11_QR0 as QR0
from rocknroller.analysis.criticality.starts import start_on_line
from rocknroller.analysis.model.diagnostics import wrap_angle
from rocknroller.numerics.trajectory_plots import plot_invariant_orbit
from rocknroller.papers.lynch_bustamante import reversals
from rocknroller.papers.output import Reproduction, new_figure, save_figure, write_csv
from rocknroller.papers.plotting import draw_critical_lines

NAME = "fig11"
OFFSET_BRACKET = (0.025, 0.035)  # fractions of |Q_J,pi crit| above the line: steady recession / precession
T_END = 1000.0


def run_with_offset(fraction: float) -> reversals.ReversalRun:
    """The fig. 11 run: θ0 = 0.95π, ψ0 = π/4, Q_R(0) = 0.1, started ``fraction * abs(Q_J,pi^crit)`` above the
    line Q_J,π^crit in Q_J, ε = 1e-3, ``T_END`` = 1000 time units."""
    offset = fraction * abs(float(QJ_crit_pi(QR0, reversals.body())))
    return reversals.run("high Q_R", start_on_line("pi", QR=QR0, offset=offset), T_END)


def compute() -> tuple[float, reversals.ReversalRun]:
    """(offset fraction, run) with zero mean visible precession over the run (Brent, 1e-4 in the fraction)."""
    from scipy.optimize import brentq

    def mean_precession(fraction: float) -> float:
        return float(np.mean(visible_precession(run_with_offset(fraction).traj)[1]))

    fraction = brentq(mean_precession, *OFFSET_BRACKET, xtol=1e-4)
    return fraction, run_with_offset(fraction)


def visible_precession(traj) -> tuple[np.ndarray, np.ndarray]:
    """(t_j, Δφ(t_j) mod 2π in [−π, π)) with Δφ(t_j) = φ(t_j) − φ(t_{j−2}) (paper §Recession)."""
    return traj.maxima.t[2:], wrap_angle(traj.maxima.phi[2:] - traj.maxima.phi[:-2])


def run(out: Path) -> Reproduction:
    """Paper fig. 11: writes ``fig11_high_QR.png`` and ``.pdf`` (orbit with the critical lines; φ mod 2π at the
    θ-maxima) and ``fig11_visible_precession.csv`` (t_j, Δφ(t_j) mod 2π) for the run of :func:`compute`; numbers:
    the offset fraction, Q_J(0) − Q_J,π^crit, the regions at the maxima, and the least and greatest Δφ(t_j)."""
    fraction, r = compute()
    traj = r.traj
    t_j, dphi = visible_precession(traj)
    regions = sorted(set(str(x) for x in region(traj.maxima.QR, traj.maxima.QJ, traj.paper_body)))
    fig = new_figure(figsize=(11, 4.5))
    axes = fig.subplots(1, 2)
    pad = 0.2 * np.ptp(traj.QR)
    lines = draw_critical_lines(axes[0], traj.paper_body, traj.QR.min() - pad, traj.QR.max() + pad)
    plot_invariant_orbit(traj, axes[0])
    crit = lines["QJpi"]
    lo, hi = min(traj.QJ.min(), crit.min()), max(traj.QJ.max(), crit.max())
    axes[0].set_ylim(lo - 0.15 * (hi - lo), hi + 0.15 * (hi - lo))
    axes[0].legend(fontsize=7)
    axes[0].set_title(rf"orbit, $Q_R(0)={QR0:g}$, start {100 * fraction:.2f}% above $Q_{{J,\pi}}^{{crit}}$",
                      fontsize=10)
    axes[1].plot(traj.maxima.t, wrap_angle(traj.maxima.phi) / math.pi, ".", color="tab:red", ms=4)
    axes[1].set_xlabel("t (time units)")
    axes[1].set_ylabel(r"$\phi$ mod $2\pi$ in $[-\pi, \pi)$ at $\theta$-maxima ($\pi$ rad)")
    axes[1].set_ylim(-1, 1)
    axes[1].set_title("visible angle at the maxima", fontsize=10)
    fig.suptitle(r"Paper fig. 11: high-$Q_R$ reversal, $\epsilon=10^{-3}$, $\theta_0=0.95\pi$, $\psi_0=\pi/4$",
                 fontsize=10)
    fig.tight_layout()
    paths = save_figure(fig, out, "fig11_high_QR")
    paths.append(write_csv(out / "fig11_visible_precession.csv", {"t_j": t_j, "delta_phi_mod_2pi": dphi},
                           [f"paper fig. 11; body: {traj.body.describe()}", f"initial: {r.initial}"]))
    numbers: dict[str, float | str] = {
        "offset fraction of |Q_J,pi crit|": fraction,
        "Q_J(0) - Q_J,pi crit": float(traj.QJ[0] - QJ_crit_pi(traj.QR[0], traj.paper_body)),
        "regions at the maxima": " ".join(regions),
        "min visible delta_phi": float(dphi.min()), "max visible delta_phi": float(dphi.max())}
    caption = (f"Q_R = {QR0:g}, started {100 * fraction:.2f} % of |Q_J,π^crit| above the line (zero mean visible "
               f"precession): the orbit stays in Region(s) {', '.join(regions)} while Δφ(t_j) mod 2π ranges over "
               f"[{dphi.min():.3f}, {dphi.max():.3f}] rad, both signs.")
    return Reproduction(NAME, caption, paths, numbers)
