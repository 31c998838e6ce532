"""Invariant densities of the loaded spheres (analysis.hierarchy.measure).

The verdicts are the known ones where they are known (Chaplygin's (det K)^(−1/2) in (γ, M) for the ball; the paper's
ρ for Routh's sphere), and the new ones carry exact witnesses; the exact divergence and div(ρ f)/ρ agree with central
differences of the numpy ``body_frame_rhs`` at random states.
"""

from __future__ import annotations

import zlib

import numpy as np
import pytest

from rocknroller.analysis.hierarchy.members import MEMBER_BODIES
from rocknroller.analysis.hierarchy.conservation import symbolic_model
from rocknroller.analysis.hierarchy.measure import (DENSITIES, check_density, flow_divergence, measure,
                                                    measure_table)
from rocknroller.analysis.model.body import MEMBERS
from rocknroller.analysis.model.equations import body_frame_rhs

BALL, ROCKNROLLER, ROUTH, TOP = MEMBERS
EPS = np.finfo(float).eps

#: One physical body per member, floats, (c1, c2, c3, I1, I2, I3, g).
PARAMS = {member: body.params for member, body in MEMBER_BODIES.items()}


@pytest.fixture(scope="module")
def results():
    return {r.member: r for r in measure_table()}


def test_chaplygins_ball_has_chaplygins_measure(results):
    r = results[BALL]
    assert r.density_exists and r.normal_vanishes and r.closed and r.parallel_witness is None
    assert {c.density: c.invariant for c in r.candidates} == {"chaplygin": True, "routh": False}
    assert "exists" in r.verdict and "sqrt(det K)" in r.verdict


def test_rouths_sphere_has_the_papers_measure_and_not_chaplygins(results):
    r = results[ROUTH]
    assert r.density_exists and r.normal_vanishes and r.closed
    checks = {c.density: c for c in r.candidates}
    assert checks["routh"].invariant and checks["routh"].witness is None
    assert not checks["chaplygin"].invariant and checks["chaplygin"].witness.value != 0
    assert "the paper's ρ" in r.verdict


@pytest.mark.parametrize("member", [ROCKNROLLER, TOP])
def test_no_density_of_gamma_alone_for_the_rocknroller_and_the_top(results, member):
    """At the witness ω = γ, γ̇ = γ × ω = 0 exactly, so f·∇ρ = 0 for every ρ(γ) and div(ρ f) = ρ div f ≠ 0."""
    r = results[member]
    assert r.linear_in_omega and not r.normal_vanishes and not r.closed and not r.density_exists
    assert not any(c.invariant for c in r.candidates)
    w = r.parallel_witness
    assert w.omega == w.gamma and sum(x * x for x in w.gamma) == 1 and w.params[6] != 0
    assert w.value != 0 and w.value == flow_divergence(member).at(w.gamma, w.omega, w.params)
    assert body_frame_rhs([*w.gamma, *w.omega, 0, 0, 0, 0, 0], w.params)[:3] == [0, 0, 0]
    assert "no invariant density" in r.verdict


def test_the_rocknrollers_obstruction_in_closed_form():
    """On the sphere n·γ = −c3 (I1 − I2) γ1 γ2 (1 + I3 + c3 γ3): it vanishes for Routh's sphere (I1 = I2) and the ball
    (c3 = 0) only."""
    d = flow_divergence(ROCKNROLLER)
    m = symbolic_model(ROCKNROLLER)
    (g1, g2, g3), (c3, (I1, I2, I3)) = m.gamma, (m.offset[2], m.inertia)
    n_gamma = sum(n * g for n, g in zip(d.n, m.gamma))
    assert m.on_sphere(n_gamma + c3 * (I1 - I2) * g1 * g2 * (1 + I3 + c3 * g3)) == 0


def test_the_tops_obstruction_is_irreducible():
    d = flow_divergence(TOP)
    m = symbolic_model(TOP)
    n_gamma = m.on_sphere(sum(n * g for n, g in zip(d.n, m.gamma)))
    _, factors = n_gamma.factor_list()
    assert len(n_gamma) == 60 and len(factors) == 1 and factors[0][1] == 1


