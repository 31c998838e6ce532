"""Laurent expansions of V_φ and V_ψ about θ = 0 and θ = π (issue 4)."""

from __future__ import annotations

import mpmath
import numpy as np
import pytest
import roundoff as ro
import sympy as sp

from rocknroller.analysis.criticality import lines as C
from rocknroller.analysis.criticality.laurent import (SYMBOLS, V_phi_sym, V_psi_sym, laurent_coefficients,
                                                      laurent_function, laurent_series, phidot_turning_point_errors)
from rocknroller.analysis.model.body import Body
from rocknroller.analysis.model.invariants import V_phi, V_psi
from rocknroller.papers.averaging_check import loglog_slope

#: Safety margin of the rounding bounds below.
MARGIN = 4.0

BODY = Body.paper()
OTHER = Body(a=0.2, I1=0.3, I2=0.3, I3=0.5, g=9.81)
S = SYMBOLS
ARGS = (S["x"], S["QJ"], S["QR"], S["a"], S["I1"], S["I3"])
EXACT = {"phi": V_phi_sym, "psi": V_psi_sym}


def _by_name(lam):
    """A lambdified function of ARGS called with keyword arguments x, QJ, QR, a, I1, I3 (for roundoff.formula_bound)."""
    return lambda x, QJ, QR, a, I1, I3: lam(x, QJ, QR, a, I1, I3)


def _subs(body, QJ, QR):
    """Exact rationals (the binary values of the doubles), so that sp.N(…, 40) really has 40 digits."""
    vals = {S["a"]: body.a, S["I1"]: body.I1, S["I3"]: body.I3, S["QJ"]: QJ, S["QR"]: QR}
    return {k: sp.Rational(v) for k, v in vals.items()}


def test_exact_sympy_rates_equal_invariants():
    """The symbolic V_φ, V_ψ used for the derivations equal rocknroller.analysis.model.invariants' (paper eqs. phidotCJQR, psidotCJQR)."""
    th = np.linspace(0.1, 3.0, 7)
    for q, num in (("phi", V_phi), ("psi", V_psi)):
        expr = EXACT[q](S["theta"])
        f = sp.lambdify((S["theta"], S["QJ"], S["QR"], S["a"], S["I1"], S["I3"]), expr, "numpy")
        got = f(th, 0.3, -0.2, BODY.a, BODY.I1, BODY.I3)
        # two double evaluations: sympy's operations (count_ops) and rocknroller.analysis.model.invariants' (≤ 30), each within
        # γ_n × the condition Σ|xᵢ ∂f/∂xᵢ| over θ, Q_J, Q_R, a, I1, I3 (``roundoff.formula_bound``), × MARGIN
        n_ops = int(sp.count_ops(expr)) + 30
        bound = MARGIN * ro.formula_bound(lambda theta, QJ, QR, a, I1, I3: f(theta, QJ, QR, a, I1, I3),
                                          {"theta": th, "QJ": 0.3, "QR": -0.2, "a": BODY.a, "I1": BODY.I1,
                                           "I3": BODY.I3}, n_ops)
        ro.assert_within(got - num(th, QR=-0.2, QJ=0.3, body=BODY), bound, q, got)


def test_leading_terms_reproduce_the_paper():
    """A₋₂ = ±(Q_J − Q_J,e^crit)/I1 with the paper's ρ₀, ρ_π (eqs. phidotCJQR th=0, th=pi); odd powers vanish."""
    a, I1, I3, QJ, QR = S["a"], S["I1"], S["I3"], S["QJ"], S["QR"]
    rho0 = 1 / sp.sqrt(I3 + I3 / I1 * (1 - a) ** 2)
    rhopi = 1 / sp.sqrt(I3 + I3 / I1 * (1 + a) ** 2)
    crit0, critpi = rho0 * (1 - a) * I3 * QR, -rhopi * (1 + a) * I3 * QR
    expected = {("phi", "0"): (QJ - crit0) / I1, ("phi", "pi"): (QJ - critpi) / I1,
                ("psi", "0"): -(QJ - crit0) / I1, ("psi", "pi"): (QJ - critpi) / I1}
    for (q, about), lead in expected.items():
        co = laurent_coefficients(q, about, 3)
        assert sp.simplify(co[-2] - lead) == 0
        for k in (-1, 1, 3):
            assert sp.expand(co[k]) == 0
        assert sp.expand(co[0]) != 0  # the O(1) term is given (and non-trivial)


