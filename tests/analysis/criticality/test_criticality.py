"""Critical lines, regions, cos θ_z, θ_e, the δ^½ bound, critical-line starts and reversals (issue 4)."""

from __future__ import annotations

import math

import mpmath
import numpy as np
import pytest
import roundoff as ro
import sympy as sp
from scipy.optimize import brentq

from rocknroller.analysis.criticality import lines as C
from rocknroller.analysis.criticality import reversals, starts, theta_z
from rocknroller.analysis.criticality.laurent import SYMBOLS, V_phi_sym, laurent_coefficients
from rocknroller.analysis.model.body import Body
from rocknroller.analysis.model.equations import EulerState
from rocknroller.analysis.model.invariants import V_phi, invariants
from rocknroller.analysis.model.kinematics import vertical_in_body
from rocknroller.analysis.routh.reduction import state_from_turning_point
from rocknroller.analysis.routh.turning_points import turning_points
from rocknroller.papers.averaging_check import loglog_slope

#: Safety margin of the rounding bounds below (first-order analysis, worst-case constants).
MARGIN = 4.0

BODY = Body.paper()
BODY_EPS = Body.paper(1e-3)
OTHER = Body(a=0.2, I1=0.3, I2=0.3, I3=0.5, g=9.81)


def _random_points(rng, n):
    """Random (Q_R, Q_J) in a box wide enough to reach all four regions."""
    QR = rng.uniform(-1.0, 1.0, n)
    QJ = rng.uniform(-0.6, 0.6, n)
    return QR, QJ


# ----------------------------------------------------------------------------- lines
@pytest.mark.parametrize("body", [BODY, OTHER])
def test_critical_lines_are_the_laurent_leading_zeros(body):
    """Q_J,e^crit zeroes the leading Laurent coefficient of V_φ (paper eqs. QJcrit_0/pi), and equals the
    printed ρ_e (1 ∓ a) I3 Q_R."""
    QR = np.array([-0.7, 0.003, 2.5])
    subs = {SYMBOLS["a"]: body.a, SYMBOLS["I1"]: body.I1, SYMBOLS["I3"]: body.I3}
    for about, fn in (("0", C.QJ_crit_0), ("pi", C.QJ_crit_pi)):
        A = laurent_coefficients("phi", about, -2)[-2]
        for qr, qj in zip(QR, fn(QR, body)):
            val = A.evalf(30, subs={**subs, SYMBOLS["QR"]: qr, SYMBOLS["QJ"]: qj})
            # A₋₂ = ±(Q_J − Q_J,e^crit)/I1 at 30 digits: the double-double evaluation (slope to 2⁻¹⁰⁶, then
            # QR·lo and the final subtraction: 2 roundings) puts the double Q_J within γ_2 |Q_J| of the line
            ro.assert_within(float(val), MARGIN * ro.gamma(2) * abs(qj) / body.I1, "A-2", qj / body.I1)
    rho0 = 1 / math.sqrt(body.I3 + body.I3 / body.I1 * (1 - body.a) ** 2)
    rhopi = 1 / math.sqrt(body.I3 + body.I3 / body.I1 * (1 + body.a) ** 2)
    # the printed form in plain double: 1 ± a, its square, I3/I1, ×, +, sqrt, 1/x, × (1 ± a), × I3, × QR — ten
    # roundings on positive terms (γ_10 relative), against the correctly rounded line (u)
    for got, want in ((C.QJ_crit_0(QR, body), rho0 * (1 - body.a) * body.I3 * QR),
                      (C.QJ_crit_pi(QR, body), -rhopi * (1 + body.a) * body.I3 * QR)):
        ro.assert_within(got - want, MARGIN * (ro.gamma(10) + ro.u) * np.abs(want), "printed", want)


