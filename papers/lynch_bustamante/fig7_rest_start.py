"""Paper fig. 7: released from rest (φ̇0 = ψ̇0 = 0, so Q_R = Q_J = 0), ε = 1e-3, ψ0 = π/4, 200 time units."""

from __future__ import annotations

from pathlib import Path

from rocknroller.analysis.criticality.starts import PSI0, THETA0
from rocknroller.analysis.model.equations import EulerState
from rocknroller.papers.lynch_bustamante import reversals
from rocknroller.papers.output import Reproduction

NAME = "fig7"


def run(out: Path) -> Reproduction:
    """Paper fig. 7: the run from rest (θ0 = 0.95π, ψ0 = π/4, ε = 1e-3, 200 time units); writes the three panels
    of :func:`~rocknroller.papers.lynch_bustamante.reversals.three_panels` as ``fig7_rest_start.png`` and ``.pdf``
    and ``fig7_rest_start_turning_points.csv``; numbers: those of
    :func:`~rocknroller.papers.lynch_bustamante.reversals.numbers` (initial invariants and rates, extents,
    counts of full- and visible-angle reversals)."""
    r = reversals.run("rest", EulerState(THETA0, 0.0, PSI0))
    nums = reversals.numbers(r)
    paths = reversals.three_panels(r, out, "fig7_rest_start",
                                   r"Paper fig. 7: from rest, $\theta_0=0.95\pi$, $\psi_0=\pi/4$, $\epsilon=10^{-3}$")
    caption = (f"From rest: the orbit alternates between Regions I and III; {nums['full-angle reversals (Q_J,0 crossings)']} "
               f"full-angle and {nums['visible-angle reversals (Q_J,pi crossings)']} visible-angle reversals in 200 "
               f"time units; Q_R extent {nums['Q_R extent (orbit)']:.4f} (paper's estimate 0.001).")
    return Reproduction(NAME, caption, paths, nums)
