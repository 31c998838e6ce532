"""Paper eq. (om2om3), steady circular rolling: the intermediate-frame system and the direct ODE keep θ fixed."""

from __future__ import annotations

import math

import numpy as np
import pytest

from rocknroller.analysis.body import Body
from rocknroller.analysis.steady_rolling import steady_rolling_omega3
from rocknroller.numerics.equations import EulerState, intermediate_frame_rhs
from rocknroller.numerics.integrate import simulate


@pytest.mark.parametrize("theta0", [0.4, 1.5, 2.5, 0.95 * math.pi])
@pytest.mark.parametrize("omega2", [0.7, -1.3])
def test_steady_rolling_is_an_equilibrium_of_form_iv(theta0, omega2):
    body = Body.paper()
    u3 = steady_rolling_omega3(body, theta0, omega2)
    d = intermediate_frame_rhs([theta0, 0.0, 0.0, 0.0, omega2, u3], body)
    assert np.max(np.abs(d[3:])) < 1e-14 * (1 + abs(u3))
    # and a slightly wrong ω3' is not
    d = intermediate_frame_rhs([theta0, 0.0, 0.0, 0.0, omega2, u3 * (1 + 1e-6)], body)
    assert abs(d[3]) > 1e-9


def test_steady_rolling_in_the_direct_ode():
    body = Body.paper()
    theta0, omega2 = 2.0, 0.9
    u3 = steady_rolling_omega3(body, theta0, omega2)
    phi_dot = omega2 / math.sin(theta0)
    traj = simulate(body, EulerState(theta0, 0.0, 0.0, 0.0, phi_dot, u3 - math.cos(theta0) * phi_dot), 50.0)
    assert np.ptp(traj.theta) < 1e-12


def test_bad_input():
    with pytest.raises(ValueError, match="theta0"):
        steady_rolling_omega3(Body.paper(), 0.0, 1.0)
    with pytest.raises(ValueError, match="omega2"):
        steady_rolling_omega3(Body.paper(), 1.0, 0.0)
    with pytest.raises(ValueError, match="symmetric"):
        steady_rolling_omega3(Body.paper(1e-3), 1.0, 1.0)
