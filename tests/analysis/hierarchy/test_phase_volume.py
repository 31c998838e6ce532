"""Phase volume along the flow (analysis.hierarchy.phase_volume): the complex-step divergence against the exact rational
one, the time average of div f against the invariant densities of Chaplygin's ball and Routh's sphere (the identity
∫ div f = −[log ρ] and the bound C/t), the forward-then-backward identity of a reversible flow, and the steady
rotations.  Each identity is paired with a mutant that must fail it: the controls can fail."""

from __future__ import annotations

import math
import zlib
from fractions import Fraction

import numpy as np
import pytest

import roundoff as ro
import rocknroller as rr
from rocknroller.analysis.hierarchy import phase_volume as pv
from rocknroller.analysis.hierarchy.measure import flow_divergence
from rocknroller.analysis.hierarchy.members import MEMBER_BODIES, member_start
from rocknroller.analysis.model.body import MEMBERS
from rocknroller.analysis.model.equations import body_frame_rhs
from rocknroller.numerics.run_limits import energy_error_bound

BALL, ROCKNROLLER, ROUTH, TOP = MEMBERS
#: The body of validation/hierarchy/chaplygin_top.py whose steady rotations at |s| = 6 are a repeller (+) and an attractor (−).
STRONG_TOP = rr.Body.chaplygin_top(0.15, 0.4, 0.5, offset=(0.3, 0.3, -0.3))
#: Rounded operations in one complex-step evaluation of div f: body_frame_rhs's ≈ 110 real operations become complex
#: ones of ≤ 4 roundings each (a complex product: 4 products, 2 sums), then 3 imaginary parts summed: ≤ 450.
DIVERGENCE_OPS = 450


def _states(rng: np.random.Generator, n: int) -> list[tuple[tuple[Fraction, ...], tuple[Fraction, ...]]]:
    """n states with exactly representable γ (a float near the unit sphere: the exact divergence is evaluated at the
    same point off the sphere, where the flow on R⁶ is the same formula) and ω in multiples of 1/64."""
    out = []
    for _ in range(n):
        g = rng.normal(size=3)
        g /= np.linalg.norm(g)
        w = rng.integers(-400, 400, 3) / 64.0
        out.append((tuple(Fraction(float(x)) for x in g), tuple(Fraction(float(x)) for x in w)))
    return out


@pytest.mark.parametrize("member", MEMBERS)
def test_divergence_is_the_exact_rational_divergence(member):
    """The complex step against n(γ)·ω/det K evaluated in exact rational arithmetic (measure.flow_divergence) at the
    same double-precision states and parameters: the difference is the rounding of one evaluation, within
    γ_450 × Σ|x ∂(div f)/∂x| over every input x (roundoff.formula_bound: the states, the offset, the moments, g)."""
    body = MEMBER_BODIES[member]
    exact = flow_divergence(member)
    states = _states(np.random.default_rng(zlib.crc32(member.encode())), 30)
    gamma = np.array([[float(x) for x in g] for g, _ in states]).T
    omega = np.array([[float(x) for x in w] for _, w in states]).T
    ours = pv.divergence(body, gamma, omega)
    truth = np.array([float(exact.at(g, w, body.params)) for g, w in states])

    def div(g1, g2, g3, w1, w2, w3, c1, c2, c3, I1, I2, I3, grav):
        sphere = rr.LoadedSphere(float(I1), float(I2), float(I3), (float(c1), float(c2), float(c3)), float(grav))
        return pv.divergence(sphere, np.array([g1, g2, g3], float), np.array([w1, w2, w3], float))

    names = ("c1", "c2", "c3", "I1", "I2", "I3", "grav")
    bound = [float(ro.formula_bound(div, {**dict(zip(("g1", "g2", "g3"), gamma[:, k])),
                                          **dict(zip(("w1", "w2", "w3"), omega[:, k])),
                                          **dict(zip(names, body.params))}, DIVERGENCE_OPS))
             for k in range(gamma.shape[1])]
    ro.assert_within(ours - truth, bound, f"complex-step div f of {member}", truth)


def test_divergence_is_odd_in_omega_bit_for_bit():
    """IEEE arithmetic is symmetric under a change of sign and complex arithmetic under conjugation, and every term of
    the complex step is odd or even in ω: div f(γ, −ω) = −div f(γ, ω) exactly (the backward sign flip rests on it)."""
    rng = np.random.default_rng(7)
    gamma = rng.normal(size=(3, 200))
    gamma /= np.linalg.norm(gamma, axis=0)
    omega = rng.normal(size=(3, 200)) * 3.0
    for body in (*MEMBER_BODIES.values(), STRONG_TOP, rr.Body.paper(1e-3)):
        assert np.array_equal(pv.divergence(body, gamma, -omega), -pv.divergence(body, gamma, omega))


