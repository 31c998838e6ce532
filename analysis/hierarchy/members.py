"""The four members of the loaded-sphere family (paper fig. 1, §2), one representative body and start each, and the
quantities whose conservation the hierarchy examines (Borisov & Mamaev 2002).

Every representative is a :class:`~rocknroller.analysis.model.body.LoadedSphere`, so that all four run the same
general equations and are measured by the same formulas; their moments and offsets are the paper's body's where the
member allows (I3 = 0.4, I1 = 0.35, |c| = 0.05 along the third axis) and generic where it does not.
"""

from __future__ import annotations

import math
from typing import Any, Callable

from rocknroller.analysis.model.body import MEMBERS, PAPER_G, LoadedSphere
from rocknroller.analysis.model.equations import EulerState
from rocknroller.analysis.model.invariants import (borisov_mamaev, energy, momentum_along_offset_line,
                                                   momentum_squared, momentum_vertical, routh_on_axis)

__all__ = ["VALUES", "member_body", "member_start", "MEMBER_BODIES"]

#: One representative body per member, in the order of ``MEMBERS`` (ball, rock'n'roller, Routh's sphere, top).
MEMBER_BODIES: dict[str, LoadedSphere] = {
    MEMBERS[0]: LoadedSphere(0.35, 0.37, 0.4, (0.0, 0.0, 0.0), PAPER_G),
    MEMBERS[1]: LoadedSphere(0.35, 0.36, 0.4, (0.0, 0.0, -0.05), PAPER_G),
    MEMBERS[2]: LoadedSphere(0.35, 0.35, 0.4, (0.0, 0.0, -0.05), PAPER_G),
    MEMBERS[3]: LoadedSphere(0.35, 0.37, 0.4, (0.03, -0.02, -0.04), PAPER_G),
}


def member_body(kind: str, g: float | None = None) -> LoadedSphere:
    """The representative body of the member ``kind`` (one of ``MEMBERS``), with gravity ``g`` if given.

    Examples
    --------
    >>> from rocknroller.analysis.hierarchy.members import member_body
    >>> print(member_body("Chaplygin's top").kind, member_body("Routh's sphere", g=0.0).g)
    Chaplygin's top 0.0
    """
    if kind not in MEMBER_BODIES:
        raise ValueError(f"kind must be one of {list(MEMBER_BODIES)}, got {kind!r}")
    body = MEMBER_BODIES[kind]
    return body if g is None else LoadedSphere(body.I1, body.I2, body.I3, body.offset, g)


def member_start() -> EulerState:
    """The start every member is measured from: tilted (θ0 = 0.6π) and spinning about all three axes, so that no
    quantity starts at zero and no symmetry of the start hides a drift.

    Examples
    --------
    >>> from rocknroller.analysis.hierarchy.members import member_start
    >>> print(member_start().omega)
    (0.7, -0.5, 1.3)
    """
    return EulerState.from_omega(0.6 * math.pi, 0.0, 0.4, (0.7, -0.5, 1.3))


#: The numeric formula of each quantity of :data:`~rocknroller.analysis.hierarchy.conservation.QUANTITIES`, by its
#: name, vectorised on body-frame states like :mod:`rocknroller.analysis.model.invariants` (Routh's Q_R itself where
#: the proof takes Q_R²; Borisov and Mamaev's B with and without gravity alike).
VALUES: dict[str, Callable[[Any, Any, Any], Any]] = {
    "energy": energy,
    "jellett": momentum_along_offset_line,
    "routh": routh_on_axis,
    "momentum_squared": momentum_squared,
    "momentum_vertical": momentum_vertical,
    "borisov_mamaev_g0": borisov_mamaev,
    "borisov_mamaev": borisov_mamaev,
}
