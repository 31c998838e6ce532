"""The four formulations of the equations of motion agree, and form (i) conserves what it must.

Form (i) (body frame, production) is compared with the paper's Euler-angle system (ii), its
Euler–Lagrange system (iii) and, for I1 = I2, the intermediate-frame system (iv), at random states.
The conservation laws of form (i) are checked in exact rational arithmetic (sympy) at random
rational states: a rational function that vanishes at random rational points is identically zero
with probability 1 (Schwartz–Zippel), and any transcription error would show as a non-zero residual.
"""

from __future__ import annotations

import math

import numpy as np
import pytest
import roundoff as ro
import sympy as sp

from rocknroller.analysis.model.body import Body
from rocknroller.analysis.model.equations import (EulerState, body_frame_rhs, euler_angle_rhs,
                                                  euler_angle_state_from_body, euler_from_state,
                                                  formulation_differences, intermediate_frame_rhs, omega_dot_by_form,
                                                  state_from_euler)
from rocknroller.analysis.model.invariants import energy, jellett, routh

N_STATES = 1000
#: Safety margin of the rounding bounds below.
MARGIN = 4.0
#: Rounded operations along a path from a state to ω̇ in forms (ii)-(iv): the 3×3 products Σᵀ K Σ (sums of 9
#: products of 3 factors), the right-hand sides, the 3×3 solve and ω̇ = Σ θ̈ + Σ̇ θ̇.
N_OPS_FORM = 50


def _form_bounds(Y, body):
    """Per state, the bound on |ω̇_form − ω̇_(i)|∞ / (1 + |ω̇_(i)|∞) (the measure of
    ``formulation_differences``): the paper's forms solve with M = Σᵀ K Σ (or K after θ̇ = Σ⁻¹ ω), whose
    condition is ≤ cond(K) cond(Σ)², Σ the Euler-rate matrix (cond ~ 1/sin θ near the poles); their terms are of
    size g a + |ω|² + |ω̇| (gravity, velocity products, M θ̈).  Rounding: γ_n (n = N_OPS_FORM) × condition × terms
    (Higham, §7.1: a linear solve errs by ≤ cond × the relative error of its data), × MARGIN."""
    from rocknroller.analysis.model.equations import _sigma_matrix

    D = np.array(body_frame_rhs(Y, body.params))
    out = []
    for y, d in zip(Y.T, D.T):
        th, ph, ps = euler_from_state(y)[:3]
        r = y[0:3] - np.array([0.0, 0.0, body.a])
        K = np.diag([body.I1, body.I2, body.I3]) + r @ r * np.eye(3) - np.outer(r, r)
        cond = np.linalg.cond(K) * np.linalg.cond(_sigma_matrix(th, ps)) ** 2
        terms = body.g * body.a + np.sum(y[3:6] ** 2) + np.max(np.abs(d[3:6]))
        out.append(MARGIN * ro.gamma(N_OPS_FORM) * cond * terms / (1.0 + np.max(np.abs(d[3:6]))))
    return np.array(out), D


def _random_states(rng, n):
    theta = rng.uniform(0.05, math.pi - 0.05, n)
    phi, psi = rng.uniform(-math.pi, math.pi, (2, n))
    rates = rng.normal(scale=2.0, size=(3, n))
    return state_from_euler(theta, phi, psi, *rates)


def _bodies():
    return [Body.paper(0.0), Body.paper(1e-3), Body.paper(0.1), Body(a=0.3, I1=0.2, I2=0.3, I3=0.45, g=3.0)]


