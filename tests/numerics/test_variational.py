"""The direct motion's chaos indicators (numerics/variational.py): the tangent vector against central differences of
two runs, λ of the unstable pure rocking against the exact step's multiplier, MEGNO → 2 on stable rocking and on a
regular release, λ of chaotic releases against the separation of two nearby runs, bad input."""

from __future__ import annotations

import math

import numpy as np
import pytest

from rocknroller.analysis.model.body import Body
from rocknroller.analysis.model.equations import EulerState
from rocknroller.numerics.budget import WorkBudgetError
from rocknroller.numerics.integrate import check_run, heyoka_integrator, simulate
from rocknroller.numerics.megno import MEGNO_CHAOTIC
from rocknroller.numerics.variational import (direct_chaos_indicators, initial_tangent, tangent_flow, tangent_norm,
                                              variational_integrator)

THETA0 = 0.95 * math.pi
#: Time between θ-maxima of releases from rest at θ0 = 0.95π (12.5-13.3 time units, measured): t_end per rock.
ROCK = 12.6


def _plain_runs(body: Body, y0: np.ndarray, times: np.ndarray) -> np.ndarray:
    """(γ, ω) at ``times`` from the body-frame state ``y0`` by simulate's own integrator (no tangent)."""
    ta = heyoka_integrator()
    ta.time, ta.state[:], ta.pars[:] = 0.0, y0, body.params
    out = []
    for t in times:
        ta.propagate_until(float(t))
        out.append(np.array(ta.state[:6]))
    return np.array(out)


def test_tangent_is_the_central_difference_of_two_runs():
    """w(t) = ∂y(t)/∂y0 · w0 against (y(t; y0 + h w0) − y(t; y0 − h w0))/(2h) on a chaotic orbit (ψ0 = 0.1).

    The central difference errs by C h² (truncation) + δ/h (δ: the runs' own error, ≤ 1e-12 of the state, Λ ≈ 3, over
    100 time units); at h = 3e-5 the truncation dominates (measured: the error falls 9-fold from h = 1e-4 to 3e-5,
    as h², and reaches round-off near 1e-7), so it is estimated from h and 2h: FD(2h) − FD(h) = 3 C h².  Bound: that
    estimate × 1.5 (margin on the h² law) + δ/h.  Measured relative errors at h = 3e-5: 3.5e-7, 3.4e-4, 3.3e-3 at
    t = 10, 50, 100 (‖w‖ = 14, 4.7, 90)."""
    body = Body.paper(1e-2)
    start = EulerState(THETA0, 0.0, 0.1)
    plan = check_run(body, start, 100.0, samples=False)
    times = np.array([10.0, 50.0, 100.0])
    states, tangents = tangent_flow(body, start, times)
    np.testing.assert_allclose(states, _plain_runs(body, plan.y0, times), rtol=0, atol=1e-12)  # the same orbit
    w0 = initial_tangent(plan.y0, plan.rate)

    def central(h: float) -> np.ndarray:
        up, down = plan.y0.copy(), plan.y0.copy()
        up[:6] += h * w0
        down[:6] -= h * w0
        return (_plain_runs(body, up, times) - _plain_runs(body, down, times)) / (2.0 * h)

    h = 3e-5
    fd, fd2 = central(h), central(2.0 * h)
    err = tangent_norm((fd - tangents).T, plan.rate)
    bound = 1.5 * tangent_norm((fd2 - fd).T, plan.rate) / 3.0 + 1e-12 * plan.rate / h
    assert np.all(err <= bound), (err, bound)
    assert np.all(err / tangent_norm(tangents.T, plan.rate) < 1e-2)  # and the difference is small: not a loose bound


