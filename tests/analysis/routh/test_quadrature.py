"""Precession quadratures of Routh's sphere against the direct ODE and against mpmath."""

from __future__ import annotations

import math

import mpmath
import numpy as np
import pytest
import roundoff as ro
from quadrature_bounds import BODY, _bound_at, quadrature_bound

from rocknroller.analysis.criticality.lines import QJ_crit_0, QJ_crit_pi
from rocknroller.analysis.model.body import Body
from rocknroller.analysis.model.diagnostics import wrap_angle
from rocknroller.analysis.model.equations import EulerState
from rocknroller.analysis.model.kinematics import primed_from_body
from rocknroller.analysis.routh.quadrature import UNRESOLVED, precession, precession_from_turning_point
from rocknroller.analysis.routh.quadrature_mp import precession_mp
from rocknroller.analysis.routh.reduction import NO_MOTION, OK, STEADY, F, state_from_turning_point
from rocknroller.analysis.routh.turning_points import solve_turning_points
from rocknroller.numerics.integrate import simulate

_QJ0, _QJPI = float(QJ_crit_0(0.01, BODY)), float(QJ_crit_pi(0.01, BODY))

#: (label, θ0 = θ_X, Q_R, Q_J) for the ODE comparisons: generic, θ_N < 1e-4, θ_X > π − 1e-3, both.
ODE_CASES = [
    ("generic", 0.95 * np.pi, 0.01, 0.002),
    ("mid-range", 2.0, -0.02, 0.03),
    ("theta_N<1e-4", 0.95 * np.pi, 0.01, _QJ0 + 2e-5),
    ("theta_X>pi-1e-3", np.pi - 5e-4, 0.01, 0.002),
    ("both ends", np.pi - 5e-4, 0.01, _QJ0 + 2e-5),
    ("theta_N<1e-6, recession side", 0.95 * np.pi, 0.01, _QJ0 - 2e-7),
]


@pytest.fixture(scope="module")
def ode_runs():
    """For each case: the direct ODE (heyoka) over 12 oscillations and the quadrature on its invariants."""
    out = {}
    for label, theta0, QR, QJ in ODE_CASES:
        st = state_from_turning_point(BODY, theta0, QR, QJ)
        initial = EulerState(theta0, 0.0, 0.0, 0.0, float(st.phi_dot), float(st.psi_dot))
        T_guess = float(precession(st.E, QR, QJ, BODY).T_theta)
        traj = simulate(BODY, initial, 12.2 * T_guess)
        # the invariants of the state actually integrated (what the quadrature must reproduce)
        pr = precession(traj.E[0], traj.QR[0], traj.QJ[0], BODY)
        assert pr.status == OK
        out[label] = (traj, pr)
    return out


def _maxima_series(traj):
    """Times and unwrapped φ, ψ at the maxima of θ, the start (a maximum, θ̇ = 0) included."""
    t = np.concatenate([[0.0], traj.maxima.t])
    phi = np.concatenate([[traj.phi[0]], traj.maxima.phi])
    psi = np.concatenate([[traj.psi[0]], traj.maxima.psi])
    return t, phi, psi


@pytest.mark.parametrize("label", [c[0] for c in ODE_CASES])
def test_ranges_of_the_cases(label, ode_runs):
    """The cases cover what they claim (θ_N < 1e-4, θ_X > π − 1e-3)."""
    traj, pr = ode_runs[label]
    if "theta_N<1e-6" in label:
        assert pr.theta_N < 1e-6
    elif "theta_N" in label or "both" in label:
        assert pr.theta_N < 1e-4
    if "theta_X" in label or "both" in label:
        assert pr.theta_X > np.pi - 1e-3
    assert len(traj.maxima) >= 11


