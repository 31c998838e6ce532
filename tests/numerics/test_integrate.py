"""The direct ODE: backends agree, invariants are conserved, every turning point is found to round-off."""

from __future__ import annotations

import math

import numpy as np
import pytest
import roundoff as ro

from rocknroller.analysis.model.body import Body
from rocknroller.analysis.model.diagnostics import azimuth_span, wrap_angle
from rocknroller.analysis.model.equations import EulerState, turning_point_function
from rocknroller.analysis.model.invariants import energy, jellett, routh
from rocknroller.analysis.model.kinematics import angles_from_frame
from rocknroller.analysis.routh.rocking import small_amplitude_frequency, small_amplitude_frequency_as_printed
from rocknroller.numerics.integrate import simulate
from rocknroller.numerics.run_limits import energy_scale

#: Safety margin of the integration bounds below: they take each step's error at the integrator's tolerance
#: and add the steps up linearly (worst cases already); the margin covers the first-order propagation and
#: the per-step error model of ``roundoff.integration_bound``.
MARGIN = 4.0
#: Rounded operations in one evaluation of E, Q_J or Q_R (rocknroller.analysis.model.invariants; E has the most: ≤ 25).
N_OPS_INVARIANT = 25
#: numpy's SIMD arctan2 is accurate to ≤ 4 ulp (libm's scalar one to ≤ 1): two evaluations of one angle in
#: (−π, π] on different code paths differ by ≤ 8 ulp(π) = 32 u π / π ... = 8 · 4u (ulp(π) = 2⁻⁵¹ = 4u).
ATAN2_SPREAD = 8 * 4 * ro.u


def _conservation_bound(traj, q) -> float:
    """Largest change of q(γ, ω) over a run of a body that conserves it: n_steps × tolerance × κ_q for the
    integration (``roundoff.integration_bound``; κ_q = Σ|yᵢ ∂q/∂yᵢ|, the largest over the samples) plus the
    rounding of two evaluations of q, 2 γ_n κ_q (κ_q ≥ the sum of |terms| of q, which scales its rounding);
    times MARGIN."""
    kappa = float(ro.relative_condition(lambda Z: q(traj.body, Z[:, 0:3].T, Z[:, 3:6].T), traj.states[:, 0:6]).max())
    return MARGIN * (ro.integration_bound(traj.n_steps, traj.tolerance, kappa) + 2 * ro.gamma(N_OPS_INVARIANT) * kappa)


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
    """Energy error (relative to E + g a, ``energy_scale``) within the integration bound for a conserved
    quantity: n_steps (≈ 3600) × ε × κ_E, κ_E ≈ 2 (E is quadratic in ω) — ≈ 2e-12, × MARGIN."""
    traj = fig5_runs[1e-3]
    scale = energy_scale(traj.body, float(traj.E[0]))
    ro.assert_within(traj.energy_rel_error, _conservation_bound(traj, energy) / scale, "energy", 1.0)


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
    """Q_J, Q_R vary by no more than the integration bound for conserved quantities (n_steps × ε × κ_q + the
    rounding of q, × MARGIN, ``_conservation_bound``) when I1 = I2, and by far more when I1 ≠ I2."""
    sym = fig5_runs[0.0]
    for name, q, series in (("QJ", jellett, sym.QJ), ("QR", routh, sym.QR)):
        ro.assert_within(np.ptp(series), _conservation_bound(sym, q), name, np.max(np.abs(series)))
    asym_J, asym_R = _variation_against_term_scale(fig5_runs[1e-3])
    assert asym_J > 1e-5 and asym_R > 1e-3


def test_jellett_routh_conserved_relative_to_themselves():
    """A spinning start with O(1) Q_J and Q_R: each conserved to the integration bound (≈ 1e-12 of itself)."""
    traj = simulate(Body.paper(), EulerState(1.0, 0.0, 0.0, 0.0, 0.5, 3.0), 300.0)
    for name, fun, q in (("QJ", jellett, traj.QJ), ("QR", routh, traj.QR)):
        assert abs(q[0]) > 0.1
        ro.assert_within(np.ptp(q), _conservation_bound(traj, fun), name, abs(q[0]))  # ≈ 4e-12 relative


def _event_time_amplification(body, initial, t_end, n) -> float:
    """Largest change of the first n turning-point times per unit perturbation of the state at the level of
    heyoka's error control (ε max(1, ‖y‖∞) absolute per component): central differences of the run in θ0
    and ψ0 (γ moves by the angle; ‖y‖∞ = 1 for the unit vectors) and in ω1, ω2, ω3 (steps scaled by
    max(1, |ω|∞)), summed in absolute value over the five directions.  The phase error of an oscillation
    grows with time, so a perturbation at the start is the largest any step makes."""
    w0 = np.asarray(initial.omega, float)
    scales = [1.0, 1.0] + [max(1.0, float(np.abs(w0).max()))] * 3
    base = simulate(body, initial, t_end)
    t0 = np.concatenate([base.maxima.t[:n], base.minima.t[:n]])
    h = 1e-7
    total = np.zeros(t0.size)
    for k, s in enumerate(scales):
        moved = []
        for sign in (1.0, -1.0):
            p = np.array([initial.theta, initial.psi, *w0])
            p[k] += sign * h * s
            tr = simulate(body, EulerState.from_omega(p[0], initial.phi, p[1], p[2:]), t_end)
            t = np.concatenate([tr.maxima.t, tr.minima.t])
            # the same turning point, moved (θ̇0 ≠ 0 can add one right at the start)
            moved.append(t[np.abs(t[None, :] - t0[:, None]).argmin(axis=1)])
        total = total + np.abs(moved[0] - moved[1]) / (2 * h)
    return float(total.max())


