"""The loaded-sphere family's body (analysis/model/body.py, LoadedSphere) and its general equations
(analysis/model/equations.py, body_frame_rhs with seven parameters), checked against a sympy derivation of our own:
Newton–Euler about the mass centre with the contact reaction kept as an unknown (six linear equations), which the
production form eliminates by hand."""

from __future__ import annotations

import math
import random

import numpy as np
import pytest
import sympy as sp

import rocknroller as rr
from rocknroller.analysis.model.body import MEMBERS, LoadedSphere
from rocknroller.analysis.model.equations import body_frame_rhs
from rocknroller.analysis.model.invariants import energy, jellett, routh

U = np.finfo(float).eps / 2


@pytest.mark.parametrize("kwargs, message", [
    (dict(I1=0.0, I2=0.3, I3=0.4, offset=(0, 0, 0)), "I1 must be > 0"),
    (dict(I1=0.1, I2=0.1, I3=0.4, offset=(0, 0, 0)), "triangle inequality: I3"),
    (dict(I1=0.3, I2=0.3, I3=0.4, offset=(0.6, 0.6, 0.6)), "|c| < 1"),
    (dict(I1=0.3, I2=0.3, I3=0.4, offset=(0.1, 0.2)), "offset must be three real numbers"),
    (dict(I1=0.3, I2=0.3, I3=0.4, offset=5), "offset must be three real numbers"),
    (dict(I1=0.3, I2=0.3, I3=0.4, offset=(0, math.nan, 0)), "offset c2 must be a finite real number"),
    (dict(I1=0.3, I2=0.3, I3=0.4, offset=(0, 0, 0), g=-1.0), "g must be >= 0"),
])
def test_bad_parameters_are_refused_naming_the_parameter(kwargs, message):
    kwargs.setdefault("g", 9.87)
    with pytest.raises(ValueError, match=message.replace("|", r"\|")):
        LoadedSphere(**kwargs)


def test_moments_in_any_order_and_the_members_named():
    assert LoadedSphere(0.4, 0.3, 0.35, (0, 0, 0), 9.87).kind == MEMBERS[0] == "Chaplygin's ball"
    assert LoadedSphere(0.35, 0.36, 0.4, (0, 0, -0.05), 9.87).kind == "rock'n'roller"
    assert LoadedSphere(0.36, 0.4, 0.36, (0, 0.05, 0), 9.87).kind == "Routh's sphere"  # symmetric about axis 2
    assert LoadedSphere(0.35, 0.36, 0.4, (0.01, 0, -0.05), 9.87).kind == "Chaplygin's top"
    assert rr.Body.paper(1e-3).kind == "rock'n'roller" and rr.Body.paper().kind == "Routh's sphere"
    assert rr.Body(a=0.0, I1=0.35, I2=0.36, I3=0.4, g=9.87).kind == "Chaplygin's ball"


def test_on_axis_attributes_and_paper_quantities_refuse_a_loaded_sphere():
    top = rr.Body.chaplygin_top(0.35, 0.37, 0.4, offset=(0.03, -0.02, -0.05))
    for name in ("a", "epsilon", "symmetric", "is_symmetric"):
        with pytest.raises(ValueError, match=f"{name} is defined only for a mass centre on the third principal axis"):
            getattr(top, name)
    with pytest.raises(AttributeError):
        top.no_such_attribute
    gamma, omega = np.array([0.6, 0.0, -0.8]), np.array([0.1, 0.2, -0.3])
    for f, what in ((jellett, "Q_J"), (routh, "Q_R")):
        with pytest.raises(ValueError, match=f"{what} .* is defined for a mass centre on the third principal axis"):
            f(top, gamma, omega)
    with pytest.raises(ValueError, match="to_body needs the mass centre on the third principal axis"):
        top.to_body()


def test_a_body_and_its_loaded_sphere_are_the_same_body():
    body = rr.Body.paper(1e-3)
    sphere = body.as_loaded_sphere()
    assert sphere.to_body() == body and sphere.offset == body.offset == (0.0, 0.0, -0.05)
    rng = np.random.default_rng(3)
    gamma = rng.normal(size=(3, 50))
    gamma /= np.linalg.norm(gamma, axis=0)
    omega = rng.normal(size=(3, 50))
    # V = g a (1 - γ3) and g(|c| + c·γ) = g(a - a γ3) differ by the rounding of a few operations on terms ≤ E + 2ga
    E1, E2 = energy(body, gamma, omega), energy(sphere, gamma, omega)
    assert np.all(np.abs(E1 - E2) <= 8 * U * (np.abs(E1) + 2 * body.g * body.a))


