"""rocknroller: Routh's sphere and the rock'n'roller.

Public API re-exported from ``analysis`` and ``numerics`` (no physics lives here)::

    from rocknroller import Body, EulerState, simulate
"""

from analysis.body import Body
from numerics.equations import EulerState
from numerics.integrate import simulate
from numerics.trajectory import Trajectory, TurningPoints, azimuth_span

__all__ = ["Body", "EulerState", "simulate", "Trajectory", "TurningPoints", "azimuth_span"]
__version__ = "0.1.0"