@pytest.mark.parametrize("label", [c[0] for c in ODE_CASES if "theta_N" not in c[0] and "both" not in c[0]])
def test_F_equals_theta_dot_squared_along_ode(label, ode_runs):
    """F(θ(t)) = θ̇(t)² along the trajectory to ≤ 1e-11 of max θ̇².

    Cases with θ_N ≥ 1e-3: near θ = 0 the body-frame state fixes θ only to ~ε absolutely, and
    F' ~ F/θ there, so a passage at θ_N ≪ 1e-3 limits the comparison itself (not F).
    """
    traj, pr = ode_runs[label]
    theta_dot = primed_from_body(traj.psi, traj.omega)[0]  # ω1' = θ̇ (paper eq. angledot)
    F_val = F(traj.theta, traj.E[0], traj.QR[0], traj.QJ[0], BODY)
    scale = np.max(theta_dot**2)
    assert np.max(np.abs(F_val - theta_dot**2)) <= 1e-11 * scale


@pytest.mark.parametrize("label", [c[0] for c in ODE_CASES])
def test_T_theta_equals_spacing_of_ode_maxima(label, ode_runs):
    traj, pr = ode_runs[label]
    t, _, _ = _maxima_series(traj)
    assert np.max(np.abs(np.diff(t) / pr.T_theta - 1.0)) <= 1e-10
    assert pr.tau == 2 * pr.T_theta
    assert abs((t[2::2] - t[:-2:2]) / pr.tau - 1.0).max() <= 1e-10


@pytest.mark.parametrize("label", [c[0] for c in ODE_CASES])
def test_increments_equal_ode_unwrapped_angles_between_maxima(label, ode_runs):
    """Δφ, Δψ per T_θ (and per τ) against the unwrapped φ, ψ of the ODE between maxima, ≤ 1e-9."""
    traj, pr = ode_runs[label]
    _, phi, psi = _maxima_series(traj)
    assert np.max(np.abs(np.diff(phi) - pr.delta_phi)) <= 1e-9
    assert np.max(np.abs(np.diff(psi) - pr.delta_psi)) <= 1e-9
    assert np.max(np.abs(phi[2:] - phi[:-2] - pr.delta_phi_tau)) <= 2e-9
    assert np.max(np.abs(psi[2:] - psi[:-2] - pr.delta_psi_tau)) <= 2e-9
    # visible angles: what an observer sees of the same increments
    assert np.max(np.abs(wrap_angle(np.diff(phi) - pr.visible_phi))) <= 1e-9
    assert np.max(np.abs(wrap_angle(np.diff(phi) - pr.visible_half_phi, np.pi))) <= 1e-9
    assert -np.pi < pr.visible_phi <= np.pi and -np.pi / 2 < pr.visible_half_phi <= np.pi / 2


def test_full_angle_jump_sign_follows_critical_line(ode_runs):
    """Passing near θ = 0, φ jumps by ≈ ±π with the sign of Q_J − Q_J,0^crit (paper §2.6)."""
    _, above = ode_runs["theta_N<1e-4"]
    _, below = ode_runs["theta_N<1e-6, recession side"]
    # Δφ ∓ π is smooth across the line, with ∂(Δφ ∓ π)/∂Q_J ≈ 159 here (quadrature, linear from offsets
    # 1e-4 down to 1e-10): the difference is 2π + 159 × (2e-5 + 2e-7) = 2π + 3.2e-3, up to O(ΔQ_J²) ~ 1e-5
    assert above.delta_phi - below.delta_phi == pytest.approx(2 * np.pi, abs=4e-3)