def test_region_matches_signs_of_V_phi_near_both_ends():
    """≥ 1000 random points: the region from the lines equals the one read off the signs of V_φ computed
    directly (rocknroller.analysis.model.invariants.V_phi) at θ = 1e-6 and θ = π − 1e-6."""
    rng = np.random.default_rng(4)
    for body in (BODY, OTHER):
        QR, QJ = _random_points(rng, 1500)
        reg = C.region(QR, QJ, body)
        s0 = np.sign(V_phi(1e-6, QR=QR, QJ=QJ, body=body))
        spi = np.sign(V_phi(np.pi - 1e-6, QR=QR, QJ=QJ, body=body))
        expected = np.select([(s0 < 0) & (spi > 0), (s0 > 0) & (spi > 0), (s0 > 0) & (spi < 0), (s0 < 0) & (spi < 0)],
                             ["I", "II", "III", "IV"], "?")
        assert np.all(reg == expected)
        assert set(reg) == set(C.REGIONS)  # every region sampled
        assert np.all(QR[reg == "I"] > 0) and np.all(QR[reg == "III"] < 0)


def test_region_on_line_labels_and_tolerance():
    QR = np.array([1.0, 1.0, 0.0, 1.0])
    QJ = np.array([C.QJ_crit_0(1.0, BODY), C.QJ_crit_pi(1.0, BODY), 0.0, C.QJ_crit_pi(1.0, BODY) * (1 + 1e-9)])
    assert list(C.region(QR, QJ, BODY)) == [C.ON_LINE_0, C.ON_LINE_PI, C.ON_BOTH, "IV"]
    assert C.region(1.0, QJ[3], BODY, tol=1e-8) == C.ON_LINE_PI
    assert C.region(2.0, 0.0, BODY) == "I"
    with pytest.raises(ValueError, match="tol"):
        C.region(1.0, 0.0, BODY, tol=1.5)
    with pytest.raises(ValueError, match="QJ"):
        C.region(1.0, float("nan"), BODY)


# ----------------------------------------------------------------------------- cos θ_z
_XTOL, _RTOL = 1e-16, 4 * np.finfo(float).eps


def _numeric_zero_cos(QR, QJ, body):
    """cos of the zero of V_φ by Brent's method on rocknroller.analysis.model.invariants.V_phi (independent of the closed form)."""
    out = []
    for r, j in zip(QR, QJ):
        th = brentq(lambda t: float(V_phi(t, QR=r, QJ=j, body=body)), 1e-9, np.pi - 1e-9, xtol=_XTOL, rtol=_RTOL, maxiter=500)
        out.append(math.cos(th))
    return np.array(out)


def _closed_form(q, a, I1, I3, one):
    """The closed form of theta_z.cos_theta_z as a function of q = Q_J/Q_R and the constants (for its condition only)."""
    beta = I3 - q * q / I1
    root = np.sqrt(beta * (I3 - I1) * (I3 + one) - a * a * beta * I3 + I1 * I3 * (I3 + one))
    return (a * beta * I3 + q * root) / (beta * (I3 - I1) + I1 * I3)


def _cos_theta_z_bound(QR, QJ, body):
    """Bound on |closed form − numeric zero| of cos θ_z, both in double.

    Closed form: ~20 rounded operations (q, β, the radicand, √, numerator, denominator) × its condition
    Σ|xᵢ ∂cos/∂xᵢ| over q, a, I1, I3 and the constant 1 (``roundoff.formula_bound``).  Numeric zero: Brent stops
    within 2 (xtol + rtol θ) of the computed root, which lies within δu/|u'(θ)| of the true one, u = Q_J − ρ f I3 Q_R
    the numerator of V_φ (rounding δu ≤ γ_12 (|Q_J| + |ρ f I3 Q_R|), u' by central differences); cos adds
    |sin θ| × that + its own rounding u.
    """
    c = theta_z.cos_theta_z(QR, QJ, body)
    closed = ro.formula_bound(_closed_form, {"q": QJ / QR, "a": body.a, "I1": body.I1, "I3": body.I3, "one": 1.0}, 20)
    th = np.arccos(c)
    numer = lambda t: QJ - _rho(t, body) * (np.cos(t) - body.a) * body.I3 * QR  # noqa: E731
    h = 1e-6
    du = np.abs(numer(th + h) - numer(th - h)) / (2 * h)
    du_round = ro.gamma(12) * (np.abs(QJ) + np.abs(_rho(th, body) * (np.cos(th) - body.a) * body.I3 * QR))
    numeric = np.sin(th) * (du_round / du + 2 * (_XTOL + _RTOL * th)) + ro.u
    return MARGIN * (closed + numeric)


