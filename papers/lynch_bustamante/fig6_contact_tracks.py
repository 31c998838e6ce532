"""Paper fig. 6: contact tracks for six initial spin phases ψ0, ε = 1e-3, 1000 time units, from rest at 0.95π."""

from __future__ import annotations

import math
from pathlib import Path

from rocknroller.analysis.model.body import Body
from rocknroller.analysis.model.equations import EulerState
from rocknroller.numerics.integrate import simulate
from rocknroller.numerics.trajectory_plots import plot_contact_track
from rocknroller.papers.output import Reproduction, new_figure, save_figure, write_csv

NAME = "fig6"
T_END = 1000.0
EPSILON = 1e-3
PSI0 = (math.pi / 100, math.pi / 8, math.pi / 4, 3 * math.pi / 8, 3.9 * math.pi / 8, math.pi / 2)
LABELS = (r"$\pi/100$", r"$\pi/8$", r"$\pi/4$", r"$3\pi/8$", r"$3.9\pi/8$", r"$\pi/2$")


def compute():
    """The six trajectories of fig. 6: ε = 1e-3, released at rest from θ0 = 0.95π, φ0 = 0, each ψ0 of
    ``PSI0``, ``T_END`` = 1000 time units."""
    body = Body.paper(EPSILON)
    return [simulate(body, EulerState(0.95 * math.pi, 0.0, psi0), T_END) for psi0 in PSI0]


def run(out: Path) -> Reproduction:
    """Paper fig. 6: writes ``fig6_contact_tracks.png`` and ``.pdf`` (the contact tracks of :func:`compute`,
    panels A–F) and ``fig6_Phi.csv`` (ψ0, Φ from the ODE, π − 2ψ0); numbers: Φ/π for each ψ0."""
    runs = compute()
    fig = new_figure(figsize=(11, 7.5))
    axes = fig.subplots(2, 3)
    for k, (ax, traj, label) in enumerate(zip(axes.flat, runs, LABELS)):
        plot_contact_track(traj, ax)
        ax.set_title(rf"({'ABCDEF'[k]}) $\psi_0=${label}, $\Phi={traj.Phi / math.pi:.3f}\pi$")
    fig.suptitle(r"Paper fig. 6: $\epsilon=10^{-3}$, released at rest from $\theta_0=0.95\pi$, 1000 time units")
    fig.tight_layout()
    outputs = save_figure(fig, out, "fig6_contact_tracks")
    Phi = [traj.Phi for traj in runs]
    outputs.append(write_csv(out / "fig6_Phi.csv", {
        "psi0": PSI0, "Phi_ODE": Phi, "pi_minus_2psi0": [math.pi - 2 * p for p in PSI0]},
        [f"paper fig. 6: azimuth span Phi of phi mod pi at the theta-maxima within {T_END:g} time units",
         f"body: {runs[0].body.describe()}", "initial: theta0=0.95pi, at rest, phi0=0"]))
    numbers = {f"Phi/pi (psi0={label.strip('$')})": phi / math.pi for label, phi in zip(LABELS, Phi)}
    caption = ("Contact tracks for ψ0 ∈ {π/100, π/8, π/4, 3π/8, 3.9π/8, π/2}; Φ is the span of φ mod π at the "
               "θ-maxima (paper's rule of thumb Φ ≈ π − 2ψ0).")
    return Reproduction(NAME, caption, outputs, numbers)
