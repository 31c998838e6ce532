"""Reduction θ̇² = F(θ) of Routh's sphere: symbolic proof, consistency with the invariants, turning points."""

from __future__ import annotations

import re
from types import SimpleNamespace

import mpmath
import numpy as np
import pytest
import roundoff as ro
import sympy as sp

from rocknroller.analysis.criticality.lines import QJ_crit_0, QJ_crit_pi
from rocknroller.analysis.model.body import Body
from rocknroller.analysis.model.invariants import V_phi
from rocknroller.analysis.routh.quadrature_mp import _mp_body, _mp_terms, turning_points_mp
from rocknroller.analysis.routh.reduction import (NO_MOTION, OK, STEADY, D_coefficient, F, NoMotionError,
                                                  SteadyRollingError, effective_potential, invariants_from_euler,
                                                  potential, reduced_N, reduced_P, state_from_turning_point, tilt_xy,
                                                  u_ends, u_numerator)
from rocknroller.analysis.routh.turning_points import solve_turning_points, turning_points

EPS = np.finfo(float).eps
#: Safety margin of the rounding bounds below.
MARGIN = 4.0


def _sym(a, I1, I3, g):
    return Body(a=float(a), I1=float(I1), I2=float(I1), I3=float(I3), g=float(g))


# ----------------------------------------------------------------------------- symbolic
def test_F_derived_symbolically_from_energy_and_invariants():
    """Derive F from E = T + V with v = ω × r, ω3' = ρ Q_R and Jellett's Q_J, and compare with the code.

    ρ = 1/R is kept as a symbol (the reduction is algebraic in it) and s² = 1 − c² is imposed at the end.
    """
    c, s, R, thd, E, QR, QJ = sp.symbols("c s R thetadot E Q_R Q_J", real=True)
    a, I1, I3, g = sp.symbols("a I1 I3 g", positive=True)
    f = c - a
    w3 = QR / R  # ω3' = ρ Q_R, paper eq. routh
    w2 = (QJ - I3 * f * w3) / (I1 * s)  # paper eq. jellett solved for ω2'
    w = sp.Matrix([thd, w2, w3])
    r = sp.Matrix([0, s, f])
    v = w.cross(r)  # paper eq. constraint
    T = v.dot(v) / 2 + (I1 * thd**2 + I1 * w2**2 + I3 * w3**2) / 2
    energy = sp.expand(T + g * a * (1 - c))

    def on_circle(expr):
        num, den = sp.fraction(sp.together(expr))
        return sp.expand(sp.expand(num).subs(s**2, 1 - c**2)), den

    assert on_circle(energy.coeff(thd, 1))[0] == 0  # no cross term: E = ½ D θ̇² + U
    D_sym = 2 * energy.coeff(thd, 2)
    U_sym = energy.coeff(thd, 0)
    F_sym = 2 * (E - U_sym) / D_sym

    body = SimpleNamespace(a=a, I1=I1, I3=I3, g=g)
    x, y = 1 - c, 1 + c
    u = QJ - I3 * QR * f / R
    N = reduced_N(x * y, f, R, u, QR, body)
    P = reduced_P(x * y, E - potential(x, body), N)
    F_code = P / (x * y * D_coefficient(x, body))
    assert on_circle(D_sym - D_coefficient(x, body))[0] == 0
    assert on_circle(F_sym - F_code)[0] == 0
    # and the test can fail: a wrong potential sign is detected
    P_bad = reduced_P(x * y, E + potential(x, body), N)
    assert on_circle(F_sym - P_bad / (x * y * D_coefficient(x, body)))[0] != 0


