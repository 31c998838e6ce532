"""Direct runs in the lanes of heyoka's batch integrator (numerics/ensembles/batch.py): the same turning points as the scalar
integrator's simulate() within a derived round-off bound, on 200 random jobs; bit-identical between widths, splits
and lane positions; bad input refused before any work."""

from __future__ import annotations

import math
import warnings

import numpy as np
import pytest
from hypothesis import given, settings
from hypothesis import strategies as st

import rocknroller as rr
from rocknroller.analysis.model.diagnostics import wrap_angle
from rocknroller.numerics.ensembles.batch import MAX_LANES, MIN_LANES, batch_width, run_batch
from rocknroller.numerics.ensembles.ensemble import Job, run_ensemble
from rocknroller.numerics.run_limits import energy_error_bound

#: Unit round-off of double precision.
U = float(np.finfo(float).eps) / 2.0
#: Perturbation of θ0 by which the amplification of a run is measured (large against round-off, small enough that
#: the turning points move linearly: the second-order term, ~δ² S², stays below 1e-10 of the first at S ≤ 1e3).
DELTA = 1e-8


def _sensitivity(job: Job, run: rr.TurningPointRun) -> tuple[float, float]:
    """max |Δt_k|/δ and max |Δy_k|∞/δ of the θ-maxima under θ0 → θ0 + δ: how much the motion amplifies an error in
    its state by t_end, measured by a second run (a finite difference of the flow)."""
    s = job.initial
    moved = rr.simulate(job.body, rr.EulerState(s.theta + DELTA, s.phi, s.psi, s.theta_dot, s.phi_dot, s.psi_dot),
                        job.t_end, samples=False)
    n = min(len(run.maxima), len(moved.maxima))
    if n == 0:
        return 1.0, 1.0
    dt = np.max(np.abs(moved.maxima.t[:n] - run.maxima.t[:n])) / DELTA
    dy = np.max(np.abs(moved.maxima.states[:n] - run.maxima.states[:n])) / DELTA
    return float(dt), float(dy)


def _bounds(job: Job, run: rr.TurningPointRun, tol: float = 2.0 * U) -> tuple[float, float]:
    """The largest differences of the turning points' times and states between two integrators of the same run.

    Each integrator keeps its local error per step within its tolerance ``tol`` of max(1, ‖y‖∞) (heyoka's default,
    machine epsilon, is 2u; the state's size is at most ``scale`` over the run); an error committed at any step is amplified by the
    flow by at most what an error at the start is, which the perturbed run measures (S_t, S_y, at least 1); so each
    run's turning points are within n_steps · 2u · scale · S of the exact ones, and two runs' within twice that; the
    times also carry their location to the rounding of t (Newton to 4u|t|, numerics/events.py).  × 10 margin (the
    finite-difference S is the growth in one direction, the worst direction's can be a few times larger).
    """
    S_t, S_y = _sensitivity(job, run)
    scale = max(1.0, float(np.max(np.abs(run.maxima.states))) if len(run.maxima) else 1.0)
    per_run = run.n_steps * tol * scale
    return 10.0 * (2.0 * per_run * max(1.0, S_t) + 8.0 * U * job.t_end), 10.0 * 2.0 * per_run * max(1.0, S_y)


_jobs = st.lists(st.builds(
    lambda eps, theta, psi, rates, t_end: Job(rr.Body.paper(eps), rr.EulerState(theta, 0.0, psi, *rates), t_end),
    # ε = 0 (Routh's sphere) or one that I2 = (1 + ε) I1 resolves (Body.paper refuses ε below ~1e-16)
    st.one_of(st.just(0.0), st.floats(1e-12, 0.02)), st.floats(0.2, 3.0), st.floats(0.0, 2 * math.pi),
    st.tuples(*[st.floats(-0.5, 0.5)] * 3), st.floats(5.0, 40.0)), min_size=8, max_size=8)


