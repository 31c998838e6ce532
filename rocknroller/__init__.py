"""rocknroller: Routh's sphere and the rock'n'roller.

Public API re-exported from ``analysis`` and ``numerics`` (no physics lives here)::

    from rocknroller import Body, EulerState, simulate
"""

from rocknroller._version import __version__
from rocknroller.citation import cite
from rocknroller.analysis.averaging import predict_slow_motion
from rocknroller.analysis.body import Body
from rocknroller.analysis.quadrature import precession, precession_mp
from rocknroller.analysis.reduction import F, turning_points
from rocknroller.analysis.slow_diagnostics import azimuth_span
from rocknroller.analysis.slow_pendulum import pendulum_constants, pendulum_prediction
from rocknroller.numerics.equations import EulerState
from rocknroller.numerics.integrate import simulate
from rocknroller.numerics.trajectory import Trajectory, TurningPoints

__all__ = [
    "__version__", "cite", "Body", "EulerState", "simulate", "Trajectory", "TurningPoints", "azimuth_span",
    "F", "turning_points", "precession", "precession_mp",
    "predict_slow_motion", "pendulum_constants", "pendulum_prediction",
]