@pytest.mark.parametrize("end", ["zero", "pi"])
def test_cancellation_free_u_is_an_identity(end):
    """f_e ρ_e − f ρ = ±z [I3 (f_e + f) + f_e² (2 − z)] / [R R_e (f_e R + f R_e)], z = x or y.

    Since f_e ρ_e − f ρ = (f_e R − f R_e)/(R R_e) = (f_e² R² − f² R_e²)/(R R_e (f_e R + f R_e)), it is
    the polynomial identity f_e² R² − f² R_e² = ±z [...] with R² = I3 + s² + (I3/I1) f², s² = z (2 − z).
    """
    z, a, I1, I3 = sp.symbols("z a I1 I3", positive=True)
    k = I3 / I1
    if end == "zero":
        fe, f, sign = 1 - a, 1 - a - z, 1
    else:
        fe, f, sign = -(1 + a), z - 1 - a, -1
    R2 = I3 + z * (2 - z) + k * f**2
    Re2 = I3 + k * fe**2
    num = z * (sign * I3 * (fe + f) + fe**2 * (2 - z))
    assert sp.expand(fe**2 * R2 - f**2 * Re2 - num) == 0
    assert sp.expand(fe**2 * R2 - f**2 * Re2 + num) != 0  # the sign matters: the check can fail


# ----------------------------------------------------------------------------- numeric consistency
def test_F_equals_theta_dot_squared_of_random_states():
    """(E, Q_R, Q_J) of random Euler states through rocknroller.analysis.model.invariants: F(θ) = θ̇² to round-off."""
    rng = np.random.default_rng(3)
    body = Body.paper()
    n = 2000
    theta = rng.uniform(0.05, np.pi - 0.05, n)
    thd, phd, psd = rng.normal(size=(3, n))
    E, QR, QJ = invariants_from_euler(body, theta, thd, phd, psd)
    F_val = F(theta, E, QR, QJ, body)
    # two stages: (E, Q_R, Q_J) from the Euler state (≤ 60 rounded operations: the frame, ω, E, Q_R, Q_J), each
    # within γ_60 × its condition over θ, the rates and the parameters (``roundoff.formula_bound``); then F (≤ 40
    # operations, γ_40 × its condition over θ, E, Q_R, Q_J and the parameters: it measures E − U), to which the
    # first stage's errors are carried by |∂F/∂E|, |∂F/∂Q_R|, |∂F/∂Q_J| (central differences); × MARGIN
    params = {"a": body.a, "I1": body.I1, "I3": body.I3, "g": body.g}
    stage1 = ro.formula_bound(lambda theta, thd, phd, psd, a, I1, I3, g: np.array(
        invariants_from_euler(_sym(a, I1, I3, g), theta, thd, phd, psd)),
        {"theta": theta, "thd": thd, "phd": phd, "psd": psd, **params}, 60)
    F_of = lambda theta, E, QR, QJ, a, I1, I3, g: F(theta, E, QR, QJ, _sym(a, I1, I3, g))  # noqa: E731
    args = {"theta": theta, "E": E, "QR": QR, "QJ": QJ, **params}
    carried = 0.0
    for k, name in enumerate(("E", "QR", "QJ")):
        h = 1e-7 * np.maximum(np.abs(args[name]), 1e-300)
        up, down = dict(args), dict(args)
        up[name], down[name] = args[name] + h, args[name] - h
        carried = carried + np.abs(F_of(**up) - F_of(**down)) / (2 * h) * stage1[k]
    bound = MARGIN * (carried + ro.formula_bound(F_of, args, 40))
    ro.assert_within(F_val - thd**2, bound, "F", thd**2)


