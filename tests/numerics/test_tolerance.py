"""The accuracy knob of the direct runs (numerics/run_limits.py): ``tol`` through simulate, run_batch, Job and
run_ensemble; its default is heyoka's, to the bit; a looser one lowers the Taylor order and stays within the energy
bound derived at that tolerance; bad values refused naming ``tol``."""

from __future__ import annotations

import math
import warnings

import numpy as np
import pytest

import rocknroller as rr
from rocknroller.numerics.ensembles.batch import run_batch
from rocknroller.numerics.ensembles.ensemble import Job, run_ensemble
from rocknroller.numerics.events import THETA_MIN
from rocknroller.numerics.integrate import heyoka_integrator
from rocknroller.numerics.run_limits import DEFAULT_TOL, TOL_MAX, check_tol, theta_min

BODY = rr.Body.paper(1e-3)
START = rr.EulerState(0.95 * math.pi, psi=0.3)


def _same(a: rr.TurningPointRun, b: rr.TurningPointRun) -> bool:
    return (all(np.array_equal(getattr(x, n), getattr(y, n)) for x, y in ((a.maxima, b.maxima), (a.minima, b.minima))
                for n in ("t", "theta", "phi", "psi", "QR", "QJ", "states"))
            and a.energy_rel_error == b.energy_rel_error and a.n_steps == b.n_steps)


def test_the_default_is_heyokas_to_the_bit():
    """No tol and tol = ε give the same run, bit for bit: scalar, in lanes, and as a Job."""
    assert DEFAULT_TOL == float(np.finfo(float).eps) and heyoka_integrator().tol == DEFAULT_TOL
    assert _same(rr.simulate(BODY, START, 60.0, samples=False), rr.simulate(BODY, START, 60.0, samples=False,
                                                                             tol=DEFAULT_TOL))
    (default,), (explicit,) = run_batch([(BODY, START, 60.0)]), run_batch([(BODY, START, 60.0)], tol=DEFAULT_TOL)
    assert _same(default, explicit)
    assert Job(BODY, START, 60.0) == Job(BODY, START, 60.0, DEFAULT_TOL)


@pytest.mark.parametrize("tol, order", [(1e-11, 14), (1e-8, 11), (TOL_MAX, 8)])
def test_a_looser_tolerance_lowers_the_order_within_its_energy_bound(tol, order):
    """heyoka's order p = ⌈−ln(tol)/2⌉ + 1; the run's energy error grows above the default's but stays within
    energy_error_bound(tol, n_steps), and the turning points are the default run's."""
    assert heyoka_integrator("double", tol).order == order == math.ceil(-math.log(tol) / 2) + 1
    with warnings.catch_warnings():
        warnings.simplefilter("error")  # an AccuracyWarning fails the test
        loose = rr.simulate(BODY, START, 300.0, samples=False, tol=tol)
    exact = rr.simulate(BODY, START, 300.0, samples=False)
    assert loose.tolerance == tol and exact.tolerance == DEFAULT_TOL
    assert exact.energy_rel_error < loose.energy_rel_error <= loose.energy_tolerance
    assert len(loose.maxima) == len(exact.maxima) and len(loose.minima) == len(exact.minima)


def test_the_smallest_tilt_resolved_scales_with_tol():
    """theta_min(tol) = THETA_MIN · tol/ε: a release from rest at θ0 = 1e-4 rad runs at the default tolerance, and is
    refused before any work at tol = 1e-6 (theta_min = 5.1e-4 rad), naming the bound."""
    assert theta_min(DEFAULT_TOL) == THETA_MIN and theta_min(1e-6) == pytest.approx(THETA_MIN * 1e-6 / DEFAULT_TOL)
    start = rr.EulerState(1e-4)
    assert len(rr.simulate(BODY, start, 20.0, samples=False).maxima) > 0
    with pytest.raises(ValueError, match=r"theta0=0.0001: .*below theta_min\(tol\) = 0.000512 rad"):
        rr.simulate(BODY, start, 20.0, samples=False, tol=1e-6)
    with pytest.raises(ValueError, match=r"theta_min\(tol\)"):
        Job(BODY, start, 20.0, 1e-6)