@pytest.mark.parametrize("eps, theta0", [(1e-2, 0.95 * math.pi), (3e-3, 0.95 * math.pi), (1e-2, 0.9 * math.pi)])
def test_unstable_rocking_grows_by_the_exact_step_multiplier(eps, theta0):
    """Pure rocking about the unstable axis (ψ0 = 0, an exact periodic motion that the integrator keeps exactly:
    γ1 = ω2 = ω3 = 0 stay 0 in floating point) is a saddle of the one-step map: λ per rock = ln μ, μ the largest
    multiplier of the exact step's Jacobian (:func:`rocking_jacobian`: fourth-order central differences of
    ``exact_step``, an independent computation through ``simulate``).  Tolerance 1e-9 relative: that Jacobian's
    entries are good to ~1e-10 (its docstring: O(h⁴) truncation ~1e-12, round-off ~1e-10), × 10.  Measured:
    2.0e-12, 6.3e-12 and 1.4e-11 over 100 rocks (ln μ = 1.801, 1.076, 0.998); MEGNO 91, 54, 61."""
    from rocknroller.analysis.slow.dynamics.period_doubling import rocking_jacobian

    body = Body.paper(eps)
    mu = float(np.max(np.abs(np.linalg.eigvals(rocking_jacobian(body, theta0, eps, 0.0)))))
    run = direct_chaos_indicators(body, EulerState(theta0, 0.0, 0.0), 1300.0)
    assert run.indicators.lyapunov_per_rock == pytest.approx(math.log(mu), rel=1e-9)
    assert not run.indicators.regular


#: ⟨Y⟩ of an orbit whose tangent grows linearly, ‖w‖ = 1 + t/t0, is 2 − (2/x) ∫₀ˣ ln(1 + u)/u du ≈ 2 − (ln²x + π²/3)/x,
#: x = t/t0.  Measured on the orbits below: t0 ≈ 23-31 time units (a fit of ‖w‖ over the later half), ⟨Y⟩ = 1.56-1.57
#: after 300 rocks and 1.91-1.92 after 3000 (x ≈ 1300: the law gives 1.96; the early transient, where ‖w‖ oscillates
#: before the shear takes over, costs the rest).  Tolerance after 3000 rocks: 0.15, the law's deviation at t0 = 120
#: time units (4-5 times the measured t0).
MEGNO_TOLERANCE_3000 = 0.15


@pytest.mark.parametrize("eps, psi0, what", [(3e-3, math.pi / 2, "pure rocking about the stable axis (K = 1.3 < 4)"),
                                             (1e-2, math.pi / 4, "the regular release of issue 23")])
def test_megno_tends_to_two_on_regular_motion(eps, psi0, what):
    """MEGNO → 2 (linear growth of ‖w‖ by the shear of neighbouring orbits) on regular motion: regular after a few
    hundred rocks (⟨Y⟩ between 1 and 3, stable periodic 0 and chaotic ≥ 3 excluded), within MEGNO_TOLERANCE_3000 of 2
    after 3000, and λ → 0 (its least-squares slope over the later half, ≈ 1/t for ln t, below 1e-4)."""
    body = Body.paper(eps)
    start = EulerState(THETA0, 0.0, psi0)
    run = direct_chaos_indicators(body, start, 3000 * ROCK)
    ind = run.indicators
    n300 = int(np.searchsorted(ind.t, 300 * ROCK))
    assert 1.0 < ind.mean_megno[n300] < MEGNO_CHAOTIC, (what, ind.mean_megno[n300])
    assert ind.regular and abs(ind.megno - 2.0) <= MEGNO_TOLERANCE_3000, (what, ind.megno)
    assert ind.lyapunov < 1e-4, (what, ind.lyapunov)
    assert run.energy_rel_error < 1e-13  # 4.8e-15 measured over 40 000 time units


