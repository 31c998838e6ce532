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

from rocknroller.analysis.model.body import Body
from rocknroller.analysis.model.equations import EulerState
from rocknroller.papers.averaging_check import loglog_slope
from rocknroller.analysis.model.equations import fig5_start

__all__ = [
    "Check", "CHECKS", "run_checks", "check_formulations", "check_integrators", "check_small_amplitude",
    "check_reduction_and_quadrature", "check_criticality", "check_averaging"
]


@dataclass(frozen=True)
class Check:
    """One row of the verification table: it passes when ``error <= tolerance``, or, for a row that shows a
    formula to be wrong (``must_exceed``), when ``error > tolerance``."""

    group: str
    name: str
    reference: str
    error: float
    tolerance: float
    must_exceed: bool = False

    @property
    def passed(self) -> bool:
        if not np.isfinite(self.error):
            return False
        return bool(self.error > self.tolerance if self.must_exceed else self.error <= self.tolerance)

    @property
    def bound(self) -> str:
        """The condition on the error, as the table prints it: ``<= 2.0e-13``, or ``> 1.0e-02`` for a formula
        shown wrong."""
        return f"{'>' if self.must_exceed else '<='} {self.tolerance:.1e}"

    def as_dict(self) -> dict:
        return {**asdict(self), "passed": self.passed}


# ------------------------------------------------------------------------------------------- ODE
def check_formulations() -> list[Check]:
    """Paper systems (ii), (iii) and (iv) against the body-frame form (i): the largest scaled difference
    in ω̇ over 200 random states, for the body at ε = 0.1 and the symmetric body (tolerance 2e-13)."""
    from rocknroller.analysis.model.equations import formulation_differences, state_from_euler

    rng = np.random.default_rng(5)
    n = 200
    Y = state_from_euler(rng.uniform(0.05, math.pi - 0.05, n), rng.uniform(-3, 3, n), rng.uniform(-3, 3, n),
                         *rng.normal(scale=2.0, size=(3, n)))
    names = {"ii": "paper Euler-angle system (ii)", "iii": "paper Euler-Lagrange system (iii)",
             "iv": "paper intermediate-frame system (iv)"}
    out = []
    for label, body in (("asymmetric eps=0.1", Body.paper(0.1)), ("symmetric", Body.paper())):
        for form, err in formulation_differences(Y, body).items():
            out.append(Check("equations", f"{names[form]}, {label}", "body-frame form (i)", err, 2e-13))
    return out


def check_integrators() -> list[Check]:
    """The default integrator (heyoka) from the fig. 5 start, ε = 1e-3: the state over 100 time units against
    scipy DOP853, the first five θ-maxima times against 80-bit long double, and the relative energy error over 1500."""
    from rocknroller.numerics.integrate import simulate

    body = Body.paper(1e-3)
    ini = fig5_start()
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
    """The small-amplitude frequency √(ga/(I1 + (1 − a)²)) (ε = 1e-3) against the direct ODE at amplitude
    1e-3 (relative error, tolerance 1e-5)."""
    from rocknroller.analysis.routh.rocking import small_amplitude_frequency
    from rocknroller.analysis.routh.rocking import measured_frequency

    body = Body.paper(1e-3)
    err = abs(measured_frequency(body, 0.0) / small_amplitude_frequency(body, body.I1) - 1.0)
    return [Check("ODE", "small-amplitude frequency sqrt(ga/(I1+(1-a)^2))", "direct ODE, amplitude 1e-3", err, 1e-5)]


# ------------------------------------------------------------------------------------ quadrature
def _symmetric_run(theta0: float, QR: float, QJ: float, t_end: float = 60.0):
    from rocknroller.analysis.routh.reduction import state_from_turning_point
    from rocknroller.numerics.integrate import simulate

    body = Body.paper()
    st = state_from_turning_point(body, theta0, QR, QJ)
    return body, simulate(body, EulerState(theta0, 0.0, 0.3, 0.0, float(st.phi_dot), float(st.psi_dot)), t_end)


def check_reduction_and_quadrature() -> list[Check]:
    """On two symmetric-body ODE runs (a passage near the vertical, a maximum near θ = π): F(θ) = θ̇², the
    turning points θ_N, θ_X, and the quadrature's T_θ, Δφ, Δψ against the ODE; the double-precision rule against
    mpmath at 40 digits."""
    from rocknroller.analysis.model.equations import euler_from_state
    from rocknroller.analysis.model.invariants import invariants
    from rocknroller.analysis.routh.quadrature import precession
    from rocknroller.analysis.routh.quadrature_mp import precession_mp
    from rocknroller.analysis.routh.reduction import F
    from rocknroller.analysis.routh.turning_points import turning_points

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


