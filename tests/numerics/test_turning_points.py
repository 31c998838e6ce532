"""Turning points of θ where they are hard to get right: a start that is itself a turning point to its rounding
(issue 25, item 2), small amplitudes near the pole, down to ``THETA_MIN`` and refused below it (item 21), and
steady rolling, whose dγ3/dt is round-off."""

from __future__ import annotations

import dataclasses
import math
import re

import numpy as np
import pytest

from rocknroller.analysis.model.body import Body
from rocknroller.analysis.model.equations import EulerState, turning_point_function
from rocknroller.analysis.routh.rocking import small_amplitude_frequency
from rocknroller.numerics.ensembles.ensemble import Job
from rocknroller.numerics.events import THETA_MIN, start_turning_point
from rocknroller.numerics.integrate import simulate

BODY = Body.paper(1e-3)
#: Safety margin of the first-order error bounds below (each adds worst cases linearly already).
MARGIN = 4.0
#: Starts from Euler rates with θ̇0 = 0 where dγ3/dt = γ1 ω2 − γ2 ω1 rounds to −2.2e-19 and −4.3e-19, not 0: the
#: integrator reported a θ-maximum at t = 6.5e-17 and 3.1e-17 (θ falls from there: the start is the maximum).
STARTS_AT_A_MAXIMUM = [EulerState(0.1, 0.0, math.pi / 4, 0.0, 0.3, -0.2),
                       EulerState(0.1, 0.0, math.pi / 4, 0.0, 0.7, 1.3)]


def _events(run) -> tuple[np.ndarray, np.ndarray]:
    """Times and kinds (+1 maximum, −1 minimum) of every turning point, in time order."""
    t = np.concatenate([run.maxima.t, run.minima.t])
    kind = np.concatenate([np.ones(len(run.maxima), int), -np.ones(len(run.minima), int)])
    order = np.argsort(t, kind="stable")
    return t[order], kind[order]


@pytest.mark.parametrize("method", ["heyoka", "scipy"])
@pytest.mark.parametrize("start", STARTS_AT_A_MAXIMUM)
def test_a_start_at_a_maximum_to_its_rounding_is_not_reported(start, method):
    """The start is a maximum to its rounding (``start_turning_point``): no turning point is reported at t ≈ 0,
    the first is the minimum that follows, and they alternate."""
    y0 = start.to_body_state()
    assert turning_point_function(y0) != 0.0
    assert start_turning_point(BODY, y0).kind == 1  # θ̈ < 0: a maximum
    t, kind = _events(simulate(BODY, start, 10.0, method=method))
    assert kind[0] == -1 and np.all(kind[1:] != kind[:-1])
    assert t[0] > 1.0  # the first minimum, about a quarter rocking period later


def test_the_ode_and_the_slow_prediction_start_from_the_same_sample():
    """``first_maximum`` (where ``predict_slow_motion``'s series of maxima starts) and the ODE classify a start alike:
    one that is its own maximum (t = 0) is a sample of neither; one with θ̇0 = 1e-9 (θ still rising, |dγ3/dt| far
    above its rounding) has its first maximum a moment later, the same sample for both."""
    from rocknroller.analysis.slow.map.family import first_maximum

    for start in STARTS_AT_A_MAXIMUM:
        assert first_maximum(BODY, start).t == 0.0
        run = simulate(BODY, start, 10.0, samples=False)
        assert run.minima.t[0] < run.maxima.t[0]
    rising = dataclasses.replace(STARTS_AT_A_MAXIMUM[0], theta_dot=1e-9)
    assert start_turning_point(BODY, rising.to_body_state()) is None
    run = simulate(BODY, rising, 10.0, samples=False)
    assert 0.0 < run.maxima.t[0] < run.minima.t[0]
    # the same first integration step and the same root of dγ3/dt on it: the same time to the bit
    assert first_maximum(BODY, rising).t == run.maxima.t[0]