@pytest.mark.parametrize("gamma, omega, match", [
    (np.zeros((2, 4)), np.zeros((2, 4)), "shape"),
    (np.zeros((3, 4)), np.zeros((3, 5)), "shape"),
    (np.array([0.0, 0.0, 1.0]), np.array([math.nan, 0.0, 0.0]), "finite"),
])
def test_divergence_refuses_bad_states(gamma, omega, match):
    with pytest.raises(ValueError, match=match):
        pv.divergence(MEMBER_BODIES[TOP], gamma, omega)


def test_divergence_refuses_a_body_that_is_not_one():
    with pytest.raises(ValueError, match="body must be"):
        pv.divergence((0.0, 0.0, -0.05, 0.35, 0.36, 0.4, 9.87), [0.0, 0.0, 1.0], [0.0, 0.0, 1.0])


def _density_check(member: str, t_end: float) -> tuple[list[float], list[float], list[float]]:
    """For each checkpoint t: t·average, −[log ρ]₀ᵗ along the same run (its grid holds the checkpoints), and the
    identity's tolerance: t × the quadrature bound + the orbit's drift of log ρ.  The run errs by at most
    energy_error_bound(ε, n) in each state component relative to max(1, ‖y‖∞) (the energy bound's derivation: each
    step ≤ ε of the state, added linearly over the steps; ‖y‖∞ ≤ 2 at the members' start), and |∇γ log ρ| ≤ 2 for both
    members (ball: ½ log Σ q_i γ_i², gradient ≤ max q/min q = 1.1; Routh's sphere: ≤ 0.1 + 0.4): × 4."""
    body = MEMBER_BODIES[member]
    rate = pv.phase_volume_rate(body, member_start(), t_end)
    run = rr.simulate(body, member_start(), t_end, dt=t_end / 8)
    on_grid = np.isin(run.t, [t for t, _ in rate.checkpoints])
    log_rho = pv.log_density(body, run.gamma[:, on_grid])
    drift = 4.0 * energy_error_bound(run.tolerance, run.n_steps)
    return ([t * a for t, a in rate.checkpoints], list(float(pv.log_density(body, run.gamma[:, 0])) - log_rho),
            [t * rate.error + drift for t, _ in rate.checkpoints])


@pytest.mark.parametrize("member", [BALL, ROUTH])
def test_with_a_density_the_average_is_minus_the_change_of_log_rho_over_t(member):
    """div f = −d/dt log ρ along the flow: t·average = log ρ(0) − log ρ(t) at every checkpoint, and |average| ≤ C/t
    with C the range of log ρ over the sphere (log_density_range): the average tends to 0 like 1/t."""
    t_avg, minus_change, tolerance = _density_check(member, 2000.0)
    ro.assert_within(np.subtract(t_avg, minus_change), tolerance, f"∫ div f + [log ρ] of {member}", minus_change)
    assert max(abs(x) for x in t_avg) <= pv.log_density_range(MEMBER_BODIES[member])
    assert max(abs(x) for x in minus_change) > 1e6 * max(tolerance)  # the identity is not 0 = 0


@pytest.mark.parametrize("member", [BALL, ROUTH])
def test_a_divergence_of_the_wrong_sign_fails_the_density_identity(member, monkeypatch):
    """The control: with div f negated the averages change sign, and t·average = −[log ρ] fails by 2|[log ρ]|."""
    right = pv.divergence
    monkeypatch.setattr(pv, "divergence", lambda body, gamma, omega: -right(body, gamma, omega))
    t_avg, minus_change, tolerance = _density_check(member, 2000.0)
    assert max(abs(a - b) - tol for a, b, tol in zip(t_avg, minus_change, tolerance)) > 0.0


@pytest.mark.parametrize("member", [BALL, ROUTH])
def test_log_density_range_bounds_log_rho_on_a_grid_of_the_sphere(member):
    """C ≥ the range of log ρ over 10⁵ points of the sphere (the ball's C is exact: the grid comes within 1e-3)."""
    body = MEMBER_BODIES[member]
    rng = np.random.default_rng(3)
    gamma = rng.normal(size=(3, 100_000))
    gamma /= np.linalg.norm(gamma, axis=0)
    gamma = np.concatenate([gamma, np.eye(3), -np.eye(3)], axis=1)
    log_rho = pv.log_density(body, gamma)
    C = pv.log_density_range(body)
    assert np.ptp(log_rho) <= C
    if member == BALL:
        assert np.ptp(log_rho) >= C - 1e-3


