"""Paper fig. 9: a start on the critical line Q_J = Q_J,0^crit (full-angle reversals), ψ̇0 = 0.378.

The paper's rounded φ̇0 = 0.379 puts the start above the line, in Region II (the caption gives by how much); here φ̇0 is solved so that the
start lies exactly on it, and the paper's rounded start is recorded beside it.
"""

from __future__ import annotations

from pathlib import Path

from rocknroller.analysis.criticality.lines import QJ_crit_0
from rocknroller.analysis.criticality.starts import FIG9_PSI_DOT0 as PSI_DOT0
from rocknroller.analysis.criticality.starts import PSI0, THETA0, start_on_line
from rocknroller.analysis.routh.reduction import invariants_from_euler
from rocknroller.papers.lynch_bustamante import reversals
from rocknroller.papers.output import Reproduction

NAME = "fig9"
PAPER_PHI_DOT0 = 0.379


def paper_start_offset() -> tuple[float, float, float]:
    """(Q_R, Q_J, (Q_J − Q_J,0^crit)/Q_J,0^crit) of the paper's rounded start φ̇0 = 0.379, ψ̇0 = 0.378."""
    body = reversals.body()
    _, QR, QJ = invariants_from_euler(body, THETA0, 0.0, PAPER_PHI_DOT0, PSI_DOT0, PSI0)
    crit = float(QJ_crit_0(QR, body))
    return float(QR), float(QJ), (float(QJ) - crit) / crit


def run(out: Path) -> Reproduction:
    """Paper fig. 9: the start on Q_J,0^crit with ψ̇0 = 0.378 (φ̇0 solved), 200 time units; writes the three
    panels of :func:`~rocknroller.papers.lynch_bustamante.reversals.three_panels` as ``fig9_full_reversal.png``
    and ``.pdf`` and ``fig9_full_reversal_turning_points.csv``; numbers: those of
    :func:`~rocknroller.papers.lynch_bustamante.reversals.numbers`, and Q_R, Q_J and the relative offset above
    Q_J,0^crit of the paper's rounded start (:func:`paper_start_offset`)."""
    r = reversals.run("on QJ,0 crit", start_on_line("0", PSI_DOT0))
    nums = reversals.numbers(r)
    QR_p, QJ_p, rel = paper_start_offset()
    nums.update({"paper start Q_R": QR_p, "paper start Q_J": QJ_p, "paper start (Q_J-Q_J0crit)/Q_J0crit": rel})
    paths = reversals.three_panels(r, out, "fig9_full_reversal",
                                   r"Paper fig. 9: start on $Q_J=Q_{J,0}^{crit}$, $\dot\psi_0=0.378$")
    caption = (f"Start on Q_J,0^crit needs φ̇0 = {r.initial.phi_dot:.6f} (paper: 0.379, which is {100 * rel:.0f} % above "
               f"the line); Q_R(0) = {nums['Q_R(0)']:.6f} (caption: 0.0030); "
               f"{nums['full-angle reversals (Q_J,0 crossings)']} full-angle and "
               f"{nums['visible-angle reversals (Q_J,pi crossings)']} visible-angle reversals in 200 time units.")
    return Reproduction(NAME, caption, paths, nums)
