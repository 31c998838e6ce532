"""Borisov and Mamaev's quantity B = M² − 2K r² (the paper's Conclusions): a first integral without gravity only.

Checked three ways: sympy proves d(M²)/dt = 2T d(r²)/dt + 2 g a M·(e3 × γ) along the direct equations
(``body_frame_rhs``, any moments), so dB/dt = 0 at g = 0 and not otherwise; the direct ODE (heyoka) and an
independent integrator (scipy's DOP853 on the same right-hand side) keep B to round-off at g = 0 for asymmetric
bodies; with gravity B swings by a large part of itself (docs/theory/further_integral.md).
"""

from __future__ import annotations

import math

import numpy as np
import pytest
import sympy as sp
from scipy.integrate import solve_ivp

from rocknroller.analysis.model.body import Body
from rocknroller.analysis.model.equations import EulerState, body_frame_rhs
from rocknroller.analysis.model.invariants import borisov_mamaev, contact_momentum, energy
from rocknroller.numerics.integrate import simulate

U = 0.5 * np.finfo(float).eps
START = EulerState.from_omega(0.6 * math.pi, 0.0, 0.0, (0.3, 1.0, -0.7))


def _vec(*xs):
    return sp.Matrix(xs)


def test_the_identity_symbolically():
    """Along body_frame_rhs (K ω̇ = P, γ̇ = γ × ω; any a, I1, I2, I3, g) with M = K ω and T = ½ ω·K ω:
    d(M²)/dt = 2T d(r²)/dt + 2 g a M·(e3 × γ) and dE/dt = 0, exactly.  Ṁ = K̇ ω + P and Ṫ = ω·P + ½ ω·K̇ ω need no
    inverse of K.  So dB/dt = 2 g a M·(e3 × γ): zero at g = 0, and not identically zero otherwise."""
    a, I1, I2, I3, g = sp.symbols("a I1 I2 I3 g", positive=True)
    g1, g2, g3, w1, w2, w3 = sp.symbols("g1 g2 g3 w1 w2 w3", real=True)
    gam, om, e3 = _vec(g1, g2, g3), _vec(w1, w2, w3), _vec(0, 0, 1)
    r = gam - a * e3
    inertia = sp.diag(I1, I2, I3)
    gdot = gam.cross(om)
    P = -om.cross(inertia * om) - r.cross(om.cross(gdot) + om.cross(om.cross(r))) + g * a * e3.cross(gam)

    def K_of(v):
        return inertia + (v.dot(v)) * sp.eye(3) - v * v.T

    K = K_of(r)
    Kdot = sp.Matrix(3, 3, lambda i, j: sum(sp.diff(K[i, j], x) * dx for x, dx in zip((g1, g2, g3), gdot)))
    M = K * om
    Mdot = Kdot * om + P
    T = sp.Rational(1, 2) * om.dot(M)
    Tdot = om.dot(P) + sp.Rational(1, 2) * om.dot(Kdot * om)
    Edot = Tdot + g * a * (-gdot[2])
    r2dot = 2 * r.dot(gdot)
    dM2 = 2 * M.dot(Mdot)
    assert sp.expand(Edot) == 0
    gravity_term = 2 * g * a * M.dot(e3.cross(gam))
    assert sp.expand(dM2 - (2 * T * r2dot + gravity_term)) == 0
    # B = M² − 2E r² with E constant: dB/dt = gravity_term, not identically zero for g > 0
    sample = {a: sp.Rational(1, 20), I1: sp.Rational(7, 20), I2: sp.Rational(9, 25), I3: sp.Rational(2, 5),
              g: sp.Rational(987, 100), g1: sp.Rational(3, 5), g2: 0, g3: sp.Rational(4, 5), w1: 1, w2: 2, w3: -1}
    assert gravity_term.subs(sample) != 0

    # the sympy system is the package's: the same ω̇ = K⁻¹P at a random state (a 3×3 solve with K's condition
    # number ≈ (1 + a)²/I_min ≈ 3 on terms of size ~|P|: 64 u of the largest component is a generous bound)
    values = dict(zip((a, I1, I2, I3, g, g1, g2, g3, w1, w2, w3),
                      (0.05, 0.35, 0.36, 0.4, 9.87, 0.6, 0.0, 0.8, 1.0, 2.0, -1.0)))
    ref = np.array(sp.Matrix(K.subs(values)).evalf(30).LUsolve(sp.Matrix(P.subs(values)).evalf(30)), float).ravel()
    y = np.array([0.6, 0.0, 0.8, 1.0, 2.0, -1.0, 1.0, 0.0, 0.0, 0.0, 0.0])
    pkg = np.array(body_frame_rhs(y, Body(0.05, 0.35, 0.36, 0.4, 9.87).params)[3:6], float)
    assert np.max(np.abs(pkg - ref)) <= 64 * U * np.max(np.abs(ref))