def test_u_numerator_matches_V_phi_and_mpmath():
    """u = I1 s² V_φ (rocknroller.analysis.model.invariants.V_phi); near the ends against 50-digit mpmath."""
    rng = np.random.default_rng(4)
    body = Body.paper()
    theta = rng.uniform(0.1, 3.0, 500)
    QR, QJ = rng.normal(scale=0.01, size=(2, 500))
    x, y = tilt_xy(theta)
    u = u_numerator(x, y, QR, QJ, body)
    ref = body.I1 * np.sin(theta) ** 2 * V_phi(theta, QR=QR, QJ=QJ, body=body)
    # two evaluations of u = Q_J − I3 f ρ Q_R (≤ 25 rounded operations each, V_φ's path with sin, cos, √ and the
    # product and quotient by I1 s²), γ_50 × the condition over θ, Q_R, Q_J and the parameters, × MARGIN
    def direct(theta, QR, QJ, a, I1, I3):
        b = _sym(a, I1, I3, body.g)
        return b.I1 * np.sin(theta) ** 2 * V_phi(theta, QR=QR, QJ=QJ, body=b)

    bound = MARGIN * ro.formula_bound(direct, {"theta": theta, "QR": QR, "QJ": QJ, "a": body.a, "I1": body.I1,
                                               "I3": body.I3}, 50)
    ro.assert_within(u - ref, bound, "u", ref)
    # Near the ends u = u_e + (variation): the variation keeps its relative precision down to z = 1e-20,
    # so u is a smooth function of θ (the fixed rounding of u_e = Q_J − Q_J,e^crit is shared by all θ).
    for QJc, small_x in ((float(QJ_crit_0(0.01, body) + 1e-14), True),
                         (float(QJ_crit_pi(0.01, body) + 1e-14), False)):
        u_e = float(u_ends(0.01, QJc, body)[0 if small_x else 1])
        for z in (1e-20, 1e-12, 1e-6, 0.3):
            xx, yy = (z, 2 - z) if small_x else (2 - z, z)
            got = float(u_numerator(xx, yy, 0.01, QJc, body)) - u_e
            with mpmath.workdps(50):
                # the end values f_e = 1 − a, −(1 + a) as the code holds them (rounded once)
                fe = mpmath.mpf(1.0 - body.a) if small_x else mpmath.mpf(-(1.0 + body.a))
                X = mpmath.mpf(z) if small_x else 2 - mpmath.mpf(z)
                f = fe - X if small_x else fe + (2 - X)
                R = mpmath.sqrt(body.I3 + X * (2 - X) + body.I3 / body.I1 * f * f)
                Re = mpmath.sqrt(body.I3 + body.I3 / body.I1 * fe * fe)
                want = body.I3 * mpmath.mpf(0.01) * (fe / Re - f / R)
            # ... up to the rounding of u itself (ulp of u_e + variation, twice: u and u − u_e); the direct formula
            # errs by ε |Q_J|.  The variation x [I3 (f₀ + f) + f₀² y]/[R R₀ (f₀ R + f R₀)]: ≤ 16 rounded operations on
            # positive terms (two square roots), γ_16 relative
            bound = ro.gamma(16) * abs(float(want)) + 2 * np.spacing(abs(u_e) + abs(float(want)))
            ro.assert_within(got - float(want), bound, "variation", float(want))


def test_state_from_turning_point_round_trip():
    body = Body.paper()
    theta0 = np.array([0.3, 1.5, 0.95 * np.pi, np.pi - 1e-4])
    QR = np.array([0.01, -0.02, 0.003, 0.0])
    QJ = np.array([0.002, 0.01, -0.004, 0.001])
    st = state_from_turning_point(body, theta0, QR, QJ)
    assert np.all(st.theta_dot == 0.0)
    E, QR2, QJ2 = invariants_from_euler(body, theta0, st.theta_dot, st.phi_dot, st.psi_dot)
    # two stages: the rates from (θ0, Q_R, Q_J) (≤ 40 operations each, γ_40 × their condition over θ0, Q_R, Q_J and
    # the parameters), carried by |∂(E, Q_R, Q_J)/∂rate| (central differences), and (E, Q_R, Q_J) from the rates
    # (≤ 60 operations, γ_60 × their condition); × MARGIN
    params = {"a": body.a, "I1": body.I1, "I3": body.I3, "g": body.g}
    rates = ro.formula_bound(lambda theta0, QR, QJ, a, I1, I3, g: np.array(
        [(s := state_from_turning_point(_sym(a, I1, I3, g), theta0, QR, QJ)).phi_dot, s.psi_dot]),
        {"theta0": theta0, "QR": QR, "QJ": QJ, **params}, 40)
    inv = lambda theta0, thd, phd, psd, a, I1, I3, g: np.array(  # noqa: E731
        invariants_from_euler(_sym(a, I1, I3, g), theta0, thd, phd, psd))
    args = {"theta0": theta0, "thd": st.theta_dot, "phd": st.phi_dot, "psd": st.psi_dot, **params}
    bound = ro.formula_bound(inv, args, 60)
    for k, name in enumerate(("phd", "psd")):
        h = 1e-7 * np.maximum(np.abs(args[name]), 1e-300)
        up, down = dict(args), dict(args)
        up[name], down[name] = args[name] + h, args[name] - h
        bound = bound + np.abs(inv(**up) - inv(**down)) / (2 * h) * rates[k]
    bound = MARGIN * bound
    ro.assert_within(np.array([E - st.E, QR2 - QR, QJ2 - QJ]), bound, "round trip", np.array([st.E, QR, QJ]))
    # exact: both are _U_xy of tilt_xy(θ0) with the same arguments (the same operations)
    assert np.array_equal(st.E, effective_potential(theta0, QR, QJ, body))


