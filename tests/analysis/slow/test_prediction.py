"""First-order ε-averaging of the slow (Q_R, Q_J) motion, checked against the direct ODE.

Reference: rocknroller.numerics.integrate.simulate (heyoka, form (i)).  Paper body, θ0 = 0.95π, released from
rest.  The full error table (all ψ0, three ε) is in docs/averaging.md; its generator is
``python validation/averaging_table.py``.
"""

from __future__ import annotations

import math
import warnings

import numpy as np
import pytest
import roundoff as ro
from scipy.optimize import brentq

from rocknroller.analysis.model.body import Body
from rocknroller.analysis.model.diagnostics import azimuth_span, mean_crossings, slow_period, unwrap_phase, wrap_angle
from rocknroller.analysis.model.equations import EulerState, euler_from_state, state_from_euler
from rocknroller.analysis.model.invariants import energy
from rocknroller.analysis.routh.quadrature import precession
from rocknroller.analysis.routh.quadrature_mp import precession_mp
from rocknroller.analysis.slow.map import compiled_map as slow_map
from rocknroller.analysis.slow.map import family as fam
from rocknroller.analysis.slow.map import harmonic
from rocknroller.analysis.slow.map import orbit as so
from rocknroller.analysis.slow.dynamics import pendulum as slow_pendulum
from rocknroller.analysis.slow import prediction as av
from rocknroller.analysis.slow.map import table as slow_table
from rocknroller.analysis.slow.dynamics.pendulum import pendulum_constants, pendulum_prediction
from rocknroller.numerics.integrate import simulate
from rocknroller.papers.averaging_check import (OdeSlowSummary, loglog_slope, ode_slow_summary, relative_errors,
                                                sample_errors)

THETA0 = 0.95 * math.pi
PSI0 = {"pi/8": math.pi / 8, "pi/4": math.pi / 4, "3pi/8": 3 * math.pi / 8, "3.9pi/8": 3.9 * math.pi / 8}
EPS = (1e-2, 1e-3, 1e-4)
SYM = Body.paper(0.0)
E0 = fam.rest_energy(SYM, THETA0)
#: "Falls at least linearly": an error aε + bε² has the log-log slope 1 + O(bε/a) over the fitted range;
#: 0.9 admits |bε/a| up to ~0.2 at the largest ε and rejects any O(√ε) or O(1) part (slope ≤ 0.5 or 0).
MIN_SLOPE = 0.9


@pytest.fixture(scope="module")
def table() -> av.SlowMapTable:
    # built from scratch: the tests never depend on a pre-existing cache
    return av.build_table(SYM, THETA0)


@pytest.fixture(scope="module")
def constants():
    return pendulum_constants(SYM, THETA0)


_ODE: dict = {}


def ode(eps: float, psi0: float, t_end: float = 1000.0) -> OdeSlowSummary:
    """Direct-ODE turning-point samples of the body released from rest (memoised)."""
    key = (eps, psi0, t_end)
    if key not in _ODE:
        _ODE[key] = ode_slow_summary(Body.paper(eps), THETA0, psi0, t_end)
    return _ODE[key]


# ----------------------------------------------------------------------------- one step
def _direct_step(eps: float, QR: float, QJ: float, psi: float) -> dict[str, float]:
    """One maximum → maximum of the asymmetric body by the direct ODE, started at the maximum with
    the given (E, Q_R, Q_J, ψ) (θ_X solved from the energy of the ε-body)."""
    body = Body.paper(eps)
    st = lambda th: state_from_euler(th, 0.0, psi, 0.0, *_rates(th, QR, QJ))  # noqa: E731
    th = brentq(lambda x: float(energy(body, st(x)[0:3], st(x)[3:6])) - E0, THETA0 - 0.02, THETA0 + 0.02,
                xtol=1e-16, rtol=1e-15)
    tr = simulate(body, EulerState(th, 0.0, psi, 0.0, *_rates(th, QR, QJ)), 30.0, dt=1.0)
    Y = tr.maxima.states[0]
    ang = euler_from_state(Y)
    return {"QR": float(tr.maxima.QR[0]), "QJ": float(tr.maxima.QJ[0]), "Theta": 2.0 * float(ang[2]),
            "t": float(tr.maxima.t[0]), "phi": float(ang[1])}


def _rates(theta: float, QR: float, QJ: float) -> tuple[float, float]:
    from rocknroller.analysis.model.invariants import V_phi, V_psi

    return float(V_phi(theta, QR=QR, QJ=QJ, body=SYM)), float(V_psi(theta, QR=QR, QJ=QJ, body=SYM))


def test_first_order_step_equals_finite_difference_of_direct_ode():
    """ε-derivatives from the variational equations = Richardson finite differences of the ODE."""
    QR, QJ, psi = 2.0e-3, -3.0e-5, 0.3
    step = so.first_order_step(SYM, E0, QR, QJ, psi)
    h = 1e-6
    f0, f1, f2 = (_direct_step(e, QR, QJ, psi) for e in (0.0, h, 2 * h))
    for name in so.FIRST_ORDER_NAMES:
        wrap = (lambda x: float(wrap_angle(x))) if name in ("Theta", "phi") else float
        d1, d2 = wrap(f1[name] - f0[name]) / h, wrap(f2[name] - f0[name]) / (2 * h)
        fd = 2.0 * d1 - d2  # Richardson: O(h²)
        # FD round-off ~1e-15/h relative to the state (~1) times the sensitivity
        assert fd == pytest.approx(step.d[name], rel=1e-5, abs=1e-6), name