def _rho(theta, body):
    from rocknroller.analysis.model.invariants import rho

    return rho(theta, body)


@pytest.mark.parametrize("body", [BODY, OTHER])
def test_cos_theta_z_equals_numeric_zero(body):
    """Corrected closed form = numeric zero of V_φ to round-off (``_cos_theta_z_bound``) in ≥ 1000 random Region I/III
    cases."""
    rng = np.random.default_rng(7)
    QR = rng.uniform(-1.0, 1.0, 1000)
    t = np.concatenate([rng.uniform(0, 1, 980), rng.uniform(0, 1e-6, 10), 1 - rng.uniform(0, 1e-6, 10)])
    QJ = C.QJ_crit_pi(QR, body) + t * (C.QJ_crit_0(QR, body) - C.QJ_crit_pi(QR, body))  # between the lines
    assert np.all(np.isin(C.region(QR, QJ, body), ("I", "III")))
    assert np.any(QJ / QR < 0) and np.any(QJ / QR > 0)
    err = theta_z.cos_theta_z(QR, QJ, body) - _numeric_zero_cos(QR, QJ, body)
    ro.assert_within(err, _cos_theta_z_bound(QR, QJ, body), "cos_theta_z", 1.0)


def test_cos_theta_z_printed_form_fails():
    """Erratum: the printed β = I3 − q² (no 1/I1) and the always-+ root miss the zero of V_φ."""
    QR = np.array([1.0, 1.0, -1.0])
    QJ = np.array([0.2, -0.2, 0.2])  # q = 0.2, −0.2 (Region I), −0.2 (Region III)
    assert set(C.region(QR, QJ, BODY)) <= {"I", "III"}
    good, printed = theta_z.cos_theta_z(QR, QJ, BODY), theta_z.cos_theta_z_printed(QR, QJ, BODY)
    ro.assert_within(good - _numeric_zero_cos(QR, QJ, BODY), _cos_theta_z_bound(QR, QJ, BODY), "cos_theta_z", 1.0)
    assert np.all(np.abs(printed - good) > 0.05)
    assert np.all(np.abs(V_phi(np.arccos(np.clip(printed, -1, 1)), QR=QR, QJ=QJ, body=BODY)) > 1e-3)
    # each error alone also fails: the right β with the + root fails for q < 0
    q = -0.2
    beta = BODY.I3 - q * q / BODY.I1
    a, I1, I3 = BODY.a, BODY.I1, BODY.I3
    plus = (a * beta * I3 + math.sqrt(I1 * (I3 - beta) * (beta * (I3 - I1) * (I3 + 1) - a * a * beta * I3
                                                          + I1 * I3 * (I3 + 1)))) / (beta * (I3 - I1) + I1 * I3)
    assert abs(V_phi(math.acos(plus), QR=1.0, QJ=q, body=BODY)) > 1e-3


