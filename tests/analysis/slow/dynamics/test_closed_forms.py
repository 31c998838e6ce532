"""The closed forms of the slow motion near pure rocking and their regimes (``analysis/slow/dynamics/pendulum.py``): the pendulum
at large amplitude, the linear beat 2π/|ν1 − ν2| at small, the parameter R² = |K|/(T0 Δν)² between them with its
crossover R² = 1, and the domain of the pendulum's constants.

The direct ODE keeps only its turning points (``simulate(..., samples=False)``) over three beat periods, enough for
the slow period (crossings of the mean) on either side of the crossover; ε = 1e-2 keeps the runs short (~1 s).
"""

from __future__ import annotations

import math
import warnings

import numpy as np
import pytest
from scipy.optimize import brentq

from rocknroller.analysis.model.body import Body
from rocknroller.analysis.model.equations import EulerState
from rocknroller.analysis.slow.dynamics import pendulum as pm
from rocknroller.analysis.slow import prediction as av
from rocknroller.numerics.integrate import simulate
from rocknroller.papers.averaging_check import relative_errors

EPS = 1e-2
BODY = Body.paper(EPS)
BEAT = pm.beat_prediction(BODY, 1e-3 * math.pi).slow_period


def ode(theta0: float, psi0: float, body: Body = BODY):
    """The direct ODE's turning points from rest at (θ0, ψ0) over three beat periods."""
    return simulate(body, EulerState(theta0, 0.0, psi0), 3.0 * BEAT, samples=False)


def pendulum(theta0: float, psi0: float) -> pm.PendulumPrediction:
    with warnings.catch_warnings():
        warnings.simplefilter("ignore", pm.ClosedFormRegimeWarning)
        return pm.pendulum_prediction(BODY, theta0, psi0)


def beat(theta0: float) -> pm.BeatPrediction:
    with warnings.catch_warnings():
        warnings.simplefilter("ignore", pm.ClosedFormRegimeWarning)
        return pm.beat_prediction(BODY, theta0)


def crossover_theta0(body: Body = BODY) -> float:
    """θ0 with R² = 1 (the pendulum's constants converge there for ε ≥ 1e-4)."""
    return brentq(lambda th: pm.regime_ratio(body, th) - 1.0, *pm.PENDULUM_THETA0_RANGE, xtol=1e-7)


# ----------------------------------------------------------------------------- the pendulum constants' domain (#23)
@pytest.mark.parametrize("theta0", [1e-3, 1e-6, 1e-10, 1e-20, 1e-108, math.nextafter(pm.PENDULUM_THETA0_RANGE[0], 0.0),
                                    math.nextafter(pm.PENDULUM_THETA0_RANGE[1], 4.0), math.pi, 0.0, -0.1, math.nan,
                                    math.inf, "banana"])
def test_pendulum_constants_refuse_outside_their_domain_before_any_work(theta0, monkeypatch):
    """Below 0.005π the quadratures did not converge (a RuntimeError after up to 4096 nodes, 8 minutes at 1e-108):
    now a ValueError naming theta0 and the range, before any quadrature."""
    def no_work(*args):
        raise AssertionError("a quadrature ran")

    monkeypatch.setattr(pm, "_quadratures", no_work)
    with pytest.raises(ValueError, match=r"^theta0 must lie in \[0.005pi, 0.999pi\] = \[0.015708, 3.13845\] for the "
                                         r"pendulum constants, got theta0="):
        pm.pendulum_constants(BODY, theta0)


def test_pendulum_constants_converge_across_their_domain():
    """The rule's last change stays below the accepted round-off floor at both ends of the range and between (the
    ends: 0.005π, where the slopes' round-off ∝ 1/θ0² is ~5e-9, and 0.999π, 256 nodes)."""
    lo, hi = pm.PENDULUM_THETA0_RANGE
    for theta0 in np.concatenate([np.geomspace(lo, 0.1 * math.pi, 5), np.linspace(0.2 * math.pi, hi, 5)]):
        c = pm.pendulum_constants(BODY, float(theta0))
        assert c.rel_change <= pm._RTOL_ACCEPT and c.kappa > 0.0, (theta0 / math.pi, c.rel_change)


# ----------------------------------------------------------------------------- the two ends and the crossover (#1)
def test_regime_ratio_is_the_crossover_parameter():
    """R² grows like θ0²/ε (κ ∝ θ0², T0 Δν ∝ ε), so the crossover θ0 grows like √ε; below the pendulum constants'
    range R² continues as θ0² (within 1e-3 of the quadratic through the range's lower end)."""
    lo = pm.PENDULUM_THETA0_RANGE[0]
    small = Body.paper(1e-3)
    # ν1 − ν2 ∝ ε (1 + O(ε)): the ratio is 10 to O(ε)
    assert pm.regime_ratio(small, 2 * lo) / pm.regime_ratio(BODY, 2 * lo) == pytest.approx(10.0, rel=EPS)
    assert crossover_theta0(small) / crossover_theta0() == pytest.approx(math.sqrt(0.1), rel=2e-2)
    assert pm.regime_ratio(BODY, 0.5 * lo) == pytest.approx(0.25 * pm.regime_ratio(BODY, lo), rel=1e-12)
    assert pm.regime_ratio(BODY, 2 * lo) == pytest.approx(4.0 * pm.regime_ratio(BODY, lo), rel=1e-3)
    assert math.isnan(pm.regime_ratio(Body.paper(0.0), 0.1))
    assert pm.beat_prediction(Body.paper(0.0), 0.1).slow_period == math.inf  # no beat without asymmetry