def _step_period_bound(step: so.FirstOrderStep, E0: float, margin: float = 4.0) -> float:
    """Bound on the error of the period T of ``first_order_step``'s heyoka run (variational integrator at ε).

    Each step errs by ≤ ε max(1, ‖(y, z)‖∞) in every component (heyoka's error control on the 22-component state);
    the steps are counted by ``simulate`` on the same orbit (the same equations for y).  A state error δ changes
    T_θ(E, Q_R, Q_J) by Σ_q |∂T/∂q| ‖∇q‖₁ δ (q = E, Q_R, Q_J; ∂T/∂q from the quadrature by central differences,
    ∇q at the start) and shifts the event at the end by ‖∇h‖₁ δ/|ḣ| (h = dγ3/dt); the event's Newton iteration
    stops within 4e-16 t (then converges quadratically) and t rounds (u t).  × margin; against 30-digit mpmath.
    """
    from rocknroller.analysis.model.equations import body_frame_rhs, turning_point_function
    from rocknroller.analysis.model.invariants import jellett, routh
    from rocknroller.analysis.routh.reduction import state_from_turning_point

    QR, QJ = step.QR, step.QJ
    st = state_from_turning_point(SYM, step.theta_X, QR, QJ)
    initial = EulerState(step.theta_X, 0.0, step.psi, 0.0, float(st.phi_dot), float(st.psi_dot))
    n_steps = simulate(SYM, initial, step.T).n_steps
    scale = max(1.0, float(np.abs(so._variational_integrator().state).max()))
    y0 = initial.to_body_state()
    def qs(y):
        return np.array([q(SYM, y[0:3], y[3:6]) for q in (energy, routh, jellett)])

    grad_q = np.abs(ro.fd_jacobian(lambda y6: qs(np.concatenate([y6, y0[6:]])), y0[:6], 1e-7)).sum(axis=1)
    dT = []
    for k, q0 in enumerate((E0, QR, QJ)):
        h = 1e-6 * abs(q0)
        args = [[E0, QR, QJ], [E0, QR, QJ]]
        args[0][k] += h
        args[1][k] -= h
        dT.append(abs(float(precession(*args[0], SYM).T_theta) - float(precession(*args[1], SYM).T_theta)) / (2 * h))
    h_dot = abs(float(np.dot(ro.fd_jacobian(lambda y: [turning_point_function(y)], y0, 1e-7)[0],
                             body_frame_rhs(y0, SYM.params))))
    phase = (abs(y0[3]) + abs(y0[4]) + abs(y0[0]) + abs(y0[1])) / h_dot
    amp = float(np.dot(dT, grad_q)) + phase
    return margin * (ro.integration_bound(n_steps, 2 * ro.u, scale * amp) + 4e-16 * step.T + ro.u * step.T)


def test_batch_lanes_are_independent():
    """The table orbits run in heyoka's batch mode, one per lane: an orbit's numbers do not depend on the lane it
    runs in nor on its companions (bit for bit), so a table does not depend on how its nodes are grouped; the
    scalar ``first_order_step`` (one orbit, padded with its copies) gives the same numbers."""
    QR = np.array([2.0e-3, -1.0e-3, 4.0e-4, 3.0e-3, 0.0])
    QJ = np.array([-3.0e-5, 2.0e-5, 1.0e-5, -1.0e-5, 0.0])
    psi = np.array([0.3, 1.1, 2.0, 2.9, 0.7])
    from rocknroller.analysis.routh.turning_points import turning_points

    thX = np.array([float(turning_points(E0, q, j, SYM)[1]) for q, j in zip(QR, QJ)])
    a = so.first_order_steps(SYM, E0, QR, QJ, psi, thX)
    b = so.first_order_steps(SYM, E0, QR[::-1], QJ[::-1], psi[::-1], thX[::-1])  # other lanes, other companions
    for name in so.FIRST_ORDER_NAMES:
        assert np.array_equal(a.d[name], b.d[name][::-1]), name
    assert np.array_equal(a.T, b.T[::-1])
    one = so.first_order_step(SYM, E0, QR[2], QJ[2], psi[2], theta_X=thX[2])
    assert one.T == a.T[2] and all(one.d[k] == a.d[k][2] for k in so.FIRST_ORDER_NAMES)


def test_symmetric_step_equals_quadrature():
    """The symmetric orbit of the variational run reproduces T_θ, Δψ and Δφ (mod π) of the quadratures (T_θ against
    the 30-digit one, within ``_step_period_bound``)."""
    QR, QJ = 4.0e-3, -1.0e-4
    step = so.first_order_step(SYM, E0, QR, QJ, 1.1)
    pr = precession(E0, QR, QJ, SYM)
    ro.assert_within(step.T - float(precession_mp(E0, QR, QJ, SYM, dps=30).T_theta), _step_period_bound(step, E0),
                     "T", step.T)
    assert float(wrap_angle(step.dpsi - float(pr.delta_psi), math.pi)) == pytest.approx(0.0, abs=1e-10)
    assert float(wrap_angle(step.dphi - float(pr.visible_half_phi), math.pi)) == pytest.approx(0.0, abs=1e-10)


def test_response_has_only_harmonics_0_and_2():
    """Three orbits determine the response at any ψ_n (rotational symmetry of Routh's sphere)."""
    sc = harmonic.step_coefficients(SYM, E0, 3.0e-3, 5.0e-5)
    for psi in (0.4, 2.0):
        direct = so.first_order_step(SYM, E0, 3.0e-3, 5.0e-5, psi)
        for name in so.FIRST_ORDER_NAMES:
            assert float(sc.response(name, psi)) == pytest.approx(direct.d[name], rel=1e-8, abs=1e-9), name


def test_pure_rocking_is_exact_and_kick_is_sin_theta():
    """At Q = 0: no response at ψ = 0 or π/2 (rocking about a principal axis is exact), ΔQ = C0 sin Θ."""
    sc = harmonic.step_coefficients(SYM, E0, 0.0, 0.0)
    for name in ("QR", "QJ"):
        c0, c1, s1 = sc.harmonics[name]
        assert abs(c0) < 1e-10 * abs(s1) and abs(c1) < 1e-10 * abs(s1)


# ----------------------------------------------------------------------------- tables and map
def test_table_interpolates_the_coefficients(table):
    assert table.interp_error < 1e-9  # its own check at three off-grid points
    rng = np.random.default_rng(7)
    for _ in range(3):
        Q = np.array(table.chart(rng.uniform(-1, 1), rng.uniform(-1, 1)))
        sc = harmonic.step_coefficients(SYM, E0, *Q)
        vals = dict(zip(av.TABLE_FUNCTIONS, table.evaluate(Q)))
        assert vals["T"] == pytest.approx(sc.T, rel=1e-11)
        assert float(wrap_angle(vals["W"] - sc.W)) == pytest.approx(0.0, abs=1e-9)
        assert float(wrap_angle(vals["dphi"] - sc.dphi, math.pi)) == pytest.approx(0.0, abs=1e-9)
        # k_Q is ΔQ with its phase advanced by W/2
        w = 0.5 * vals["W"]
        for name in ("QR", "QJ"):
            c0, c1, s1 = (vals[f"k{name}_{h}"] for h in ("c0", "c1", "s1"))
            back = (c0, c1 * math.cos(w) + s1 * math.sin(w), -c1 * math.sin(w) + s1 * math.cos(w))
            scale = max(abs(x) for x in sc.harmonics[name])
            assert np.allclose(back, sc.harmonics[name], rtol=0, atol=1e-9 * scale), name


