"""Paper fig. 10: the (Q_R, Q_J) orbits of figs. 7, 8 and 9 together, with the critical lines."""

from __future__ import annotations

from pathlib import Path

import numpy as np

from rocknroller.analysis.criticality.starts import PSI0, THETA0, start_on_line
from rocknroller.analysis.model.equations import EulerState
from rocknroller.papers.lynch_bustamante import fig8_visible_reversal as fig8
from rocknroller.papers.lynch_bustamante import fig9_full_reversal as fig9
from rocknroller.papers.lynch_bustamante import reversals
from rocknroller.papers.output import Reproduction, new_figure, save_figure
from rocknroller.papers.plotting import draw_critical_lines

NAME = "fig10"


def runs() -> list[reversals.ReversalRun]:
    """The three runs of paper figs. 7, 8 and 9 (ε = 1e-3, θ0 = 0.95π, ψ0 = π/4, 200 time units): from rest,
    on Q_J,π^crit with fig. 8's ψ̇0 and on Q_J,0^crit with fig. 9's ψ̇0."""
    return [reversals.run("fig. 7: from rest", EulerState(THETA0, 0.0, PSI0)),
            reversals.run("fig. 8: on Q_J,pi crit", start_on_line("pi", fig8.PSI_DOT0)),
            reversals.run("fig. 9: on Q_J,0 crit", start_on_line("0", fig9.PSI_DOT0))]


def run(out: Path) -> Reproduction:
    """Paper fig. 10: writes ``fig10_combined.png`` and ``.pdf`` (the orbits of :func:`runs` in the (Q_R, Q_J)
    plane with the critical lines); numbers: the Q_R and Q_J extents (peak to peak) of each orbit."""
    rr = runs()
    fig = new_figure(figsize=(7, 5.5))
    ax = fig.subplots()
    QR_all = np.concatenate([r.traj.QR for r in rr])
    QJ_all = np.concatenate([r.traj.QJ for r in rr])
    pad = 0.1 * np.ptp(QR_all)
    draw_critical_lines(ax, rr[0].traj.paper_body, QR_all.min() - pad, QR_all.max() + pad)
    for k, r in enumerate(rr):
        ax.plot(r.traj.QR, r.traj.QJ, lw=0.6, color=f"C{k + 2}", label=r.label)
    ax.set_ylim(QJ_all.min() - 0.1 * np.ptp(QJ_all), QJ_all.max() + 0.1 * np.ptp(QJ_all))
    ax.set_xlabel(r"$Q_R$")
    ax.set_ylabel(r"$Q_J$")
    ax.ticklabel_format(style="sci", scilimits=(-2, 2))
    ax.legend(fontsize=8)
    ax.set_title(r"Paper fig. 10: orbits of figs. 7–9, $\epsilon=10^{-3}$, 200 time units", fontsize=10)
    paths = save_figure(fig, out, "fig10_combined")
    numbers = {f"Q_R extent, {r.label}": float(np.ptp(r.traj.QR)) for r in rr}
    numbers.update({f"Q_J extent, {r.label}": float(np.ptp(r.traj.QJ)) for r in rr})
    caption = ("The three orbits together. Their extent along Q_R is "
               + ", ".join(f"{np.ptp(r.traj.QR):.4f}" for r in rr)
               + " (figs. 7, 8, 9); the paper estimates 0.001 from this figure.")
    return Reproduction(NAME, caption, paths, numbers)
