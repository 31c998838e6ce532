"""Shared machinery of the paper's recession figures 7–11: the runs and their three-panel plots.

Paper §numerics (Recession and criticality): ε = 1e-3, released at θ0 = 0.95π with θ̇0 = 0, φ0 = 0,
ψ0 = π/4, 200 time units.  Starts "on a critical line" are placed by computation
(:func:`rocknroller.analysis.criticality.starts.critical_start`), not by the paper's rounded rates.
"""

from __future__ import annotations

import math
from dataclasses import dataclass
from pathlib import Path

import numpy as np

from rocknroller.analysis.criticality.reversals import reversal_analysis
from rocknroller.analysis.criticality.starts import EPSILON, THETA0
from rocknroller.analysis.model.body import Body
from rocknroller.analysis.model.equations import EulerState
from rocknroller.numerics.integrate import simulate
from rocknroller.numerics.trajectory import Trajectory
from rocknroller.numerics.trajectory_plots import plot_invariant_orbit
from rocknroller.papers.output import new_figure, save_figure, write_csv
from rocknroller.papers.plotting import draw_critical_lines

T_END = 200.0


@dataclass(frozen=True)
class ReversalRun:
    label: str
    initial: EulerState
    traj: Trajectory


def body() -> Body:
    """The body of figs. 7–11: the paper's at ε = 1e-3."""
    return Body.paper(EPSILON)


def run(label: str, initial: EulerState, t_end: float = T_END) -> ReversalRun:
    """The direct ODE run of :func:`body` from ``initial`` over ``t_end`` time units (default 200), labelled
    ``label``."""
    return ReversalRun(label, initial, simulate(body(), initial, t_end))


def numbers(r: ReversalRun) -> dict[str, float | int | str]:
    """Initial invariants, extents and the critical crossings of each type."""
    ra = reversal_analysis(r.traj)
    return {"Q_R(0)": float(r.traj.QR[0]), "Q_J(0)": float(r.traj.QJ[0]),
            "phi_dot0": r.initial.phi_dot, "psi_dot0": r.initial.psi_dot,
            "Q_R extent (orbit)": float(np.ptp(r.traj.QR)), "Q_J extent (orbit)": float(np.ptp(r.traj.QJ)),
            "full-angle reversals (Q_J,0 crossings)": ra.count("0"),
            "visible-angle reversals (Q_J,pi crossings)": ra.count("pi")}


def three_panels(r: ReversalRun, out: Path, name: str, title: str) -> list[Path]:
    """Orbit with critical lines; φ(t) solid where θ ≥ θ0/2, dashed otherwise; φ mod π where θ ≥ θ0/2."""
    traj = r.traj
    fig = new_figure(figsize=(8.5, 10))
    axes = fig.subplots(3, 1)
    ax = axes[0]
    pad = 0.15 * max(np.ptp(traj.QR), 1e-12)
    draw_critical_lines(ax, traj.paper_body, traj.QR.min() - pad, traj.QR.max() + pad)
    plot_invariant_orbit(traj, ax)
    qj_pad = 0.15 * np.ptp(traj.QJ)
    ax.set_ylim(traj.QJ.min() - qj_pad, traj.QJ.max() + qj_pad)
    ax.legend(fontsize=7, loc="upper left", bbox_to_anchor=(1.01, 1.0))
    ax.set_title(r"orbit in the $(Q_R, Q_J)$ plane", fontsize=10)
    high = traj.theta >= 0.5 * THETA0
    ax = axes[1]
    ax.plot(traj.t, np.where(high, traj.phi, np.nan) / math.pi, "-", color="tab:red", lw=1,
            label=r"$\theta\geq 0.5\theta_0$")
    ax.plot(traj.t, np.where(high, np.nan, traj.phi) / math.pi, "--", color="tab:blue", lw=1,
            label=r"$\theta<0.5\theta_0$")
    ax.set_xlabel("t (time units)")
    ax.set_ylabel(r"$\phi$ ($\pi$ rad)")
    ax.legend(fontsize=7)
    ax = axes[2]
    ax.plot(traj.t[high], np.mod(traj.phi[high], math.pi) / math.pi, ".", ms=1, color="tab:red")
    ax.set_xlabel("t (time units)")
    ax.set_ylabel(r"$\phi$ mod $\pi$ ($\pi$ rad)")
    ax.set_ylim(0, 1)
    fig.suptitle(title, fontsize=10)
    fig.tight_layout()
    paths = save_figure(fig, out, name)
    header = [title, f"body: {traj.body.describe()}", f"initial: {r.initial}"]
    paths.append(write_csv(out / f"{name}_turning_points.csv", {
        "kind": ["max"] * len(traj.maxima) + ["min"] * len(traj.minima),
        "t": [*traj.maxima.t, *traj.minima.t], "Q_R": [*traj.maxima.QR, *traj.minima.QR],
        "Q_J": [*traj.maxima.QJ, *traj.minima.QJ], "phi": [*traj.maxima.phi, *traj.minima.phi]}, header))
    return paths