# ----------------------------------------------------------------------------- turning points
def _cases():
    """(label, E, QR, QJ) from turning points θ0, including θ_N down to 1e-10 and θ_X up to π − 1e-8."""
    body = Body.paper()
    out = []
    for theta0, QR, QJ in ((0.95 * np.pi, 0.01, 0.002), (2.0, -0.005, 0.03), (0.95 * np.pi, 0.0, 0.0),
                           (0.3, 0.02, 0.01)):
        out.append((f"theta0={theta0:.3f}", float(state_from_turning_point(body, theta0, QR, QJ).E), QR, QJ))
    QJ0, QJpi = float(QJ_crit_0(0.01, body)), float(QJ_crit_pi(0.01, body))
    for d in (4e-5, 4e-8, 4.4e-11):  # Q_J just off Q_J,0^crit: θ_N ≈ 2.3 d, from 1e-4 down to 1e-10
        QJ = QJ0 + d
        out.append((f"QJ=crit0+{d:g}", float(state_from_turning_point(body, 0.95 * np.pi, 0.01, QJ).E), 0.01, QJ))
    for d in (1e-3, 1e-6, 1e-8):  # θ_X = π − d, near and off Q_J,π^crit
        for dq in (1e-9, 1e-4):
            QJ = QJpi + dq
            out.append((f"thetaX=pi-{d:g},QJ=critpi+{dq:g}",
                        float(state_from_turning_point(body, np.pi - d, 0.01, QJ).E), 0.01, QJ))
    return out


def _amplification(E, QR, QJ, theta, body):
    """(2 s² |E − V| + N) / |z dP/dz| at a root z (z = x or y) of P = 2 s² (E − V) − N (reduction):
    the relative shift of the root per unit relative rounding of P's terms (E − V is evaluated
    without cancellation, so the terms are of the size of the kinetic energy at the root)."""
    with mpmath.workdps(40):
        mb = _mp_body(body)
        theta = mpmath.mpf(theta)
        x0, y0 = 2 * mpmath.sin(theta / 2) ** 2, 2 * mpmath.cos(theta / 2) ** 2
        use_x = x0 <= y0
        z0 = x0 if use_x else y0

        def P(z):
            return _mp_terms(z, 2 - z, E, QR, QJ, mb)[0] if use_x else _mp_terms(2 - z, z, E, QR, QJ, mb)[0]
        if z0 == 0:
            return 1.0
        dP = mpmath.diff(P, z0, h=z0 * mpmath.mpf(10) ** -15)
        K = E - potential(x0, mb)
        return float(4 * x0 * y0 * abs(K) / abs(z0 * dP))


