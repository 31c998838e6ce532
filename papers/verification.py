"""The verification table behind ``rocknroller verify``: each formula against an independent reference.

Every check returns a :class:`Check` with the measured error, the tolerance (set by the accuracy of
the method, not by the result) and the reference it was compared with.  The checks are small versions
of the acceptance tests, meant to let an installed copy verify itself in a few minutes.
"""

from __future__ import annotations

import math
from dataclasses import asdict, dataclass
from typing import Callable

import numpy as np

from analysis.body import Body
from numerics.equations import EulerState

__all__ = ["Check", "CHECKS", "run_checks"]


@dataclass(frozen=True)
class Check:
    """One row of the verification table."""

    group: str
    name: str
    reference: str
    error: float
    tolerance: float

    @property
    def passed(self) -> bool:
        return bool(np.isfinite(self.error) and self.error <= self.tolerance)

    def as_dict(self) -> dict:
        return {**asdict(self), "passed": self.passed}


def _fig5_initial() -> EulerState:
    return EulerState.from_omega(0.95 * math.pi, 0.0, 0.0, (0.0, 0.001, -0.001))


# ------------------------------------------------------------------------------------------- ODE
def check_formulations() -> list[Check]:
    from numerics.equations import (body_frame_rhs, euler_angle_rhs, euler_angle_state_from_body,
                                    intermediate_frame_rhs, intermediate_state_from_euler_angle, state_from_euler)

    rng = np.random.default_rng(5)
    n = 200
    Y = state_from_euler(rng.uniform(0.05, math.pi - 0.05, n), rng.uniform(-3, 3, n), rng.uniform(-3, 3, n),
                         *rng.normal(scale=2.0, size=(3, n)))
    out = []
    for label, body in (("asymmetric eps=0.1", Body.paper(0.1)), ("symmetric", Body.paper())):
        D = np.array(body_frame_rhs(Y, body.params))
        err = 0.0
        for y, d in zip(Y.T, D.T):
            x2 = euler_angle_state_from_body(y)
            err = max(err, np.max(np.abs(euler_angle_rhs(x2, body)[3:] - d[3:6])) / (1 + np.max(np.abs(d[3:6]))))
        out.append(Check("equations", f"paper Euler-angle system (ii), {label}", "body-frame form (i)", err, 2e-13))
    body = Body.paper()
    D = np.array(body_frame_rhs(Y, body.params))
    err = 0.0
    for y, d in zip(Y.T, D.T):
        x4 = intermediate_state_from_euler_angle(euler_angle_state_from_body(y))
        d4 = intermediate_frame_rhs(x4, body)
        _, _, ps, u1, u2, _ = x4
        sg, ch = math.sin(ps), math.cos(ps)
        wdot = np.array([ch * d4[3] + sg * d4[4] + d4[2] * (-sg * u1 + ch * u2),
                         -sg * d4[3] + ch * d4[4] + d4[2] * (-ch * u1 - sg * u2), d4[5]])
        err = max(err, np.max(np.abs(wdot - d[3:6])) / (1 + np.max(np.abs(d[3:6]))))
    out.append(Check("equations", "paper intermediate-frame system (iv)", "body-frame form (i)", err, 2e-13))
    return out


def check_integrators() -> list[Check]:
    from numerics.integrate import simulate

    body = Body.paper(1e-3)
    ini = _fig5_initial()
    hy = simulate(body, ini, 100.0)
    sc = simulate(body, ini, 100.0, method="scipy")
    ext = simulate(body, ini, 100.0, precision="extended")
    long = simulate(body, ini, 1500.0)
    return [
        Check("ODE", "heyoka state over 100 time units", "scipy DOP853", float(np.max(np.abs(hy.states - sc.states))),
              1e-9),
        Check("ODE", "times of the first 5 theta-maxima", "heyoka in 80-bit long double",
              float(np.max(np.abs(hy.maxima.t[:5] - ext.maxima.t[:5]))), 1e-11),
        Check("ODE", "relative energy error, fig-5 run (1500 t.u.)", "E(0)", long.energy_rel_error, 1e-13),
    ]


def check_small_amplitude() -> list[Check]:
    from papers.lynch_bustamante.table_small_amplitude import linear_frequency, measured_frequency

    body = Body.paper(1e-3)
    err = abs(measured_frequency(body, 0.0) / linear_frequency(body, body.I1) - 1.0)
    return [Check("ODE", "small-amplitude frequency sqrt(ga/(I1+(1-a)^2))", "direct ODE, amplitude 1e-3", err, 1e-5)]


# ------------------------------------------------------------------------------------ quadrature
def _symmetric_run(theta0: float, QR: float, QJ: float, t_end: float = 60.0):
    from analysis.reduction import state_from_turning_point
    from numerics.integrate import simulate

    body = Body.paper()
    st = state_from_turning_point(body, theta0, QR, QJ)
    return body, simulate(body, EulerState(theta0, 0.0, 0.3, 0.0, float(st.phi_dot), float(st.psi_dot)), t_end)