# ----------------------------------------------------------------------------- against mpmath
def _plane_points(rng, n_generic, n_small_N, n_near_pi):
    """(E, Q_R, Q_J) spread over the plane; some with θ_N < 1e-3, some with θ_X > π − 1e-3."""
    pts = []
    while len(pts) < n_generic:
        theta0 = rng.uniform(0.55, 0.99) * np.pi
        QR, QJ = rng.uniform(-0.03, 0.03, 2)
        pts.append((theta0, QR, QJ))
    while len(pts) < n_generic + n_small_N:
        QR = rng.uniform(-0.03, 0.03)
        QJ = float(QJ_crit_0(QR, BODY)) + rng.choice([-1, 1]) * 10 ** rng.uniform(-12, -4)
        theta0 = rng.uniform(0.55, 0.99) * np.pi
        pts.append((theta0, QR, QJ))
    while len(pts) < n_generic + n_small_N + n_near_pi:
        theta0 = np.pi - 10 ** rng.uniform(-8, -3)
        QR = rng.uniform(-0.03, 0.03)
        QJ = float(QJ_crit_pi(QR, BODY)) + rng.choice([-1, 1]) * 10 ** rng.uniform(-9, -2)
        pts.append((theta0, QR, QJ))
    theta0, QR, QJ = (np.array(v) for v in zip(*pts))
    E = state_from_turning_point(BODY, theta0, QR, QJ).E
    return E, QR, QJ


def _compare_with_mpmath(E, QR, QJ, dps=40):
    """Per point: relative differences of T_θ and the largest difference of Δφ, Δψ and the visible φ (per T_θ)
    against mpmath, and their bounds (``quadrature_bound``); the angles relative to max(|Δ|, 1 rad)."""
    from rocknroller.analysis.routh.turning_points import solve_turning_points

    dbl = precession(E, QR, QJ, BODY)
    assert np.all(dbl.status == OK)
    bT, bA = quadrature_bound(solve_turning_points(E, QR, QJ, BODY), dbl.n_nodes)
    errT, errA, scale = np.zeros(E.size), np.zeros(E.size), np.zeros(E.size)
    for i in range(E.size):
        ref = precession_mp(E[i], QR[i], QJ[i], BODY, dps=dps)
        errT[i] = float(dbl.T_theta[i] / ref.T_theta - 1)
        for k in ("delta_phi", "delta_psi", "visible_phi"):
            r = getattr(ref, k)
            errA[i] = max(errA[i], abs(float(getattr(dbl, k)[i] - r)))
            scale[i] = max(scale[i], abs(float(r)), 1.0)
    return (errT, errA / scale), (bT, bA / scale), dbl


def _check_spread(dbl, n_small_N, n_near_pi):
    assert np.count_nonzero(dbl.theta_N < 1e-3) >= n_small_N
    assert np.count_nonzero(dbl.theta_X > np.pi - 1e-3) >= n_near_pi


def test_double_against_mpmath_40_digits_small():
    """12 points (4 with θ_N < 1e-3, 4 with θ_X > π − 1e-3): double precision to round-off (``quadrature_bound``)."""
    E, QR, QJ = _plane_points(np.random.default_rng(11), 4, 4, 4)
    errs, bounds, dbl = _compare_with_mpmath(E, QR, QJ)
    _check_spread(dbl, 4, 4)
    ro.assert_within(errs[0], bounds[0], "T_theta", 1.0)
    ro.assert_within(errs[1], bounds[1], "angles", 1.0)


@pytest.mark.slow
def test_double_against_mpmath_40_digits_200_points():
    """≥ 200 points over the plane, ≥ 50 with θ_N < 1e-3 and ≥ 20 with θ_X > π − 1e-3: to round-off
    (``quadrature_bound``)."""
    E, QR, QJ = _plane_points(np.random.default_rng(12), 130, 50, 20)
    errs, bounds, dbl = _compare_with_mpmath(E, QR, QJ)
    assert E.size >= 200
    _check_spread(dbl, 50, 20)
    ro.assert_within(errs[0], bounds[0], "T_theta", 1.0)
    ro.assert_within(errs[1], bounds[1], "angles", 1.0)


