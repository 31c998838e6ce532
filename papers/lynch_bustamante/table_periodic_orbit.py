"""Paper §7.2: the periodic orbit near ψ0 = 2.965π/8 (ε = 1e-3, released at rest from θ0 = 0.95π).

The motion is periodic when the slow period P of Θ = 2ψ (sampled at the θ-maxima) is a whole number of
rocking half-periods T_θ (the mean spacing of the maxima).  We solve P/T_θ = N for ψ0 near the paper's
value by the secant method on the direct ODE, and count how often the contact track is traversed in
1000 time units: once out and once back per slow period (the libration of Θ retraces it), 2·1000/P.
"""

from __future__ import annotations

import math
from pathlib import Path

from rocknroller.analysis.model.body import Body
from rocknroller.analysis.model.equations import EulerState
from rocknroller.numerics.integrate import simulate
from rocknroller.papers.output import Reproduction, write_csv

NAME = "table_periodic_orbit"
EPSILON = 1e-3
T_END = 1000.0
PAPER_PSI0 = 2.965 * math.pi / 8


def rocks_per_slow_period(psi0: float, body: Body) -> tuple[float, float, float]:
    """(P/T_θ, P, T_θ) from a direct run of T_END time units."""
    traj = simulate(body, EulerState(0.95 * math.pi, 0.0, psi0), T_END)
    P, T_theta = traj.slow_period, traj.maxima_spacing
    if P is None or T_theta is None:
        raise ValueError(f"psi0={psi0!r}: no slow period (or fewer than two theta-maxima) in {T_END:g} time units")
    return P / T_theta, P, T_theta


def periodic_psi0(body: Body, guess: float = PAPER_PSI0, tol: float = 1e-10) -> tuple[float, int]:
    """ψ0 near ``guess`` at which P/T_θ is the nearest whole number N (secant method)."""
    ratio0 = rocks_per_slow_period(guess, body)[0]
    N = int(round(ratio0))
    x0, x1 = guess, guess * (1 + 1e-3)
    f0, f1 = ratio0 - N, rocks_per_slow_period(x1, body)[0] - N
    for _ in range(30):
        if f1 == f0:
            break
        x0, x1, f0 = x1, x1 - f1 * (x1 - x0) / (f1 - f0), f1
        f1 = rocks_per_slow_period(x1, body)[0] - N
        if abs(x1 - x0) < tol:
            break
    return x1, N


def run(out: Path) -> Reproduction:
    """Paper §7.2: writes ``table_periodic_orbit.csv`` (ψ0, ψ0/(π/8), P/T_θ, P, T_θ and the traversals of
    the track in 1000 time units, at the paper's ψ0 = 2.965π/8 and at the solved periodic ψ0); numbers: the
    periodic ψ0/(π/8), N = P/T_θ there, P/T_θ at the paper's ψ0, and P and the traversals at the periodic ψ0."""
    body = Body.paper(EPSILON)
    psi0, N = periodic_psi0(body)
    rows = [(label, p, *rocks_per_slow_period(p, body)) for label, p in
            (("paper 2.965pi/8", PAPER_PSI0), ("periodic (solved)", psi0))]
    path = write_csv(out / "table_periodic_orbit.csv", {
        "case": [r[0] for r in rows], "psi0": [r[1] for r in rows], "psi0_over_pi_8": [8 * r[1] / math.pi for r in rows],
        "P_over_T_theta": [r[2] for r in rows], "slow_period": [r[3] for r in rows], "T_theta": [r[4] for r in rows],
        "traversals_in_1000": [2 * T_END / r[3] for r in rows]},
        [f"paper 7.2 periodic orbit; body: {body.describe()}", "released at rest from theta0=0.95pi, phi0=0"])
    numbers = {"psi0_periodic/(pi/8)": 8 * psi0 / math.pi, "rocks_per_slow_period": N,
               "P_over_T_theta_at_paper_psi0": rows[0][2], "slow_period": rows[1][3],
               "traversals_in_1000": 2 * T_END / rows[1][3]}
    caption = (f"The orbit is periodic at ψ0 = {8 * psi0 / math.pi:.5f}π/8 (paper: 2.965π/8), where the slow period "
               f"P = {rows[1][3]:.3f} equals {N} rocking half-periods; the track is traversed "
               f"{2 * T_END / rows[1][3]:.1f} times in 1000 time units (paper: 'some fifteen').")
    return Reproduction(NAME, caption, [path], numbers)
