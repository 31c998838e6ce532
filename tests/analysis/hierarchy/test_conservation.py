"""The loaded spheres' first integrals (analysis.hierarchy.conservation), checked three ways.

1. The verdicts sympy reaches for every member × quantity are the known ones (Chaplygin 1903, Routh 1884, Jellett 1872,
   Borisov & Mamaev 2002).
2. Every witness is exact and honest: γ on the unit sphere, the member's own physical parameters, g ≠ 0 unless the
   quantity is stated at g = 0, and its value of dQ/dt recomputed here from an independent sympy transcription of the
   quantity (sympy.Matrix) and the package's ``body_frame_rhs`` evaluated in exact rational arithmetic.
3. At a random floating-point state the exact symbolic dQ/dt equals a central difference of the numpy invariants
   (``analysis.model.invariants``) along the numpy ``body_frame_rhs``.
"""

from __future__ import annotations

import zlib
from fractions import Fraction

import numpy as np
import pytest
import sympy as sp

from rocknroller.analysis.hierarchy.members import MEMBER_BODIES
from rocknroller.analysis.hierarchy.conservation import (QUANTITIES, derivative_along_flow, exact_value, proof_table,
                                                         prove, symbolic_model)
from rocknroller.analysis.model.body import MEMBERS, Body, LoadedSphere
from rocknroller.analysis.model.equations import body_frame_rhs
from rocknroller.analysis.model.invariants import (borisov_mamaev, contact_momentum, energy, jellett, momentum_squared,
                                                   momentum_vertical, routh)

BALL, ROCKNROLLER, ROUTH, TOP = MEMBERS
EPS = np.finfo(float).eps

#: The known integrals of each member (the hierarchy of Borisov & Mamaev 2002, paper fig. 1).
CONSERVED = {
    BALL: {"energy", "jellett", "momentum_squared", "momentum_vertical", "borisov_mamaev_g0", "borisov_mamaev"},
    ROCKNROLLER: {"energy", "borisov_mamaev_g0"},
    ROUTH: {"energy", "jellett", "routh", "borisov_mamaev_g0"},
    TOP: {"energy", "borisov_mamaev_g0"},
}
WITHOUT_GRAVITY = {q.name: q.without_gravity for q in QUANTITIES}

#: One physical body per member, floats, (c1, c2, c3, I1, I2, I3, g).
PARAMS = {member: body.params for member, body in MEMBER_BODIES.items()}


@pytest.fixture(scope="module")
def table():
    return {(p.member, p.quantity): p for p in proof_table()}


def test_the_table_covers_every_defined_pair(table):
    """7 quantities for the three members with c on the third axis, 6 for the top (Q_R is undefined there)."""
    assert len(table) == 27
    assert (TOP, "routh") not in table
    with pytest.raises(ValueError, match="third axis"):
        prove(TOP, "routh")
    assert proof_table() is proof_table()  # cached


@pytest.mark.parametrize("member", MEMBERS)
def test_verdicts_are_the_known_ones(table, member):
    found = {q for (m, q), p in table.items() if m == member and p.conserved}
    assert found == CONSERVED[member]


def test_conserved_means_a_zero_remainder_and_no_witness(table):
    for p in table.values():
        assert (p.remainder_terms == 0) == p.conserved
        assert (p.witness is None) == p.conserved


def _independent_quantity(quantity: str, params: tuple[Fraction, ...], gamma, omega):
    """The quantity from its definition, by sympy.Matrix (no code shared with the module)."""
    c1, c2, c3, I1, I2, I3, g = (sp.Rational(x.numerator, x.denominator) for x in params)
    c = sp.Matrix([c1, c2, c3])
    r = gamma + c
    K = sp.diag(I1, I2, I3) + r.dot(r) * sp.eye(3) - r * r.T
    M = K * omega
    T = omega.dot(M) / 2
    return {
        "energy": T + g * c.dot(gamma),
        "jellett": M.dot(r),
        "routh": omega[2] ** 2 * (I3 + gamma[0] ** 2 + gamma[1] ** 2 + I3 / I1 * r[2] ** 2),
        "momentum_squared": M.dot(M),
        "momentum_vertical": M.dot(gamma),
        "borisov_mamaev_g0": M.dot(M) - 2 * T * r.dot(r),
        "borisov_mamaev": M.dot(M) - 2 * T * r.dot(r),
    }[quantity]