def test_raw_data_are_reversible(table):
    """The unsymmetrised first-order data already have the parities of a reversible map."""
    for u in (0.3, -0.7):
        Q = u * table.U * table.e
        a, b = harmonic.step_coefficients(SYM, E0, *Q), harmonic.step_coefficients(SYM, E0, *(-Q))
        # exact: T_θ depends on Q through squares, the product Q_R Q_J and u → −u only (rocknroller.analysis.routh.reduction, the
        # double-double u_ends included), the same operations on negated inputs, and rounding to nearest is
        # symmetric under negation
        assert a.T == b.T
        # W = wrap(2Δψ − 2π) with Δψ(−Q) = −Δψ(Q) exactly (as T_θ): the doubling, the −2π and wrap_angle's two
        # subtractions round (≤ 3u (|2Δψ| + 2π) each), × 4 (margin)
        dpsi = 0.5 * (a.W + 2 * math.pi)
        bound = 4 * 2 * 3 * ro.u * (abs(2 * dpsi) + 2 * math.pi)
        ro.assert_within(a.W + b.W, bound, "W", a.W)
        for name in ("QR", "QJ"):  # ΔQ(−Q, −Θ - W)... at first order: even after the half-twist shift
            wa, wb = 0.5 * a.W, 0.5 * b.W
            ka = np.array(a.harmonics[name]); kb = np.array(b.harmonics[name])
            rot = lambda h, w: np.array([h[0], h[1] * math.cos(w) - h[2] * math.sin(w),  # noqa: E731
                                         h[1] * math.sin(w) + h[2] * math.cos(w)])
            assert np.allclose(rot(ka, wa), rot(kb, wb), rtol=0, atol=1e-8 * np.abs(ka).max())


def test_map_is_reversible(table):
    """N steps forward, reverse Q, N steps: back to the reversed start, to round-off and the tables' parity defect.

    Exact reversibility M∘R∘M = R (R: Q → −Q, Θ kept, and t → −t for the accumulated time) makes the composite
    (N steps from the reversed end) ∘ R ∘ (N steps forward) equal to R, so an error δ made at forward step n
    reaches the end as R M⁻ⁿ δ, bounded by |(J_n ⋯ J_1)⁻¹| δ, and one made at step m of the reversed run as
    |J'_N ⋯ J'_{m+1}| δ (Jacobians by central differences of the map along both runs).  The local errors are
    the kernel's rounding (``_map_local_errors`` for one computation) and, on the reversed run, the parity
    defect of the run-time tables at the points it visits (their 6-point stencil is not symmetric: ~1e-13 of
    each function, an interpolation error, not rounding); the conversions u, v ↔ Q_R, Q_J at the start, the
    reversal and the end add γ_2 |Q| each.  Times ``FAST_MAP_MARGIN``.
    """
    eps, N = 3e-3, 25
    Q0 = np.array(table.chart(0.2, 0.1))
    fwd = av.iterate_slow_map(table, eps, 0.7, 1e9, Q0=Q0, n_steps=N)
    Q_rev = (-fwd.QR[-1], -fwd.QJ[-1])
    back = av.iterate_slow_map(table, eps, 0.5 * fwd.Theta[-1], 1e9, Q0=Q_rev, n_steps=N)
    ft = slow_map._fast(table)

    def run(Q, Th):  # the kernel's rows (u, v, Θ, t, φ) from the start onwards, as iterate_slow_map computes them
        u, v = float(ft.e @ np.asarray(Q)), float(ft.n @ np.asarray(Q))
        rows = ft.iterate(eps, u, v, Th, 0.0, 1e9, N)[0]
        return np.vstack([[u, v, Th, 0.0, 0.0], rows[:, [1, 2, 3, 0, 4]]])

    Xf, Xb = run(Q0, 1.4), run(Q_rev, fwd.Theta[-1])
    conv = lambda Q: ro.gamma(2) * (abs(Q[0]) + abs(Q[1])) * np.array([1.0, 1.0, 0, 0, 0])  # noqa: E731
    Jf = [_map_jacobian(ft, eps, Xf[n], table) for n in range(N)]
    Jb = [_map_jacobian(ft, eps, Xb[n], table) for n in range(N)]
    df = [_map_local_errors(ft, eps, Xf[n], Xf[n + 1], plain=False) for n in range(N)]
    db = [_map_local_errors(ft, eps, Xb[n], Xb[n + 1], plain=False, defect=True) for n in range(N)]
    B = conv(Q0)  # the start's conversion, carried by R M⁰ = R
    P = np.eye(5)
    for J, d in zip(Jf, df):  # forward errors: |(J_n ⋯ J_1)⁻¹| δ_n
        P = J @ P
        B = B + np.abs(np.linalg.inv(P)) @ d
    B = B + ro.propagated_bound(np.array(Jb), np.array([conv(Q_rev) * 2 + db[0], *db[1:]]))[-1]  # + reversal's
    B = FAST_MAP_MARGIN * B + conv(Q0)  # the end's conversion to Q
    for k, name in enumerate(("QR", "QJ")):
        ro.assert_within((back.QR, back.QJ)[k][-1] + Q0[k], abs(table.e[k]) * B[0] + abs(table.n[k]) * B[1], name,
                         Q0[k])
    ro.assert_within(float(wrap_angle(back.Theta[-1] - 1.4)), B[2] + 2 * ro.u * abs(back.Theta[-1]), "Theta", 1.4)
    ro.assert_within(back.t[-1] - fwd.t[-1], B[3], "t", fwd.t[-1])


def _reference_map(table: av.SlowMapTable, eps: float, psi0: float, t_end: float,
                   Q0=(0.0, 0.0), n_steps: int | None = None) -> np.ndarray:
    """The drift–kick–drift map evaluated plainly: 6-point Lagrange weights Π (r − j)/(k − j) on the
    fine grid, T_j(y) = cos(j arccos y), and the implicit midpoint kick by fixed-point iteration until
    the change is within 1e-13 of the kick (+ 4 ulp).  Rows (t, u, v, Θ, φ) at the maxima."""
    ft = slow_map._fast(table)
    off = np.arange(-2, 4)

    def ev(u, v):
        x = u / ft.U
        y = (v - np.polynomial.chebyshev.chebval(x, table.c_coef)) / np.polynomial.chebyshev.chebval(x, table.w_coef)
        assert abs(x) <= 1.0 and abs(y) <= 1.0
        s = (x + 1.0) / ft.dx
        i = min(max(int(s), 2), ft.n_fine - 4)
        w = np.array([np.prod([(s - i - j) / (k - j) for j in off if j != k]) for k in off])
        return (w @ ft.rows[i - 2:i + 4]).reshape(-1, ft.nv) @ np.cos(np.arange(ft.nv) * np.arccos(y))

    def kick(k, th, first, n):
        return eps * (k[first] + k[first + 1] * math.cos(th) + k[first + 2] * math.sin(th))

    u, v = float(ft.e @ np.asarray(Q0, float)), float(ft.n @ np.asarray(Q0, float))
    Th, t, phi, f, out = 2.0 * psi0, 0.0, 0.0, ev(u, v), []
    while True:
        a = np.array([u, v, Th + 0.5 * f[16]])
        x = a.copy()
        for _ in range(60):
            m = 0.5 * (a + x)
            k = ev(m[0], m[1])
            dk = np.array([kick(k, m[2], j, 3) for j in (0, 3, 6)])
            x_new = a + dk
            tol = np.array([1e-13 * (abs(dk[0]) + abs(dk[1])) + 4 * math.ulp(abs(x_new[0]) + abs(x_new[1]))] * 2
                           + [1e-13 * abs(dk[2]) + 4 * math.ulp(x_new[2])])
            done = bool(np.all(np.abs(x_new - x) <= tol))
            x = x_new
            if done:
                break
        else:
            raise AssertionError("reference kick did not converge")
        f1 = ev(x[0], x[1])
        t_next = t + 0.5 * (f[15] + f1[15]) + kick(k, m[2], 9, 3)
        if t_next > t_end:
            break
        phi += 0.5 * (f[17] + f1[17]) + kick(k, m[2], 12, 3)
        t, u, v, f = t_next, x[0], x[1], f1
        Th = x[2] + 0.5 * f[16]
        out.append((t, u, v, Th, phi))
        if n_steps is not None and len(out) >= n_steps:
            break
    return np.array(out)


