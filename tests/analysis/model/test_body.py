"""Body: validation, paper defaults, the polar-cap parameters of App. A.1 (and its sign erratum)."""

from __future__ import annotations

import math

import numpy as np
import pytest
import roundoff as ro
import sympy as sp
from hypothesis import given
from hypothesis import strategies as st

from rocknroller.analysis.model.body import Body, polar_cap_offset_as_printed, polar_cap_volume

#: Safety margin of the first-order rounding bounds below (their constants are worst cases already).
MARGIN = 2.0


def _polar_cap_rounding(d: float) -> dict[str, float]:
    """Relative rounding bounds of Body.from_polar_cap(d)'s V, a, I3, I1 against the exact values at the same
    double d (first order; analysis/model/body.py's formulas, Higham's γ_n for each sum, every term's own rounding:
    a rounded constant u, d**k by pow ≤ 1 ulp = 2u, each product or quotient u).

    V = π (2/3 + d − d³/3); a = (π/4)(1 − d²)²/V; I3 = (π/2)(8/15 + d − 2d³/3 + d⁵/5)/V; I1 = I3 − a (d + a).
    A sum of terms with relative errors ≤ k u, added with m roundings, errs by ≤ γ_{k+m} Σ|terms|.
    """
    u, g = ro.u, ro.gamma
    tV = np.abs([2 / 3, d, d**3 / 3])
    rV = g(5) * tV.sum() / abs(2 / 3 + d - d**3 / 3) + g(2)                   # bracket; π and the product
    one_m = abs(1 - d * d)
    ra = 2 * (g(2) * (1 + d * d) / one_m) + g(4) + rV                          # (1 − d²)², π/4, ×, /V
    tI3 = np.abs([8 / 15, d, 2 * d**3 / 3, d**5 / 5])
    rI3 = g(7) * tI3.sum() / abs(8 / 15 + d - 2 * d**3 / 3 + d**5 / 5) + g(3) + rV
    a = (math.pi / 4) * (1 - d * d) ** 2 / polar_cap_volume(d)
    I3 = (math.pi / 2) * (8 / 15 + d - 2 * d**3 / 3 + d**5 / 5) / polar_cap_volume(d)
    gap = a * (d + a)
    rgap = ra * (1 + abs(a) / abs(d + a)) + g(2) * (abs(d) + abs(a)) / abs(d + a) if gap else 0.0
    rI1 = (abs(I3) * rI3 + abs(gap) * rgap) / abs(I3 - gap) + u
    return {"V": rV, "a": ra, "I3": rI3, "I1": rI1}


def test_paper_defaults():
    b = Body.paper()
    assert (b.a, b.I3, b.g) == (0.05, 0.4, 9.87)
    # I1 = (1 − 2.5 a) I3: three roundings, and the representation of 0.05, 0.4, 0.35 (u each, entering with
    # weights 2.5a/(1 − 2.5a) = 1/7, 1 and 1): ≤ γ_3 + (15/7) u < γ_6
    ro.assert_within(b.I1 / 0.35 - 1, MARGIN * ro.gamma(6), "rel", 1.0)
    assert b.I2 == b.I1 and b.epsilon == 0.0 and b.is_symmetric


def test_epsilon_roundtrip():
    b = Body.paper(1e-3)
    # I2 = (1 + ε) I1 against 1.001 I1: 1 + ε rounds (u), 1e-3 and 1.001 are represented (u, ε u), two products
    ro.assert_within(b.I2 / (1.001 * b.I1) - 1, MARGIN * ro.gamma(4), "rel", 1.0)
    # ε = (I2 − I1)/I1: I2 carries 2u of itself (1 + ε, the product), I2 − I1 is exact (Sterbenz) and so loses
    # (1 + ε)/ε of relative precision; the division rounds and 1e-3 is represented: ≤ (2 + 2(1 + ε)/ε) u
    for eps, got in ((1e-3, b.epsilon), (0.02, b.with_epsilon(0.02).epsilon)):
        ro.assert_within(got / eps - 1, MARGIN * (2 + 2 * (1 + eps) / eps) * ro.u, "epsilon", 1.0)
    assert b.symmetric().I2 == b.I1


