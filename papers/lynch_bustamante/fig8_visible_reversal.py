"""Paper fig. 8: a start on the critical line Q_J = Q_J,π^crit (visible-angle reversals), ψ̇0 = 0.002.

The paper gives φ̇0 = −0.002, ψ̇0 = 0.002 and quotes Q_R = 0.0030 in the caption; here φ̇0 is solved so that
the start lies exactly on the line, and Q_R is computed.
"""

from __future__ import annotations

from pathlib import Path

from rocknroller.analysis.criticality.starts import FIG8_PSI_DOT0 as PSI_DOT0
from rocknroller.analysis.criticality.starts import start_on_line
from rocknroller.papers.animation import animate
from rocknroller.papers.lynch_bustamante import reversals
from rocknroller.papers.output import Reproduction

NAME = "fig8"
#: The short animation of the run (``rocknroller animate`` makes longer ones): frames per second and seconds.
ANIMATION_FPS = 10
ANIMATION_SECONDS = 4


def run(out: Path) -> Reproduction:
    """Paper fig. 8: the start on Q_J,π^crit with ψ̇0 = 0.002 (φ̇0 solved), 200 time units; writes the three
    panels of :func:`~rocknroller.papers.lynch_bustamante.reversals.three_panels` as ``fig8_visible_reversal.png``
    and ``.pdf`` and ``fig8_visible_reversal_turning_points.csv``, and ``fig8_animation.gif`` (10 fps, 4 s);
    numbers: those of :func:`~rocknroller.papers.lynch_bustamante.reversals.numbers`."""
    r = reversals.run("on QJ,pi crit", start_on_line("pi", PSI_DOT0))
    nums = reversals.numbers(r)
    paths = reversals.three_panels(r, out, "fig8_visible_reversal",
                                   r"Paper fig. 8: start on $Q_J=Q_{J,\pi}^{crit}$, $\dot\psi_0=0.002$")
    paths.append(animate(r.traj, out / "fig8_animation.gif", fps=ANIMATION_FPS, duration=ANIMATION_SECONDS,
                         title="paper fig. 8 start", progress=False, dpi=60))
    caption = (f"Start on Q_J,π^crit with φ̇0 = {r.initial.phi_dot:.6f}: Q_R(0) = {nums['Q_R(0)']:.6f} (caption: 0.0030), "
               f"Q_J(0) = {nums['Q_J(0)']:.6f}; {nums['visible-angle reversals (Q_J,pi crossings)']} visible-angle and "
               f"{nums['full-angle reversals (Q_J,0 crossings)']} full-angle reversals in 200 time units. "
               f"fig8_animation.gif: the body rolling and its (Q_R, Q_J) over the critical lines, "
               f"{ANIMATION_FPS * ANIMATION_SECONDS} frames over the 200 time units.")
    return Reproduction(NAME, caption, paths, nums)
