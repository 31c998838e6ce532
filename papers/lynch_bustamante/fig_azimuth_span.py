"""Package figure: the azimuth span Φ(ψ0) — direct ODE, averaged map, pendulum closed form, and π − 2ψ0.

Paper §7.2 observes Φ ≈ π − 2ψ0 (fig. 6) without explanation; the averaging gives Φ = 2λ(π − 2ψ0)
near pure rocking, λ → ½ as θ0 → π (docs/averaging.md).  ε = 1e-3, released at rest from θ0 = 0.95π.
"""

from __future__ import annotations

import math
from pathlib import Path

import numpy as np

from rocknroller.analysis.model.body import Body
from rocknroller.analysis.model.equations import EulerState
from rocknroller.analysis.slow.dynamics.pendulum import pendulum_constants, pendulum_prediction
from rocknroller.analysis.slow.prediction import load_or_build_table, predict_slow_motion
from rocknroller.numerics.integrate import simulate
from rocknroller.papers.output import Reproduction, new_figure, save_figure, write_csv

NAME = "fig_azimuth_span"
EPSILON = 1e-3
THETA0 = 0.95 * math.pi
T_END = 1000.0
PSI0 = tuple(np.linspace(0.02, 0.98, 13) * math.pi / 2)


def compute() -> dict[str, list[float]]:
    """Columns psi0, Phi_ODE, Phi_map, Phi_pendulum, pi_minus_2psi0: the azimuth span Φ for each ψ0 of
    ``PSI0`` from the direct ODE, the averaged map and the pendulum closed form (ε = 1e-3, released at rest
    from θ0 = 0.95π, 1000 time units), and the paper's π − 2ψ0."""
    body = Body.paper(EPSILON)
    table = load_or_build_table(body, THETA0)
    consts = pendulum_constants(body, THETA0)
    rows: dict[str, list[float]] = {"psi0": list(PSI0), "Phi_ODE": [], "Phi_map": [], "Phi_pendulum": [],
                                    "pi_minus_2psi0": []}
    for psi0 in PSI0:
        rows["Phi_ODE"].append(simulate(body, EulerState(THETA0, 0.0, psi0), T_END).Phi)
        rows["Phi_map"].append(predict_slow_motion(body, THETA0, psi0, T_END, table=table, order=1).Phi)
        rows["Phi_pendulum"].append(pendulum_prediction(body, THETA0, psi0, T_END, constants=consts).Phi)
        rows["pi_minus_2psi0"].append(math.pi - 2 * psi0)
    return rows


def run(out: Path) -> Reproduction:
    """Package figure (Φ ≈ π − 2ψ0 of paper §7.2, fig. 6): writes ``fig_azimuth_span.png`` and ``.pdf``
    (Φ/π against ψ0/π) and ``fig_azimuth_span.csv`` (the columns of :func:`compute`); numbers: the largest
    relative deviation from the ODE's Φ of the map, of the pendulum and of π − 2ψ0."""
    rows = compute()
    x = np.array(rows["psi0"]) / math.pi
    fig = new_figure(figsize=(6, 4.5))
    ax = fig.subplots()
    ax.plot(x, np.array(rows["pi_minus_2psi0"]) / math.pi, "k:", label=r"$\pi-2\psi_0$ (paper's rule)")
    ax.plot(x, np.array(rows["Phi_pendulum"]) / math.pi, "-", color="tab:green", label="pendulum closed form")
    ax.plot(x, np.array(rows["Phi_map"]) / math.pi, "s", mfc="none", color="tab:blue", label="averaged map")
    ax.plot(x, np.array(rows["Phi_ODE"]) / math.pi, "o", ms=3, color="tab:red", label="direct ODE")
    ax.set_xlabel(r"$\psi_0/\pi$")
    ax.set_ylabel(r"$\Phi/\pi$")
    ax.set_title(rf"Azimuth span, $\epsilon={EPSILON:g}$, $\theta_0=0.95\pi$, {T_END:g} time units", fontsize=10)
    ax.legend()
    ax.grid(alpha=0.3)
    outputs = save_figure(fig, out, NAME)
    outputs.append(write_csv(out / f"{NAME}.csv", rows, [
        "azimuth span Phi of phi mod pi at the theta-maxima", f"body: {Body.paper(EPSILON).describe()}",
        f"released at rest from theta0={THETA0!r}, phi0=0, t_end={T_END:g}"]))
    ode, mp, pd = (np.array(rows[k]) for k in ("Phi_ODE", "Phi_map", "Phi_pendulum"))
    numbers = {"max |map/ODE - 1|": float(np.max(np.abs(mp / ode - 1))),
               "max |pendulum/ODE - 1|": float(np.max(np.abs(pd / ode - 1))),
               "max |(pi-2psi0)/ODE - 1|": float(np.max(np.abs(np.array(rows["pi_minus_2psi0"]) / ode - 1)))}
    caption = ("Φ(ψ0) from the direct ODE, the averaged map and the pendulum closed form Φ = 2λ(π − 2ψ0), against "
               "the paper's π − 2ψ0.")
    return Reproduction(NAME, caption, outputs, numbers)