#: Rounded operations per run-time function value, in either implementation: the six Lagrange weights
#: (five rounded factors r − j, four products and a rounded 1/Π(k − j) or division: ≤ 12 relative), the
#: 6-term stencil sum, the nv-term Chebyshev sum in v, and T_j(y) itself (by the recurrence or as
#: cos(j arccos y): ≤ nv² u absolute, |T_j| ≤ 1, charged as nv² more operations on the same |terms|).
def _eval_ops(nv: int) -> int:
    return 12 + 6 + nv + nv * nv


#: Safety margin of the fast-map bound.  Its constants are already worst cases (Higham's γ_n for every sum in
#: any order, every rounding at its maximum and of one sign, added linearly over the steps); the margin only
#: covers the first-order (linearised) propagation and the finite-difference Jacobians (relative error ~1e-6).
FAST_MAP_MARGIN = 2.0


def _condition_sums(ft, u: float, v: float) -> np.ndarray:
    """Σ_k Σ_j |w_k| |c_kj| for each of the 18 run-time functions at (u, v): the sum of the absolute values of
    the terms of its 6 × nv stencil (|T_j| ≤ 1), which multiplies γ_n in the rounding error of its value."""
    s = (u / ft.U + 1.0) / ft.dx
    i = min(max(int(s), 2), ft.n_fine - 4)
    off = np.arange(-2, 4)
    w = np.array([np.prod([(s - i - j) / (k - j) for j in off if j != k]) for k in off])
    return np.abs(w) @ np.abs(ft.rows[i - 2:i + 4]).reshape(6, -1, ft.nv).sum(axis=2)


def _harm(k, th: float, first: int) -> float:
    return k[first] + k[first + 1] * math.cos(th) + k[first + 2] * math.sin(th)


def _kick_derivatives(ft, m) -> tuple[np.ndarray, np.ndarray]:
    """The 18 run-time functions at m = (u, v, Θ), and the (5, 3) derivatives of the kicks (k_u, k_v, k_Θ, k_t,
    k_φ) with respect to m (``values_and_jacobian`` for u, v; the harmonics for Θ)."""
    out = np.array(ft.values_and_jacobian(m[0], m[1]))
    k, du, dv = out[:18], out[18:33], out[33:48]
    th = m[2]
    D = np.array([[_harm(du, th, f), _harm(dv, th, f), -k[f + 1] * math.sin(th) + k[f + 2] * math.cos(th)]
                  for f in (0, 3, 6, 9, 12)])
    return k, D


#: Parity in Q of the 18 run-time functions (k_u, k_v harmonics even, k_Θ odd, k_t even, k_φ odd, T even, W and
#: Δφ odd): the parities that make the map reversible (``rocknroller.analysis.slow.map.chart._ODD``, ``_EVEN``).
_RUN_TIME_PARITY = np.array([1.0] * 6 + [-1.0] * 3 + [1.0] * 3 + [-1.0] * 3 + [1.0, -1.0, -1.0])


