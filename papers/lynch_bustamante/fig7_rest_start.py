"""Paper fig. 7: released from rest (φ̇0 = ψ̇0 = 0, so Q_R = Q_J = 0), ε = 1e-3, ψ0 = π/4, 200 time units."""

from __future__ import annotations

from pathlib import Path

from rocknroller.numerics.equations import EulerState
from rocknroller.papers.lynch_bustamante import reversals
from rocknroller.papers.output import Reproduction

NAME = "fig7"


def run(out: Path) -> Reproduction:
    r = reversals.run("rest", EulerState(reversals.THETA0, 0.0, reversals.PSI0))
    nums = reversals.numbers(r)
    paths = reversals.three_panels(r, out, "fig7_rest_start",
                                   r"Paper fig. 7: from rest, $\theta_0=0.95\pi$, $\psi_0=\pi/4$, $\epsilon=10^{-3}$")
    caption = (f"From rest: the orbit alternates between Regions I and III; {nums['full-angle reversals (Q_J,0 crossings)']} "
               f"full-angle and {nums['visible-angle reversals (Q_J,pi crossings)']} visible-angle reversals in 200 "
               f"time units; Q_R extent {nums['Q_R extent (orbit)']:.4f} (paper's estimate 0.001).")
    return Reproduction(NAME, caption, paths, nums)