def test_rouths_det_K_factors_into_the_papers_measure():
    """det K = (I1 + r·r)(I1 I3 + I1 s² + I3 f²) for Routh's sphere, identically: the paper's ρ² = I1/(second factor),
    and the first factor is what separates Chaplygin's candidate from it."""
    m = symbolic_model(ROUTH)
    (r1, r2, r3), (I1, _, I3) = m.r, m.inertia
    assert m.det_mass_matrix == (I1 + r1 ** 2 + r2 ** 2 + r3 ** 2) * (I1 * I3 + I1 * (r1 ** 2 + r2 ** 2) + I3 * r3 ** 2)


def test_divergence_is_linear_in_omega_for_every_member(results):
    assert all(r.linear_in_omega for r in results.values())
    assert measure_table() is measure_table()


def test_undefined_candidates_and_unknown_names_are_refused():
    with pytest.raises(ValueError, match="third axis"):
        check_density(TOP, "routh")
    with pytest.raises(ValueError, match="density must be one of"):
        check_density(BALL, "lebesgue")
    with pytest.raises(ValueError, match="member must be one of"):
        measure("a cube")


def _mass_matrix(gamma, params):
    c, inertia = np.array(params[:3]), np.array(params[3:6])
    r = gamma + c
    return np.diag(inertia) + (r @ r) * np.eye(3) - np.outer(r, r)


def _numpy_density(name: str, params):
    """ρ(γ) in (γ, ω) from numpy: sqrt(det K), or det K (I3 + s² + (I3/I1) f²)^(−1/2)."""
    c3, I1, I3 = params[2], params[3], params[5]

    def chaplygin(y):
        return np.sqrt(np.linalg.det(_mass_matrix(y[:3], params)))

    def routh(y):
        g1, g2, g3 = y[:3]
        return np.linalg.det(_mass_matrix(y[:3], params)) / np.sqrt(I3 + g1 * g1 + g2 * g2 + I3 / I1 * (g3 + c3) ** 2)

    return {"chaplygin": chaplygin, "routh": routh}[name]


def _divergence(field, y, h):
    """Σ_i ∂field_i/∂y_i over the six (γ, ω) coordinates by central differences."""
    out = 0.0
    for i in range(6):
        e = np.zeros(11)
        e[i] = h
        out += (field(y + e)[i] - field(y - e)[i]) / (2 * h)
    return out


def _state(member: str, seed: str):
    rng = np.random.default_rng(zlib.crc32(f"{member}/{seed}".encode()))
    gamma = rng.normal(size=3)
    return np.concatenate([gamma / np.linalg.norm(gamma), rng.normal(size=3), [1.0, 0.0, 0.0, 0.0, 0.0]])


def _tolerance(field, y, h):
    """Central differences err by a h² + O(h⁴) (estimated by Richardson, |D(h) − D(2h)|/3, taken twice) plus the
    round-off of each evaluation over 2h: f = K⁻¹P is computed to ~cond(K) × 64 ε × its size, cond(K) ≤ (I_max +
    (1 + |c|)²)/I_min < 12 here; six such quotients add up."""
    size = float(np.max(np.abs(field(y)[:6])))
    return lambda value_h, value_2h: 2 * abs(value_h - value_2h) / 3 + 6 * 12 * 64 * EPS * size / h


@pytest.mark.parametrize("member", MEMBERS)
def test_exact_divergence_matches_central_differences(member):
    params = PARAMS[member]
    y = _state(member, "divergence")

    def field(x):
        return np.array(body_frame_rhs(x, params))
    h = 1e-4
    exact = float(flow_divergence(member).at(y[:3], y[3:6], params))
    numeric, numeric_2h = _divergence(field, y, h), _divergence(field, y, 2 * h)
    assert abs(numeric - exact) <= _tolerance(field, y, h)(numeric, numeric_2h), (numeric, exact)


@pytest.mark.parametrize("member, density", [(m, d.name) for m in MEMBERS for d in DENSITIES
                                             if not d.on_axis_only or m != TOP])
def test_density_condition_matches_central_differences(member, density):
    """div(ρ f)/ρ at a random state: the module's exact value against central differences of ρ f (numpy)."""
    params = PARAMS[member]
    y = _state(member, density)
    rho = _numpy_density(density, params)

    def field(x):
        return rho(x) * np.array(body_frame_rhs(x, params))
    h = 1e-4
    exact = float(check_density(member, density).at(y[:3], y[3:6], params))
    numeric, numeric_2h = _divergence(field, y, h) / rho(y), _divergence(field, y, 2 * h) / rho(y)
    assert abs(numeric - exact) <= _tolerance(field, y, h)(numeric, numeric_2h) / rho(y), (numeric, exact)