def _map_local_errors(ft, eps: float, x: np.ndarray, y: np.ndarray, *, plain: bool = True,
                      defect: bool = False) -> np.ndarray:
    """Bound on the difference of two computations of ONE step of the slow map from the same maximum
    x = (u, v, Θ, t, φ) (y: the next maximum), for (u, v, Θ, t, φ).

    ``plain=True``: the kernel against the plain evaluation of ``_reference_map``.  ``plain=False``: the kernel
    against the exact map of the run-time tables (one computation).  ``defect=True`` adds the parity defect
    |f(Q) ∓ f(−Q)| of the run-time functions at the points used (the reversed run of ``test_map_is_reversible``
    evaluates them at −Q; the 6-point stencil is not symmetric, so the defect is the interpolation error,
    ~1e-13 relative, plus rounding).

    The computations differ by (a) the rounding of the run-time functions, each within γ_n Σ|terms|
    (n = ``_eval_ops``; per computation; summation order free, SIMD or not); (b) the rounding of cos/sin and of
    their argument Θ_m (u|Θ_m| absolute per computation); (c) the stopping of the implicit kick
    x' = a + ε k((a + x')/2): the plain fixed-point iteration stops on a change ≤ tol and is then within
    η/(1 − η) tol of its fixed point, η = ‖(ε/2) ∂k/∂m‖∞ its contraction; the kernel's simplified Newton stops
    on a change ≤ tol with contraction η_N (its Jacobian at the first iterate m₀ against the one at the
    solution) or on a predicted remaining error ≤ 1e-3 tol; (d) an error δk of the kick moves the solution by
    (I − (ε/2) ∂k/∂m)⁻¹ ε δk; (e) the time and φ kicks: taken at the previous midpoint by the plain iteration
    (off by ≤ tol/2) and at the solution's midpoint (off by half its error); (f) the additions that accumulate
    u, v, Θ, t, φ (≤ 3 rounded operations on each, per computation).
    The input (u/U + 1)/dx of the stencil is the same three IEEE operations in both: identical, not counted.
    """
    n_comp = 2 if plain else 1
    h, g = 0.5 * eps, ro.gamma(_eval_ops(ft.nv))

    def fun_err(q) -> np.ndarray:  # error bound of the 18 run-time function values at q = (u, v)
        err = n_comp * g * _condition_sums(ft, q[0], q[1])
        if defect:
            err = err + np.abs(np.array(ft.values(q[0], q[1])) - _RUN_TIME_PARITY * np.array(ft.values(-q[0], -q[1])))
        return err

    f, f1 = np.array(ft.values(x[0], x[1])), np.array(ft.values(y[0], y[1]))
    a = np.array([x[0], x[1], x[2] + 0.5 * f[16]])                 # after the first half drift
    xe = np.array([y[0], y[1], y[2] - 0.5 * f1[16]])                # the kick's end point
    m = 0.5 * (a + xe)
    k, Dk = _kick_derivatives(ft, m)
    m0 = a + h * np.array([_harm(f, a[2], j) for j in (0, 3, 6)])  # the kernel's first iterate
    _, Dk0 = _kick_derivatives(ft, m0)
    eta = float(np.abs(h * Dk[:3]).sum(axis=1).max())
    eta_N = float(np.abs(np.linalg.solve(np.eye(3) - h * Dk0[:3], h * (Dk[:3] - Dk0[:3]))).sum(axis=1).max())
    assert eta < 0.5 and eta_N < 0.5, (eta, eta_N)
    # (a), (b): error of each kick value
    Em = fun_err(m)
    c, s = abs(math.cos(m[2])), abs(math.sin(m[2]))
    dk = np.array([Em[j] + Em[j + 1] * c + Em[j + 2] * s
                   + n_comp * ro.gamma(5) * (abs(k[j]) + abs(k[j + 1]) * c + abs(k[j + 2]) * s)
                   + n_comp * (abs(k[j + 1]) + abs(k[j + 2])) * 2 * ro.u * abs(m[2]) for j in (0, 3, 6, 9, 12)])
    dW = np.array([fun_err(x)[15:18], fun_err(y)[15:18]])          # T, W, Δφ at the two ends
    # (c) stopping tolerances of the kick, as both implementations compute them
    kick = eps * np.array([_harm(k, m[2], j) for j in (0, 3, 6)])
    tol_q = 1e-13 * (abs(kick[0]) + abs(kick[1])) + 4 * np.spacing(abs(y[0]) + abs(y[1]))
    tol = np.array([tol_q, tol_q, 1e-13 * abs(kick[2]) + 4 * np.spacing(abs(xe[2]))])
    stop = (max(eta_N / (1 - eta_N), 1e-3) + (eta / (1 - eta) if plain else 0.0)) * tol
    # (d) the kick's end point; the first half drift enters Θ with 0.5 δW(Q), the second adds 0.5 δW(Q')
    inv = np.abs(np.linalg.inv(np.eye(3) - h * Dk[:3]))
    dx = inv @ (eps * dk[:3] + np.array([0.0, 0.0, 0.5 * dW[0, 1]])) + stop + n_comp * 3 * ro.u * np.abs(xe)
    dx[2] += 0.5 * dW[1, 1] + n_comp * 3 * ro.u * abs(y[2])
    # (e) time and φ: drifts at both ends, kick at the midpoint, end point moved by dx
    dm = 0.5 * dx + (0.5 * tol if plain else 0.0)
    grad = (np.array(ft.values(y[0] + 1e-6 * ft.U, y[1])) - np.array(ft.values(y[0] - 1e-6 * ft.U, y[1])))
    grad = np.abs(grad[[15, 17]]) / (2e-6 * ft.U)                   # |∂T/∂u|, |∂Δφ/∂u| at Q'
    out = [*dx]
    for r, (fi, gi) in enumerate(((0, 0), (2, 1))):                 # t: T, k_t; φ: Δφ, k_φ
        out.append(0.5 * (dW[0, fi] + dW[1, fi]) + eps * dk[3 + r] + eps * np.abs(Dk[3 + r]) @ dm
                   + 0.5 * grad[gi] * dx[0] + n_comp * 3 * ro.u * abs(y[3 + r]))
    return np.array(out)


def _map_jacobian(ft, eps: float, x: np.ndarray, table) -> np.ndarray:
    """∂x_{n+1}/∂x_n of one step of the map in x = (u, v, Θ, t, φ), by central differences of the kernel's step
    (t and φ only accumulate: their columns are unit vectors)."""
    def step(z):
        row = ft.iterate(eps, z[0], z[1], z[2], 0.0, 1e9, 1)[0][0]
        return np.array([row[1], row[2], row[3], row[0], row[4]])

    J = np.eye(5)
    J[:, :3] = ro.fd_jacobian(step, x[:3], [1e-6 * table.U, 1e-6 * table.U, 1e-6])
    return J


@pytest.mark.parametrize("eps, psi0, Q0", [(1e-3, math.pi / 8, None), (5e-3, math.pi / 4, None),
                                           (1e-4, 3 * math.pi / 8, None), (3e-3, 0.7, (0.2, 0.1))])
def test_fast_map_equals_plain_evaluation(table, eps, psi0, Q0):
    """The compiled kernel (simplified Newton, stencil dot products in C) is the same map as the plain
    evaluation (NumPy: its sums in whatever order its SIMD kernels take) to round-off.

    Bound, maximum by maximum and for each of (Q_R, Q_J, Θ, t, φ): the local differences of one step from the
    same maximum, ``_map_local_errors`` (γ_n × the stencil's Σ|terms| for each function, n = 18 + nv + nv²
    rounded operations (``_eval_ops``); the kick's stopping rule; ≤ 3 rounded additions per variable; all ×2 for
    the two implementations), carried to
    maximum n by the map's own tangent: B_n = Σ_{m≤n} |J_n ⋯ J_{m+1}| δ_m (``roundoff.propagated_bound``), with
    the Jacobians J computed along this run by central differences of the map.  The twist amplifies an error
    in Q into Θ and back (up to ~10³ over the ~75 steps to t = 1000, ``roundoff.amplification``); times
    ``FAST_MAP_MARGIN``.  A difference of 1e-10 relative in any series exceeds it.  Also checks the cost: one
    Jacobian and two or three plain evaluations per step."""
    Q0 = (0.0, 0.0) if Q0 is None else table.chart(*Q0)
    fast = av.iterate_slow_map(table, eps, psi0, 1000.0, Q0=Q0)
    ref = _reference_map(table, eps, psi0, 1000.0, Q0=Q0)
    assert ref.shape == (fast.t.size, 5) and fast.t.size > 50
    ft = slow_map._fast(table)
    u0, v0 = float(ft.e @ np.asarray(Q0)), float(ft.n @ np.asarray(Q0))
    X = np.vstack([[u0, v0, 2.0 * psi0, 0.0, 0.0], ref[:, [1, 2, 3, 0, 4]]])  # (u, v, Θ, t, φ), the start first
    local = np.array([_map_local_errors(ft, eps, X[n], X[n + 1]) for n in range(len(ref))])
    jac = np.array([_map_jacobian(ft, eps, X[n], table) for n in range(len(ref))])
    B = FAST_MAP_MARGIN * ro.propagated_bound(jac, local)
    # the first-order propagation holds: the largest growth of a relative error along the run times the bound
    # stays far below the variables' own size (the map is not chaotic on these runs)
    scale = np.array([table.U, table.w_coef[0], 1.0, 1000.0, 1.0])  # the release tables' rectangle: w = V
    assert ro.amplification(jac, scale) * np.max(B / scale) < 1e-6
    QR, QJ = (ref[:, 1] * table.e[k] + ref[:, 2] * table.n[k] for k in (0, 1))
    # Q = u e + v n: two more roundings in each implementation; unwrapping Θ: one subtraction of 2πk in each
    for k, (name, got, want) in enumerate((("QR", fast.QR, QR), ("QJ", fast.QJ, QJ))):
        bound = (np.abs(table.e[k]) * B[:, 0] + np.abs(table.n[k]) * B[:, 1]
                 + 2 * ro.gamma(2) * (np.abs(ref[:, 1] * table.e[k]) + np.abs(ref[:, 2] * table.n[k])))
        ro.assert_within(got - want, bound, name, want)
    Th = np.unwrap(ref[:, 3])
    ro.assert_within(fast.Theta - Th, B[:, 2] + 2 * 2 * ro.u * np.abs(Th), "Theta", Th)
    ro.assert_within(fast.t - ref[:, 0], B[:, 3], "t", ref[:, 0])
    ro.assert_within(fast.phi - ref[:, 4], B[:, 4], "phi", ref[:, 4])
    # both stop at the same maximum: the next one lies beyond t_end by far more than the bound on t
    t_next = X[-1, 3] + ft.iterate(eps, *X[-1, :3], 0.0, 1e9, 1)[0][0, 0]
    assert t_next - 1000.0 > 1e3 * B[-1, 3]
    # per step: the Jacobian at the predictor, one confirming kick evaluation (occasionally two),
    # the drift at the end point; the fixed-point iteration it replaces needed 5-6 kick evaluations
    rows, (n_jac, n_plain) = ft.iterate(eps, u0, v0, 2.0 * psi0, 0.0, 1000.0, None)
    assert np.array_equal(rows[:, 0], fast.t)  # exact: the same kernel call on the same input as iterate_slow_map
    n = fast.t.size + 1  # the step past t_end is computed too
    assert n_jac == n and n_plain <= 3 * n