@pytest.mark.parametrize("psi0", [0.5, math.pi / 4, 1.2])
def test_beat_is_the_small_amplitude_end(psi0):
    """At 0.005π (R² = 0.043) the beat's slow period is within its regime bound 1/√(1 − R²) − 1 of the ODE (plus the
    O(ε) of the normal form itself), with no warning, whatever ψ0; the pendulum's is off by a factor > 4 and warns."""
    theta0 = 0.005 * math.pi
    with warnings.catch_warnings():
        warnings.simplefilter("error", pm.ClosedFormRegimeWarning)
        b = pm.beat_prediction(BODY, theta0)
    assert b.regime_ratio < 0.05
    err = relative_errors(b, ode(theta0, psi0))["slow_period"]
    assert abs(err) <= 1.0 / math.sqrt(1.0 - b.regime_ratio) - 1.0 + EPS, err
    with pytest.warns(pm.ClosedFormRegimeWarning, match="the pendulum closed form is used outside its regime"):
        p = pm.pendulum_prediction(BODY, theta0, psi0)
    assert p.slow_period > 4.0 * b.slow_period


@pytest.mark.parametrize("psi0", [0.5, math.pi / 4, 1.2])
def test_pendulum_is_the_large_amplitude_end(psi0):
    """At 0.1π (R² = 19) the pendulum's slow period is within its regime bound √(1 + 1/R²) − 1 of the ODE (plus
    O(ε)), with no warning; the beat's is off by more than a factor 2 and warns."""
    theta0 = 0.1 * math.pi
    with warnings.catch_warnings():
        warnings.simplefilter("error", pm.ClosedFormRegimeWarning)
        p = pm.pendulum_prediction(BODY, theta0, psi0)
    assert p.regime_ratio > 10.0
    err = relative_errors(p, ode(theta0, psi0))["slow_period"]
    assert abs(err) <= math.sqrt(1.0 + 1.0 / p.regime_ratio) - 1.0 + EPS, err
    with pytest.warns(pm.ClosedFormRegimeWarning, match="the linear beat closed form is used outside its regime"):
        b = pm.beat_prediction(BODY, theta0)
    assert b.slow_period > 2.0 * p.slow_period


def test_errors_against_the_ode_cross_at_the_named_crossover():
    """The warning names the crossover θ0 (R² = 1) to 5 %; on the ODE the beat is the closer form at R² = 1/2 and
    the pendulum at R² = 3 (their errors cross at R² = 1.1 to 1.9 for ψ0 = 1.2 to 0.5: docs/averaging.md), for ψ0
    on both sides of π/4; both forms warn there, each naming the other as the closer one on its side."""
    theta_c = crossover_theta0()
    for R2, closer in ((0.5, "beat"), (3.0, "pendulum")):
        theta0 = theta_c * math.sqrt(R2)
        with pytest.warns(pm.ClosedFormRegimeWarning) as caught:
            pm.pendulum_prediction(BODY, theta0, 0.5)
            pm.beat_prediction(BODY, theta0)
        messages = [str(w.message) for w in caught]
        assert len(messages) == 2
        for msg in messages:
            named = float(msg.split("R^2 = 1, is at theta0 ~ ")[1].split("pi")[0]) * math.pi
            assert named == pytest.approx(theta_c, rel=5e-2), msg
            assert (f"the {'pendulum (pendulum_prediction)' if closer == 'pendulum' else 'linear beat'}" in
                    msg.split("for this body and eps; ")[1]), msg
        for psi0 in (0.5, 1.2):
            ref = ode(theta0, psi0)
            e_pend = relative_errors(pendulum(theta0, psi0), ref)["slow_period"]
            e_beat = relative_errors(beat(theta0), ref)["slow_period"]
            assert (abs(e_beat) < abs(e_pend)) == (closer == "beat"), (R2, psi0, e_pend, e_beat)


@pytest.mark.slow
def test_both_ends_against_the_map():
    """The averaged map (order 1, the region tables of each release's energy) against the ODE and the closed form of
    each end: at 0.005π the map and the beat, at 0.1π the map and the pendulum, all within the O(ε) of the map
    (5e-3 at ε = 1e-2) or the closed form's regime bound; the map holds on both sides of the crossover."""
    for theta0, form in ((0.005 * math.pi, beat), (0.1 * math.pi, lambda th: pendulum(th, 0.5))):
        with warnings.catch_warnings():
            warnings.simplefilter("ignore", av.AveragingValidityWarning)
            pred = av.predict_slow_motion(BODY, theta0, 0.5, 3.0 * BEAT, order=1)
        closed = form(theta0)
        R2 = closed.regime_ratio
        bound = 1.0 / math.sqrt(1.0 - R2) - 1.0 if R2 < 1.0 else math.sqrt(1.0 + 1.0 / R2) - 1.0
        assert abs(relative_errors(pred, ode(theta0, 0.5))["slow_period"]) <= 5e-3
        assert abs(closed.slow_period / pred.slow_period - 1.0) <= bound + EPS
