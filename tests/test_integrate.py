"""The direct ODE: backends agree, invariants are conserved, every turning point is found to round-off."""

from __future__ import annotations

import math

import numpy as np
import pytest

from rocknroller.analysis.body import Body
from rocknroller.analysis.kinematics import angles_from_frame
from rocknroller.analysis.quadrature import wrap_angle
from rocknroller.analysis.rocking import small_amplitude_frequency, small_amplitude_frequency_as_printed
from rocknroller.numerics.equations import EulerState, turning_point_function
from rocknroller.numerics.integrate import simulate
from rocknroller.analysis.slow_diagnostics import azimuth_span


@pytest.fixture(scope="module")
def fig5_runs(fig5_initial):
    """The paper's figure-5 runs (1500 time units), symmetric and ε = 1e-3, heyoka."""
    return {eps: simulate(Body.paper(eps), fig5_initial, 1500.0) for eps in (0.0, 1e-3)}


def test_backends_agree_over_100_time_units(fig5_initial):
    body = Body.paper(1e-3)
    hy = simulate(body, fig5_initial, 100.0)
    sc = simulate(body, fig5_initial, 100.0, method="scipy")
    assert np.max(np.abs(hy.states - sc.states)) <= 1e-9
    assert len(hy.maxima) == len(sc.maxima) and len(hy.minima) == len(sc.minima)
    assert np.max(np.abs(hy.maxima.t - sc.maxima.t)) <= 1e-9


def test_energy_fig5_heyoka(fig5_runs):
    assert fig5_runs[1e-3].energy_rel_error <= 1e-13


def test_energy_fig5_scipy(fig5_initial):
    traj = simulate(Body.paper(1e-3), fig5_initial, 1500.0, method="scipy")
    assert traj.energy_rel_error <= 1e-10


def _variation_against_term_scale(traj):
    """ptp of Q_J and Q_R over the run, relative to the size of the terms they are summed from.

    Q_J = I1 s ω2' + I3 f ω3' can be far smaller than its two terms (here 5e-4 against 0.3), so its
    evaluation alone carries an error ~1e-16 × the terms; that, not |Q_J|, is the scale of round-off.
    """
    g, w = traj.gamma, traj.omega
    b = traj.body
    terms_J = np.max(np.abs(b.I1 * (g[0] * w[0] + g[1] * w[1])) + np.abs(b.I3 * (g[2] - b.a) * w[2]))
    return float(np.ptp(traj.QJ) / terms_J), float(np.ptp(traj.QR) / np.max(np.abs(traj.QR)))


def test_jellett_routh_conserved_only_when_symmetric(fig5_runs):
    sym_J, sym_R = _variation_against_term_scale(fig5_runs[0.0])
    asym_J, asym_R = _variation_against_term_scale(fig5_runs[1e-3])
    assert sym_J <= 1e-12 and sym_R <= 1e-12
    assert asym_J > 1e-5 and asym_R > 1e-3


def test_jellett_routh_conserved_relative_to_themselves():
    """A spinning start with O(1) Q_J and Q_R: each conserved to 1e-12 of its own value."""
    traj = simulate(Body.paper(), EulerState(1.0, 0.0, 0.0, 0.0, 0.5, 3.0), 300.0)
    for q in (traj.QJ, traj.QR):
        assert abs(q[0]) > 0.1
        assert np.ptp(q) / abs(q[0]) <= 1e-12


def test_turning_point_times_against_extended_precision(fig5_initial):
    body = Body.paper(1e-3)
    dbl = simulate(body, fig5_initial, 150.0)
    ext = simulate(body, fig5_initial, 150.0, precision="extended")
    assert len(dbl.maxima) >= 10
    assert np.max(np.abs(dbl.maxima.t[:10] - ext.maxima.t[:10])) <= 1e-11
    assert np.max(np.abs(dbl.minima.t[:10] - ext.minima.t[:10])) <= 1e-11


def test_every_turning_point_found_once(fig5_runs):
    """Events alternate max/min, and dγ3/dt changes sign exactly once between neighbouring events."""
    for traj in fig5_runs.values():
        t_max, t_min = traj.maxima.t, traj.minima.t
        assert t_min[0] < t_max[0]  # released at rest from a maximum: a minimum comes first
        events = np.sort(np.concatenate([t_max, t_min]))
        kinds = np.isin(events, t_max)
        assert np.all(kinds[1:] != kinds[:-1])
        assert events[0] > 1.0  # no spurious event at t = 0 although θ̇0 = 0
        # a fine scan between events finds no other sign change of dγ3/dt
        t = np.linspace(1e-6, traj.t[-1] - 1e-6, 300_000)
        g = turning_point_function(traj.state_at(t).T)
        changes = np.count_nonzero(np.sign(g[1:]) != np.sign(g[:-1]))
        assert changes == events.size
        # maxima are maxima: θ there exceeds θ on the neighbouring grid samples
        idx = np.searchsorted(traj.t, t_max)
        assert np.array_equal(traj.t[idx], t_max) and idx[0] > 0 and idx[-1] < traj.t.size - 1
        assert np.all(traj.theta[idx] > traj.theta[idx - 1]) and np.all(traj.theta[idx] > traj.theta[idx + 1])
        assert np.all(traj.maxima.theta > 0.9 * math.pi)