@pytest.mark.parametrize("member", [ROCKNROLLER, TOP])
def test_the_density_is_written_only_for_the_ball_and_routhss_sphere(member):
    with pytest.raises(ValueError, match="Chaplygin's ball"):
        pv.log_density(MEMBER_BODIES[member], [0.0, 0.0, 1.0])
    with pytest.raises(ValueError, match="Routh's sphere"):
        pv.log_density_range(MEMBER_BODIES[member])


@pytest.mark.parametrize("t_end", [5.0, 20.0])
def test_backward_from_the_end_retraces_the_forward_run(t_end):
    """Forward from x0 over [0, T] to x1, then backward from x1 over [0, T]: the same orbit, so the same average.  The
    two runs agree to the rounding of x1 (a few u, rebuilt from its angles) grown by the flow over T (Λ T ≤ 60
    radians: far below 1e9), so to 2⁻²⁰ of the rate beside the quadrature bounds.  The mutant that forgets the
    backward sign (the forward run from (γ1, −ω1)) gives −rate and fails by 2|rate|."""
    top, x0 = MEMBER_BODIES[TOP], member_start()
    x1 = pv.advance(top, x0, t_end)
    fwd, bwd = pv.phase_volume_rate(top, x0, t_end), pv.phase_volume_rate(top, x1, t_end, backward=True)
    tolerance = fwd.error + bwd.error + 2.0**-20 * abs(fwd.rate)
    assert abs(fwd.rate - bwd.rate) <= tolerance
    unsigned = pv.phase_volume_rate(top, pv.reversed_state(x1), t_end)
    assert abs(fwd.rate - unsigned.rate) > 1e3 * tolerance


def test_a_start_at_rest_has_opposite_rates_forward_and_backward_bit_for_bit():
    """At rest (γ0, −0) = (γ0, 0): the backward run is the forward run, its div f negated value by value."""
    start = rr.EulerState(0.6 * math.pi, psi=1.0)
    fwd = pv.phase_volume_rate(STRONG_TOP, start, 50.0)
    bwd = pv.phase_volume_rate(STRONG_TOP, start, 50.0, backward=True)
    assert bwd.rate == -fwd.rate != 0.0 and np.array_equal(bwd.running, -fwd.running)


def test_the_rates_checkpoints_are_its_running_average():
    """rate is the running average at t_end; the checkpoints lie on the panel ends (fsum there, cumsum in running)."""
    r = pv.phase_volume_rate(MEMBER_BODIES[TOP], member_start(), 100.0)
    assert r.checkpoints[-1] == (r.t_end, r.rate) and r.t[-1] == pytest.approx(r.t_end, rel=1e-15)
    for t, average in r.checkpoints:
        k = int(np.argmin(np.abs(r.t - t)))
        assert r.t[k] == pytest.approx(t, rel=1e-15)
        assert abs(r.running[k] - average) <= len(r.t) * ro.u * np.max(np.abs(r.running * r.t)) / t
    assert r.drift == abs(r.checkpoints[-1][1] - r.checkpoints[-2][1]) and r.error < 1e-12


def test_the_rate_refuses_what_simulate_refuses():
    with pytest.raises(ValueError, match="t_end"):
        pv.phase_volume_rate(MEMBER_BODIES[TOP], member_start(), -1.0)
    with pytest.raises(ValueError, match="MAX_DENSE_RADIANS"):
        pv.phase_volume_rate(MEMBER_BODIES[TOP], member_start(), 1e7)


def test_reversed_state_negates_the_rates_exactly():
    start = rr.EulerState(2.0, 0.1, 0.4, theta_dot=0.3, phi_dot=-1.2, psi_dot=2.5)
    y, y_rev = start.to_body_state(), pv.reversed_state(start).to_body_state()
    assert np.array_equal(y_rev[3:6], -y[3:6]) and np.array_equal(y_rev[[0, 1, 2, 6, 7, 8]], y[[0, 1, 2, 6, 7, 8]])


@pytest.mark.parametrize("spin", [0.5, 3.0, 6.0])
def test_a_steady_rotation_is_a_fixed_point_and_its_mirror_has_the_opposite_divergence(spin):
    """ω = s γ, γ̇ = 0 exactly; ω̇ within the Newton tolerance carried through K⁻¹ (|K⁻¹| ≤ 1/min I); the trace of the
    complex-step Jacobian is div f there; ±s share γ, with opposite divergence and mirrored stability."""
    up, down = pv.steady_rotation(STRONG_TOP, spin), pv.steady_rotation(STRONG_TOP, -spin)
    assert up.gamma == down.gamma
    rhs = body_frame_rhs(np.array([*up.gamma, *up.omega, 0, 0, 0, 0, 0]), STRONG_TOP.params)
    scale = spin * spin * 0.5 + STRONG_TOP.g
    assert max(abs(x) for x in rhs[3:6]) <= 64 * ro.u * scale / 0.15 * 4
    assert float(pv.divergence(STRONG_TOP, up.gamma, up.omega)) == pytest.approx(up.divergence, rel=1e-12)
    assert down.divergence == pytest.approx(-up.divergence, rel=1e-12) and up.divergence > 0.0
    mirror = {"attracting": "repelling", "repelling": "attracting", "saddle": "saddle", "neutral": "neutral"}
    assert mirror[up.stability] == down.stability