def test_every_witness_is_exact_and_honest(table):
    """The witness value is dQ/dt = ∇Q·f, recomputed with ∇Q from sympy.diff of an independent transcription and f
    from the package's ``body_frame_rhs`` run on Fractions (exact: it uses only + − × ÷)."""
    for (member, quantity), p in table.items():
        if p.conserved:
            continue
        w = p.witness
        assert sum(x * x for x in w.gamma) == 1
        assert LoadedSphere(*map(float, w.params[3:6]), offset=tuple(map(float, w.params[:3])),
                            g=float(w.params[6])).kind == member
        assert (w.params[6] == 0) == WITHOUT_GRAVITY[quantity]
        xs = sp.symbols("x1:7")
        Q = _independent_quantity(quantity, w.params, sp.Matrix(xs[:3]), sp.Matrix(xs[3:]))
        f = body_frame_rhs([*w.gamma, *w.omega, *[Fraction(0)] * 5], w.params)[:6]
        at = dict(zip(xs, (sp.Rational(v.numerator, v.denominator) for v in (*w.gamma, *w.omega))))
        exact = sum(sp.diff(Q, x).subs(at) * sp.Rational(fx.numerator, fx.denominator) for x, fx in zip(xs, f))
        assert exact != 0
        assert Fraction(int(sp.numer(exact)), int(sp.denom(exact))) == w.value, (member, quantity)


def test_the_reduction_is_the_remainder_modulo_the_sphere():
    """``on_sphere`` equals sympy's general division by γ·γ − 1, leaves no γ3², and does not change the value on the
    sphere."""
    d = derivative_along_flow(ROCKNROLLER, "momentum_squared")
    m = symbolic_model(ROCKNROLLER)
    sphere = sum(g * g for g in m.gamma) - 1
    assert d.reduced == d.numerator.rem(sphere)
    assert max(mon[0] for mon in d.reduced.monoms()) <= 1  # γ3 leads the ring's generators
    point = [Fraction(2, 7), Fraction(3, 7), Fraction(-6, 7)], [Fraction(1), Fraction(-1, 3), Fraction(5)]
    params = tuple(Fraction(x).limit_denominator(1000) for x in PARAMS[ROCKNROLLER])
    assert exact_value(ROCKNROLLER, d.reduced, d.denominator, *point, params) == d.at(*point, params)


def test_jellett_is_the_papers_QJ_for_rouths_sphere():
    """M·r = I1(γ1ω1 + γ2ω2) + I3(γ3 − a)ω3 where I1 = I2 and c = (0, 0, −a), as polynomials and in numpy."""
    m = symbolic_model(ROUTH)
    (g1, g2, g3), (w1, w2, w3), (I1, _, I3) = m.gamma, m.omega, m.inertia
    assert derivative_along_flow(ROUTH, "jellett").value == I1 * (g1 * w1 + g2 * w2) + I3 * (g3 + m.offset[2]) * w3
    gamma, omega = np.array([0.6, 0.0, -0.8]), np.array([0.3, -1.0, 0.7])
    body = Body(0.05, 0.35, 0.35, 0.4, 9.87)
    M, r = contact_momentum(body, gamma, omega), gamma - np.array([0.0, 0.0, 0.05])
    assert abs(M @ r - jellett(body, gamma, omega)) <= 16 * EPS * (np.abs(M) @ np.abs(r))


def test_points_must_satisfy_the_members_constraints():
    d = derivative_along_flow(ROUTH, "energy")
    with pytest.raises(ValueError, match="I2 = I1"):
        d.at((0, 0, 1), (1, 0, 0), (0, 0, -0.05, 0.35, 0.36, 0.4, 9.87))
    with pytest.raises(ValueError, match="g = 0"):
        derivative_along_flow(TOP, "borisov_mamaev_g0").at((0, 0, 1), (1, 0, 0), PARAMS[TOP])
    with pytest.raises(ValueError, match="member must be one of"):
        prove("a cube", "energy")
    with pytest.raises(ValueError, match="quantity must be one of"):
        prove(BALL, "entropy")