def test_cos_theta_z_sympy_derivation():
    """The closed form is the root of the squared condition selected by sgn(q) (sympy, exact)."""
    d = theta_z.cos_theta_z_sympy()
    q, beta = d["symbols"]["q"], d["symbols"]["beta"]
    I1 = SYMBOLS["I1"]
    I3 = SYMBOLS["I3"]
    qpos = sp.sqrt(I1 * (I3 - beta))
    plus, minus = d["roots"]
    closed = d["closed_form"]
    rng = np.random.default_rng(5)
    for _ in range(20):  # exact rationals, evaluated at 50 digits
        I1v = sp.Rational(int(rng.integers(20, 40)), 100)
        I3v = I1v + sp.Rational(int(rng.integers(1, 15)), 100)
        av = sp.Rational(int(rng.integers(0, 30)), 100)
        bv = I3v - sp.Rational(int(rng.integers(1, 99)), 100) * I3v * I1v  # q² = I1 (I3 − β) < I1² I3 ... I1 I3
        sub = {SYMBOLS["a"]: av, I1: I1v, I3: I3v, beta: bv}
        r_plus, r_minus = (sp.N(r.subs(sub), 50) for r in (plus, minus))
        c_pos = sp.N(closed.subs(q, qpos).subs(sub), 50)
        c_neg = sp.N(closed.subs(q, -qpos).subs(sub), 50)
        # q > 0 takes one root, q < 0 the other: the sign of the root follows sgn(q) (50-digit evaluations of the
        # same exact numbers: 10⁻⁵⁰ per operation; 1e-45 leaves a factor ≥ 10³; the roots differ by > 1e-10)
        pos_is_plus = abs(c_pos - r_plus) < 1e-45
        assert pos_is_plus or abs(c_pos - r_minus) < 1e-45
        assert abs(c_neg - (r_minus if pos_is_plus else r_plus)) < 1e-45
        assert abs(r_plus - r_minus) > 1e-10


def test_cos_theta_z_errors():
    with pytest.raises(ValueError, match="QR must be nonzero"):
        theta_z.cos_theta_z(0.0, 0.1, BODY)
    with pytest.raises(ValueError, match="Regions I/III"):
        theta_z.cos_theta_z(0.0001, 0.3, BODY)  # Region II


# ----------------------------------------------------------------------------- θ_e and the necessary condition
def test_theta_e_is_the_extremum():
    rng = np.random.default_rng(3)
    QR, QJ = _random_points(rng, 400)
    m = np.isin(C.region(QR, QJ, BODY), ("II", "IV"))
    QR, QJ = QR[m][:40], QJ[m][:40]
    te = theta_z.theta_e(QR, QJ, BODY)
    h = 1e-4
    for r, j, t in zip(QR, QJ, te):
        v, vl, vr = (float(V_phi(x, QR=r, QJ=j, body=BODY)) for x in (t, t - h, t + h))
        if j > C.QJ_crit_0(r, BODY):  # Region II: minimum
            assert v < vl and v < vr
        else:
            assert v > vl and v > vr
    with pytest.raises(ValueError, match="Regions II/IV"):
        theta_z.theta_e(1.0, 0.0, BODY)


def test_necessary_condition():
    QR, QJ = np.array([1.0, 1.0, 0.0]), np.array([0.0, 0.0, 0.5])  # Region I twice, Region II
    tz = float(theta_z.theta_z(1.0, 0.0, BODY))
    te = float(theta_z.theta_e(0.0, 0.5, BODY))
    got = theta_z.necessary_condition(np.array([tz + 1e-6, tz - 1e-6, te + 1e-6]), QR, QJ, BODY)
    assert list(got) == [True, False, True]
    with pytest.raises(ValueError, match="theta_X"):
        theta_z.necessary_condition(0.0, 1.0, 0.0, BODY)


# ----------------------------------------------------------------------------- δ^½ bound
def test_delta_bound_coefficient_matches_paper():
    d = theta_z.delta_bound_sympy()
    assert sp.simplify(d["C1"] ** 2 - d["C1_paper"] ** 2) == 0