@pytest.mark.parametrize("body", _bodies(), ids=lambda b: f"eps={b.epsilon:.3g},a={b.a}")
def test_paper_forms_agree_with_body_frame(body):
    """ω̇ by forms (ii), (iii) and, for I1 = I2, (iv) equals form (i)'s to round-off; the Euler rates of
    form (ii) equal those of form (i)'s state."""
    rng = np.random.default_rng(2024)
    Y = _random_states(rng, N_STATES)
    diff = formulation_differences(Y, body)
    assert set(diff) == ({"ii", "iii", "iv"} if body.is_symmetric else {"ii", "iii"})
    bounds, D = _form_bounds(Y, body)
    per_state: dict[str, list[float]] = {form: [] for form in diff}  # formulation_differences' measure, per state
    for y, d in zip(Y.T, D.T):
        for form, wdot in omega_dot_by_form(y, body).items():
            per_state[form].append(np.max(np.abs(wdot - d[3:6])) / (1.0 + np.max(np.abs(d[3:6]))))
    for form, values in per_state.items():
        assert max(values) == diff[form]
        ro.assert_within(np.array(values), bounds, form, 1.0)
    from rocknroller.analysis.model.equations import _sigma_matrix

    errs, bounds, sizes = [], [], []
    for y in Y.T[:100]:  # kinematics: Euler rates from form (i)'s ω, two ways through Σ⁻¹ (≤ 20 operations each,
        # amplified by cond(Σ)), relative to the rates' size
        d2 = euler_angle_rhs(euler_angle_state_from_body(y), body)
        th, _, ps = euler_from_state(y)[:3]
        errs.append(np.max(np.abs(d2[:3] - euler_from_state(y)[3:])))
        bounds.append(MARGIN * 2 * ro.gamma(20) * np.linalg.cond(_sigma_matrix(th, ps)) * (1 + np.abs(d2[:3]).max()))
        sizes.append(np.abs(d2[:3]).max())
    ro.assert_within(np.array(errs), np.array(bounds), "rates", np.array(sizes))


def test_formulation_differences_detect_a_wrong_form(monkeypatch):
    """A transcription error in one form shows: g replaced by 1.01 g in form (ii)'s right-hand side."""
    import rocknroller.analysis.model.equations as eq

    body = Body.paper(0.1)
    Y = _random_states(np.random.default_rng(3), 50)
    wrong = Body(a=body.a, I1=body.I1, I2=body.I2, I3=body.I3, g=1.01 * body.g)
    true_rhs = eq.euler_angle_rhs
    monkeypatch.setattr(eq, "euler_angle_rhs", lambda x, b: true_rhs(x, wrong))
    diff = formulation_differences(Y, body)
    assert diff["ii"] > 1e-4 and diff["ii"] > 1e3 * _form_bounds(Y, body)[0].max() and diff["iii"] < 1e-11


def test_form_iv_refuses_asymmetric_body():
    with pytest.raises(ValueError, match="symmetric"):
        intermediate_frame_rhs(np.ones(6), Body.paper(1e-3))


def test_kinematics_of_body_frame_state():
    """γ̇ and ė_X of form (i) equal the time derivatives of the Euler-angle expressions."""
    rng = np.random.default_rng(3)
    body = Body.paper(0.01)
    for _ in range(50):
        th, ph, ps = rng.uniform(0.1, 3.0), rng.uniform(-3, 3), rng.uniform(-3, 3)
        rates = rng.normal(size=3)
        y = state_from_euler(th, ph, ps, *rates)
        d = np.array(body_frame_rhs(y, body.params))
        h = 1e-6
        yp = state_from_euler(th + h * rates[0], ph + h * rates[1], ps + h * rates[2], *rates)
        ym = state_from_euler(th - h * rates[0], ph - h * rates[1], ps - h * rates[2], *rates)
        fd = (yp - ym) / (2 * h)
        assert np.allclose(d[0:3], fd[0:3], atol=1e-9) and np.allclose(d[6:9], fd[6:9], atol=1e-9)


def _rational_state(rng):
    """Rational γ and e_X on the unit sphere, orthogonal (stereographic + Gram–Schmidt-free rotation)."""
    u, v = (sp.Rational(int(rng.integers(-9, 10)), int(rng.integers(1, 10))) for _ in range(2))
    n = 1 + u**2 + v**2
    gamma = [2 * u / n, 2 * v / n, (1 - u**2 - v**2) / n]
    omega = [sp.Rational(int(rng.integers(-20, 21)), int(rng.integers(1, 9))) for _ in range(3)]
    return gamma, omega


