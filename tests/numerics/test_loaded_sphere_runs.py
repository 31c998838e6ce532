"""The direct ODE for every member of the loaded-sphere family (LoadedSphere, seven parameters): simulate on both
backends, the turning points, the lanes of run_ensemble, the chaos indicators, and Chaplygin's ball's integrals."""

from __future__ import annotations

import math

import numpy as np
import pytest

import rocknroller as rr
from rocknroller.analysis.hierarchy.members import member_body, member_start
from rocknroller.analysis.model.body import MEMBERS
from rocknroller.analysis.model.equations import turning_point_function
from rocknroller.analysis.model.invariants import energy, momentum_squared, momentum_vertical
from rocknroller.numerics.run_limits import energy_error_bound, energy_scale

TOP = rr.Body.chaplygin_top(0.35, 0.37, 0.4, offset=(0.03, -0.02, -0.05))
START = rr.EulerState(0.9 * math.pi, psi=0.3)


def test_a_top_on_heyoka_and_on_dop853_has_the_same_turning_points():
    """DOP853 at rtol 1e-13 (its own tolerance, 10 × heyoka's per-step error at least): the maxima's times agree to
    DOP853's global error, ≲ 1e-13 per unit time × 60 units × the rocking's amplification (≤ 10 here, measured by
    the two backends of the on-axis body); so 1e-9."""
    ours = rr.simulate(TOP, START, 60.0, samples=False)
    ref = rr.simulate(TOP, START, 60.0, samples=False, method="scipy", rtol=1e-13, atol=1e-15)
    assert len(ours.maxima) == len(ref.maxima) >= 7
    np.testing.assert_allclose(ours.maxima.t, ref.maxima.t, rtol=0, atol=1e-9)
    np.testing.assert_allclose(ours.maxima.states[:, :6], ref.maxima.states[:, :6], rtol=0, atol=1e-9)
    assert ours.energy_rel_error <= energy_error_bound(ours.tolerance, ours.n_steps)


def test_a_tops_turning_points_are_roots_of_the_tilts_rate():
    """At each reported turning point dγ3/dt = γ1 ω2 − γ2 ω1 vanishes to its rounding (terms ≤ |ω|, a few u each; the
    event's time is exact to a rounding of t, which moves h by |ḣ| u t)."""
    run = rr.simulate(TOP, START, 60.0, samples=False)
    for tp in (run.maxima, run.minima):
        h = turning_point_function(tp.states.T)
        rate = np.max(np.abs(tp.states[:, 3:6]))
        assert np.all(np.abs(h) <= 64 * np.finfo(float).eps * rate * (1 + rate * tp.t))
    assert np.all(np.diff(np.sort(np.concatenate([run.maxima.t, run.minima.t]))) > 0)
    assert np.all(run.maxima.theta > run.minima.theta[: len(run.maxima)].min())


def test_the_paper_quantities_refuse_a_tops_run_and_its_outputs_leave_them_out():
    run = rr.simulate(TOP, START, 30.0, samples=False)
    with pytest.raises(ValueError, match="Q_R .* third principal axis"):
        run.maxima.QR
    with pytest.raises(ValueError, match="Q_J .* third principal axis"):
        run.QJ_extent
    pytest.importorskip("pandas")
    assert list(run.maxima.to_dataframe().columns) == ["t", "theta", "phi", "psi"]


@pytest.mark.parametrize("kind", MEMBERS)
def test_every_member_runs_in_the_lanes_as_in_the_scalar_integrator(kind):
    """The batch integrator's lanes and the scalar one round differently (README): the maxima agree to round-off
    grown over the run, ≤ 1e-9 over 100 time units for these regular runs (measured ~1e-12)."""
    body = member_body(kind)
    jobs = [rr.Job(body, rr.EulerState.from_omega(0.6 * math.pi, 0.0, psi, (0.7, -0.5, 1.3)), 100.0)
            for psi in (0.1, 0.5, 0.9)]
    lanes = rr.run_ensemble(jobs, progress=False)
    scalar = rr.run_ensemble(jobs, progress=False, lanes=1)
    for a, b in zip(lanes, scalar):
        assert len(a.maxima) == len(b.maxima) > 5
        np.testing.assert_allclose(a.maxima.t, b.maxima.t, rtol=0, atol=1e-9)


def test_an_ensemble_mixes_bodies_of_both_kinds_in_batches_of_one_kind():
    body = rr.Body.paper(1e-3)
    jobs = [rr.Job(body, rr.EulerState(0.95 * math.pi, psi=0.3), 100.0), rr.Job(TOP, START, 100.0),
            rr.Job(body.as_loaded_sphere(), rr.EulerState(0.95 * math.pi, psi=0.3), 100.0)]
    on_axis, top, general = rr.run_ensemble(jobs, progress=False)
    assert on_axis.maxima.body == body and top.maxima.body == TOP
    # the same body by the two forms: the same motion to round-off (the gravity torque's rounding differs)
    np.testing.assert_allclose(on_axis.maxima.t, general.maxima.t, rtol=0, atol=1e-9)