@pytest.mark.parametrize("quantity", ["phi", "psi"])
@pytest.mark.parametrize("about", ["0", "pi"])
def test_coefficients_agree_with_sympy_series(quantity, about):
    """Independent derivation: sympy.series of the exact expression, compared at 40 digits for random values."""
    x = S["x"]
    th = x if about == "0" else sp.pi - x
    ref = sp.series(EXACT[quantity](th), x, 0, 5).removeO()
    ours = laurent_series(quantity, about, 4)
    for body, QJ, QR in ((BODY, 0.3, -0.2), (OTHER, -0.05, 0.7)):
        sub = _subs(body, QJ, QR)
        for k in range(-2, 5):
            r = sp.N(ref.coeff(x, k).subs(sub), 40)
            o = sp.N(ours.coeff(x, k).subs(sub), 40)
            # two 40-digit evaluations of the same exact number (10⁻⁴⁰ per operation, a few hundred operations,
            # moderate cancellation): 1e-30 leaves a factor ≥ 10⁶; not a double-precision comparison
            assert abs(r - o) <= 1e-30 * (1 + abs(r))


@pytest.mark.parametrize("body", [BODY, OTHER])
@pytest.mark.parametrize("quantity", ["phi", "psi"])
@pytest.mark.parametrize("about", ["0", "pi"])
def test_truncation_error_falls_with_first_omitted_power(body, quantity, about):
    """Error of the series truncated at order n at θ = x (about 0) or π − x (about π) ∝ x^{n+2}
    (the next power, odd ones vanish).  Exact values and series at 40 digits (mpmath); slope fitted."""
    QJ, QR = 0.0123, -0.0456
    xs = [mpmath.mpf(2) ** -k for k in range(5, 11)]
    with mpmath.workdps(40):
        th = S["x"] if about == "0" else sp.pi - S["x"]
        exact = sp.lambdify(ARGS, EXACT[quantity](th), "mpmath")
        vals = dict(QJ=mpmath.mpf(QJ), QR=mpmath.mpf(QR), a=mpmath.mpf(body.a), I1=mpmath.mpf(body.I1),
                    I3=mpmath.mpf(body.I3))
        ex = [exact(x, vals["QJ"], vals["QR"], vals["a"], vals["I1"], vals["I3"]) for x in xs]
        for n in (-2, 0, 2, 4):
            ser = sp.lambdify(ARGS, laurent_series(quantity, about, n), "mpmath")
            err = [abs(ser(x, vals["QJ"], vals["QR"], vals["a"], vals["I1"], vals["I3"]) - e) for x, e in zip(xs, ex)]
            slope = loglog_slope([float(x) for x in xs], [float(e) for e in err])
            assert abs(slope - (n + 2)) < 0.05, (n, slope)