def _theta_z_mp(delta, body, dps=40):
    """θ_z(δ) at 40 digits: the zero of the numerator of V_φ (sympy V_phi_sym, mpmath)."""
    s = SYMBOLS
    numer = sp.expand(V_phi_sym(s["theta"]) * s["I1"] * sp.sin(s["theta"]) ** 2)
    f = sp.lambdify((s["theta"], s["QJ"], s["QR"], s["a"], s["I1"], s["I3"]), numer, modules="mpmath")
    with mpmath.workdps(dps):
        a, I1, I3 = (mpmath.mpf(v) for v in (body.a, body.I1, body.I3))
        rpi = 1 / mpmath.sqrt(I3 + I3 / I1 * (1 + a) ** 2)
        QR = mpmath.mpf(1)
        QJ = -rpi * (1 + a) * I3 * QR * (1 - mpmath.mpf(delta))
        x = mpmath.findroot(lambda x: f(mpmath.pi - x, QJ, QR, a, I1, I3),
                            (mpmath.mpf(1e-12), mpmath.mpf(1.2) * mpmath.sqrt(delta) * 2), solver="anderson")
        return mpmath.pi - x


@pytest.mark.parametrize("body", [BODY, OTHER])
def test_delta_expansion_error_powers(body):
    """θ_z(δ) vs a 40-digit root: one-term error ∝ δ^{3/2}, two-term error ∝ δ^{5/2} (fitted slopes)."""
    deltas = np.array([1e-2, 3e-3, 1e-3, 3e-4, 1e-4])
    exact = np.array([float(_theta_z_mp(d, body)) for d in deltas])
    e1 = np.abs(theta_z.theta_z_expansion(deltas, body, terms=1) - exact)
    e2 = np.abs(theta_z.theta_z_expansion(deltas, body, terms=2) - exact)
    s1, s2 = loglog_slope(deltas, e1), loglog_slope(deltas, e2)
    assert abs(s1 - 1.5) < 0.05 and abs(s2 - 2.5) < 0.1
    assert np.all(e2 < e1)


def _theta_z_round_trip_bound(QR, QJ, tz, E):
    """|θ_X(E) − θ_z| for E = U(θ_z): θ_z = arccos of the closed form (its rounding, ``_cos_theta_z_bound``'s closed
    part, over sin θ_z, + u), and the root of P = 2 s² (E − V) − N at the rounded E: P's rounding at the root (γ_20 ×
    the size of its terms) and E's (γ_15 |E| × ∂P/∂E = 2 s²), over |∂P/∂θ| (central differences)."""
    from rocknroller.analysis.routh.reduction import _P_and_terms, tilt_xy

    c = np.cos(tz)
    closed = ro.formula_bound(_closed_form, {"q": QJ / QR, "a": BODY.a, "I1": BODY.I1, "I3": BODY.I3, "one": 1.0}, 20)
    theta_err = closed / np.sin(tz) + ro.u * tz
    P = lambda th: _P_and_terms(*tilt_xy(th), E, QR, QJ, BODY)  # noqa: E731
    h = 1e-7
    dP = np.abs(P(tz + h)[0] - P(tz - h)[0]) / (2 * h)
    x, y = tilt_xy(tz)
    root_err = (ro.gamma(20) * P(tz)[1] + ro.gamma(15) * np.abs(E) * 2 * x * y) / dP
    return MARGIN * (theta_err + root_err + ro.u * np.abs(tz))


def test_delta_bound_against_turning_points():
    """The bound is saturated at θ_X = θ_z: a symmetric start at the turning point θ_z(δ) has θ_X = θ_z from
    rocknroller.analysis.routh.turning_points.turning_points, V_φ(θ_X) = 0, and the expansions approach that θ_X with the powers of δ."""
    QR = 0.003
    deltas = np.array([3e-3, 1e-3, 3e-4, 1e-4])  # two-term error 3e-8 .. 6e-12, above arccos rounding (~1e-14)
    QJ = C.QJ_crit_pi(QR, BODY) * (1 - deltas)
    tz = theta_z.theta_z(QR, QJ, BODY)
    E = state_from_turning_point(BODY, tz, QR, QJ).E
    _, theta_X = turning_points(E, QR, QJ, BODY)
    ro.assert_within(theta_X - tz, _theta_z_round_trip_bound(QR, QJ, tz, E), "theta_X", tz)
    # δ = 1 − Q_J/Q_J,π^crit with Q_J = Q_J,π^crit (1 − δ): 1 − δ, the product and the quotient round (γ_3 of 1 − δ);
    # 1 − ratio is exact (Sterbenz)
    ro.assert_within(theta_z.delta_of(QR, QJ, BODY) - deltas, MARGIN * ro.gamma(3) * (1 - deltas), "delta", deltas)
    e1 = np.abs(theta_z.theta_z_expansion(deltas, BODY, 1) - theta_X)
    e2 = np.abs(theta_z.theta_z_expansion(deltas, BODY, 2) - theta_X)
    assert abs(loglog_slope(deltas, e1) - 1.5) < 0.05
    assert abs(loglog_slope(deltas, e2) - 2.5) < 0.1