# ----------------------------------------------------------------------------------- criticality
def check_criticality() -> list[Check]:
    """Critical lines, regions, cos θ_z, the δ expansion, the Laurent series and critical-line starts."""
    from scipy.optimize import brentq

    from rocknroller.analysis.criticality import lines as C
    from rocknroller.analysis.criticality import starts, theta_z
    from rocknroller.analysis.criticality.laurent import laurent_function
    from rocknroller.analysis.model.invariants import V_phi

    body = Body.paper()
    rng = np.random.default_rng(17)
    out = []
    # regions from the critical lines against the signs of V_φ next to θ = 0 and θ = π
    QR, QJ = rng.uniform(-1, 1, 500), rng.uniform(-0.4, 0.4, 500)
    near0, nearpi = np.sign(V_phi(1e-6, QR=QR, QJ=QJ, body=body)), np.sign(V_phi(math.pi - 1e-6, QR=QR, QJ=QJ, body=body))
    expected = np.select([(near0 < 0) & (nearpi > 0), (near0 > 0) & (nearpi > 0), (near0 > 0) & (nearpi < 0)],
                         ["I", "II", "III"], "IV")
    out.append(Check("criticality", "region I-IV from the critical lines (500 random points)",
                     "signs of V_phi at theta = 1e-6 and pi - 1e-6",
                     float(np.mean(C.region(QR, QJ, body) != expected)), 0.0))
    # corrected cos θ_z against the numeric zero of V_φ
    t = rng.uniform(0, 1, 200)
    QR = rng.uniform(-1, 1, 200)
    QJ = C.QJ_crit_pi(QR, body) + t * (C.QJ_crit_0(QR, body) - C.QJ_crit_pi(QR, body))
    roots = np.array([math.cos(brentq(lambda th: float(V_phi(th, QR=r, QJ=j, body=body)), 1e-9, math.pi - 1e-9, xtol=1e-16,
                                      rtol=4 * np.finfo(float).eps)) for r, j in zip(QR, QJ)])
    out.append(Check("criticality", "cos(theta_z), corrected closed form (200 points in Regions I, III)",
                     "Brent root of V_phi", float(np.max(np.abs(theta_z.cos_theta_z(QR, QJ, body) - roots))), 1e-12))
    out.append(Check("criticality", "cos(theta_z) as printed in the paper, a misprint: its error must exceed 0.01",
                     "Brent root of V_phi",
                     float(np.max(np.abs(theta_z.cos_theta_z_printed(QR, QJ, body) - roots))), 0.01, must_exceed=True))
    # δ expansion of θ_z near Q_J = Q_J,π^crit (1 − δ): error powers 3/2 (one term) and 5/2 (two terms)
    deltas = np.array([1e-2, 3e-3, 1e-3, 3e-4])
    QR1 = 0.01
    exact = theta_z.theta_z(QR1, C.QJ_crit_pi(QR1, body) * (1 - deltas), body)
    for terms, power in ((1, 1.5), (2, 2.5)):
        err = np.abs(theta_z.theta_z_expansion(deltas, body, terms=terms) - exact)
        out.append(Check("criticality", f"delta expansion of theta_z, {terms} term(s): error power {power}",
                         "closed-form theta_z, fitted log-log slope", abs(loglog_slope(deltas, err) - power), 0.1))
    # Laurent series about θ = π truncated at order 2: error falls as x⁴
    xs = np.array([0.2, 0.1, 0.05, 0.025])
    fn = laurent_function("phi", "pi", 2, body)
    err = np.abs(fn(xs, QR=-0.0456, QJ=0.0123) - V_phi(math.pi - xs, QR=-0.0456, QJ=0.0123, body=body))
    out.append(Check("criticality", "Laurent series of V_phi about pi to order 2: error power 4",
                     "V_phi, fitted log-log slope", abs(loglog_slope(xs, err) - 4.0), 0.1))
    # starts placed on the critical lines
    worst = 0.0
    for line, crit in (("pi", C.QJ_crit_pi), ("0", C.QJ_crit_0)):
        cs = starts.critical_start(Body.paper(1e-3), 0.95 * math.pi, math.pi / 4, line, QR=rng.uniform(-0.01, 0.01, 50))
        worst = max(worst, float(np.max(np.abs(cs.QJ / crit(cs.QR, body) - 1))))
    out.append(Check("criticality", "initial states placed on the critical lines (100 starts)",
                     "Q_J^crit(Q_R) of the start", worst, 1e-14))
    return out


# ------------------------------------------------------------------------------------- averaging
def _abs_error(error: float | None) -> float:
    """|error|, or NaN (a failed check) for a quantity not measurable on one side (a relative error of None)."""
    return math.nan if error is None else abs(error)


def check_averaging() -> list[Check]:
    """Averaged map and pendulum closed form against the direct ODE (θ0 = 0.95π, ψ0 = π/4, at rest).

    Tolerances: the first-order map's error is O(ε) (docs/averaging.md): ≤ 5e-3 at ε = 1e-2 is the
    acceptance bound, and 5e-4 at ε = 1e-3; the closed form is first order in K = εκ with larger
    constants: 1e-2 on the slow period at ε = 1e-4.
    """
    from rocknroller.analysis.slow.dynamics.pendulum import pendulum_constants
    from rocknroller.analysis.slow.prediction import load_or_build_table
    from rocknroller.papers.averaging_check import compare_with_ode

    theta0, psi0, t_end = 0.95 * math.pi, math.pi / 4, 1000.0
    out = []
    for eps, tol in ((1e-2, 5e-3), (1e-3, 5e-4)):
        body = Body.paper(eps)
        cmp = compare_with_ode(body, theta0, psi0, t_end, table=load_or_build_table(body, theta0),
                               constants=pendulum_constants(body, theta0))
        for key in ("slow_period", "QR_extent", "Phi"):
            out.append(Check("averaging", f"averaged map: {key}, eps={eps:g}, psi0=pi/4", "direct ODE",
                             _abs_error(cmp.map_errors[key]), tol))
    body = Body.paper(1e-4)
    cmp = compare_with_ode(body, theta0, psi0, 3000.0, table=load_or_build_table(body, theta0),
                           constants=pendulum_constants(body, theta0))
    out.append(Check("averaging", "pendulum closed form: slow period, eps=1e-4, psi0=pi/4", "direct ODE",
                     _abs_error(cmp.pendulum_errors["slow_period"]), 1e-2))
    return out


CHECKS: tuple[Callable[[], list[Check]], ...] = (
    check_formulations,
    check_integrators,
    check_small_amplitude,
    check_reduction_and_quadrature,
    check_criticality,
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
