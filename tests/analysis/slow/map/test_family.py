"""The first maximum of θ from any start (``analysis.slow.map.family.first_maximum``): where the prediction from a state
begins."""

from __future__ import annotations

import math

import pytest

import rocknroller.analysis.slow.map.family as family
from rocknroller.analysis.model.body import Body
from rocknroller.analysis.model.equations import EulerState
from rocknroller.numerics.integrate import simulate

BODY = Body.paper(1e-2)
#: θ still rising: the first maximum a fraction of a rocking period later.
RISING = EulerState(theta=2.0, theta_dot=0.3, phi=0.0, phi_dot=0.5, psi=0.5, psi_dot=1.0)


def test_first_maximum_needs_no_quadrature_of_the_period(monkeypatch):
    """Issue 25, item 4: locating the first maximum cost 25 ms of a 30 ms prediction, 5/6 of it the quadrature of
    T_θ that only bounds how far to look.  Now a closed-form small-amplitude period bounds the first look, and the
    quadrature runs only where that look finds no maximum; the maximum is the ODE's first (same run, same bits)."""
    def no_quadrature(*args, **kwargs):
        raise AssertionError("the period's quadrature was computed")

    monkeypatch.setattr(family, "precession", no_quadrature)
    monkeypatch.setattr(family, "precession_mp", no_quadrature)
    found = family.first_maximum(BODY, RISING)
    run = simulate(BODY, RISING, 10.0 * found.t, samples=False)
    assert 0.0 < found.t == run.maxima.t[0]
    assert (found.theta, found.psi, found.phi, found.QR, found.QJ) == (
        run.maxima.theta[0], run.maxima.psi[0], run.maxima.phi[0], run.maxima.QR[0], run.maxima.QJ[0])


def test_a_maximum_past_the_first_look_is_found_over_the_period(monkeypatch):
    """Where the small-amplitude bound looks too short (forced here by a frequency 1e6 times too high) the period's
    quadrature sets the look, as before, and finds the same maximum."""
    expected = family.first_maximum(BODY, RISING)
    calls = []

    def fast(body, moment):
        calls.append(moment)
        return 1e6

    monkeypatch.setattr(family, "small_amplitude_frequency", fast)
    assert family.first_maximum(BODY, RISING) == expected and calls


def test_steady_rolling_still_refused_with_its_cause():
    """Steady rolling (no oscillation of θ) is refused naming the cause, after the first look finds no maximum."""
    from rocknroller.analysis.routh.steady_rolling import steady_rolling_omega3

    body, theta0, omega2 = Body.paper(), 2.0, 0.9
    phi_dot = omega2 / math.sin(theta0)
    psi_dot = steady_rolling_omega3(body, theta0, omega2) - math.cos(theta0) * phi_dot
    with pytest.raises(ValueError, match="no oscillation of theta"):
        family.first_maximum(body, EulerState(theta0, 0.0, 0.0, 0.0, phi_dot, psi_dot))