@pytest.mark.parametrize(
    "kwargs, fragment",
    [
        (dict(a=1.0, I1=0.35, I2=0.35, I3=0.4, g=9.87), "0 <= a < 1"),
        (dict(a=-0.1, I1=0.35, I2=0.35, I3=0.4, g=9.87), "0 <= a < 1"),
        (dict(a=0.05, I1=0.0, I2=0.35, I3=0.4, g=9.87), "I1 must be > 0"),
        (dict(a=0.05, I1=0.35, I2=0.35, I3=-0.4, g=9.87), "I3 must be > 0"),
        (dict(a=0.05, I1=0.36, I2=0.35, I3=0.4, g=9.87), "I1 <= I2"),
        (dict(a=0.05, I1=0.35, I2=0.4, I3=0.4, g=9.87), "I2 < I3"),
        (dict(a=0.05, I1=0.1, I2=0.2, I3=0.4, g=9.87), "triangle inequality"),
        (dict(a=0.05, I1=0.35, I2=0.35, I3=0.4, g=-1e-300), "g must be >= 0"),
        (dict(a=float("nan"), I1=0.35, I2=0.35, I3=0.4, g=9.87), "a must be a finite"),
        (dict(a=0.05, I1=0.35, I2=float("inf"), I3=0.4, g=9.87), "I2 must be a finite"),
    ],
)
def test_bad_parameters_are_named(kwargs, fragment):
    with pytest.raises(ValueError, match=fragment.replace("(", r"\(").replace("+", r"\+")):
        Body(**kwargs)


def test_bad_epsilon():
    with pytest.raises(ValueError, match="epsilon"):
        Body.paper(-1e-3)
    with pytest.raises(ValueError, match="epsilon"):
        Body.paper(0.2)  # I2 = 1.2 I1 > I3


def test_frozen():
    with pytest.raises(AttributeError):
        Body.paper().a = 0.1  # type: ignore[misc]


@given(st.floats(min_value=-0.95, max_value=1.0))
def test_polar_cap_bodies_are_valid(d):
    """A valid body with its asymmetry I3 − I1 = a(d + a) resolved, or (d within ~6e-6 of 1, where
    I3 − I1 ≈ (3/4)(1 − d)² vanishes beside I3 in double precision) a ValueError that says so."""
    try:
        b = Body.from_polar_cap(d)
    except ValueError as exc:
        assert d > 1.0 - 1e-5 and ("too close to 1" in str(exc) or "-1 < d < 1" in str(exc))
        return
    assert 0.0 <= b.a < 1.0 and b.I1 < b.I3
    # I1 against the textbook form π(4/15 + d/4 + d³/6 − 3d⁵/20)/V − a².  Both forms divide by V, whose
    # bracket 2/3 + d − d³/3 (like the numerators) cancels to O((1 + d)²) as d → −1 (0.0025 at d = −0.95).
    # Bound: the library's rounding (``_polar_cap_rounding``) plus the direct form's: its bracket (terms with
    # ≤ 4u each, three additions: γ_7 Σ|terms|), π, the product and /V (γ_2 and V's error), a² (2 rel(a) + u)
    # and the final subtraction; × MARGIN.  Nothing cancels in the direct form as d → 1 (only I3 − I1 does).
    V = polar_cap_volume(d)
    p = 4 / 15 + d / 4 + d**3 / 6 - 3 * d**5 / 20
    I1_direct = math.pi * p / V - b.a**2
    r = _polar_cap_rounding(d)
    t_p = abs(4 / 15) + abs(d / 4) + abs(d**3 / 6) + abs(3 * d**5 / 20)
    err_direct = (math.pi / V) * (ro.gamma(7) * t_p + abs(p) * (ro.gamma(3) + r["V"])) \
        + b.a**2 * (2 * r["a"] + ro.u) + ro.u * abs(I1_direct)
    ro.assert_within(b.I1 - I1_direct, MARGIN * (abs(b.I1) * r["I1"] + err_direct), "I1", b.I1)


def test_polar_cap_moment_gap_identity():
    """I3 − I1 = a(d + a) for every d (sympy, exact integration with symbolic d): the form
    Body.from_polar_cap uses, free of cancellation as d → 1."""
    d = sp.symbols("d", real=True)
    _, a, I3, I1 = _truncated_ball_exact(d)
    assert sp.simplify(I3 - I1 - a * (d + a)) == 0
    for bad in (1.0, 1.0 - 1e-7, 1.0 - 1e-15):
        with pytest.raises(ValueError, match="d < 1|too close to 1"):
            Body.from_polar_cap(bad)


def _truncated_ball_exact(d_value: sp.Rational):
    """Mass, centroid height and moments of the unit ball cut at z = d, by exact integration (sympy)."""
    z, rho = sp.symbols("z rho", real=True)
    d = d_value
    R2 = 1 - z**2  # squared radius of the slice at height z
    V = sp.integrate(sp.pi * R2, (z, -1, d))
    zc = sp.integrate(sp.pi * R2 * z, (z, -1, d)) / V
    # disc of radius R: ∫ (x²+y²) dA = π R⁴/2; ∫ x² dA = π R⁴/4
    I3 = sp.integrate(sp.pi * R2**2 / 2, (z, -1, d)) / V
    I1_centre = sp.integrate(sp.pi * R2**2 / 4 + sp.pi * R2 * z**2, (z, -1, d)) / V
    return V, -zc, I3, I1_centre - zc**2


