"""rocknroller: Routh's sphere and the rock'n'roller.

Public API re-exported from ``analysis`` and ``numerics`` (no physics lives here)::

    from rocknroller import Body, EulerState, simulate
"""

from rocknroller._version import __version__
from rocknroller.citation import cite
from analysis.averaging import predict_slow_motion
from analysis.body import Body
from analysis.quadrature import precession, precession_mp
from analysis.reduction import F, turning_points
from analysis.slow_diagnostics import azimuth_span
from analysis.slow_pendulum import pendulum_constants, pendulum_prediction
from numerics.equations import EulerState
from numerics.integrate import simulate
from numerics.trajectory import Trajectory, TurningPoints

__all__ = [
    "__version__", "cite", "Body", "EulerState", "simulate", "Trajectory", "TurningPoints", "azimuth_span",
    "F", "turning_points", "precession", "precession_mp",
    "predict_slow_motion", "pendulum_constants", "pendulum_prediction",
]