@pytest.mark.parametrize("symmetric", [True, False])
def test_conservation_laws_exact(symmetric):
    """dE/dt = 0 exactly for form (i); dQ_J/dt = dQ_R²/dt = 0 exactly when I1 = I2 (paper §2.3)."""
    rng = np.random.default_rng(11)
    a, I1, I3, g = sp.Rational(1, 20), sp.Rational(7, 20), sp.Rational(2, 5), sp.Rational(987, 100)
    I2 = I1 if symmetric else sp.Rational(351, 1000)
    y_sym = sp.symbols("g1 g2 g3 w1 w2 w3")
    p = (a, I1, I2, I3, g)
    rhs = body_frame_rhs(list(y_sym) + [1, 0, 0, 0, 0], p)[:6]
    gam, om = y_sym[:3], y_sym[3:]
    r = (gam[0], gam[1], gam[2] - a)
    v = (om[1] * r[2] - om[2] * r[1], om[2] * r[0] - om[0] * r[2], om[0] * r[1] - om[1] * r[0])
    E = sum(vi**2 for vi in v) / 2 + (I1 * om[0] ** 2 + I2 * om[1] ** 2 + I3 * om[2] ** 2) / 2 + g * a * (1 - gam[2])
    QJ = I1 * (gam[0] * om[0] + gam[1] * om[1]) + I3 * (gam[2] - a) * om[2]
    QR2 = om[2] ** 2 * (I3 + gam[0] ** 2 + gam[1] ** 2 + (I3 / I1) * (gam[2] - a) ** 2)
    rates = {name: sum(sp.diff(q, yi) * fi for yi, fi in zip(y_sym, rhs)) for name, q in
             (("E", E), ("QJ", QJ), ("QR2", QR2))}
    for _ in range(5):
        gamma, omega = _rational_state(rng)
        subs = dict(zip(y_sym, gamma + omega))
        values = {k: sp.nsimplify(expr.subs(subs)) for k, expr in rates.items()}
        assert values["E"] == 0
        if symmetric:
            assert values["QJ"] == 0 and values["QR2"] == 0
    if not symmetric:  # and the check can fail: Q_J is not conserved for I1 != I2
        gamma, omega = _rational_state(rng)
        assert rates["QJ"].subs(dict(zip(y_sym, gamma + omega))) != 0


def test_numeric_invariants_match_symbolic_definitions():
    """rocknroller.analysis.model.invariants evaluates the same E, Q_J, Q_R as the definitions in the intermediate frame."""
    body = Body.paper(0.0)
    th, ps, td, pd, sd = 2.0, 0.7, 0.3, -0.4, 1.1
    y = state_from_euler(th, 0.2, ps, td, pd, sd)
    s, c = math.sin(th), math.cos(th)
    f = c - body.a
    u1, u2, u3 = td, s * pd, c * pd + sd
    v = (f * u2 - s * u3, -f * u1, s * u1)  # paper eq. (constraint)
    E = 0.5 * sum(x * x for x in v) + 0.5 * (body.I1 * (u1**2 + u2**2) + body.I3 * u3**2) + body.g * body.a * (1 - c)
    QJ = body.I1 * s * u2 + body.I3 * f * u3
    QR = u3 * math.sqrt(body.I3 + s * s + body.I3 / body.I1 * f * f)
    # two evaluations (≤ 25 rounded operations each, from (γ, ω) and from the Euler rates), each within γ_25 × the
    # condition κ = Σ|yᵢ ∂q/∂yᵢ| of q (which measures the size of its terms), × MARGIN
    for name, fun, want in (("E", energy, E), ("QJ", jellett, QJ), ("QR", routh, QR)):
        kappa = float(ro.relative_condition(lambda Z, f=fun: f(body, Z[:, 0:3].T, Z[:, 3:6].T), y[None, 0:6])[0])
        ro.assert_within(fun(body, y[0:3], y[3:6]) - want, MARGIN * 2 * ro.gamma(25) * kappa, name, want)


def test_initial_states_that_would_overflow_are_refused():
    """Fuzzing found states whose body-frame ω overflowed to inf (ψ̇ = 1.8e308) and from_omega at θ = 5e-324 giving
    φ̇ = inf (named as a derived rate): both are refused, naming what the user gave."""
    from rocknroller.analysis.model.equations import RATE_MAX

    with pytest.raises(ValueError, match=r"^psi_dot must satisfy \|psi_dot\| <= 1e\+150"):
        EulerState(0.0, 0.0, 0.0, 0.0, 1.0, 1.7976931348623157e308)
    with pytest.raises(ValueError, match=r"^omega must be three finite numbers"):
        EulerState(1.0, omega=(0.0, 2 * RATE_MAX, 0.0))
    with pytest.raises(ValueError, match=r"^theta0=5e-324 is too close to the vertical for omega"):
        EulerState.from_omega(5e-324, 0.0, 0.0, (0.0, 1.0, 0.0))
    assert np.all(np.isfinite(EulerState(1.0, 0.0, 0.0, RATE_MAX, RATE_MAX, -RATE_MAX).to_body_state()))