@pytest.mark.parametrize("label,E,QR,QJ", _cases())
def test_turning_points_against_mpmath(label, E, QR, QJ):
    """Roots against mpmath findroot at 30 digits on the same (E, Q_R, Q_J) doubles.

    Compared in the exact end variables (θ_N and π − θ_X).  Tolerance: the bisection in w narrows to 600/2⁷² (below
    the rounding of x), so each root is as good as P's rounding allows: γ_16 (the operations of P) × the
    amplification of the rounding of P's terms into the root (``_amplification``), + u for θ from the end variable;
    near π, θ_X as a double is off by ≤ ½ ulp(π) and np.pi by u π; × MARGIN.
    """
    body = Body.paper()
    tN, tX = turning_points(E, QR, QJ, body)
    ref = SimpleNamespace(**dict(zip(("theta_N", "theta_X"), turning_points_mp(E, QR, QJ, body, dps=30))))
    assert 0.0 <= tN < tX < np.pi
    rel_N = MARGIN * (ro.gamma(16) * _amplification(E, QR, QJ, ref.theta_N, body) + ro.u)
    rel_X = MARGIN * (ro.gamma(16) * _amplification(E, QR, QJ, ref.theta_X, body) + ro.u)
    if ref.theta_N == 0:  # Q_J exactly critical (pure rocking): the motion passes through θ = 0
        assert tN <= 1e-60
    else:
        ro.assert_within(tN - float(ref.theta_N), rel_N * float(ref.theta_N), "theta_N", float(ref.theta_N))
    dX = float(mpmath.pi - ref.theta_X)
    absX = MARGIN * (0.5 * np.spacing(np.pi) + ro.u * np.pi)  # θ_X as a double, π as np.pi
    # y = 2 cos²(θ/2) ≈ (π − θ)²/2, from the double θ_X: dy/dθ ≈ −(π − θ), and cos(θ/2) ≈ (π − θ)/2 rounds
    y_ref = 2 * float(mpmath.cos(ref.theta_X / 2)) ** 2
    bound_y = dX * (rel_X * dX + absX) + MARGIN * ro.gamma(4) * y_ref
    ro.assert_within(float(tilt_xy(tX)[1]) - y_ref, bound_y, "y_X", y_ref)
    ro.assert_within((np.pi - tX) - dX, rel_X * dX + absX, "pi - theta_X", dX)


def test_turning_points_reach_the_ends():
    """θ_N ≈ 1e-10 and θ_X ≈ π − 1e-8 are found, and F changes sign across each root."""
    body = Body.paper()
    QJ0, QJpi = float(QJ_crit_0(0.01, body)), float(QJ_crit_pi(0.01, body))
    cases = ((0.95 * np.pi, QJ0 + 4.4e-11, "N"), (np.pi - 1e-8, QJpi + 1e-9, "X"))
    for theta0, QJ, which in cases:
        E = float(state_from_turning_point(body, theta0, 0.01, QJ).E)
        tp = solve_turning_points(E, 0.01, QJ, body)
        assert tp.status == OK
        if which == "N":
            assert 1e-11 < tp.theta_N < 1e-9
            z, to_xy = float(tp.x_N), (lambda z: (z, 2 - z))
        else:
            assert abs(tp.y_X / tilt_xy(theta0)[1] - 1) <= 1e-6
            z, to_xy = float(tp.y_X), (lambda z: (2 - z, z))
        for factor, sign in ((1 - 1e-6, -1.0), (1 + 1e-6, 1.0)):
            x, y = to_xy(z * factor)
            theta = 2 * np.arctan2(np.sqrt(x), np.sqrt(y))  # F is evaluated from θ: keep θ away from π's ulp
            if which == "X":
                from rocknroller.analysis.routh.reduction import _P_xy
                val = _P_xy(np.array(x), np.array(y), E, 0.01, QJ, body)
            else:
                val = F(theta, E, 0.01, QJ, body)
            assert np.sign(val) == sign  # forbidden (F < 0) towards the end, allowed inside