def test_maxima_are_simulate_maxima_on_a_regular_orbit():
    """The samples are the θ-maxima: on the regular release (300 rocks) the same as simulate's, in number, time and θ.
    Both integrate the same equations at machine precision; their differences grow linearly on a regular orbit
    (measured 3.1e-10 in t and 5.5e-12 in θ after 303 maxima): tolerances 3e-9 and 5e-11 (× 10)."""
    body = Body.paper(1e-2)
    start = EulerState(THETA0, 0.0, math.pi / 4)
    run = direct_chaos_indicators(body, start, 300 * ROCK)
    ref = simulate(body, start, 300 * ROCK, samples=False).maxima
    assert len(run.t_maxima) == len(ref) >= 300
    np.testing.assert_allclose(run.t_maxima, ref.t, rtol=0, atol=3e-9)
    np.testing.assert_allclose(run.theta_maxima, ref.theta, rtol=0, atol=5e-11)


def _separation_slopes(body: Body, psi0: float, t_end: float) -> tuple[float, float, float]:
    """MEGNO, and the growth rates over the same window of (i) ln d, d the distance (tangent norm, (γ, ω) at the k-th
    θ-maxima) of two runs whose ψ0 differ by 1e-10, and (ii) the tangent's ℓ: from the 10th maximum (the transient in
    which both turn towards the unstable direction) to the last one with d ≤ 1e-3 (before d saturates)."""
    start = EulerState(THETA0, 0.0, psi0)
    run = direct_chaos_indicators(body, start, t_end)
    a = simulate(body, start, t_end, samples=False).maxima
    b = simulate(body, EulerState(THETA0, 0.0, psi0 + 1e-10), t_end, samples=False).maxima
    n = min(len(a), len(b))
    d = tangent_norm((a.states[:n, :6] - b.states[:n, :6]).T, run.rate)
    beyond = np.flatnonzero(d > 1e-3)
    k0, k1 = 10, (int(beyond[0]) if beyond.size else n)
    assert k1 - k0 >= 30, "the window must span enough rocks"
    window = (run.t_maxima >= a.t[k0]) & (run.t_maxima <= a.t[k1 - 1])
    sep = float(np.polyfit(a.t[k0:k1], np.log(d[k0:k1]), 1)[0])
    var = float(np.polyfit(run.t_maxima[window], run.indicators.log_growth[window], 1)[0])
    return run.indicators.megno, sep, var


#: λ from the tangent against the growth rate of two nearby runs over the same window.  Measured relative differences:
#: −4.6 % (ε = 1e-2, ψ0 = 0.1), −5.1 % (ψ0 = 0.3), −1.2 % (ε = 3e-3, ψ0 = 0.001), −0.1 % (ε = 3e-3, ψ0 = 0.05), +0.1 %
#: (ε = 1e-3, ψ0 = 0.001).  The two differ only through the transients in which the separation (started along ψ)
#: and the tangent (started along w0) turn towards the unstable direction, and the finite size of d near the window's
#: top; tolerance 15 % (3 × the largest measured).
LAMBDA_AGREEMENT = 0.15


def test_chaotic_release_megno_and_lambda_against_two_nearby_runs():
    """Issue 23's chaotic release (θ0 = 0.95π, ε = 1e-2, ψ0 = 0.1; two runs 1e-10 apart in ψ0 separate to 3e-3 in
    (Q_R, Q_J) after 100 rocks): MEGNO > 3 after ~100 rocks (10.6 measured), and λ agrees with the separation's
    growth (0.0128 against 0.0135 per time unit measured)."""
    megno, sep, var = _separation_slopes(Body.paper(1e-2), 0.1, 1300.0)
    assert megno > MEGNO_CHAOTIC
    assert var == pytest.approx(sep, rel=LAMBDA_AGREEMENT)


@pytest.mark.parametrize("eps, psi0", [(1e-2, 0.3), (3e-3, 0.001), (3e-3, 0.05), (1e-3, 0.001)])
def test_other_chaotic_releases_against_two_nearby_runs(eps, psi0):
    """The other chaotic and weakly chaotic (separatrix layer) releases of issue 23's table, over 200 rocks: MEGNO
    20.1, 20.7, 7.3, 6.1 measured."""
    megno, sep, var = _separation_slopes(Body.paper(eps), psi0, 1300.0 if eps == 1e-2 else 2600.0)
    assert megno > MEGNO_CHAOTIC
    assert var == pytest.approx(sep, rel=LAMBDA_AGREEMENT)