@pytest.mark.parametrize("theta0,QR,QJ", [
    (0.95 * np.pi, 0.01, 0.002),
    (0.95 * np.pi, 0.01, _QJ0 + 1e-9),  # θ_N ~ 2e-9
    (np.pi - 1e-6, 0.01, _QJPI + 1e-7),  # θ_X = π − 1e-6
])
def test_mpmath_30_and_50_digits_agree(theta0, QR, QJ):
    E = float(state_from_turning_point(BODY, theta0, QR, QJ).E)
    lo, hi = precession_mp(E, QR, QJ, BODY, dps=30), precession_mp(E, QR, QJ, BODY, dps=50)
    for k in ("T_theta", "delta_phi", "delta_psi", "theta_N", "theta_X"):
        a, b = getattr(lo, k), getattr(hi, k)
        # 30-digit arithmetic (10⁻³⁰ relative per operation) amplified by the conditioning of the roots near the ends
        # (θ_N ~ 2e-9, π − θ_X = 1e-6: up to ~10⁴): 1e-25 leaves a factor ≥ 10
        assert abs(a - b) <= mpmath.mpf(1e-25) * max(abs(b), 1), k


def test_mpmath_theta0_mode_pins_the_turning_point():
    ref = precession_mp(None, 0.01, 0.002, BODY, dps=30, theta0=0.95 * np.pi)
    # 30-digit arithmetic: the root pinned to ~10⁻³⁰ × its condition; 10⁻²⁸ leaves a factor 100
    assert abs(ref.theta_X - mpmath.mpf(0.95 * np.pi)) <= mpmath.mpf(10) ** -28
    dbl, upper = precession_from_turning_point(0.95 * np.pi, 0.01, 0.002, BODY)
    assert upper and dbl.theta_X == 0.95 * np.pi
    bT, _ = _bound_at(float(dbl.E), 0.01, 0.002, dbl.n_nodes)
    ro.assert_within(float(dbl.T_theta / ref.T_theta) - 1, bT, "T_theta", 1.0)


# ----------------------------------------------------------------------------- the rule itself
def test_node_count_follows_the_tolerance():
    """Looser tolerance, fewer nodes and a larger (but still bounded) error: the check is real."""
    E, QR, QJ = _plane_points(np.random.default_rng(5), 20, 0, 10)
    tight = precession(E, QR, QJ, BODY)
    loose = precession(E, QR, QJ, BODY, rtol=1e-4)
    assert np.all(loose.n_nodes <= tight.n_nodes) and np.any(loose.n_nodes < tight.n_nodes)
    err_loose = np.max(np.abs(loose.T_theta / tight.T_theta - 1))
    assert 0 < err_loose <= 1e-4
    near_pi = tight.theta_X > np.pi - 1e-3
    assert np.median(tight.n_nodes[near_pi]) >= np.median(tight.n_nodes[~near_pi])


def test_vectorised_statuses_never_nan():
    """Points without a result are masked (their status says why), never NaN; a single such point raises."""
    E = np.array([1.0, 0.0, 1.0])
    QR = np.array([0.01, 0.01, 0.01])
    QJ = np.array([0.002, 0.002, 0.002])
    tp = solve_turning_points(1.0, 0.01, 0.002, BODY)
    E[2] = float(tp.U_min)
    pr = precession(E, QR, QJ, BODY)
    assert list(pr.status) == [OK, NO_MOTION, STEADY]
    for name in ("theta_N", "theta_X", "T_theta", "tau", "delta_phi", "delta_psi", "visible_phi"):
        field = getattr(pr, name)
        assert list(np.ma.getmaskarray(field)) == [False, True, True], name
        assert np.all(np.isfinite(field.data)), name
    assert "no_motion" in pr.status_text()[1] and "steady" in pr.status_text()[2]
    assert UNRESOLVED not in pr.status
    with pytest.raises(ValueError, match="no motion"):
        precession(0.0, 0.01, 0.002, BODY)
    with pytest.raises(ValueError, match="steady circular rolling"):
        precession(E[2], 0.01, 0.002, BODY)