def test_delta_errors():
    for bad in (0.0, 1.0, -0.1, 1.5):
        with pytest.raises(ValueError, match=r"delta must lie in the open interval \(0, 1\)"):
            theta_z.theta_z_expansion(bad, BODY)
    with pytest.raises(ValueError, match="QR must be nonzero"):
        theta_z.delta_of(0.0, 0.1, BODY)


# ----------------------------------------------------------------------------- critical-line starts
def _on_line_bounds(body, line, gamma, omega, QJ):
    """Bounds on |Q_J − Q_J,e^crit(Q_R)| and |Q_R − Q_R given| for a start built on a line and Q_R, Q_J recomputed
    from (γ, ω): the construction (rates from Q_R and the line, ω from the rates) and the recomputation each round
    ≤ 25 operations, carried by κ = Σ|yᵢ ∂Q/∂yᵢ| (which also measures the cancellation in Q_J), Q_R's through the
    line's slope; the line itself rounds by γ_2 |Q_J|; × MARGIN."""
    from rocknroller.analysis.model.invariants import jellett, routh

    g, w = np.asarray(gamma, float).reshape(3, -1), np.asarray(omega, float).reshape(3, -1)
    n = max(g.shape[1], w.shape[1])
    Y = np.vstack([np.broadcast_to(g, (3, n)), np.broadcast_to(w, (3, n))]).T
    kJ, kR = (ro.relative_condition(lambda Z, q=q: q(body, Z[:, 0:3].T, Z[:, 3:6].T), Y) for q in (jellett, routh))
    slope = abs(float(C.QJ_crit(line, 1.0, body)))
    bJ = MARGIN * (2 * 2 * ro.gamma(25) * (kJ + slope * kR) + ro.gamma(2) * np.abs(QJ))
    return bJ, MARGIN * 2 * 2 * ro.gamma(25) * kR


@pytest.mark.parametrize("body", [BODY, BODY_EPS])
@pytest.mark.parametrize("line", C.LINES)
def test_critical_start_lands_on_line(body, line):
    """(Q_R, Q_J) recomputed from the body-frame state (rocknroller.analysis.model.invariants) lie on the line to round-off
    (``_on_line_bounds``)."""
    rng = np.random.default_rng(11)
    theta0 = rng.uniform(0.55 * np.pi, 0.99 * np.pi, 200)
    psi0 = rng.uniform(0, np.pi, 200)
    QR = rng.uniform(-0.1, 0.1, 200)
    for kw in ({"QR": QR}, {"psi_dot0": rng.uniform(-0.5, 0.5, 200)}):
        st = starts.critical_start(body, theta0, psi0, line, **kw)
        gamma = vertical_in_body(theta0, psi0)
        _, QRr, QJr = invariants(body, gamma, st.omega)
        crit = C.QJ_crit(line, QRr, body)
        bJ, bR = _on_line_bounds(body, line, gamma, st.omega, QJr)
        ro.assert_within(QJr - crit, bJ, "QJ on line", QJr)
        ro.assert_within(QRr - st.QR, bR, "QR", st.QR)
    # the requested spin rate is reproduced to rounding (ω3' = c φ̇ + ψ̇ cancels near θ = π)
    pd = rng.uniform(-0.5, 0.5, 200)
    st = starts.critical_start(body, theta0, psi0, line, psi_dot0=pd)
    assert np.max(np.abs(st.psi_dot0 - pd) / np.abs(pd)) <= 1e-10