def test_renormalisation_keeps_the_sum_of_logarithms():
    """Renormalising at every maximum changes nothing: ℓ over 30 rocks equals ln ‖w‖ of the tangent carried without
    renormalisation (tangent_flow) at the same times, to the rounding of ~30 logarithms and of the integration
    (1e-9 absolute: ℓ ≈ 50, the unstable rocking, where the two runs take the same steps up to the renormalisation's
    effect on the step size)."""
    body = Body.paper(1e-2)
    start = EulerState(THETA0, 0.0, 0.0)
    run = direct_chaos_indicators(body, start, 400.0)
    _, w = tangent_flow(body, start, run.t_maxima)
    np.testing.assert_allclose(run.indicators.log_growth, np.log(tangent_norm(w.T, run.rate)), rtol=0, atol=1e-9)


def test_initial_tangent_is_fixed_unit_and_on_the_sphere():
    body = Body.paper(1e-2)
    plan = check_run(body, EulerState(THETA0, 0.0, math.pi / 4), 10.0, samples=False)
    w0 = initial_tangent(plan.y0, plan.rate)
    assert float(tangent_norm(w0, plan.rate)) == pytest.approx(1.0, abs=1e-15)
    assert abs(float(w0[:3] @ plan.y0[:3])) < 1e-15  # δγ ⟂ γ0: tangent to |γ| = 1
    np.testing.assert_allclose(w0[3:] / plan.rate, w0[3] / plan.rate)  # (1, 1, 1) in δω/Λ
    assert variational_integrator() is variational_integrator()  # one copy per thread


@pytest.mark.parametrize("kwargs, fragment", [
    (dict(t_end=0.0), "t_end must be a finite number > 0"),
    (dict(t_end=float("nan")), "t_end must be a finite number > 0"),
    (dict(t_end="long"), "t_end must be a finite number > 0"),
    (dict(t_end=50.0), "t_end=50.0: the indicators need at least MIN_SAMPLES = 8"),
    (dict(t_end=1e12), "is too long.*MAX_RADIANS"),
    (dict(t_end=1e6, budget=1.0), "budget"),
    (dict(budget=-1.0), "budget must be a number of seconds > 0"),
    (dict(initial=EulerState(math.pi)), "no motion"),
    (dict(initial=(THETA0, 0.0, 0.1)), "initial must be a rocknroller"),
    (dict(body="paper"), "body must be a rocknroller"),
])
def test_bad_input_is_refused(kwargs, fragment):
    args = dict(body=Body.paper(1e-2), initial=EulerState(THETA0, 0.0, 0.1), t_end=200.0)
    budget = kwargs.pop("budget", 3600.0)
    args.update(kwargs)
    with pytest.raises(ValueError, match=fragment):
        direct_chaos_indicators(args["body"], args["initial"], args["t_end"], budget=budget)


def test_budget_refusal_is_a_work_budget_error():
    with pytest.raises(WorkBudgetError, match="variational run"):
        direct_chaos_indicators(Body.paper(1e-2), EulerState(THETA0, 0.0, 0.1), 1e6, budget=1.0)


@pytest.mark.parametrize("times, w0, fragment", [
    ([], None, "times must be a non-empty"),
    ([2.0, 1.0], None, "times must be a non-empty"),
    ([-1.0], None, "times must be a non-empty"),
    ([1.0, float("inf")], None, "times must be a non-empty"),
    ([1.0], [1.0, 0.0], "w0 must be 6 finite numbers"),
    ([1.0], [1.0, 0.0, 0.0, 0.0, 0.0, float("nan")], "w0 must be 6 finite numbers"),
])
def test_tangent_flow_bad_input(times, w0, fragment):
    with pytest.raises(ValueError, match=fragment):
        tangent_flow(Body.paper(1e-2), EulerState(THETA0, 0.0, 0.1), times, w0)
