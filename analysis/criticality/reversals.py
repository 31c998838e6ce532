"""Reversal analysis of a direct run: the region and the sign of φ̇ at every turning point, and the critical crossings.

Paper §Recession: the full angle φ reverses when Q_J − Q_J,0^crit changes sign between passages near θ_N (judged at
consecutive θ-minima); the visible angle (φ mod π) reverses when Q_J − Q_J,π^crit changes sign between passages near
θ_X (judged at consecutive θ-maxima).
"""

from __future__ import annotations

from dataclasses import dataclass
from typing import TYPE_CHECKING

import numpy as np
from numpy.typing import NDArray

from rocknroller.analysis.criticality.lines import on_line, region
from rocknroller.analysis.model.kinematics import rates_from_omega
from rocknroller.analysis.routh.reduction import u_ends

if TYPE_CHECKING:  # pragma: no cover
    from rocknroller.numerics.trajectory import Trajectory

__all__ = ["TurningPointRegion", "Crossing", "ReversalAnalysis", "reversal_analysis"]


# ----------------------------------------------------------------------------- reversal analysis
@dataclass(frozen=True)
class TurningPointRegion:
    """Turning points of a trajectory in time order with their region and the sign of φ̇ there."""

    t: NDArray[np.float64]
    kind: NDArray[np.str_]          # "max" (θ_X) or "min" (θ_N)
    theta: NDArray[np.float64]
    QR: NDArray[np.float64]
    QJ: NDArray[np.float64]
    region: NDArray[np.str_]
    phi_dot: NDArray[np.float64]
    phi_dot_sign: NDArray[np.int64]


@dataclass(frozen=True)
class Crossing:
    """A critical crossing between two consecutive turning points of the relevant kind (paper §Recession).

    ``line`` "0": Q_J,0^crit judged at the θ-minima (full-angle reversal); "pi": Q_J,π^crit judged at
    the θ-maxima (visible-angle reversal).
    """

    line: str
    kind: str
    t_before: float
    t_after: float
    region_before: str
    region_after: str


@dataclass(frozen=True)
class ReversalAnalysis:
    turning_points: TurningPointRegion
    crossings: list[Crossing]

    def count(self, line: str) -> int:
        """Number of crossings of one line ("0" or "pi")."""
        return sum(1 for c in self.crossings if c.line == line)


def reversal_analysis(traj: "Trajectory", tol: float = 0.0) -> ReversalAnalysis:
    """Regions and φ̇ signs at every turning point of a direct-ODE trajectory, and its critical crossings.

    Paper §Recession: the full angle reverses when Q_J − Q_J,0^crit changes sign between passages near θ_N
    (checked at consecutive θ-minima); the visible angle reverses when Q_J − Q_J,π^crit changes sign between
    passages near θ_X (checked at consecutive θ-maxima).  φ̇ at a turning point comes from the body-frame state
    (φ̇ = (γ1 ω1 + γ2 ω2)/s², :func:`rocknroller.analysis.model.kinematics.rates_from_omega`), not from V_φ.

    Parameters
    ----------
    traj : rocknroller.numerics.trajectory.Trajectory
    tol : float
        Passed to :func:`region`; a sample within tol of a line does not count as a side.

    Examples
    --------
    >>> import math
    >>> import rocknroller as rr
    >>> body = rr.Body.paper(epsilon=1e-3)
    >>> start = rr.EulerState.from_omega(0.95 * math.pi, 0.0, 0.0, (0.0, 1e-3, -1e-3))
    >>> traj = rr.simulate(body, start, 60.0)
    >>> rev = rr.reversal_analysis(traj)
    >>> print(*rev.turning_points.kind[:4], set(rev.turning_points.region.tolist()))
    min max min max {'II'}
    >>> print(rev.count("0"), rev.count("pi"))  # no crossing of either line within four rocks
    0 0
    """
    body = traj.paper_body
    parts = []
    for label, tp in (("max", traj.maxima), ("min", traj.minima)):
        omega = tp.states[:, 3:6].T
        phi_dot = rates_from_omega(tp.theta, tp.psi, omega)[1] if len(tp) else np.zeros(0)
        parts.append((np.full(len(tp), label), tp.t, tp.theta, tp.QR, tp.QJ, phi_dot))
    kind, t, th, QR, QJ, pd = (np.concatenate(v) for v in zip(*parts))
    order = np.argsort(t, kind="stable")
    kind, t, th, QR, QJ, pd = (v[order] for v in (kind, t, th, QR, QJ, pd))
    reg = np.asarray(region(QR, QJ, body, tol=tol)) if t.size else np.zeros(0, "<U11")
    tpr = TurningPointRegion(t=t, kind=kind, theta=th, QR=QR, QJ=QJ, region=np.atleast_1d(reg), phi_dot=pd,
                             phi_dot_sign=np.sign(pd).astype(np.int64))
    crossings: list[Crossing] = []
    for line, judged_at, name in (("0", "min", "full-angle reversal"), ("pi", "max", "visible-angle reversal")):
        idx = np.flatnonzero(kind == judged_at)
        if idx.size < 2:
            continue
        u = u_ends(QR[idx], QJ[idx], body)[0 if line == "0" else 1]
        side = np.where(on_line(u, QJ[idx], tol), 0, np.sign(u))
        prev = None
        for j, sgn in zip(idx, side):
            if sgn == 0:
                continue
            if prev is not None and sgn != prev[1]:
                crossings.append(Crossing(line=line, kind=name, t_before=float(t[prev[0]]), t_after=float(t[j]),
                                          region_before=str(tpr.region[prev[0]]),
                                          region_after=str(tpr.region[j])))
            prev = (j, sgn)
    crossings.sort(key=lambda c: c.t_after)
    return ReversalAnalysis(turning_points=tpr, crossings=crossings)