@settings(max_examples=25, deadline=None, derandomize=True)
@given(_jobs)
def test_lanes_give_the_scalar_integrators_turning_points_within_round_off(jobs):
    """25 × 8 = 200 random jobs (asymmetry, tilt, spin phase, rates, length), run as one ensemble in lanes: every
    turning point of each job's scalar run, the same count, times and states within the derived bound."""
    with warnings.catch_warnings():
        warnings.simplefilter("error")  # an AccuracyWarning would fail the test
        lanes = run_ensemble(jobs, progress=False)
        for job, summary in zip(jobs, lanes):
            run = rr.simulate(job.body, job.initial, job.t_end, samples=False)
            assert summary.n_maxima == len(run.maxima)
            bound_t, bound_y = _bounds(job, run)
            assert np.max(np.abs(summary.maxima.t - run.maxima.t), initial=0.0) <= bound_t
            assert np.max(np.abs(summary.maxima.states - run.maxima.states), initial=0.0) <= bound_y
            # θ, φ, ψ: atan2 of components of γ and e_X of size sin θ, so within bound_y / sin θ (φ, ψ unwrapped: a
            # wrong branch would be off by 2π).  A passage through the pole itself (θ at a minimum within 1e-8, down
            # to round-off: the planar rocking of a start with ψ0 = 0 and no spin) leaves φ and ψ separately
            # undefined, only φ + ψ (numerics/trajectory.py): there φ and ψ may take either side's turn, φ + ψ not.
            if len(run.maxima):
                bound_angles = bound_y / float(np.min(np.sin(run.maxima.theta)))
                a, b = summary.maxima, run.maxima
                through_pole = len(run.minima) and float(np.min(run.minima.theta)) < 1e-8
                pairs = [(a.theta, b.theta), (a.phi + a.psi, b.phi + b.psi)]
                if through_pole:
                    pairs += [(wrap_angle(a.phi - b.phi), 0.0), (wrap_angle(a.psi - b.psi), 0.0)]
                else:
                    pairs += [(a.phi, b.phi), (a.psi, b.psi)]
                for x, y in pairs:
                    assert np.max(np.abs(x - y)) <= 2.0 * bound_angles
            assert summary.energy_rel_error <= energy_error_bound(U * 2.0, summary.n_steps)


@settings(max_examples=3, deadline=None, derandomize=True)
@given(_jobs, st.sampled_from([1e-11, 1e-8]))
def test_lanes_at_a_looser_tolerance_give_simulates_turning_points_within_its_bound(jobs, tol):
    """3 × 8 random jobs at tol = 1e-11 (DOP853's best energy error) or 1e-8, as an ensemble in lanes and each by
    simulate at the same tol: the same count, times and states within the bound derived at that tol, the energy error
    within its bound, which scales with tol."""
    jobs = [Job(job.body, job.initial, job.t_end, tol) for job in jobs]
    with warnings.catch_warnings():
        warnings.simplefilter("error")
        lanes = run_ensemble(jobs, progress=False)
        for job, summary in zip(jobs, lanes):
            run = rr.simulate(job.body, job.initial, job.t_end, samples=False, tol=tol)
            assert summary.n_maxima == len(run.maxima)
            bound_t, bound_y = _bounds(job, run, tol)
            assert np.max(np.abs(summary.maxima.t - run.maxima.t), initial=0.0) <= bound_t
            assert np.max(np.abs(summary.maxima.states - run.maxima.states), initial=0.0) <= bound_y
            assert summary.energy_rel_error <= energy_error_bound(tol, summary.n_steps)


@pytest.mark.parametrize("tol", [2.0 * U, 1e-11])
def test_minima_and_a_long_run_match_the_scalar_integrator(tol):
    """The release of the paper's figures (θ0 = 0.95π, 1000 time units, 75 maxima, passages within 2e-5 rad of the
    pole where φ and ψ turn by π), at the default tolerance and at 1e-11: maxima and minima within the bound, φ and ψ
    on the same branch."""
    job = Job(rr.Body.paper(1e-3), rr.EulerState(0.95 * math.pi, psi=0.3), 1000.0, tol)
    (lane,) = run_batch([(job.body, job.initial, job.t_end)], tol=tol)
    run = rr.simulate(job.body, job.initial, job.t_end, samples=False, tol=tol)
    bound_t, bound_y = _bounds(job, run, tol)
    for a, b in ((lane.maxima, run.maxima), (lane.minima, run.minima)):
        assert len(a) == len(b) > 70
        assert np.max(np.abs(a.t - b.t)) <= bound_t
        assert np.max(np.abs(a.states - b.states)) <= bound_y
        assert np.max(np.abs(a.phi - b.phi)) < 1e-6 and np.max(np.abs(a.psi - b.psi)) < 1e-6