@pytest.mark.parametrize("line", C.LINES)
def test_critical_start_reaches_the_ode_on_the_line(line):
    """The ODE's initial body-frame state (EulerState.from_omega → to_body_state) keeps ω as given:
    started on a line, it lies on it to round-off (``_on_line_bounds``) also at θ0 = 0.999π and 0.001π, where φ̇ and ψ̇
    are large and nearly opposite.  (Rebuilding ω from the Euler rates, as before, put the θ0 = 0.999π
    start on the Q_J,0 line 6e-12 off it.)"""
    from rocknroller.analysis.model.equations import EulerState

    for theta0 in (0.001 * np.pi, 0.05 * np.pi, 0.95 * np.pi, 0.999 * np.pi):
        for psi0 in (0.0, np.pi / 4, 2.0):
            st = starts.critical_start(BODY_EPS, theta0, psi0, line, QR=0.01)
            omega = np.asarray(st.omega, float).reshape(3)
            y = EulerState.from_omega(theta0, 0.0, psi0, omega).to_body_state()
            assert np.array_equal(y[3:6], omega)  # exact: ω is copied, not rebuilt from the rates
            _, QR, QJ = invariants(BODY_EPS, y[:3], y[3:6])
            bJ, _ = _on_line_bounds(BODY_EPS, line, y[:3], y[3:6], QJ)
            ro.assert_within(QJ - C.QJ_crit(line, QR, BODY_EPS), bJ, "QJ on line", QJ)


def test_critical_start_offset_is_signed_distance():
    st = starts.critical_start(BODY, 0.95 * np.pi, 0.0, "pi", QR=0.003, offset=np.array([-1e-4, 1e-4]))
    _, QR, QJ = invariants(BODY, vertical_in_body(0.95 * np.pi, 0.0), st.omega)
    np.testing.assert_allclose(QJ - C.QJ_crit_pi(QR, BODY), [-1e-4, 1e-4], rtol=1e-11)
    assert list(C.region(QR, QJ, BODY)) == ["IV", "I"]


def test_critical_start_errors():
    for bad in (0.0, np.pi, -0.1, 4.0):
        with pytest.raises(ValueError, match="theta0 must lie in the open interval"):
            starts.critical_start(BODY, bad, 0.0, "pi", QR=0.003)
    with pytest.raises(ValueError, match="exactly one of QR and psi_dot0"):
        starts.critical_start(BODY, 2.0, 0.0, "pi")
    with pytest.raises(ValueError, match="exactly one of QR and psi_dot0"):
        starts.critical_start(BODY, 2.0, 0.0, "pi", QR=0.1, psi_dot0=0.1)
    with pytest.raises(ValueError, match="line must be one of"):
        starts.critical_start(BODY, 2.0, 0.0, "2pi", QR=0.1)
    # a steady-rolling tilt is not a turning point: find (QR, QJ) whose U has its minimum at theta0
    from rocknroller.analysis.routh.turning_points import solve_turning_points

    QR, QJ = 0.5, C.QJ_crit_pi(0.5, BODY) + 0.05
    tp = solve_turning_points(1.0, QR, QJ, BODY)
    with pytest.raises(ValueError, match="steady circular rolling"):
        starts.critical_start(BODY, float(tp.theta_min), 0.0, "pi", QR=QR, offset=0.05)


