"""Paper eq. (om2om3), steady circular rolling: the intermediate-frame system and the direct ODE keep θ fixed."""

from __future__ import annotations

import math

import numpy as np
import pytest
import roundoff as ro

from rocknroller.analysis.model.body import Body
from rocknroller.analysis.model.equations import EulerState, intermediate_frame_rhs
from rocknroller.analysis.routh.steady_rolling import steady_rolling_omega3
from rocknroller.numerics.integrate import simulate


@pytest.mark.parametrize("theta0", [0.4, 1.5, 2.5, 0.95 * math.pi])
@pytest.mark.parametrize("omega2", [0.7, -1.3])
def test_steady_rolling_is_an_equilibrium_of_form_iv(theta0, omega2):
    body = Body.paper()
    u3 = steady_rolling_omega3(body, theta0, omega2)
    d = intermediate_frame_rhs([theta0, 0.0, 0.0, 0.0, omega2, u3], body)
    # the residual of an exact equilibrium, from two stages: ω3' (≤ 20 rounded operations, γ_20 × its condition over
    # θ0, ω2' and the parameters, ``roundoff.formula_bound``) carried by |∂ω̇/∂ω3'| (central difference), and the
    # right-hand side (≤ 60 operations, γ_60 × its condition over θ, ω2', ω3' and the parameters); × 4 (margin)
    def body_of(a, I1, I3, g):
        return Body(a=a, I1=I1, I2=I1, I3=I3, g=g)

    params = {"a": body.a, "I1": body.I1, "I3": body.I3, "g": body.g}
    du3 = ro.formula_bound(lambda theta0, omega2, **p: steady_rolling_omega3(body_of(**p), theta0, omega2),
                           {"theta0": theta0, "omega2": omega2, **params}, 20)
    def rhs(theta, u2, u3, **p):
        return intermediate_frame_rhs([theta, 0.0, 0.0, 0.0, u2, u3], body_of(**p))[3:]

    h = 1e-7 * abs(u3)
    carried = np.abs(rhs(theta0, omega2, u3 + h, **params) - rhs(theta0, omega2, u3 - h, **params)) / (2 * h) * du3
    bound = 4 * (carried + ro.formula_bound(rhs, {"theta": theta0, "u2": omega2, "u3": u3, **params}, 60))
    ro.assert_within(d[3:], bound, "residual", 1 + abs(u3))
    # and a slightly wrong ω3' is not
    d = intermediate_frame_rhs([theta0, 0.0, 0.0, 0.0, omega2, u3 * (1 + 1e-6)], body)
    assert abs(d[3]) > 1e-9


def test_steady_rolling_in_the_direct_ode():
    body = Body.paper()
    theta0, omega2 = 2.0, 0.9
    u3 = steady_rolling_omega3(body, theta0, omega2)
    phi_dot = omega2 / math.sin(theta0)
    initial = EulerState(theta0, 0.0, 0.0, 0.0, phi_dot, u3 - math.cos(theta0) * phi_dot)
    traj = simulate(body, initial, 50.0)
    # θ stays put to n_steps × ε × A, A = the swing of θ (ptp over the run) per unit perturbation of the state at
    # heyoka's error level (θ0 by 1 rad, the rates by max(1, |ω|∞)), by central differences; plus the rounding
    # of θ = atan2(hypot(γ1, γ2), γ3) at two samples (≤ 1 + 4 ulp each); × 4 (margin)
    h, scale = 1e-7, max(1.0, float(np.abs(traj.omega).max()))
    amp = 0.0
    for k, s in enumerate((1.0, scale, scale, scale)):
        p = np.array([theta0, 0.0, phi_dot, initial.psi_dot])
        p[k] += h * s
        amp += np.ptp(simulate(body, EulerState(p[0], 0.0, 0.0, p[1], p[2], p[3]), 50.0).theta) / h
    bound = 4 * (ro.integration_bound(traj.n_steps, traj.tolerance, amp) + 2 * 5 * np.spacing(theta0))
    ro.assert_within(np.ptp(traj.theta), bound, "theta", theta0)


def test_bad_input():
    with pytest.raises(ValueError, match="theta0"):
        steady_rolling_omega3(Body.paper(), 0.0, 1.0)
    with pytest.raises(ValueError, match="omega2"):
        steady_rolling_omega3(Body.paper(), 1.0, 0.0)
    with pytest.raises(ValueError, match="symmetric"):
        steady_rolling_omega3(Body.paper(1e-3), 1.0, 1.0)