@pytest.mark.parametrize("d", [sp.Rational(3, 5), sp.Rational(0), sp.Rational(-1, 3), sp.Rational(9, 10)])
def test_polar_cap_against_exact_integration(d):
    """Against the exact values at the rational d: the rounding of the formulas (``_polar_cap_rounding``) plus
    the representation of d as a double (u |d| relative), carried by each quantity's condition number
    |d f'(d)/f(d)| (sympy, exact), plus the rounding of the exact value to a double (u); × MARGIN."""
    exact = dict(zip(("V", "a", "I3", "I1"), _truncated_ball_exact(d)))
    x = sp.symbols("x", real=True)
    symbolic = dict(zip(("V", "a", "I3", "I1"), _truncated_ball_exact(x)))
    b = Body.from_polar_cap(float(d))
    r = _polar_cap_rounding(float(d))
    got = {"V": polar_cap_volume(float(d)), "a": b.a, "I3": b.I3, "I1": b.I1}
    for name, want in exact.items():
        f = symbolic[name]
        cond = abs(float((x * sp.diff(f, x) / f).subs(x, d)))
        bound = MARGIN * (r[name] + cond * ro.u + ro.u)
        ro.assert_within(got[name] / float(want) - 1, bound, name, 1.0)


def test_polar_cap_printed_sign_is_wrong():
    """Paper App. A.1 prints a = (π/4)(d²(2 − d²) − 1)/V, which is negative for every |d| < 1."""
    d = 0.6
    printed = polar_cap_offset_as_printed(d)
    assert printed < 0 < Body.from_polar_cap(d).a
    # same π/4 and V; the brackets differ: d²(2 − d²) − 1 cancels (4 roundings on terms of size d²(2 − d²) + 1
    # against |result| (1 − d²)²), (1 − d²)² has 2 γ_2 (1 + d²)/(1 − d²) + u; the products and quotients: γ_4
    cancel = (d * d * (2 - d * d) + 1) / (1 - d * d) ** 2
    bound = ro.gamma(4) * cancel + 2 * ro.gamma(2) * (1 + d * d) / (1 - d * d) + ro.gamma(5)
    ro.assert_within(printed / -Body.from_polar_cap(d).a - 1, MARGIN * bound, "rel", 1.0)


def test_polar_cap_bowling_ball_matches_paper_to_printed_digits():
    """Paper App. A.1: d = 0.6 gives a = 0.085, I1 = 0.362, I3 = 0.42 (as printed, 2-3 digits)."""
    b = Body.from_polar_cap(0.6)
    assert abs(b.a - 0.085) < 1e-3
    assert abs(b.I1 - 0.362) < 5e-4 and abs(b.I3 - 0.42) < 5e-3


def test_hemisphere():
    """d = 0: centroid at 3/8, I3 = 2/5 (classical values, independent of the App. A.1 formulas)."""
    b = Body.from_polar_cap(0.0)
    r = _polar_cap_rounding(0.0)  # the rounding of the formulas; 3/8 is exact, 2/5 and 2/5 − 9/64 round (u, 2u)
    ro.assert_within(b.a / (3 / 8) - 1, MARGIN * r["a"], "rel", 1.0)
    ro.assert_within(b.I3 / (2 / 5) - 1, MARGIN * (r["I3"] + ro.u), "rel", 1.0)
    ro.assert_within(b.I1 / (2 / 5 - (3 / 8) ** 2) - 1, MARGIN * (r["I1"] + ro.gamma(2) * (2 / 5) / (2 / 5 - 9 / 64)),
                     "rel", 1.0)


def test_polar_cap_bad_d():
    for d in (-1.0, 1.5, float("nan")):
        with pytest.raises(ValueError, match="d"):
            Body.from_polar_cap(d)


@pytest.mark.parametrize("eps, shown", [(1e-3, "0.001"), (1e-8, "1e-08"), (0.1, "0.1"), (0.0, "0")])
def test_epsilon_is_shown_to_the_digits_it_resolves(eps, shown):
    """``describe`` (CSV headers, reports) showed ε = (I2 − I1)/I1 with its round-off: 0.0009999999999998899 for
    ``--eps 1e-3``.  Shown to the digits the subtraction resolves, the requested ε reads back exactly, while the
    value itself stays the computed one."""
    body = Body.paper(eps)
    assert body.epsilon_text() == shown and f"epsilon={shown}" in body.describe()
    assert float(shown) == pytest.approx(body.epsilon, rel=0, abs=4 * 2.2e-16)