# ----------------------------------------------------------------------------- reversals against the direct ODE
@pytest.mark.parametrize("line", C.LINES)
def test_ode_started_on_line_crosses_it(line):
    """Paper §numerics "Recession and Criticality" (figs. 8, 9): ε = 1e-3, θ0 = 0.95π, ψ0 = π/4, started on each line; the direct ODE shows ≥ 1
    crossing of that line within 200 time units; φ̇ at the turning points has the sign of V_φ there."""
    from rocknroller.analysis.model.equations import EulerState
    from rocknroller.numerics.integrate import simulate
    from rocknroller.papers.lynch_bustamante import fig8_visible_reversal as fig8
    from rocknroller.papers.lynch_bustamante import fig9_full_reversal as fig9

    psi_dot0 = fig9.PSI_DOT0 if line == "0" else fig8.PSI_DOT0
    st = starts.critical_start(BODY_EPS, 0.95 * np.pi, np.pi / 4, line, psi_dot0=psi_dot0)
    init = EulerState.from_omega(0.95 * np.pi, 0.0, np.pi / 4, st.omega)
    traj = simulate(BODY_EPS, init, 200.0)
    ra = reversals.reversal_analysis(traj)
    assert ra.count(line) >= 1
    other = "pi" if line == "0" else "0"
    assert ra.count(other) == 0  # paper: "no visible (full) angle reversal"
    tp = ra.turning_points
    assert tp.t.size == len(traj.maxima) + len(traj.minima) and np.all(np.diff(tp.t) > 0)
    assert np.all(tp.phi_dot_sign == np.sign(V_phi(tp.theta, QR=tp.QR, QJ=tp.QJ, body=BODY_EPS)))
    for c in ra.crossings:
        assert c.region_before != c.region_after


@pytest.mark.parametrize("QR, QJ, bad", [(1e308, 0.0, "QR"), (1e308, -1e308, "QR"), (0.01, 1e300, "QJ"),
                                          (5e-324, 0.0, "QR"), (0.01, -1e-200, "QJ"), (math.inf, 0.0, "QR")])
def test_invariants_outside_the_resolved_range_are_refused(QR, QJ, bad):
    """Fuzzing found overflow (QJ_crit_0(1e308) = -inf, region of 1e308) and silently wrong offsets for subnormal
    Q (the double-double product underflows): every criticality function refuses such Q, naming it."""
    from rocknroller.analysis.routh.reduction import Q_RANGE

    message = rf"^{bad} must be 0 or finite with {Q_RANGE[0]:g} <= \|{bad}\|"
    calls = [C.region, theta_z.delta_of, theta_z.cos_theta_z, theta_z.theta_z, theta_z.theta_e]
    if bad == "QR":
        calls += [lambda QR, QJ, body: C.QJ_crit_0(QR, body), lambda QR, QJ, body: C.QJ_crit_pi(QR, body)]
    for call in calls:
        with pytest.raises(ValueError, match=message):
            call(QR, QJ, BODY)
    # the ends of the range are accepted and give finite values
    for q in Q_RANGE:
        assert np.isfinite(C.QJ_crit_0(q, BODY)) and np.isfinite(theta_z.delta_of(q, q, BODY))


def test_critical_start_names_psi_dot0_when_it_leaves_the_range():
    with pytest.raises(ValueError, match="psi_dot0"):
        starts.critical_start(BODY, 0.95 * math.pi, 0.0, "pi", psi_dot0=1e300)


def test_a_critical_start_gives_its_state():
    """Users converted a CriticalStart to a state by hand (``EulerState.from_omega(θ0, 0, ψ0, start.omega)``);
    ``state()`` is that conversion, bit for bit, and refuses a start computed over arrays."""
    body = Body.paper(1e-3)
    st = starts.critical_start(body, 0.95 * np.pi, np.pi / 4, "pi", psi_dot0=0.002)
    assert st.state() == EulerState.from_omega(0.95 * np.pi, 0.0, np.pi / 4, np.asarray(st.omega).reshape(3))
    assert st.state(phi0=0.3).phi == 0.3
    many = starts.critical_start(body, np.array([0.9, 0.95]) * np.pi, np.pi / 4, "pi", psi_dot0=0.002)
    with pytest.raises(ValueError, match="single start"):
        many.state()
