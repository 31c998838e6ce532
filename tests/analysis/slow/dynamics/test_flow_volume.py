"""The flow's volume along direct runs (:mod:`rocknroller.analysis.slow.dynamics.flow_volume`): the integrator's L̇
against the exact symbolic divergence, its maxima against the exact map's step, and Livšic's test and the smooth fit
on data whose answer is known (a function of the point against one with a drift), then on the chaotic sea."""

from __future__ import annotations

import math
from fractions import Fraction

import numpy as np
import pytest

from rocknroller.analysis.hierarchy.measure import flow_divergence
from rocknroller.analysis.model.body import Body
from rocknroller.analysis.slow.dynamics import flow_volume as fv
from rocknroller.analysis.slow.map.maps import EVALUATION_ULPS, ExactMap

U = float(np.finfo(float).eps)
THETA0 = 0.9 * math.pi


def test_divergence_against_the_symbolic_one():
    """The integrator's L̇ is div f: L(h)/h at the witness state of analysis.hierarchy.measure against the exact
    divergence there, to h |d div/dt|/|div| ≲ 1e-5 (h = 1e-6; the rate of change of div is ≲ 10 a unit time)."""
    member = Body.paper(0.03)
    gamma, omega = (Fraction(2, 7), Fraction(3, 7), Fraction(-6, 7)), (Fraction(1), Fraction(2), Fraction(-1))
    a, I1, I2, I3, g = (Fraction(v) for v in member.params)
    exact = float(flow_divergence("rock'n'roller").at(gamma, omega, (0, 0, -a, I1, I2, I3, g)))
    ta = fv._divergence_integrator()
    ta.time, ta.pars[:] = 0.0, member.params
    ta.state[:] = [*(float(v) for v in gamma + omega), 0.0]
    ta.propagate_until(1e-6)
    assert exact != 0.0 and abs(ta.state[6] / 1e-6 - exact) <= 1e-5 * abs(exact)


def test_divergence_run_follows_the_map():
    """The run's maxima are the map's iterates: the first one against ExactMap's step, to both evaluations' error."""
    F = ExactMap(Body.paper(0.0), THETA0, 0.03)
    x0 = [0.02, 5e-4, 1.0]
    d = fv.divergence_run(F, x0, 1).points[0] - F(x0)
    d[2] = (d[2] + math.pi) % (2 * math.pi) - math.pi
    assert np.max(np.abs(d)) <= 2 * EVALUATION_ULPS * U * 4 * math.pi


def test_recurrence_spread_separates_a_density_from_a_drift():
    """Values that are a function of the point give |ΔL| ∝ radius; a drift μ k added (mixed dynamics' signature)
    gives |ΔL| ≥ μ × min_separation."""
    rng = np.random.default_rng(2)
    x = rng.random((20000, 3)) * [1.0, 1.0, 2 * math.pi]
    f = np.sin(3 * x[:, 0]) + x[:, 1] ** 2 + 0.1 * np.cos(x[:, 2])
    small, large = (fv.recurrence_spread(x, f, r, min_separation=100) for r in (0.02, 0.08))
    assert small.pairs > 100 and small.median < 0.5 * large.median
    drift = fv.recurrence_spread(x, f + 1e-3 * np.arange(len(f)), 0.02, min_separation=100)
    assert drift.median > 10 * small.median and drift.median >= 0.1


@pytest.mark.slow
def test_chaotic_orbit_keeps_its_volume():
    """The measurement (docs/theory/hierarchy_measure_numbers.md) as a test: in the chaotic sea at θ0 = 0.9π,
    ε = 0.03, L stays bounded (its range after 2·10⁴ rocks within twice that after 2000; a contraction μ ≠ 0 would
    grow it tenfold) and close returns carry equal L (|ΔL| falls with the radius)."""
    F = ExactMap(Body.paper(0.0), THETA0, 0.03)
    run = fv.divergence_run(F, [0.0, 0.0, 0.002], 20000)
    assert run.max_abs() <= 2 * run.max_abs(2000)
    near, far = (fv.recurrence_spread(run.points, run.log_volume, r) for r in (0.01, 0.03))
    assert near.pairs > 100 and near.median < 0.6 * far.median


def test_section_fit_separates_a_density_from_a_drift():
    """A smooth function of the section point is fitted to far below its size; the same with a drift μ k is not."""
    rng = np.random.default_rng(3)
    x = rng.random((4000, 3)) * [0.1, 0.01, 2 * math.pi]
    f = 1e-3 * np.exp(5 * x[:, 0]) * np.cos(x[:, 2] - 100 * x[:, 1])
    rms, _ = fv.section_fit(x, f, 8, 4)
    drift_rms, _ = fv.section_fit(x, f + 1e-6 * np.arange(len(f)), 8, 4)
    assert rms < 1e-4 * np.std(f) and drift_rms > 0.1 * np.std(1e-6 * np.arange(len(f)))


@pytest.mark.parametrize("n", [0, fv.MAX_ROCKS + 1, 2.5, True])
def test_divergence_run_checks_its_length_first(n):
    """The run's record grows with n_rocks: a length outside [1, MAX_ROCKS] is refused before any integration."""
    with pytest.raises(ValueError, match="n_rocks"):
        fv.divergence_run(ExactMap(Body.paper(0.0), THETA0, 0.03), [0.0, 0.0, 0.002], n)