@pytest.mark.parametrize("theta0", [1e-10, 1e-12, 2.0 * THETA_MIN])
def test_turning_points_near_the_pole_agree_with_dop853(theta0):
    """Released from rest at θ0 ≤ 1e-10 the integrator used to report two maxima in a row (0.0008 apart at 1e-10,
    and maxima below θ0 at 1e-12).  Now 11 maxima and 12 minima in 60 time units, alternating, as DOP853 finds with
    its absolute tolerance scaled to the tilt (atol = rtol θ0: each of γ1, γ2 ≈ θ then kept to rtol of itself).

    Bounds: each heyoka step errs by at most its tolerance ε absolutely in γ1, γ2 (ε applies to max(1, ‖y‖∞) = 1),
    each DOP853 step by atol + rtol θ0 = 2 rtol θ0; over n steps the tilt components are off by δγ ≤ n × that, and a
    turning point near the pole, a root of dγ3/dt ≈ −θ θ̇ (slope (θ0 Ω)² there, changed by θ0 Ω δγ), moves by
    δγ/(θ0 Ω), Ω the slower of the two small-amplitude rocking frequencies; θ and φ at the maxima by δγ/θ0 (Φ by
    twice that, two maxima); × MARGIN."""
    start = EulerState(theta0, 0.0, 0.3)  # ψ0 = 0.3: off the principal axes, so that φ, ψ and Φ are not trivial
    hy = simulate(BODY, start, 60.0)
    rtol = 3e-14
    sc = simulate(BODY, start, 60.0, method="scipy", rtol=rtol, atol=rtol * theta0)
    t_hy, k_hy = _events(hy)
    t_sc, k_sc = _events(sc)
    assert (len(hy.maxima), len(hy.minima)) == (11, 12) == (len(sc.maxima), len(sc.minima))
    assert np.all(k_hy[1:] != k_hy[:-1]) and np.array_equal(k_hy, k_sc)
    d_gamma = hy.n_steps * hy.tolerance + sc.n_steps * 2.0 * rtol * theta0
    omega = min(small_amplitude_frequency(BODY, BODY.I1), small_amplitude_frequency(BODY, BODY.I2))
    assert np.max(np.abs(t_hy - t_sc)) <= MARGIN * d_gamma / (theta0 * omega)
    assert np.max(np.abs(hy.maxima.theta - sc.maxima.theta)) <= MARGIN * d_gamma
    assert abs(hy.Phi - sc.Phi) <= MARGIN * 2.0 * d_gamma / theta0


def test_turning_points_alternate_over_a_long_run_near_the_pole():
    """Over 3e5 time units at θ0 = 1e-8 (about 120 000 turning points) the integrator's events, located on the
    Taylor polynomial of dγ3/dt, put a root near the end of a step into two steps or none, twice here (at a rate of
    ≈ 2^(p+2) e^(−2(p+1))/θ0 per root and step length); checked and located on the dense output they alternate."""
    run = simulate(BODY, EulerState(1e-8, 0.0, 0.3), 3e5, samples=False)
    t, kind = _events(run)
    assert t.size > 100_000 and kind[0] == -1 and np.all(kind[1:] != kind[:-1])


@pytest.mark.parametrize("start", [EulerState(0.5 * THETA_MIN), EulerState(1e-14, 0.0, 0.3), EulerState(1e-300)])
def test_tilts_below_theta_min_are_refused_up_front(start):
    """The energy bounds the tilt by θ_E (here θ0, from rest): below THETA_MIN = 2¹⁰ u the turning points are not
    resolved, and the run (or a Job) is refused naming theta0 and the bound; the start's tilt θ0 = THETA_MIN/2 lies
    just below the bound that 2 THETA_MIN (test above) lies just above."""
    fragment = re.escape(f"theta0={start.theta!r}: ") + r".*" + re.escape(f"THETA_MIN = {THETA_MIN:.3g} rad")
    with pytest.raises(ValueError, match=fragment):
        simulate(BODY, start, 60.0)
    with pytest.raises(ValueError, match=fragment):
        Job(BODY, start, 60.0)


def test_a_spinning_top_within_theta_min_of_the_pole_is_refused():
    """Spinning fast at θ0 = 1e-14 the body keeps its tilt tiny although its energy would allow any tilt: its
    maxima of θ (≈ 1e-14) are below THETA_MIN, so the run is refused after the fact, naming theta0 and the bound."""
    with pytest.raises(ValueError, match=r"theta0=1e-14: theta has maxima as small as .*THETA_MIN = 1.14e-13 rad"):
        simulate(BODY, EulerState(1e-14, psi_dot=5.0), 20.0)


def test_steady_rolling_has_no_turning_points():
    """Steady rolling keeps θ constant to its last digits: dγ3/dt on the dense output stays within its rounding
    (``H_ROUND_ULPS``) and no turning point is reported (the integrator's events gave 6 maxima and 8 minima of
    round-off in 50 time units)."""
    from rocknroller.analysis.routh.steady_rolling import steady_rolling_omega3

    body, theta0, omega2 = Body.paper(), 2.0, 0.9
    phi_dot = omega2 / math.sin(theta0)
    psi_dot = steady_rolling_omega3(body, theta0, omega2) - math.cos(theta0) * phi_dot
    run = simulate(body, EulerState(theta0, 0.0, 0.0, 0.0, phi_dot, psi_dot), 50.0)
    assert len(run.maxima) == len(run.minima) == 0
