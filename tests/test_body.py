"""Body: validation, paper defaults, the polar-cap parameters of App. A.1 (and its sign erratum)."""

from __future__ import annotations

import math

import pytest
import sympy as sp
from hypothesis import given
from hypothesis import strategies as st

from rocknroller.analysis.body import Body, polar_cap_offset_as_printed, polar_cap_volume


def test_paper_defaults():
    b = Body.paper()
    assert (b.a, b.I3, b.g) == (0.05, 0.4, 9.87)
    assert b.I1 == pytest.approx(0.35, rel=1e-15)  # the paper's stated I1
    assert b.I2 == b.I1 and b.epsilon == 0.0 and b.is_symmetric


def test_epsilon_roundtrip():
    b = Body.paper(1e-3)
    assert b.I2 == pytest.approx(1.001 * b.I1, rel=1e-15)
    assert b.epsilon == pytest.approx(1e-3, rel=1e-12)
    assert b.with_epsilon(0.02).epsilon == pytest.approx(0.02, rel=1e-12)
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
        (dict(a=0.05, I1=0.35, I2=0.35, I3=0.4, g=0.0), "g must be > 0"),
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
    # bracket 2/3 + d − d³/3 (like the numerators) cancels to O((1 + d)²) as d → −1 (0.0025 at d = −0.95):
    # each carries an absolute error of a few 1e-16 over V/π (measured ≤ 4e-16 π/V), i.e. a few ulps of
    # I1 = O(0.4) away from d = −1.  Nothing cancels in the direct form as d → 1 (only I3 − I1 does).
    V = polar_cap_volume(d)
    I1_direct = math.pi * (4 / 15 + d / 4 + d**3 / 6 - 3 * d**5 / 20) / V - b.a**2
    assert b.I1 == pytest.approx(I1_direct, rel=0, abs=1e-15 * math.pi / V)


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
    V, a, I3, I1 = _truncated_ball_exact(d)
    b = Body.from_polar_cap(float(d))
    assert polar_cap_volume(float(d)) == pytest.approx(float(V), rel=1e-14)
    assert b.a == pytest.approx(float(a), rel=1e-13)
    assert b.I3 == pytest.approx(float(I3), rel=1e-13)
    assert b.I1 == pytest.approx(float(I1), rel=1e-13)


def test_polar_cap_printed_sign_is_wrong():
    """Paper App. A.1 prints a = (π/4)(d²(2 − d²) − 1)/V, which is negative for every |d| < 1."""
    d = 0.6
    printed = polar_cap_offset_as_printed(d)
    assert printed < 0 < Body.from_polar_cap(d).a
    assert printed == pytest.approx(-Body.from_polar_cap(d).a, rel=1e-15)


def test_polar_cap_bowling_ball_matches_paper_to_printed_digits():
    """Paper App. A.1: d = 0.6 gives a = 0.085, I1 = 0.362, I3 = 0.42 (as printed, 2-3 digits)."""
    b = Body.from_polar_cap(0.6)
    assert abs(b.a - 0.085) < 1e-3
    assert abs(b.I1 - 0.362) < 5e-4 and abs(b.I3 - 0.42) < 5e-3


def test_hemisphere():
    """d = 0: centroid at 3/8, I3 = 2/5 (classical values, independent of the App. A.1 formulas)."""
    b = Body.from_polar_cap(0.0)
    assert b.a == pytest.approx(3 / 8, rel=1e-15)
    assert b.I3 == pytest.approx(2 / 5, rel=1e-15)
    assert b.I1 == pytest.approx(2 / 5 - (3 / 8) ** 2, rel=1e-15)


def test_polar_cap_bad_d():
    for d in (-1.0, 1.5, float("nan")):
        with pytest.raises(ValueError, match="d"):
            Body.from_polar_cap(d)