@pytest.mark.parametrize("sign", (1.0, -1.0))
def test_a_start_at_rest_in_an_equilibrium_of_a_top_is_refused(sign):
    """The vertical along ±c (mass centre straight below or above the centre), to the rounding of γ0."""
    c = np.array(TOP.offset)
    up = sign * c / np.linalg.norm(c)  # γ = (s sin ψ, s cos ψ, cos θ)
    start = rr.EulerState(math.acos(up[2]), psi=math.atan2(up[0], up[1]))
    with pytest.raises(ValueError, match="no motion"):
        rr.simulate(TOP, start, 10.0)
    tilted = rr.EulerState(math.acos(up[2]) + 1e-6, psi=math.atan2(up[0], up[1]))
    assert len(rr.simulate(TOP, tilted, 10.0, samples=False).maxima) >= 0  # a start off it moves


def test_a_ball_at_rest_is_refused():
    with pytest.raises(ValueError, match="no motion"):
        rr.simulate(rr.Body.chaplygin_ball(0.35, 0.37, 0.4), START, 10.0)


def test_chaplygins_ball_keeps_its_three_integrals_over_ten_thousand_time_units():
    """E, M·M and M·γ (Chaplygin 1903) within the run's round-off bound (energy_error_bound: the per-step tolerance
    summed over the steps, × 10; each integral is a polynomial of degree ≤ 4 in the state with O(1) terms here, so
    its relative error is a few times the state's), each against its own size."""
    ball = member_body(MEMBERS[0])
    run = rr.simulate(ball, member_start(), 1e4, progress=False)
    bound = energy_error_bound(run.tolerance, run.n_steps)
    gamma, omega = run.gamma, run.omega
    E = energy(ball, gamma, omega)
    assert np.max(np.abs(E - E[0])) <= bound * energy_scale(ball, E[0])
    for f in (momentum_squared, momentum_vertical):
        q = f(ball, gamma, omega)
        assert np.max(np.abs(q - q[0])) <= bound * np.max(np.abs(q))


@pytest.mark.slow
def test_the_direct_megno_calls_chaplygins_ball_regular_at_fifty_random_starts():
    """Chaplygin's ball is integrable: every orbit is regular, so MEGNO above its chaos threshold at any start would be a
    false positive of the indicator.  50 random starts (tilt, spin phase, ω), 1000 time units each."""
    ball = member_body(MEMBERS[0])
    rng = np.random.default_rng(2026)
    verdicts = []
    for _ in range(50):
        start = rr.EulerState.from_omega(rng.uniform(0.05, math.pi - 0.05), 0.0, rng.uniform(0, 2 * math.pi),
                                         tuple(rng.normal(size=3)))
        verdicts.append(rr.direct_chaos_indicators(ball, start, 1000.0).indicators.regular)
    assert all(verdicts)


def test_the_tilt_of_another_axis_is_followed_by_relabelling_the_axes():
    """top.relabelled(1) follows the tilt of principal axis 1: its run from the same physical state (components renamed
    cyclically) is the same motion, and its θ-maxima are the turning points of γ1 in the original run.  The two runs
    round differently (the same products in another order): 1e-9 over 30 time units of a regular run (measured
    ~1e-12)."""
    from rocknroller.analysis.model.kinematics import angles_from_frame

    original = rr.simulate(TOP, START, 30.0)
    y0 = START.to_body_state()
    order = [1, 2, 0]
    gamma, omega, ex = y0[0:3][order], y0[3:6][order], y0[6:9][order]
    theta, phi, psi = (float(v) for v in angles_from_frame(gamma, ex))
    renamed = rr.simulate(TOP.relabelled(1), rr.EulerState.from_omega(theta, phi, psi, omega), 30.0)
    assert len(renamed.maxima) >= 3
    there = original.state_at(renamed.maxima.t)
    np.testing.assert_allclose(there[:, 0:3][:, order], renamed.maxima.states[:, 0:3], rtol=0, atol=1e-9)
    np.testing.assert_allclose(there[:, 3:6][:, order], renamed.maxima.states[:, 3:6], rtol=0, atol=1e-9)
    rate_of_gamma1 = there[:, 1] * there[:, 5] - there[:, 2] * there[:, 4]  # (γ × ω)_1
    assert np.all(np.abs(rate_of_gamma1) <= 1e-9)
    with pytest.raises(ValueError, match="axis must be 1, 2 or 3"):
        TOP.relabelled(0)
