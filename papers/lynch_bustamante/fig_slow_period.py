"""Package figure: the slow period of the (Q_R, Q_J) oscillation against ψ0 and ε (ODE, map, closed form).

Released at rest from θ0 = 0.95π.  The slow period is that of Θ = 2ψ sampled at the θ-maxima; the
pendulum gives 4K(m)T0/√(εκ), m = sin²((π − 2ψ0)/2), so it scales as ε^(−1/2).
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

NAME = "fig_slow_period"
THETA0 = 0.95 * math.pi
EPSILONS = (1e-4, 3e-4, 1e-3, 3e-3)  # below the period doubling at eps ~ 9.4e-3 (K = 4)
PSI0 = tuple(np.array([0.1, 0.2, 0.3, 0.4, 0.5, 0.6, 0.7, 0.8, 0.9]) * math.pi / 2)


def t_end_for(eps: float) -> float:
    """At least three slow periods: the period grows like ε^(−1/2)."""
    return 1500.0 * math.sqrt(1e-3 / eps) if eps < 1e-3 else 1000.0


def compute() -> dict[str, list]:
    """Columns eps, psi0, P_ODE, P_map, P_pendulum: the slow period of Θ = 2ψ for each ε of ``EPSILONS``
    and ψ0 of ``PSI0`` (released at rest from θ0 = 0.95π, over :func:`t_end_for` (ε)) from the direct ODE, the
    averaged map and the pendulum closed form; None where not measurable within the run."""
    rows: dict[str, list] = {"eps": [], "psi0": [], "P_ODE": [], "P_map": [], "P_pendulum": []}
    for eps in EPSILONS:
        body = Body.paper(eps)
        table = load_or_build_table(body, THETA0)
        consts = pendulum_constants(body, THETA0)
        t_end = t_end_for(eps)
        for psi0 in PSI0:
            rows["eps"].append(eps)
            rows["psi0"].append(psi0)
            rows["P_ODE"].append(simulate(body, EulerState(THETA0, 0.0, psi0), t_end).slow_period)
            rows["P_map"].append(predict_slow_motion(body, THETA0, psi0, t_end, table=table, order=1).slow_period)
            rows["P_pendulum"].append(pendulum_prediction(body, THETA0, psi0, t_end, constants=consts).slow_period)
    return rows


def _array(values: list) -> np.ndarray:
    """Periods as floats, NaN where not measurable within the run (None; an empty cell in the CSV)."""
    return np.array([np.nan if v is None else v for v in values], float)


def run(out: Path) -> Reproduction:
    """Package figure: writes ``fig_slow_period.png`` and ``.pdf`` (slow period × √ε against ψ0/π, one colour
    per ε) and ``fig_slow_period.csv`` (the columns of :func:`compute`); numbers: how many ODE periods are not
    measurable, and for each ε the largest relative deviation of the map and of the pendulum from the ODE."""
    rows = compute()
    eps, psi0 = np.array(rows["eps"]), np.array(rows["psi0"])
    P_ode, P_map, P_pend = _array(rows["P_ODE"]), _array(rows["P_map"]), _array(rows["P_pendulum"])
    fig = new_figure(figsize=(6.5, 4.5))
    ax = fig.subplots()
    for k, e in enumerate(EPSILONS):
        sel = eps == e
        color = f"C{k}"
        scale = math.sqrt(e)
        ax.plot(psi0[sel] / math.pi, P_pend[sel] * scale, "-", color=color,
                label=rf"$\epsilon={e:g}$: pendulum")
        ax.plot(psi0[sel] / math.pi, P_map[sel] * scale, "s", mfc="none", color=color,
                label="averaged map (colour = eps)" if k == 0 else None)
        ax.plot(psi0[sel] / math.pi, P_ode[sel] * scale, "o", ms=3, color="k",
                label="direct ODE" if k == 0 else None)
    ax.set_xlabel(r"$\psi_0/\pi$")
    ax.set_ylabel(r"slow period $\times\sqrt{\epsilon}$ (time units)")
    ax.set_title(r"Slow period of $\Theta=2\psi$ at the $\theta$-maxima, $\theta_0=0.95\pi$", fontsize=10)
    ax.legend(fontsize=8)
    ax.grid(alpha=0.3)
    outputs = save_figure(fig, out, NAME)
    outputs.append(write_csv(out / f"{NAME}.csv", rows, [
        "slow period of Theta = 2 psi sampled at the theta-maxima (mean crossings)",
        f"body: paper body with I2=(1+eps)I1; released at rest from theta0={THETA0!r}"]))
    numbers: dict[str, float | int | str] = {"not measurable (ODE)": int(np.isnan(P_ode).sum())}
    for e in EPSILONS:
        sel = eps == e
        numbers[f"max |map/ODE-1|, eps={e:g}"] = float(np.nanmax(np.abs(P_map[sel] / P_ode[sel] - 1)))
        numbers[f"max |pendulum/ODE-1|, eps={e:g}"] = float(np.nanmax(np.abs(P_pend[sel] / P_ode[sel] - 1)))
    caption = ("Slow period × √ε against ψ0 for ε = 1e-4, 3e-4, 1e-3, 3e-3: direct ODE (dots), averaged map (squares), "
               "pendulum closed form (lines); the √ε scaling collapses the curves.")
    return Reproduction(NAME, caption, outputs, numbers)
