"""The exact one-step map (direct ODE from a solved maximum) and its ε-derivatives: the first is the variational
equations' (``slow.orbit.first_order_step``, an independent check of them), the second holds only the harmonics 0,
2 and 4 of ψ_n (five orbits per Q determine it)."""

from __future__ import annotations

import math

import numpy as np
import pytest

from rocknroller.analysis.model.body import Body
from rocknroller.analysis.routh.reduction import invariants_from_euler
from rocknroller.analysis.slow.map.exact_step import STEP_NAMES, eps_derivatives, exact_step
from rocknroller.analysis.slow.map.family import family_member, maximum_state, rest_energy
from rocknroller.analysis.slow.map.orbit import first_order_step

SYM = Body.paper(0.0)
E = rest_energy(SYM, 0.95 * math.pi)
#: Off the critical lines and inside the reachable region at this energy; the second crosses the layer of W.
STARTS = ((0.01, 0.003, 0.4), (-0.02, 0.001, 1.3))


@pytest.mark.parametrize("QR, QJ, psi", STARTS)
def test_first_derivative_is_the_variational_one(QR, QJ, psi):
    """Richardson-extrapolated central differences of the exact step against the first-order variational
    equations, for every component: within the extrapolation's own correction |D(h/2) − D(h)|/15 (an O(h⁴) term,
    larger than the O(h⁶) remainder) plus the exact steps' round-off carried by the stencil, 1.5 · 2 · 1e-13/(h/2)
    (a step's values are accurate to ~1e-13 relative to their size, which is ≤ 60 here)."""
    d = eps_derivatives(SYM, E, QR, QJ, psi)
    var = first_order_step(SYM, E, QR, QJ, psi).d
    ref = np.array([var[k] for k in STEP_NAMES])
    roundoff = 1.5 * 2 * 1e-13 * 60 / (d.h / 2)
    assert np.all(np.abs(d.d1 - ref) <= d.d1_error + roundoff), (d.d1 - ref, d.d1_error)
    # the check has teeth: the corrections are far below the derivatives themselves
    assert np.all(d.d1_error + roundoff < 1e-3 * np.abs(ref))


def test_second_derivative_has_harmonics_0_2_4_of_psi():
    """At fixed (E, Q), ∂²/∂ε² of the step at ψ_n = kπ/5 (k = 0..4) fixes c0 + Σ_{m=1,2} (c_m cos 2mψ + s_m sin 2mψ);
    that series predicts the second derivative at two other ψ_n within their error estimates (harmonics ≥ 6 of ψ
    absent), while the 4th harmonic is far above them (present, as the rotational symmetry allows)."""
    QR, QJ = STARTS[0][:2]
    psis = np.arange(5) * math.pi / 5
    ders = [eps_derivatives(SYM, E, QR, QJ, p) for p in psis]
    d2 = np.array([d.d2 for d in ders])
    err = np.array([d.d2_error for d in ders]).max(axis=0)

    def basis(psi):
        th = 2 * np.atleast_1d(psi)
        return np.stack([np.ones_like(th), np.cos(th), np.sin(th), np.cos(2 * th), np.sin(2 * th)], axis=-1)

    coef = np.linalg.solve(basis(psis), d2)  # (5 harmonics, 5 components)
    for psi in (0.3, 1.1):
        d = eps_derivatives(SYM, E, QR, QJ, psi)
        pred = (basis(psi) @ coef)[0]
        # the fit carries each sample's error with weights Σ|basis · inverse| ≤ 5 · (2/5) · 5 = 4 (DFT)
        assert np.all(np.abs(d.d2 - pred) <= d.d2_error + 4 * err), (d.d2 - pred, d.d2_error + 4 * err)
    fourth = np.hypot(coef[3], coef[4])
    assert np.all(fourth[[0, 2, 3, 4]] > 100 * (4 * err[[0, 2, 3, 4]]))