def test_bad_input_raises():
    with pytest.raises(ValueError, match="no motion"):
        precession_mp(0.0, 0.01, 0.002, BODY)
    with pytest.raises(ValueError, match="steady circular rolling"):
        precession_mp(float(solve_turning_points(1.0, 0.01, 0.002, BODY).U_min), 0.01, 0.002, BODY)
    with pytest.raises(ValueError, match="theta0 must lie in the open interval"):
        precession_from_turning_point(np.pi, 0.01, 0.0, BODY)
    with pytest.raises(ValueError, match="theta0 must lie in the open interval"):
        precession_mp(None, 0.01, 0.0, BODY, theta0=0.0)
    with pytest.raises(ValueError, match="dps must be"):
        precession_mp(1.0, 0.01, 0.0, BODY, dps=5)
    with pytest.raises(ValueError, match="rtol must"):
        precession(1.0, 0.01, 0.0, BODY, rtol=0.5)
    # below the rules' round-off the doubling cannot meet the tolerance: refused, not a table of unresolved points
    for bad in (3e-15, 0.0, "x", math.nan):
        with pytest.raises(ValueError, match=r"rtol must lie in \[1e-14, 0.001\]"):
            precession(1.0, 0.01, 0.0, BODY, rtol=bad)
    for call in (lambda: precession(1.0, 0.01, 0.0, Body.paper(1e-3)),
                 lambda: precession_mp(1.0, 0.01, 0.0, Body.paper(1e-3))):
        with pytest.raises(ValueError, match="symmetric body"):
            call()


def test_near_steady_rolling_is_flagged_not_silently_inaccurate():
    """Close to steady rolling E − U(θ) is a small difference on the whole interval: such points are
    UNRESOLVED (use mpmath) rather than returned with lost digits; a little further away, full accuracy."""
    QR, QJ = 0.02, 0.05
    U_min = float(solve_turning_points(1.0, QR, QJ, BODY).U_min)
    near = precession(U_min * (1 + np.array([1e-10, 1e-6, 1e-4])), QR, QJ, BODY)
    assert np.all(near.status == UNRESOLVED) and np.all(np.ma.getmaskarray(near.T_theta))
    for d in (0.05, 0.5):
        E = U_min * (1 + d)
        pr, ref = precession(E, QR, QJ, BODY), precession_mp(E, QR, QJ, BODY, dps=30)
        # resolved: the estimate is below the library's own threshold for UNRESOLVED (quadrature._MAX_ROUNDING)
        assert pr.status == OK and pr.rounding_error <= 1e-12
        bT, bA = _bound_at(E, QR, QJ, pr.n_nodes)
        ro.assert_within(float(pr.T_theta / ref.T_theta) - 1, bT, "T_theta", 1.0)
        ro.assert_within(float(pr.delta_phi - ref.delta_phi), bA, "delta_phi", float(ref.delta_phi))
    # the mpmath backend resolves what double precision cannot
    ref = precession_mp(U_min * (1 + 1e-6), QR, QJ, BODY, dps=30)
    assert 0 < ref.theta_X - ref.theta_N < 1e-2


# ----------------------------------------------------------------------------- ERRATA §12
def _phi_sweep_across_pi_line(delta: float, offsets: np.ndarray):
    """Δφ per T_θ (unwrapped along the offsets) at θ_X = π − δ, Q_R = 0.01, Q_J = Q_J,π^crit + offset·|Q_J,π^crit|."""
    QR = 0.01
    crit = float(QJ_crit_pi(QR, BODY))
    pr, upper = precession_from_turning_point(np.pi - delta, QR, crit + offsets * abs(crit), BODY)
    assert np.all(pr.status == OK) and np.all(upper)
    return np.unwrap(pr.delta_phi), crit


