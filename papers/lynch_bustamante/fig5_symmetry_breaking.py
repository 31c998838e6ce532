"""Paper fig. 5: contact track and φ at the θ-maxima, symmetric body against ε = 1e-3, 1500 time units.

Initial state (paper §7.1): θ0 = 0.95π, φ0 = ψ0 = 0, ω = (0, 0.001, −0.001).
"""

from __future__ import annotations

import math
from pathlib import Path

from rocknroller.analysis.model.body import Body
from rocknroller.numerics.integrate import simulate
from rocknroller.papers.output import Reproduction, new_figure, save_figure, write_csv
from rocknroller.analysis.model.equations import FIG5_OMEGA0, FIG5_THETA0, fig5_start

NAME = "fig5"
T_END = 1500.0
EPSILONS = (0.0, 1e-3)
def compute():
    """The two trajectories, keyed by ε."""
    return {eps: simulate(Body.paper(eps), fig5_start(), T_END) for eps in EPSILONS}


def run(out: Path) -> Reproduction:
    """Paper fig. 5: writes ``fig5_symmetry_breaking.png`` and ``.pdf`` (contact track and φ at the θ-maxima,
    ε = 0 and 1e-3) and ``fig5_maxima_sym.csv``, ``fig5_maxima_eps1e-3.csv`` (t, θ, φ, ψ, Q_R, Q_J at the
    θ-maxima); numbers for each ε: Φ, the range of φ at the maxima, the number of maxima, the relative energy error."""
    from rocknroller.numerics.trajectory_plots import plot_contact_track, plot_phi_at_maxima

    runs = compute()
    fig = new_figure(figsize=(9, 8.5))
    axes = fig.subplots(2, 2)
    numbers: dict[str, float | int | str] = {}
    outputs = []
    for row, (eps, traj) in enumerate(runs.items()):
        label = "symmetric, $I_2=I_1$" if eps == 0 else rf"$\epsilon={eps:g}$"
        plot_contact_track(traj, axes[row, 0])
        axes[row, 0].set_title(f"contact track, {label}")
        plot_phi_at_maxima(traj, axes[row, 1])
        axes[row, 1].set_title(rf"$\phi$ at $\theta$-maxima, {label}")
        key = "sym" if eps == 0 else "eps1e-3"
        numbers[f"Phi_{key}"] = traj.Phi
        numbers[f"phi_range_at_maxima_{key}"] = float(traj.maxima.phi.max() - traj.maxima.phi.min())
        numbers[f"n_maxima_{key}"] = len(traj.maxima)
        numbers[f"energy_rel_error_{key}"] = traj.energy_rel_error
        outputs.append(write_csv(out / f"fig5_maxima_{key}.csv", {
            "t": traj.maxima.t, "theta": traj.maxima.theta, "phi": traj.maxima.phi, "psi": traj.maxima.psi,
            "Q_R": traj.maxima.QR, "Q_J": traj.maxima.QJ},
            [f"paper fig. 5, {label}", f"body: {traj.body.describe()}", f"initial: {fig5_start()}"]))
    fig.suptitle(rf"Paper fig. 5: $\theta_0={FIG5_THETA0 / math.pi:g}\pi$, $\omega_0={FIG5_OMEGA0}$, "
                 rf"{T_END:g} time units")
    fig.tight_layout()
    outputs = save_figure(fig, out, "fig5_symmetry_breaking") + outputs
    caption = ("Contact track (left) and full azimuth φ at the θ-maxima (right): the symmetric body precesses "
               "steadily; with ε = 1e-3 the precession reverses (recession).")
    return Reproduction(NAME, caption, outputs, numbers)