def test_run_time_grid_is_bounded(table):
    """The run-time form's fine grid grows with nu (64 points a term) up to 8193 points, so its memory stays
    ≤ 8193 × (18 + 48) × nv doubles (first order) whatever nu the tables allow: a table of 512 terms along takes
    no more than one of 128 (this fixture's)."""
    import dataclasses

    from rocknroller.numerics.cache import array_bytes

    nv = table.coef.shape[2]
    bound = 8193 * (18 + 48) * nv * 8 + 8193 * 4 * 8 + 2 * 2 * 8  # the rows, the chart's four functions, e and n
    wide = dataclasses.replace(table, coef=np.zeros((table.coef.shape[0], 512, nv)))
    for t in (table, wide):
        assert slow_map._FastTable(t).n_fine == 8193 and array_bytes(slow_map._FastTable(t)) == bound


def test_kernel_output_in_chunks(table, monkeypatch):
    """A run longer than one output chunk continues from the last maximum: identical rows."""
    whole = av.iterate_slow_map(table, 1e-3, 0.4, 1000.0)
    monkeypatch.setattr(slow_map, "_CHUNK", 7)
    chunked = av.iterate_slow_map(table, 1e-3, 0.4, 1000.0)
    assert whole.t.size > 3 * 7
    for name in ("t", "QR", "QJ", "Theta", "phi"):  # exact: the kernel resumes from the stored row, same operations
        assert np.array_equal(getattr(whole, name), getattr(chunked, name)), name
    few = av.iterate_slow_map(table, 1e-3, 0.4, 1000.0, n_steps=10)
    assert few.t.size == 10 and np.array_equal(few.t, whole.t[:10])


def test_run_time_jacobian(table):
    """The derivative rows of the run-time table equal central differences of its values."""
    ft = slow_map._fast(table)
    for x, y in ((0.1, 0.2), (-0.5, -0.3), (0.8, 0.6)):
        u, v = x * table.U, y * table.w_coef[0]  # the release tables' rectangle: c = 0, w = V
        out = np.array(ft.values_and_jacobian(u, v))
        assert np.array_equal(out[:18], ft.values(u, v))  # exact: the same stencil loop over the same stored values
        for d, (hu, hv) in enumerate(((1e-6 * table.U, 0.0), (0.0, 1e-4 * table.w_coef[0]))):
            fd = (np.array(ft.values(u + hu, v + hv)) - np.array(ft.values(u - hu, v - hv)))[:15] / (2 * (hu + hv))
            got = out[18 + 15 * d:33 + 15 * d]
            # central difference: truncation ~ (h/scale)² ≈ 1e-9 of the largest derivative
            assert np.max(np.abs(got - fd)) <= 1e-7 * np.max(np.abs(fd))


def test_table_cache_round_trip(tmp_path, monkeypatch):
    monkeypatch.setenv("ROCKNROLLER_CACHE", str(tmp_path))
    monkeypatch.setattr(slow_table, "_TABLES", {})
    with pytest.raises(ValueError, match="no averaging tables"):
        av.load_or_build_table(SYM, 0.9 * math.pi, build=False, nu=8, nv=4)
    with pytest.warns(av.AveragingValidityWarning, match="interpolate"):  # 8 nodes are too few: it says so
        t1 = av.load_or_build_table(SYM, 0.9 * math.pi, nu=8, nv=4)
    assert list((tmp_path / "averaging").glob("slowmap-*.npz"))
    monkeypatch.setattr(slow_table, "_TABLES", {})
    t2 = av.load_or_build_table(SYM, 0.9 * math.pi, build=False, nu=8, nv=4)
    assert np.array_equal(t1.coef, t2.coef) and t1.U == t2.U and t1.kappa == t2.kappa  # exact: binary storage
    assert t2.interp_error == t1.interp_error > 1e-7


# ----------------------------------------------------------------------------- against the ODE
@pytest.mark.parametrize("name", list(PSI0))
def test_map_agrees_with_ode_and_error_falls_linearly(table, name):
    """Slow period, Q_R extent and Φ: ≤ 5e-3 relative at ε = 1e-2; the map tracks the ODE maximum by
    maximum over 1000 time units with errors (Q, Θ, t, φ) whose log-log slope over ε ∈ {1e-2, 1e-3,
    1e-4} is ≥ 1.  (The observables' own errors, in docs/averaging.md, are aε + bε² with a and b of
    opposite signs in some cases, so a three-point slope of them is not a clean measure.)
    """
    psi0 = PSI0[name]
    track = []
    with warnings.catch_warnings():
        warnings.simplefilter("ignore", av.AveragingValidityWarning)
        for eps in EPS:
            pred = av.predict_slow_motion(Body.paper(eps), THETA0, psi0, 1000.0, table=table, order=1)
            ref = ode(eps, psi0)
            if eps == 1e-2:
                errs = relative_errors(pred, ref)
                for q in ("slow_period", "QR_extent", "Phi"):
                    assert abs(errs[q]) <= 5e-3, (q, errs[q])
            track.append(sample_errors(pred.series, ref))
    for q in ("Q", "Theta", "t", "phi"):
        s = loglog_slope(EPS, [e[q] for e in track])
        assert s >= MIN_SLOPE, (q, s, [e[q] for e in track])