def test_turning_point_times_against_extended_precision(fig5_initial):
    """Turning-point times in double against 80-bit extended precision: within n_steps × ε × the flow's
    amplification of a state error into those times (``_event_time_amplification``, measured here; the
    extended run's own error is 2¹¹ times smaller), plus the event's location (a few ulp of t), × MARGIN."""
    body = Body.paper(1e-3)
    dbl = simulate(body, fig5_initial, 150.0)
    ext = simulate(body, fig5_initial, 150.0, precision="extended")
    assert len(dbl.maxima) >= 10
    amp = _event_time_amplification(body, fig5_initial, 150.0, 10)
    bound = MARGIN * (ro.integration_bound(dbl.n_steps, dbl.tolerance, amp) + 4 * ro.u * 150.0)
    ro.assert_within(dbl.maxima.t[:10] - ext.maxima.t[:10], bound, "maxima", dbl.maxima.t[:10])
    ro.assert_within(dbl.minima.t[:10] - ext.minima.t[:10], bound, "minima", dbl.minima.t[:10])


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
        idx = np.searchsorted(traj.t, t_max)  # exact: the turning points are samples of the grid
        assert np.array_equal(traj.t[idx], t_max) and idx[0] > 0 and idx[-1] < traj.t.size - 1
        assert np.all(traj.theta[idx] > traj.theta[idx - 1]) and np.all(traj.theta[idx] > traj.theta[idx + 1])
        assert np.all(traj.maxima.theta > 0.9 * math.pi)


def test_turning_point_samples_are_consistent(fig5_runs):
    traj = fig5_runs[1e-3]
    idx = np.searchsorted(traj.t, traj.maxima.t)  # exact: the turning points are inserted into the sample grid
    assert np.array_equal(traj.t[idx], traj.maxima.t)
    assert np.array_equal(traj.phi[idx], traj.maxima.phi)
    assert np.array_equal(traj.QJ[idx], traj.maxima.QJ)


def test_phi_is_continuous(fig5_runs):
    """φ is unwrapped: no jump of ~2π between samples, and φ mod 2π matches the frame."""
    traj = fig5_runs[1e-3]
    assert np.max(np.abs(np.diff(traj.phi))) < 2.0
    assert np.max(np.abs(np.diff(traj.psi))) < 2.0
    # φ = (its value from the frame) + 2πk: the product 2πk and the sum round (2u|φ|), the test's difference
    # and wrap_angle's π − x round again (2u|φ|; the representation error of 2π cancels in the wrap), and the
    # two arctan2 evaluations (different array lengths, SIMD or scalar paths) differ by ≤ ATAN2_SPREAD
    phi_frame = angles_from_frame(traj.states[:, 0:3].T, traj.states[:, 6:9].T)[1]
    bound = MARGIN * (4 * ro.u * np.abs(traj.phi) + ATAN2_SPREAD * np.pi)
    ro.assert_within(wrap_angle(traj.phi - phi_frame), bound, "phi", traj.phi)


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
    exact half-turn step is taken in (−π, π], the convention of rocknroller.analysis.model.diagnostics.wrap_angle)."""
    traj = simulate(Body.paper(), EulerState(0.95 * math.pi), 40.0)
    # The out-of-plane components stay exactly 0 (multiplied by 0 in every step), so the computed orbit passes
    # θ = 0 itself; θ at the located minimum is |θ̇| × the event's time error: the event function dγ3/dt
    # (slope θ̇² at the root, rounding u θ̇) places it within ~u/θ̇, and the time itself rounds to ~u t
    # (located by heyoka to a few ulp: 4u t), so θ_min ≤ u (4 t_end max|ω| + 8), × MARGIN
    wmax = float(np.abs(traj.omega).max())
    ro.assert_within(traj.minima.theta, MARGIN * ro.u * (4 * 40.0 * wmax + 8), "theta_min", 1.0)
    # φ, ψ at the maxima: exact multiples of π from atan2 of exact zeros, unwrapped by adding 2πk (the
    # product and the sum round: 2u|φ| each value), plus ATAN2_SPREAD if a component were not exactly 0
    phi, psi = traj.maxima.phi, traj.maxima.psi
    ro.assert_within(np.diff(phi) - math.pi, MARGIN * (4 * ro.u * np.abs(phi).max() + ATAN2_SPREAD * math.pi),
                     "dphi", math.pi)
    ro.assert_within(phi + psi, MARGIN * (2 * ro.u * (np.abs(phi) + np.abs(psi)) + ATAN2_SPREAD * math.pi),
                     "phi+psi", np.abs(phi) + np.abs(psi))


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
    from rocknroller.analysis.model.diagnostics import slow_period, span

    traj = fig5_runs[1e-3]
    assert traj.slow_period == slow_period(traj.maxima.t, 2 * traj.maxima.psi)
    assert traj.QR_extent == span(traj.maxima.QR) > 0
    assert traj.QJ_extent == span(traj.maxima.QJ) > 0
    sym = fig5_runs[0.0]  # Q_R conserved: its extent at the maxima within the integration bound
    ro.assert_within(sym.QR_extent, _conservation_bound(sym, routh), "QR_extent", np.abs(sym.QR).max())