def test_numeric_function_matches_series():
    """laurent_function (lambdify, numpy) equals the 40-digit series to rounding; vectorised."""
    xs = np.array([0.3, 0.1, 0.01])
    for q in ("phi", "psi"):
        for about in ("0", "pi"):
            fn = laurent_function(q, about, 4, BODY)
            ser = sp.lambdify(ARGS, laurent_series(q, about, 4), "mpmath")
            got = fn(xs, QR=-0.0456, QJ=0.0123)
            with mpmath.workdps(40):
                ref = [float(ser(mpmath.mpf(x), mpmath.mpf(0.0123), mpmath.mpf(-0.0456), mpmath.mpf(BODY.a),
                                 mpmath.mpf(BODY.I1), mpmath.mpf(BODY.I3))) for x in xs]
            # the series' operations (count_ops) in double, each within γ_n × its condition over x, Q_J, Q_R and
            # the body's parameters (``roundoff.formula_bound``), + the rounding of the 40-digit value (u); × MARGIN
            expr = laurent_series(q, about, 4)
            lam = sp.lambdify(ARGS, expr, "numpy")
            cond = ro.formula_bound(_by_name(lam), {"x": xs, "QJ": 0.0123, "QR": -0.0456, "a": BODY.a, "I1": BODY.I1,
                                          "I3": BODY.I3}, int(sp.count_ops(expr)))
            ro.assert_within(got - np.array(ref), MARGIN * (cond + ro.u * np.abs(ref)), f"{q} about {about}", ref)


def test_phidot_at_theta_X_high_QR():
    """Paper §numerics "Recession and Criticality": at Q_R = 0.1 and θ_X = 0.95π, each added order improves the prediction of φ̇(θ_X).

    On the line Q_J = Q_J,π^crit the leading term predicts φ̇ = 0 (100 % error); O(1) brings it to a few %,
    each further even order by a factor ~ (π − θ_X)² × O(1)."""
    theta_X = 0.95 * np.pi
    QR = 0.1
    for offset in (0.0, 1e-3, -1e-3):
        QJ = float(C.QJ_crit_pi(QR, BODY)) + offset
        res = phidot_turning_point_errors(BODY, theta_X, QR, QJ, orders=(-2, 0, 2, 4, 6))
        errs = [res[n]["rel_error"] for n in (-2, 0, 2, 4, 6)]
        assert all(e2 < 0.1 * e1 for e1, e2 in zip(errs, errs[1:])), errs
    # the leading order is exactly zero on the line, i.e. 100 % off
    QJ = float(C.QJ_crit_pi(QR, BODY))
    on = phidot_turning_point_errors(BODY, theta_X, QR, QJ, orders=(-2,))
    # the leading term A₋₂/x² vanishes on the line up to its rounding: γ_n (n = count_ops of the term) × its
    # condition over Q_J, Q_R and the parameters (the cancellation Q_J − ρ_π (1 + a) I3 Q_R), relative to the
    # exact φ̇; the relative error itself rounds twice; × MARGIN
    expr = laurent_series("phi", "pi", -2)
    lam = sp.lambdify(ARGS, expr, "numpy")
    xv = np.pi - theta_X
    lead = ro.formula_bound(_by_name(lam), {"x": xv, "QJ": QJ, "QR": QR, "a": BODY.a, "I1": BODY.I1, "I3": BODY.I3},
                            int(sp.count_ops(expr)))
    bound = MARGIN * (float(lead) / abs(on[-2]["exact"]) + ro.gamma(2))
    ro.assert_within(on[-2]["rel_error"] - 1.0, bound, "rel_error", 1.0)


def test_errors():
    with pytest.raises(ValueError, match="about must be 0 or 'pi'"):
        laurent_coefficients("phi", 1.0, 2)
    with pytest.raises(ValueError, match="quantity"):
        laurent_coefficients("theta", "0", 2)
    with pytest.raises(ValueError, match="order"):
        laurent_coefficients("phi", "0", -3)
    with pytest.raises(ValueError, match="symmetric"):
        laurent_function("phi", "0", 2, Body.paper(1e-3))
    with pytest.raises(ValueError, match="x"):
        laurent_function("phi", "0", 2, BODY)(np.array([0.1, -0.1]), QR=0.1, QJ=0.1)
    with pytest.raises(ValueError, match="theta_X"):
        phidot_turning_point_errors(BODY, np.pi, 0.1, 0.0)