def test_visible_reversal_across_QJpi_line_is_continuous():
    """ERRATA §12.  Across Q_J = Q_J,π^crit at fixed θ_X = π − δ < π, Δφ per T_θ changes continuously:
    refining the Q_J grid 4× shrinks the largest step between neighbours ~4×, as for any smooth
    function, while a jump (α0 → −α0) would keep it.  The change totals 2π − O(δ²) over a band in Q_J
    that shrinks faster than δ^1.5, so the paper's jump is the θ_X → π limit; inside the band the
    visible angle sweeps through ±π (on the line it is nearer π than one band-width either side).
    The direct ODE, on the line and one band-width either side, follows the quadrature."""
    totals, widths = [], []
    for delta in (1e-2, 3e-3):
        W = 3e2 * delta**2  # ~10 widths either side of the line
        steps = []
        for n in (101, 401):
            d, _ = _phi_sweep_across_pi_line(delta, np.linspace(-W, W, n))
            steps.append(np.max(np.abs(np.diff(d))))
        assert steps[1] <= 0.3 * steps[0] and steps[1] < 0.1
        far = np.concatenate([-np.logspace(-1, -10, 300), np.logspace(-10, -1, 300)])
        d, _ = _phi_sweep_across_pi_line(delta, far)
        f = (d - d[0]) / (d[-1] - d[0])
        totals.append(abs(d[-1] - d[0]))
        widths.append(far[np.argmin(np.abs(f - 0.9))] - far[np.argmin(np.abs(f - 0.1))])
    assert abs(totals[1] - 2 * np.pi) < 0.2 * abs(totals[0] - 2 * np.pi) and abs(totals[1] - 2 * np.pi) < 0.05
    assert widths[1] < (3e-3 / 1e-2) ** 1.5 * widths[0]
    # the ODE on the line (offset 0, mid-sweep) and at ± one width: its increments between maxima
    d_line, crit = _phi_sweep_across_pi_line(1e-2, np.array([-widths[0], 0.0, widths[0]]))
    for off, want in zip((-widths[0], 0.0, widths[0]), d_line):
        QJ = crit + off * abs(crit)
        st = state_from_turning_point(BODY, np.pi - 1e-2, 0.01, QJ)
        traj = simulate(BODY, EulerState(np.pi - 1e-2, 0.0, 0.0, 0.0, float(st.phi_dot), float(st.psi_dot)),
                        3.2 * float(precession(st.E, 0.01, QJ, BODY).T_theta))
        _, phi, _ = _maxima_series(traj)
        assert np.max(np.abs(wrap_angle(np.diff(phi) - want))) <= 1e-9
    vis = np.abs(wrap_angle(d_line))
    assert np.pi - vis[1] < min(np.pi - vis[0], np.pi - vis[2])


def test_node_cap_is_bounded_and_large_inputs_run_in_blocks(monkeypatch):
    """max_nodes is refused above MAX_NODES_LIMIT (it used to allocate points × nodes at once); a block size
    smaller than the input gives the same numbers bit for bit."""
    import rocknroller.analysis.routh.quadrature as q

    body = Body.paper()
    with pytest.raises(ValueError, match="max_nodes must be an integer in"):
        precession(1.0, 0.01, 0.0, body, max_nodes=10**9)
    QR = np.linspace(-0.02, 0.02, 41)
    whole = precession(1.0, QR, 0.003, body)
    monkeypatch.setattr(q, "_BLOCK_ELEMENTS", 64 * 3)  # 3 points per block at 64 nodes
    blocks = precession(1.0, QR, 0.003, body)
    for name in ("T_theta", "delta_phi", "delta_psi"):
        # exact: each point's row of nodes goes through the same elementwise operations and the same pairwise sum,
        # and rows are whole multiples of any SIMD width (16·2^k nodes), so no element changes code path
        assert np.array_equal(getattr(whole, name), getattr(blocks, name)), name


def test_turning_point_start_closer_to_the_vertical_than_resolved_is_refused():
    """Fuzzing found E = nan for θ0 = 5e-324 (1 − cos θ0 underflows): refused, naming theta0 and the bound."""
    from rocknroller.analysis.routh.reduction import TILT_MIN

    with pytest.raises(ValueError, match=r"^theta0 must lie in the open interval \(0, pi\), at least 1e-150"):
        precession_from_turning_point(np.array([5e-324, 0.9 * np.pi]), 0.0, 0.0, Body.paper(0.0))
    pr, _ = precession_from_turning_point(np.array([TILT_MIN, 0.9 * np.pi]), 0.01, 0.0, Body.paper(0.0))
    assert np.all(np.isfinite(np.ma.compressed(pr.T_theta)))