def test_turning_point_samples_are_consistent(fig5_runs):
    traj = fig5_runs[1e-3]
    idx = np.searchsorted(traj.t, traj.maxima.t)
    assert np.array_equal(traj.t[idx], traj.maxima.t)
    assert np.array_equal(traj.phi[idx], traj.maxima.phi)
    assert np.array_equal(traj.QJ[idx], traj.maxima.QJ)


def test_phi_is_continuous(fig5_runs):
    """φ is unwrapped: no jump of ~2π between samples, and φ mod 2π matches the frame."""
    traj = fig5_runs[1e-3]
    assert np.max(np.abs(np.diff(traj.phi))) < 2.0
    assert np.max(np.abs(np.diff(traj.psi))) < 2.0
    # |φ| reaches ~190 here (ulp 3e-14) and is a running sum over ~3e4 steps: a few tens of ulps
    phi_frame = angles_from_frame(traj.states[:, 0:3].T, traj.states[:, 6:9].T)[1]
    assert np.max(np.abs(wrap_angle(traj.phi - phi_frame))) <= 1e-12


@pytest.mark.parametrize("psi0, moment", [(0.0, "I1"), (math.pi / 2, "I2")])
def test_small_amplitude_rocking_period(psi0, moment):
    """Rocking about a principal axis: period 2π √((I_k + (1 − a)²)/(g a)) (exact linearisation).

    The θ-maxima come twice per physical period (θ ≥ 0 is the tilt on either side), so the period
    is the spacing of every second maximum.  The paper's g a/(I1 + 1) is ~4 % off.
    """
    body = Body.paper(0.05)
    amp = 1e-3
    traj = simulate(body, EulerState(amp, 0.0, psi0), 60.0)
    period = 2.0 * traj.maxima_spacing  # the rocking passes θ = 0: two θ-maxima per period
    Ik = getattr(body, moment)
    # the amplitude correction is c amp² with c ≈ 0.07 here (1/16 for a simple pendulum): amp² bounds it
    assert period == pytest.approx(2 * math.pi / small_amplitude_frequency(body, Ik), rel=amp**2)
    assert abs(2 * math.pi / small_amplitude_frequency_as_printed(body, Ik) / period - 1) > 0.03


def test_pure_rocking_through_the_pole_keeps_phi_plus_psi():
    """Exact planar rocking passes θ = 0 to round-off; φ jumps by +π and ψ by −π (φ + ψ continuous; an
    exact half-turn step is taken in (−π, π], the convention of rocknroller.analysis.quadrature.wrap_angle)."""
    traj = simulate(Body.paper(), EulerState(0.95 * math.pi), 40.0)
    assert np.all(traj.minima.theta < 1e-12)
    assert np.allclose(np.diff(traj.maxima.phi), math.pi, atol=1e-12)
    assert np.allclose(traj.maxima.phi + traj.maxima.psi, 0.0, atol=1e-12)


def test_azimuth_span_is_cut_independent():
    phis = np.array([-0.2, 0.1, 0.3])
    assert azimuth_span(phis) == pytest.approx(0.5)
    assert azimuth_span(phis + 7 * math.pi) == pytest.approx(0.5)
    assert azimuth_span([1.0]) == 0.0


@pytest.mark.parametrize(
    "make, fragment",
    [
        (lambda: EulerState(3.5), "0 <= theta0 <= pi"),
        (lambda: EulerState(-0.1), "0 <= theta0 <= pi"),
        (lambda: EulerState(1.0, phi_dot=float("nan")), "phi_dot must be a finite"),
        (lambda: simulate(Body.paper(), EulerState(1.0), 0.0), "t_end must be"),
        (lambda: simulate(Body.paper(), EulerState(1.0), float("inf")), "t_end must be"),
        (lambda: simulate(Body.paper(), EulerState(0.0), 10.0), "no motion"),
        (lambda: simulate(Body.paper(), EulerState(math.pi), 10.0), "no motion"),
        (lambda: simulate(Body.paper(), EulerState(1.0), 10.0, method="rk4"), "method must be"),
        (lambda: EulerState.from_omega(0.0, 0, 0, (1, 0, 0)), "0 < theta0 < pi"),
    ],
)
def test_bad_input(make, fragment):
    with pytest.raises(ValueError, match=fragment):
        make()


def test_slow_diagnostics_follow_their_definitions(fig5_runs):
    from rocknroller.analysis.slow_diagnostics import slow_period, span

    traj = fig5_runs[1e-3]
    assert traj.slow_period == slow_period(traj.maxima.t, 2 * traj.maxima.psi)
    assert traj.QR_extent == span(traj.maxima.QR) > 0
    assert traj.QJ_extent == span(traj.maxima.QJ) > 0
    assert fig5_runs[0.0].QR_extent < 1e-15