def test_double_root_is_reported_and_no_motion_raises():
    body = Body.paper()
    QR, QJ = 0.02, 0.05
    tp = solve_turning_points(1.0, QR, QJ, body)
    U_min, th_min = float(tp.U_min), float(tp.theta_min)
    with pytest.raises(SteadyRollingError, match="steady circular rolling") as err:
        turning_points(U_min, QR, QJ, body)
    assert abs(float(err.value.theta) - th_min) <= 1e-6
    assert solve_turning_points(U_min, QR, QJ, body).status == STEADY
    # steady rolling: U'(θ_min) = 0, i.e. the minimum of U is where F has its double root
    h = 1e-5
    Up, Um = effective_potential([th_min + h, th_min - h], QR, QJ, body)
    assert abs(Up - Um) / (2 * h) <= 1e-6 * U_min
    # just above the minimum: a narrow rocking motion around θ_min
    tN, tX = turning_points(U_min * (1 + 1e-8), QR, QJ, body)
    assert tN < th_min < tX and tX - tN < 1e-2
    with pytest.raises(NoMotionError, match="no motion"):
        turning_points(U_min * (1 - 1e-6), QR, QJ, body)
    assert solve_turning_points(U_min * 0.5, QR, QJ, body).status == NO_MOTION
    assert isinstance(NoMotionError("x"), ValueError) and issubclass(SteadyRollingError, ValueError)


@pytest.mark.parametrize("theta0", [0.0, np.pi, -0.1, 4.0, float("nan")])
def test_theta0_outside_open_interval_raises(theta0):
    with pytest.raises(ValueError, match="theta0 must lie in the open interval"):
        state_from_turning_point(Body.paper(), theta0, 0.01, 0.0)


def test_asymmetric_body_rejected():
    body = Body.paper(1e-3)
    for call in (lambda: F(1.0, 1.0, 0.01, 0.0, body),
                 lambda: turning_points(1.0, 0.01, 0.0, body),
                 lambda: solve_turning_points(1.0, 0.01, 0.0, body),
                 lambda: state_from_turning_point(body, 1.0, 0.01, 0.0),
                 lambda: effective_potential(1.0, 0.01, 0.0, body)):
        with pytest.raises(ValueError, match="symmetric body"):
            call()
    # the conversion to invariants holds for any body (paper eq. JelletandRouth_Qtys)
    E, QR, QJ = invariants_from_euler(body, 1.0, 0.1, 0.2, 0.3, psi=0.4)
    assert np.isfinite(E) and np.isfinite(QR) and np.isfinite(QJ)


def test_bad_inputs_raise():
    body = Body.paper()
    with pytest.raises(ValueError, match="E must be finite"):
        turning_points(float("nan"), 0.0, 0.0, body)
    with pytest.raises(ValueError, match="theta must lie in the open interval"):
        F(0.0, 1.0, 0.0, 0.0, body)
    with pytest.raises(ValueError, match="theta must be finite and in"):
        invariants_from_euler(body, 4.0, 0.0, 0.0, 0.0)
    with pytest.raises(ValueError, match="phi_dot must be finite"):
        invariants_from_euler(body, 1.0, 0.0, float("inf"), 0.0)


def test_V_phi_V_psi_take_QR_QJ_by_keyword_only():
    """The paper writes V(θ; Q_J, Q_R), the package Q_R before Q_J: positional Q's would be a silent swap."""
    from rocknroller.analysis.model.invariants import V_phi, V_psi

    body = Body.paper(0.0)
    for fn in (V_phi, V_psi):
        with pytest.raises(TypeError):
            fn(1.0, 0.1, 0.2, body)
        assert fn(1.0, QR=0.1, QJ=0.2, body=body) == fn(1.0, QJ=0.2, body=body, QR=0.1)


def test_a_tilt_out_of_range_is_named_as_a_number():
    """The message showed numpy's repr (``theta0=array(0.)``, which reads as if it were a valid tilt); it names the
    first offending value as a plain number."""
    from rocknroller.analysis.routh.reduction import require_open_tilt

    for theta, shown in ((np.array(0.0), "theta0=0.0"), (np.array([1.0, 4.0, 5.0]), "theta0=4.0")):
        with pytest.raises(ValueError, match=re.escape(shown) + "$"):
            require_open_tilt(theta)