def test_contact_momentum_is_the_mass_matrix_times_omega():
    body = Body(0.05, 0.35, 0.36, 0.4, 9.87)
    y = START.to_body_state()
    gam, om = y[0:3], y[3:6]
    r = gam - np.array([0.0, 0.0, body.a])
    K = np.diag([body.I1, body.I2, body.I3]) + (r @ r) * np.eye(3) - np.outer(r, r)
    assert np.allclose(contact_momentum(body, gam, om), K @ om, rtol=8 * U, atol=0.0)


def _relative_swing(body: Body, t_end: float):
    traj = simulate(body, START, t_end)
    B = borisov_mamaev(body, traj.gamma, traj.omega)
    M = contact_momentum(body, traj.gamma, traj.omega)
    r2 = traj.gamma[0] ** 2 + traj.gamma[1] ** 2 + (traj.gamma[2] - body.a) ** 2
    scale = float(np.max(np.sum(M * M, axis=0) + 2.0 * np.abs(traj.E) * r2))  # the terms that cancel in B
    return float(np.ptp(B)), scale, traj


@pytest.mark.parametrize("eps", [0.0, 1e-2, 0.1])
def test_conserved_by_the_direct_ode_without_gravity(eps):
    """At g = 0, B keeps its value to the run's round-off: the state's error after N steps of a Taylor method at
    tolerance u is ≲ N u × the state's scale (random-walk at most linear), and B is quadratic in ω, so its swing is
    ≲ 2 × 4 N u × the scale of its terms; 10× margin."""
    body = Body(0.05, 0.35, 0.35 * (1 + eps), 0.4, 0.0)
    swing, scale, traj = _relative_swing(body, 300.0)
    bound = 10 * 2 * 4 * traj.n_steps * U * scale
    assert swing <= bound, (swing, bound)


def test_conserved_by_scipy_dop853_without_gravity():
    """The independent integrator: scipy's DOP853 on the same equations keeps B to its tolerance, bounded as for the
    Taylor run with its rtol in place of u: each step errs by ≲ rtol × the state, n steps add at most linearly, and B
    is quadratic in ω (swing ≲ 2 × 4 n rtol × the scale of its terms; 10× margin)."""
    body = Body(0.05, 0.35, 0.385, 0.4, 0.0)
    y0 = START.to_body_state()
    rtol = 1e-12
    sol = solve_ivp(lambda t, y: body_frame_rhs(y, body.params), (0.0, 100.0), y0, method="DOP853", rtol=rtol,
                    atol=rtol)
    gam, om = sol.y[0:3], sol.y[3:6]
    B = borisov_mamaev(body, gam, om)
    M = contact_momentum(body, gam, om)
    r2 = gam[0] ** 2 + gam[1] ** 2 + (gam[2] - body.a) ** 2
    scale = float(np.max(np.sum(M * M, axis=0) + 2.0 * np.abs(energy(body, gam, om)) * r2))
    n_steps = sol.t.size - 1
    assert np.ptp(B) <= 10 * 2 * 4 * n_steps * rtol * scale


@pytest.mark.parametrize("eps", [0.0, 1e-2, 0.1])
def test_not_conserved_with_gravity(eps):
    """With the paper's gravity B swings by a large part of itself (the gravity term of the identity): the paper's
    statement that B is conserved only without gravity holds."""
    body = Body(0.05, 0.35, 0.35 * (1 + eps), 0.4, 9.87)
    swing, scale, _ = _relative_swing(body, 100.0)
    assert swing > 0.1 * scale


@pytest.mark.slow
def test_the_separatrix_layer_is_chaotic_with_gravity():
    """No further smooth integral in the layer: a release at θ0 = 0.95π near the unstable rocking (ψ0 = 0.1,
    ε = 1e-2) and its twin 1e-10 away both have MEGNO above the chaos threshold and a Lyapunov exponent that spans
    many Lyapunov times over the run (validation/further_integral.py tabulates ε = 1e-3 … 2e-2)."""
    from rocknroller.numerics.megno import MEGNO_CHAOTIC
    from rocknroller.numerics.variational import direct_chaos_indicators

    body = Body.paper(1e-2)
    t_end = 5000.0
    for psi0 in (0.1, 0.1 + 1e-10):
        chaos = direct_chaos_indicators(body, EulerState(0.95 * math.pi, psi=psi0), t_end, budget=None).indicators
        assert chaos.megno > MEGNO_CHAOTIC
        assert chaos.lyapunov * t_end > 10.0