def test_the_unwrapping_grid_does_not_change_the_turning_points():
    """The default unwrapping grid of samples=False (UNWRAP_RADIANS = 1 radian of Λ, with the rate test) and the
    output grid of samples=True's spacing (DT_RADIANS = 0.15): the same turning points to the bit (the angles are the
    wrapped ones plus whole turns); the energy error is a maximum over other points, within the bound either way."""
    from rocknroller.numerics.integrate import DT_RADIANS, rate_bound

    body, start = rr.Body.paper(1e-3), rr.EulerState(0.95 * math.pi, psi=0.3)
    coarse = rr.simulate(body, start, 300.0, samples=False)
    fine = rr.simulate(body, start, 300.0, samples=False,
                       dt=DT_RADIANS / rate_bound(body, start.to_body_state()))
    for a, b in ((coarse.maxima, fine.maxima), (coarse.minima, fine.minima)):
        for name in ("t", "theta", "phi", "psi", "QR", "QJ", "states"):
            assert np.array_equal(getattr(a, name), getattr(b, name)), name
    assert max(coarse.energy_rel_error, fine.energy_rel_error) <= coarse.energy_tolerance


def test_a_lane_is_the_same_in_any_position_and_any_batch():
    runs = [(rr.Body.paper(eps), rr.EulerState(0.95 * math.pi, psi=psi), 60.0) for eps in (1e-3, 1e-2)
            for psi in (0.1, 0.7)]
    width = batch_width()
    together = run_batch(runs, width)
    for k, run in enumerate(runs):
        alone = run_batch([run], width)[0]
        shifted = run_batch(runs[k:] + runs[:k], width)[0]
        for other in (alone, shifted):
            assert np.array_equal(other.maxima.states, together[k].maxima.states)
            assert np.array_equal(other.maxima.phi, together[k].maxima.phi)
            assert other.energy_rel_error == together[k].energy_rel_error and other.n_steps == together[k].n_steps


@pytest.mark.slow
def test_sixteen_lanes_give_the_same_bits():
    """The widest batch (MAX_LANES, its compilation ~10-30 s once per machine) against the narrowest."""
    runs = [(rr.Body.paper(1e-2), rr.EulerState(0.95 * math.pi, psi=0.1 * k), 60.0) for k in range(MIN_LANES)]
    for a, b in zip(run_batch(runs, MAX_LANES), run_batch(runs, MIN_LANES), strict=True):
        assert np.array_equal(a.maxima.states, b.maxima.states) and a.n_steps == b.n_steps


@pytest.mark.parametrize("runs, width, match", [
    ([], None, r"runs: between 1 and width = \d+ runs per batch, got 0"),
    ([(rr.Body.paper(), rr.EulerState(3.0), 10.0)] * 3, 2, r"between 1 and width = 2 runs per batch, got 3"),
    ([(rr.Body.paper(), rr.EulerState(3.0), 10.0)], 1, r"width must be a whole number in \[2, 16\]"),
    ([(rr.Body.paper(), rr.EulerState(3.0), 10.0)], 17, r"width must be a whole number in \[2, 16\]"),
    ([(rr.Body.paper(), rr.EulerState(3.0), 1e12)], None, r"t_end=1000000000000.0 is too long.*MAX_RADIANS"),
    ([(rr.Body.paper(), rr.EulerState(math.pi), 10.0)], None, r"no motion"),
])
def test_bad_input_is_refused_before_any_work(runs, width, match):
    with pytest.raises(ValueError, match=match):
        run_batch(runs, width)