def test_straight_line_slope(table):
    """The turning-point samples lie on a line whose slope the map predicts; the error shrinks ∝ ε."""
    errs = []
    with warnings.catch_warnings():
        warnings.simplefilter("ignore", av.AveragingValidityWarning)
        for eps in EPS:
            pred = av.predict_slow_motion(Body.paper(eps), THETA0, PSI0["pi/4"], 1000.0, table=table, order=1)
            ref = ode(eps, PSI0["pi/4"])
            # the samples do lie on a line: residual across it ≪ extent along it
            X = np.vstack([ref.QR, ref.QJ])
            sv = np.linalg.svd(X - X.mean(axis=1, keepdims=True), compute_uv=False)
            assert sv[1] < 1e-3 * sv[0]
            errs.append(pred.line_slope / ref.line_slope - 1.0)
    s = loglog_slope(EPS, errs)
    assert s >= MIN_SLOPE, (s, errs)


# ----------------------------------------------------------------------------- closed form
def test_pendulum_constants_match_tables_and_quadrature(table, constants):
    c = constants
    assert np.allclose(c.C0, table.C0, rtol=1e-9)
    assert c.kappa == pytest.approx(table.kappa, rel=1e-7)
    h = 1e-7
    pr = precession(E0, np.array([h, 0.0]), np.array([0.0, h]), SYM)
    assert c.T0 == pytest.approx(float(precession(E0, 1e-12, 0.0, SYM).T_theta), rel=1e-11)
    assert np.allclose(c.dpsi_dQ, np.asarray(wrap_angle(pr.delta_psi, math.pi)) / h, rtol=1e-7)
    assert np.allclose(c.dphi_dQ, np.asarray(pr.visible_half_phi) / h, rtol=1e-7)


def test_closed_form_error_falls_linearly(constants):
    """Pendulum closed form against the ODE at ε = 1e-3, 1e-4, 1e-5 (K ≪ 1): the error falls linearly."""
    eps_set = (1e-3, 1e-4, 1e-5)
    for psi0 in (PSI0["pi/4"], PSI0["3pi/8"]):
        errs = []
        for eps in eps_set:
            t_end = 1000.0 if eps >= 1e-4 else 3000.0
            pred = pendulum_prediction(Body.paper(eps), THETA0, psi0, t_end, constants=constants)
            errs.append(relative_errors(pred, ode(eps, psi0, t_end)))
        for q in ("slow_period", "QR_extent", "Phi"):
            s = loglog_slope(eps_set, [e[q] for e in errs])
            assert s >= MIN_SLOPE, (q, s, errs)


def test_stable_axis_and_period_doubling(constants):
    """κ > 0: rocking at ψ = π/2 (about the body j axis, moment I2) is stable, at ψ = 0 unstable;
    it period-doubles at ε_pd = 4/κ: two direct runs at 0.95 ε_pd and 1.05 ε_pd."""
    c = constants
    assert c.kappa > 0 and c.stable_psi == pytest.approx(math.pi / 2)
    d = 1e-4

    def growth(eps: float, psi0: float) -> float:
        tr = simulate(Body.paper(eps), EulerState(THETA0, 0.0, psi0), 2000.0, dt=200.0)
        dev = np.abs(wrap_angle(tr.maxima.psi - c.stable_psi, math.pi))
        return float(dev.max() / abs(float(wrap_angle(psi0 - c.stable_psi, math.pi))))

    assert growth(0.95 * c.eps_period_doubling, math.pi / 2 - d) < 3.0
    assert growth(1.05 * c.eps_period_doubling, math.pi / 2 - d) > 30.0
    # near the other axis (ψ = 0) the motion runs away at any small ε
    tr = simulate(Body.paper(1e-3), EulerState(THETA0, 0.0, d), 1000.0, dt=100.0)
    assert np.abs(wrap_angle(tr.maxima.psi, math.pi)).max() > 1000 * d


# ----------------------------------------------------------------------------- diagnostics, input
def test_slow_period_estimator():
    t = np.arange(1, 400) * 13.26
    P = 157.3
    Theta = math.pi + 1.2 * np.cos(2 * math.pi * t / P + 0.3)
    assert slow_period(t, Theta) == pytest.approx(P, rel=1e-3)
    assert slow_period(t[:5], Theta[:5]) is None
    times, dirs = mean_crossings(np.array([0.0, 1.0, 2.0]), np.array([1.0, -1.0, 1.0]))
    assert np.allclose(times, [1 / 3, 5 / 3]) and list(dirs) == [-1, 1]  # mean 1/3


def test_mean_crossings_sample_on_the_mean():
    """A sample exactly at the mean takes the sign of the next sample (one crossing, not two)."""
    times, dirs = mean_crossings(np.arange(5.0), np.array([-1.0, 0.0, 0.0, 1.0, 0.0]))
    assert np.allclose(times, [1.0]) and list(dirs) == [1]


def test_unwrap_phase_and_line_slope():
    """unwrap_phase agrees with numpy.unwrap (steps off ±π); line_slope with the principal
    eigenvector of the scatter matrix (numpy.linalg.eigh)."""
    rng = np.random.default_rng(7)
    Theta = np.cumsum(rng.uniform(-3.1, 3.1, 500)) + 2 * math.pi * rng.integers(-3, 4, 500)
    # unwrap_phase: x − 2π K (the product and the difference round: 2u |·|); numpy.unwrap: per step the correction
    # mod(d + π, 2π) − π − d (≤ 3u (|d| + 2π)), summed cumulatively (≤ n u max|partial sum|), then added (u |·|);
    # × 4 (margin)
    got, want = unwrap_phase(Theta), np.unwrap(Theta)
    d = np.abs(np.diff(Theta))
    corr = np.abs(want - Theta)
    bound = 4 * (2 * ro.u * (np.abs(got) + corr) + np.concatenate([[0.0], np.cumsum(3 * ro.u * (d + 2 * math.pi))])
                 + Theta.size * ro.u * corr.max() + ro.u * np.abs(want))
    ro.assert_within(got - want, bound, "unwrap", want)
    assert np.array_equal(unwrap_phase(Theta[:1]), Theta[:1])  # exact: a single sample is returned as it is
    for slope in (0.03, -2.0, 40.0):
        x = rng.normal(size=200)
        y = slope * x + 0.1 * rng.normal(size=200)
        X = np.vstack([x - x.mean(), y - y.mean()])
        S = X @ X.T
        w, vecs = np.linalg.eigh(S)
        d = vecs[:, np.argmax(w)]
        ro.assert_within(av.line_slope(x, y) / (d[1] / d[0]) - 1, _slope_bound(S, d[1] / d[0], x.size), "slope", 1.0)
        S1 = np.array([[x @ x, slope * (x @ x)], [slope * (x @ x), slope**2 * (x @ x)]])
        ro.assert_within(av.line_slope(x, slope * x) / slope - 1, _slope_bound(S1, slope, x.size), "exact line", 1.0)