def _numpy_quantity(member: str, quantity: str, params):
    """The quantity as the package's numpy invariants compute it, as a function of a state of R⁶."""
    c1, c2, c3, I1, I2, I3, g = params
    sphere = LoadedSphere(I1, I2, I3, offset=(c1, c2, c3), g=g)
    weightless = LoadedSphere(I1, I2, I3, offset=(c1, c2, c3), g=0.0)

    def momentum_along_r(gamma, omega):
        return contact_momentum(sphere, gamma, omega) @ (gamma + np.array([c1, c2, c3]))

    def routh_squared(gamma, omega):
        return routh(Body(-c3, I1, I2, I3, g), gamma, omega) ** 2

    def b_with_gravity(gamma, omega):  # M·M − 2T r·r, T the kinetic energy (the energy at g = 0)
        r = gamma + np.array([c1, c2, c3])
        return momentum_squared(sphere, gamma, omega) - 2.0 * energy(weightless, gamma, omega) * (r @ r)

    functions = {"energy": lambda gamma, omega: energy(sphere, gamma, omega), "jellett": momentum_along_r,
                 "routh": routh_squared,
                 "momentum_squared": lambda gamma, omega: momentum_squared(sphere, gamma, omega),
                 "momentum_vertical": lambda gamma, omega: momentum_vertical(sphere, gamma, omega),
                 "borisov_mamaev_g0": lambda gamma, omega: borisov_mamaev(weightless, gamma, omega),
                 "borisov_mamaev": b_with_gravity}
    return lambda y: float(functions[quantity](y[:3], y[3:6]))


def _abs_scale(poly, point) -> float:
    """Σ |coefficient × monomial| at the point: the size of the terms a float evaluation adds up."""
    return float(sum(abs(float(c)) * np.prod(np.abs(point) ** np.array(e)) for e, c in poly.terms()))


@pytest.mark.parametrize("member, quantity", [(m, q.name) for m in MEMBERS for q in QUANTITIES
                                              if q.defined_for(m)])
def test_symbolic_derivative_matches_numpy_finite_differences(member, quantity):
    """Along the straight line y + s f(y) in R⁶ (f the numpy ``body_frame_rhs``), the central difference
    D(h) = [Q(y + h f) − Q(y − h f)]/2h of the numpy invariant is ∇Q·f + a h² + O(h⁴) (Q is a polynomial in s there,
    so the series is exact), which is what the module's exact dQ/dt gives at the same (float) point.

    Tolerance: the truncation a h² is estimated by Richardson, |D(h) − D(2h)|/3, taken twice; the round-off of each Q
    is at most ~32 ε × S, S the sum of the absolute values of Q's terms at the stencil (the module's polynomial with
    absolute coefficients), so the quotient errs by at most 32 ε S/h."""
    rng = np.random.default_rng(zlib.crc32(f"{member}/{quantity}".encode()))
    gamma = rng.normal(size=3)
    gamma /= np.linalg.norm(gamma)
    omega = rng.normal(size=3)
    params = list(PARAMS[member])
    if WITHOUT_GRAVITY[quantity]:
        params[6] = 0.0
    y = np.concatenate([gamma, omega, [1.0, 0.0, 0.0, 0.0, 0.0]])
    f = np.array(body_frame_rhs(y, params)[:6])
    Q = _numpy_quantity(member, quantity, params)
    d = derivative_along_flow(member, quantity)
    exact = float(d.at(gamma, omega, params))
    h = 1e-4 / max(1.0, float(np.max(np.abs(f))))

    def central(step):
        return (Q(y[:6] + step * f) - Q(y[:6] - step * f)) / (2 * step)

    point = np.concatenate([[gamma[2], gamma[0], gamma[1]], omega, params])
    scale = _abs_scale(d.value, np.abs(point) + 2 * h * np.max(np.abs(f))) / (params[3] if quantity == "routh" else 1)
    tolerance = 2 * abs(central(h) - central(2 * h)) / 3 + 32 * EPS * scale / h
    assert abs(central(h) - exact) <= tolerance, (central(h), exact, tolerance)
    assert tolerance < 1e-6 * max(1.0, scale)  # the check has teeth: far below the size of the terms