def test_maximum_state_is_the_requested_maximum():
    """The solved start has the requested E (the member's), Q_R and Q_J (the family's I1) and θ̇ = 0; for ε < 0 the
    relabelled body (moments ((1 + ε) I1, I1), ψ + π/2) has the same energy as the body it stands for.

    Bounds: Brent stops within 4 · 8.9e-16 |θ| ≈ 1.1e-14 of the root, which moves E by |dE/dθ| ≈ 0.08 of that, and
    E (~1, sums of a few terms ≤ 1) is evaluated to a few ulps: ≤ 2e-15 together, 4e-15 with a margin of 2.  The
    rates are V_φ, V_ψ at θ, whose Q_R, Q_J come back through Σ and ρ to ~10 ulps of their terms (here each term,
    e.g. I1 s² φ̇ = 3.4e-3 against Q_J = 3e-3, is ≲ 2 |Q|): ≤ 5e-15, 1e-13 with a margin of 20 for other CPUs' and
    kernels' last bits."""
    for eps in (0.01, -0.01):
        body, shift, st = maximum_state(SYM, eps, E, 0.01, 0.003, 0.4)
        got = invariants_from_euler(body, st.theta, 0.0, st.phi_dot, st.psi_dot, st.psi)
        _, QR, QJ = invariants_from_euler(SYM, st.theta, 0.0, st.phi_dot, st.psi_dot, st.psi)
        assert float(got[0]) == pytest.approx(E, rel=4e-15) and (float(QR), float(QJ)) == pytest.approx(
            (0.01, 0.003), rel=1e-13)
        assert st.theta_dot == 0.0 and shift == (0.0 if eps > 0 else math.pi / 2)
    assert family_member(SYM, -0.01)[0].I2 == SYM.I1


def test_exact_step_at_eps_zero_is_routh_sphere():
    """At ε = 0 the step keeps Q (Routh's sphere conserves it) to the integrator's round-off: heyoka at tolerance u
    over one rock (~100 steps) drifts the invariants by ≤ 100 · 10 u of their terms (|I ω| ≈ 3 |Q| here), 2e-12
    relative, 1e-11 with a margin of 5."""
    out = exact_step(SYM, 0.0, E, 0.01, 0.003, 0.4)
    assert out[:2] == pytest.approx([0.01, 0.003], rel=1e-11)


def test_bad_input():
    with pytest.raises(ValueError, match="h must satisfy"):
        eps_derivatives(SYM, E, 0.01, 0.003, 0.4, h=0.0)
    with pytest.raises(ValueError, match="eps must be finite"):
        family_member(SYM, math.nan)
    with pytest.raises(ValueError):
        maximum_state(SYM, 0.0, E, 10.0, 10.0, 0.0)  # no motion at this energy


@pytest.mark.parametrize("QR, QJ, psi", STARTS + ((0.0019994, -4.86e-5, 2.0),))
def test_second_derivative_is_the_second_order_variational_one(QR, QJ, psi):
    """The second formulation (slow.orbit.second_order_step: second-order variational equations along the start's
    curve, with the event time's second-order shift) against the extrapolated differences of the exact step, every
    component, within the extrapolation's error estimate plus the stencil's round-off, 1.5 · 32 · 1e-13 |M|/(h/2)²
    (a step's values M accurate to ~1e-13 of their size; the stencil's weights sum to 32/12 over (h/2)², × 12 for
    the extrapolation's 16/15 and margin).  The third start lies in the layer of W near Q = 0."""
    from rocknroller.analysis.slow.map.orbit import second_order_step

    d = eps_derivatives(SYM, E, QR, QJ, psi)
    var = second_order_step(SYM, E, QR, QJ, psi)
    ref = np.array([var[k] for k in STEP_NAMES])
    roundoff = 1.5 * 32 * 1e-13 * np.abs(exact_step(SYM, 0.0, E, QR, QJ, psi)) / (d.h / 2) ** 2
    assert np.all(np.abs(d.d2 - ref) <= d.d2_error + roundoff), (d.d2 - ref, d.d2_error)
    assert np.all(d.d2_error + roundoff < 1e-3 * np.abs(ref))  # the check has teeth