def _slope_bound(S, slope: float, n: int, margin: float = 4.0) -> float:
    """Relative bound on the slope tan α of the principal axis of the scatter matrix S of n centred samples.

    The entries of S are sums of n products of centred values (γ_{n+2} × sxx, syy, |sxy| ≤ √(sxx syy)); the
    angle of the principal axis moves by ≤ |δS|/(λ1 − λ2) (its gap), for α = ½ atan2(2 sxy, sxx − syy) as for
    LAPACK's eigh (backward stable: γ_10 ‖S‖); atan2, tan and d1/d0 round (γ_4); tan α = s carries δα as
    (1 + s²)/|s| relative.  × margin.
    """
    lam = np.linalg.eigvalsh(S)
    gap = lam[1] - lam[0]
    d_alpha = (ro.gamma(n + 2) * (S[0, 0] + S[1, 1]) + ro.gamma(10) * lam[1]) / gap
    return margin * (d_alpha * (1 + slope**2) / abs(slope) + ro.gamma(4))


def test_bad_input(table):
    with pytest.raises(ValueError, match="eps"):
        av.iterate_slow_map(table, -1e-3, 0.3, 100.0)
    with pytest.raises(ValueError, match="t_end"):
        av.iterate_slow_map(table, 1e-3, 0.3, 0.0)
    with pytest.raises(ValueError, match="theta0"):
        av.predict_slow_motion(Body.paper(1e-3), 3.5, 0.3)
    with pytest.raises(ValueError, match="theta0"):
        av.predict_slow_motion(Body.paper(1e-3), 0.9 * math.pi, 0.3, table=table)
    with pytest.raises(ValueError, match="the table is for the body"):
        av.predict_slow_motion(Body.from_polar_cap(0.6, epsilon=1e-3), THETA0, 0.3, table=table)
    with pytest.warns(av.AveragingValidityWarning, match="K = "):
        av.predict_slow_motion(Body.paper(1.2e-2), THETA0, PSI0["pi/4"], 200.0, table=table, order=1)
    with pytest.raises(av.AveragingRangeError, match="tabulated region"):
        av.iterate_slow_map(table, 1e-3, 0.3, 100.0, Q0=(2 * table.U, 0.0))
    with pytest.raises(av.AveragingRangeError, match="tabulated region"):  # inside at the start, leaves
        av.iterate_slow_map(table, 0.05, 0.3, 100.0)
    with pytest.raises(ValueError, match="Q0 must be two finite numbers"):
        av.iterate_slow_map(table, 1e-3, 0.3, 100.0, Q0=(math.nan, 0.0))
    with pytest.raises(ValueError, match="n_steps"):
        av.iterate_slow_map(table, 1e-3, 0.3, 100.0, n_steps=0)
    with pytest.raises(ValueError, match="unstable equilibrium"):
        pendulum_prediction(Body.paper(1e-3), THETA0, 0.0, constants=pendulum_constants(SYM, THETA0))


def test_azimuth_span_definition_shared(table):
    """Φ of the prediction uses the trajectory's azimuth_span (circle of circumference π)."""
    assert azimuth_span(np.array([0.1, math.pi - 0.1])) == pytest.approx(0.2)
    pred = av.predict_slow_motion(Body.paper(1e-3), THETA0, PSI0["pi/4"], 300.0, table=table, order=1)
    assert pred.Phi == azimuth_span(pred.series.phi)  # exact here and below: the same function on the same array
    traj = simulate(Body.paper(1e-3), EulerState(THETA0, 0.0, PSI0["pi/4"]), 100.0)
    assert traj.Phi == azimuth_span(traj.maxima.phi)
    assert slow_pendulum.azimuth_span is azimuth_span  # the closed form's Φ


# ----------------------------------------------------------------------------- slow validations
@pytest.mark.slow
def test_period_doubling_within_one_percent(constants):
    """The first-order ε_pd = 4/κ places the bifurcation to within 1 %: runs at 0.99 and 1.01 ε_pd."""
    c, d = constants, 1e-4

    def growth(eps: float) -> float:
        tr = simulate(Body.paper(eps), EulerState(THETA0, 0.0, math.pi / 2 - d), 3000.0, dt=300.0)
        return float(np.abs(wrap_angle(tr.maxima.psi - math.pi / 2, math.pi)).max() / d)

    assert growth(0.99 * c.eps_period_doubling) < 3.0
    assert growth(1.01 * c.eps_period_doubling) > 30.0


@pytest.mark.slow
def test_other_release_angle():
    """θ0 = 0.9π (its own tables, ε_pd = 0.037): map vs ODE at ε = 1e-2 and 1e-3 for ψ0 = π/4."""
    theta0 = 0.9 * math.pi
    tab = av.build_table(SYM, theta0)
    errs = []
    for eps in (1e-2, 1e-3):
        pred = av.predict_slow_motion(Body.paper(eps), theta0, math.pi / 4, 1000.0, table=tab, order=1)
        ref = ode_slow_summary(Body.paper(eps), theta0, math.pi / 4, 1000.0)
        errs.append(relative_errors(pred, ref))
        # the same sequence of critical regions; a rock whose sample lies within the map's O(ε)
        # error of a critical line may be counted on the other side at ε = 1e-2
        assert [r[0] for r in pred.region_runs] == [r[0] for r in ref.region_runs]
        slack = 1 if eps == 1e-2 else 0
        assert all(abs(a[1] - b[1]) <= slack for a, b in zip(pred.region_runs, ref.region_runs))
    for q in ("slow_period", "QR_extent", "Phi"):
        assert abs(errs[0][q]) <= 5e-3 and abs(errs[1][q]) <= 5e-4, (q, errs)


@pytest.mark.slow
@pytest.mark.parametrize("name", ["pi/8", "3.9pi/8"])
def test_closed_form_other_psi0(constants, name):
    eps_set = (1e-3, 1e-4, 1e-5)
    errs = [relative_errors(pendulum_prediction(Body.paper(e), THETA0, PSI0[name], t, constants=constants),
                            ode(e, PSI0[name], t))
            for e, t in zip(eps_set, (1000.0, 1000.0, 3000.0))]
    for q in ("slow_period", "QR_extent"):
        assert loglog_slope(eps_set, [e[q] for e in errs]) >= MIN_SLOPE, (q, errs)