BAD = [0.0, -1e-9, math.nan, math.inf, DEFAULT_TOL / 2, 2e-6, 1.0, "1e-9", True, None]


@pytest.mark.parametrize("tol", BAD, ids=repr)
def test_bad_tol_is_refused_naming_it(tol):
    message = r"tol must be a number in \[2.220446049250313e-16, 1e-06\]"
    for call in (lambda: check_tol(tol), lambda: Job(BODY, START, 10.0, tol), lambda: run_batch([(BODY, START, 10.0)],
                                                                                              tol=tol)):
        with pytest.raises(ValueError, match=message):
            call()
    if tol is not None:  # simulate's None is the default
        with pytest.raises(ValueError, match=message):
            rr.simulate(BODY, START, 10.0, tol=tol)


def test_tol_is_heyokas():
    with pytest.raises(ValueError, match="tol is heyoka's tolerance; method='scipy' takes rtol and atol"):
        rr.simulate(BODY, START, 10.0, method="scipy", tol=1e-9)
    ld_eps = float(np.finfo(np.longdouble).eps)
    if ld_eps < DEFAULT_TOL:  # 80-bit long double: its own epsilon is the floor
        with pytest.raises(ValueError, match=r"tol must be a number in \[1.0842021724855044e-19, 1e-06\]"):
            rr.simulate(BODY, START, 1.0, precision="extended", tol=ld_eps / 2)


def test_an_ensemble_batches_jobs_by_tolerance():
    """Jobs at two tolerances in one call: each job's summary is the one it gets alone in lanes at its tolerance."""
    jobs = [Job(BODY, rr.EulerState(0.95 * math.pi, psi=psi), 40.0, tol) for psi in (0.1, 0.5) for tol in (1e-9,
                                                                                                            DEFAULT_TOL)]
    mixed = run_ensemble(jobs, progress=False)
    for job, summary in zip(jobs, mixed):
        (alone,) = run_ensemble([job], progress=False)
        assert np.array_equal(summary.maxima.states, alone.maxima.states) and summary.n_steps == alone.n_steps
    assert mixed[0].energy_rel_error > mixed[1].energy_rel_error


def test_a_check_that_cannot_fail_is_not_passed_off_as_one():
    """At --tol 1e-6 over 10⁵ time units the energy bound was 2.6 (261 % of the energy): any error passed, so
    --strict could never fail.  Past ENERGY_BOUND_MAX the check says it cannot vouch for the run: an AccuracyError
    with strict, an AccuracyWarning without.  The run here: TOL_MAX over enough steps that the bound passes it."""
    from rocknroller.numerics.integrate import AccuracyError, AccuracyWarning
    from rocknroller.numerics.run_limits import ENERGY_BOUND_MAX, energy_error_bound

    body, start = rr.Body.paper(1e-3), rr.EulerState(0.95 * math.pi, 0.0, 0.3, 0.0, 0.0, 0.0)
    quiet = rr.simulate(body, start, 50.0, tol=TOL_MAX, samples=False)
    assert energy_error_bound(TOL_MAX, quiet.n_steps) <= ENERGY_BOUND_MAX  # short: the check still means something
    t_end = 50.0 * 2.0 * ENERGY_BOUND_MAX / energy_error_bound(TOL_MAX, quiet.n_steps)  # about twice the steps allowed
    with pytest.raises(AccuracyError, match="cannot vouch"):
        rr.simulate(body, start, t_end, tol=TOL_MAX, samples=False, strict=True)
    with pytest.warns(AccuracyWarning, match="cannot vouch"):
        run = rr.simulate(body, start, t_end, tol=TOL_MAX, samples=False)
    assert energy_error_bound(TOL_MAX, run.n_steps) > ENERGY_BOUND_MAX > run.energy_rel_error