def check_reduction_and_quadrature() -> list[Check]:
    from analysis.invariants import invariants
    from analysis.quadrature import precession, precession_mp
    from analysis.reduction import F, turning_points
    from numerics.equations import euler_from_state

    out = []
    # a passage close to the vertical, and a maximum close to θ = π
    for theta0, QR, QJ in ((0.95 * math.pi, 1e-4, 6.3e-5), (math.pi - 5e-4, 2e-3, 0.01)):
        body, traj = _symmetric_run(theta0, QR, QJ)
        E, qr, qj = (float(v) for v in invariants(body, traj.gamma[:, 0], traj.omega[:, 0]))
        tp = turning_points(E, qr, qj, body)
        label = f"theta_N={float(tp[0]):.1e}, pi-theta_X={math.pi - float(tp[1]):.1e}"
        rates = euler_from_state(traj.states.T)
        thd2 = rates[3] ** 2
        Fv = F(traj.theta, E, qr, qj, body)
        inner = (traj.theta > 1e-3) & (traj.theta < math.pi - 1e-3)
        out.append(Check("reduction", f"F(theta) = theta_dot^2 along the ODE ({label})", "direct ODE",
                         float(np.max(np.abs(Fv - thd2)[inner]) / np.max(thd2)), 1e-11))
        out.append(Check("reduction", f"turning points theta_N, theta_X ({label})", "direct ODE events",
                         float(max(np.max(np.abs(traj.maxima.theta - tp[1])), np.max(np.abs(traj.minima.theta - tp[0])))),
                         1e-9))
        pr = precession(E, qr, qj, body)
        T_ode = np.diff(traj.maxima.t)
        out.append(Check("quadrature", f"T_theta ({label})", "spacing of ODE maxima",
                         float(np.max(np.abs(T_ode / float(pr.T_theta) - 1))), 1e-10))
        out.append(Check("quadrature", f"delta_phi, delta_psi per T_theta ({label})", "ODE unwrapped increments",
                         float(max(np.max(np.abs(np.diff(traj.maxima.phi) - float(pr.delta_phi))),
                                   np.max(np.abs(np.diff(traj.maxima.psi) - float(pr.delta_psi))))), 1e-9))
        ref = precession_mp(E, qr, qj, body, dps=40)
        err = max(abs(float(getattr(pr, k)) / float(getattr(ref, k)) - 1) for k in ("T_theta", "delta_phi", "delta_psi"))
        out.append(Check("quadrature", f"double-precision rule ({label})", "mpmath, 40 digits", err, 2e-13))
    return out


# ------------------------------------------------------------------------------------- averaging
def check_averaging() -> list[Check]:
    """Averaged map and pendulum closed form against the direct ODE (θ0 = 0.95π, ψ0 = π/4, at rest).

    Tolerances: the first-order map's error is O(ε) (docs/averaging.md): ≤ 5e-3 at ε = 1e-2 is the
    acceptance bound, and 5e-4 at ε = 1e-3; the closed form is first order in K = εκ with larger
    constants: 1e-2 on the slow period at ε = 1e-4.
    """
    from analysis.averaging import load_or_build_table
    from analysis.slow_pendulum import pendulum_constants
    from papers.averaging_check import compare_with_ode

    theta0, psi0, t_end = 0.95 * math.pi, math.pi / 4, 1000.0
    out = []
    for eps, tol in ((1e-2, 5e-3), (1e-3, 5e-4)):
        body = Body.paper(eps)
        cmp = compare_with_ode(body, theta0, psi0, t_end, table=load_or_build_table(body, theta0),
                               constants=pendulum_constants(body, theta0))
        for key in ("slow_period", "QR_extent", "Phi"):
            out.append(Check("averaging", f"averaged map: {key}, eps={eps:g}, psi0=pi/4", "direct ODE",
                             abs(cmp.map_errors[key]), tol))
    body = Body.paper(1e-4)
    cmp = compare_with_ode(body, theta0, psi0, 3000.0, table=load_or_build_table(body, theta0),
                           constants=pendulum_constants(body, theta0))
    out.append(Check("averaging", "pendulum closed form: slow period, eps=1e-4, psi0=pi/4", "direct ODE",
                     abs(cmp.pendulum_errors["slow_period"]), 1e-2))
    return out


CHECKS: tuple[Callable[[], list[Check]], ...] = (
    check_formulations,
    check_integrators,
    check_small_amplitude,
    check_reduction_and_quadrature,
    check_averaging,
)


def run_checks(progress: Callable[[str], None] | None = None) -> list[Check]:
    """Run every check group in :data:`CHECKS`; ``progress`` is called with each group's name."""
    rows: list[Check] = []
    for fn in CHECKS:
        if progress is not None:
            progress(fn.__name__)
        rows.extend(fn())
    return rows