def test_steady_rotation_stabilities_of_the_strong_top():
    """A saddle-focus at small spin, a repeller (+s) and an attractor (−s) at |s| = 6; at rest, neutral rocking."""
    assert pv.steady_rotation(STRONG_TOP, 0.0).stability == "neutral"
    assert pv.steady_rotation(STRONG_TOP, 1.0).stability == "saddle"
    assert (pv.steady_rotation(STRONG_TOP, 6.0).stability, pv.steady_rotation(STRONG_TOP, -6.0).stability) == \
        ("repelling", "attracting")


@pytest.mark.parametrize("kwargs, match", [
    ({"spin": 101.0}, "SPIN_MAX"), ({"spin": math.nan}, "spin"), ({"spin": "3"}, "spin"),
    ({"spin": 1.0, "body": rr.Body.chaplygin_ball(0.35, 0.37, 0.4)}, "c != 0"),
])
def test_steady_rotation_refuses(kwargs, match):
    body = kwargs.pop("body", STRONG_TOP)
    with pytest.raises(ValueError, match=match):
        pv.steady_rotation(body, **kwargs)


def test_nearby_starts_at_the_rotation_and_refuses_a_large_tilt():
    rot = pv.steady_rotation(STRONG_TOP, 4.0)
    y = rot.nearby(0.0).to_body_state()
    assert np.max(np.abs(y[0:3] - rot.gamma)) <= 8 * ro.u and np.max(np.abs(y[3:6] - rot.omega)) <= 8 * ro.u * 4.0
    tilted = rot.nearby(0.1).to_body_state()
    assert math.acos(float(np.dot(tilted[0:3], rot.gamma))) == pytest.approx(0.1, rel=1e-12)
    with pytest.raises(ValueError, match="tilt"):
        rot.nearby(2.0)


@pytest.mark.slow
def test_the_rate_near_the_attracting_rotation_tends_to_its_divergence():
    """From near the attracting rotation at s = −6 the orbit contracts onto the rotation of its own energy (the family's
    member at the spin s' it settles to, −5.95 here) at the weakest rate κ = 5.9e-3 (the rotation's eigenvalues):
    after 2000 time units within δ ≈ 2e-7 of it.  Over the next T = 2000 the average differs from div f at that
    rotation by at most |∇ div f| δ/(κ T) ≲ 1e-8 (|∇ div f| ≲ 1 here), 4e-7 of the rate: 1e-6 relative holds it."""
    start = pv.advance(STRONG_TOP, pv.steady_rotation(STRONG_TOP, -6.0).nearby(0.05), 2000.0)
    y = start.to_body_state()
    settled = pv.steady_rotation(STRONG_TOP, float(y[0:3] @ y[3:6]))
    assert settled.stability == "attracting" and np.max(np.abs(y[3:6] - settled.omega)) < 1e-6
    rate = pv.phase_volume_rate(STRONG_TOP, start, 2000.0)
    assert rate.rate == pytest.approx(settled.divergence, rel=1e-6)
    assert rate.rate != pytest.approx(pv.steady_rotation(STRONG_TOP, -6.0).divergence, rel=1e-4)  # a near one fails


@pytest.mark.slow
def test_megno_calls_the_attracting_rotation_regular_and_the_chaotic_set_chaotic():
    """MEGNO (rr.direct_chaos_indicators) on the two attracting sets of validation/hierarchy/chaplygin_top.py: regular (MEGNO
    ≤ 2: a fixed point's tangent vectors do not grow) near the rotation, chaotic past the transient from +6."""
    near = pv.steady_rotation(STRONG_TOP, -6.0).nearby(0.05)
    assert rr.direct_chaos_indicators(STRONG_TOP, near, 2000.0).indicators.megno <= 2.0
    chaotic = pv.advance(STRONG_TOP, pv.steady_rotation(STRONG_TOP, 6.0).nearby(0.1), 2000.0)
    indicators = rr.direct_chaos_indicators(STRONG_TOP, chaotic, 4000.0).indicators
    assert not indicators.regular and indicators.lyapunov > 0.01