def _random_states(rng: np.random.Generator, n: int) -> np.ndarray:
    y = rng.normal(size=(11, n))
    y[0:3] /= np.linalg.norm(y[0:3], axis=0)
    return y


def test_the_general_form_on_the_axis_is_the_on_axis_form_to_round_off():
    """The seven-parameter form at c = (0, 0, −a) differs from the five-parameter one only in the rounding of the
    gravity torque: g(γ2 c3 − γ3 c2) = g·(−a γ2) against (g a)·γ2, at most 2u of g a|γ| apart.  The solve K ω̇ = P by
    the adjugate carries that difference to ω̇ as |ΔP|·‖K⁻¹‖ (K ≥ I_min), and rounds both sides the same way
    otherwise; × 8 margin for the adjugate's own rounding of the differing component."""
    rng = np.random.default_rng(7)
    y = _random_states(rng, 200)
    a, I1, I2, I3, g = 0.05, 0.35, 0.36, 0.4, 9.87
    on_axis = np.array(body_frame_rhs(y, (a, I1, I2, I3, g)))
    general = np.array(body_frame_rhs(y, (0.0, 0.0, -a, I1, I2, I3, g)))
    assert np.array_equal(on_axis[[0, 1, 2, 6, 7, 8, 9, 10]], general[[0, 1, 2, 6, 7, 8, 9, 10]])
    scale = np.max(np.abs(on_axis[3:6]), axis=0) + 2 * U * g * a / I1
    assert np.all(np.abs(on_axis[3:6] - general[3:6]) <= 8 * 2 * U * g * a / I1 + 8 * U * scale)


def _newton_euler_with_reaction():
    """The six Newton–Euler equations of a loaded sphere with the reaction R an unknown, linear in (ω̇, R):
    R − g γ = a_G (unit mass), I ω̇ + ω × Iω = (−r) × R, a_G = ω̇ × r + ω × γ̇ + ω × (ω × r), r = γ + c, γ̇ = γ × ω."""
    g1, g2, g3, w1, w2, w3, c1, c2, c3, I1, I2, I3, grav = sp.symbols("g1 g2 g3 w1 w2 w3 c1 c2 c3 I1 I2 I3 grav")
    wd = sp.Matrix(sp.symbols("wd1 wd2 wd3"))
    R = sp.Matrix(sp.symbols("R1 R2 R3"))
    gam, om, c = sp.Matrix([g1, g2, g3]), sp.Matrix([w1, w2, w3]), sp.Matrix([c1, c2, c3])
    r = gam + c
    I = sp.diag(I1, I2, I3)
    gdot = gam.cross(om)
    acc = wd.cross(r) + om.cross(gdot) + om.cross(om.cross(r))
    eqs = list(R - grav * gam - acc) + list(I * wd + om.cross(I * om) + r.cross(R))
    return (g1, g2, g3, w1, w2, w3, c1, c2, c3, I1, I2, I3, grav), list(wd) + list(R), eqs


def test_the_general_equations_agree_with_newton_euler_with_the_reaction_kept():
    """At random exact rational states (γ on the unit sphere exactly, from Pythagorean quadruples) and parameters, the
    production ω̇ equals the solution of the six Newton–Euler equations exactly, in rational arithmetic."""
    args, unknowns, eqs = _newton_euler_with_reaction()
    A, b = sp.linear_eq_to_matrix(eqs, unknowns)
    rnd = random.Random(11)
    quadruples = [(1, 2, 2, 3), (2, 3, 6, 7), (1, 4, 8, 9), (2, 6, 9, 11), (6, 6, 7, 11)]
    for _ in range(8):
        p, q, s, n = rnd.choice(quadruples)
        gamma = [sp.Rational(rnd.choice((-1, 1)) * v, n) for v in rnd.sample((p, q, s), 3)]
        omega = [sp.Rational(rnd.randint(-9, 9), rnd.randint(1, 5)) for _ in range(3)]
        c = [sp.Rational(rnd.randint(-9, 9), 100) for _ in range(3)]
        moments = [sp.Rational(rnd.randint(30, 40), 100) for _ in range(3)]
        grav = sp.Rational(987, 100)
        values = dict(zip(args, [*gamma, *omega, *c, *moments, grav]))
        solution = A.subs(values).LUsolve(b.subs(values))
        ours = body_frame_rhs([*gamma, *omega, 1, 0, 0, 0, 0], (*c, *moments, grav))[3:6]
        assert [sp.simplify(v - solution[i]) for i, v in enumerate(ours)] == [0, 0, 0]