def test_turning_point_energy_beyond_range_names_the_inputs():
    """Fuzzing found θ0 = 4e-93 with Q_R = 6e57 refused as "E must be ..." (E derived, not given): the error now
    names theta0, QR and QJ."""
    with pytest.raises(ValueError, match=r"^theta0=4.4043059857065464e-93 with QR=6.132999124217221e\+57, QJ=0.0 gives"):
        precession_from_turning_point(np.array([4.4043059857065464e-93, 0.9 * np.pi]), 6.132999124217221e57, 0.0,
                                      Body.paper(0.0))


@pytest.mark.parametrize("n", [16, 64, 256, 512, 514, 1024])
def test_gauss_legendre_rule_is_numpys_in_linear_memory(n):
    """The rule (issue 25, item 24: ``leggauss`` builds a dense n × n matrix, so ``max_nodes=65536`` ran 240 s at
    4.3 GB on its way to ~70 GB) from the tridiagonal companion matrix (dense up to ``_DENSE_UP_TO`` = 512 nodes,
    which spares scipy.linalg's import: both sides of it are tested).  Its nodes are the roots of P_n after the same
    Newton step as ``leggauss``'s: within one unit round-off of them.  It is as exact as ``leggauss``'s rule on the
    polynomials a Gauss rule integrates exactly (x^2m, 2m ≤ 2n − 2): its largest relative error at most twice
    ``leggauss``'s plus the rounding of a sum of n terms (a product and an addition each, and the weight's own
    rounding: 4·n·u).  Measured with scipy 1.13.1 (the lower bound) and 1.17.1."""
    from rocknroller.analysis.routh.quadrature import _gauss_legendre

    x, w = _gauss_legendre(n)
    xn, wn = np.polynomial.legendre.leggauss(n)
    assert x.size == w.size == n // 2 and np.all(x > 0)
    np.testing.assert_allclose(x, xn[n // 2:], rtol=0, atol=np.finfo(float).eps)
    u = np.finfo(float).eps / 2
    m = np.arange(n)
    exact = 2.0 / (2 * m + 1)
    ours = np.array([2.0 * (w @ x ** (2 * k)) for k in m]) / exact - 1.0
    numpys = np.array([wn @ xn ** (2 * k) for k in m]) / exact - 1.0
    assert np.max(np.abs(ours)) <= 2.0 * np.max(np.abs(numpys)) + 4 * n * u, (np.max(np.abs(ours)),
                                                                              np.max(np.abs(numpys)))


def test_the_largest_rule_is_built_in_linear_memory():
    """``MAX_NODES_LIMIT`` nodes: the rule needs O(n) memory (a few arrays of n doubles), not leggauss's n² doubles
    (2 GB here), and integrates a polynomial of degree 2n − 1 to its rounding."""
    import resource

    import rocknroller.analysis.routh.quadrature as q

    n = q.MAX_NODES_LIMIT
    q._gauss_legendre.cache_clear()
    before = resource.getrusage(resource.RUSAGE_SELF).ru_maxrss * 1024  # Linux: kB
    x, w = q._gauss_legendre(n)
    grown = resource.getrusage(resource.RUSAGE_SELF).ru_maxrss * 1024 - before
    assert grown < 0.05 * 8 * n * n  # well below one dense n × n matrix
    assert abs(2.0 * w.sum() - 2.0) <= n * np.finfo(float).eps
    assert abs(2.0 * (w @ x**20) - 2.0 / 21.0) <= 4 * n * np.finfo(float).eps
    with pytest.raises(ValueError, match=f"max_nodes must be an integer in \\[32, {n}\\]"):
        precession(1.0, 0.01, 0.0, Body.paper(0.0), max_nodes=2 * n)
