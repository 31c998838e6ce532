"""The start of the slow map: any initial state carried to its first maximum of θ (``slow_orbit.first_maximum``)."""

from __future__ import annotations

import math

import pytest

from rocknroller.analysis.body import Body
from rocknroller.analysis.invariants import energy
from rocknroller.analysis.slow_orbit import first_maximum, rest_energy
from rocknroller.numerics.equations import EulerState
from rocknroller.numerics.integrate import simulate

BODY = Body.paper(1e-3)


def test_release_from_rest_is_its_own_first_maximum():
    start = EulerState(theta=0.9 * math.pi, psi=0.3, phi=-0.2)
    fm = first_maximum(BODY, start)
    assert (fm.t, fm.QR, fm.QJ, fm.psi, fm.phi, fm.theta) == (0.0, 0.0, 0.0, 0.3, -0.2, 0.9 * math.pi)
    assert fm.E == rest_energy(BODY, 0.9 * math.pi)


def test_start_with_velocity_reaches_the_maximum_found_by_scipy():
    """heyoka's first maximum against DOP853's (rtol 3e-14), an independent integrator: both locate the root of
    dγ3/dt to ~1e-12 in t; the invariants there agree to the DOP853 run's own energy error scale."""
    start = EulerState(theta=0.7 * math.pi, psi=0.4, theta_dot=0.3, phi_dot=0.2, psi_dot=-0.1)
    fm = first_maximum(BODY, start)
    assert fm.t > 0.0
    ref = simulate(BODY, start, 2.0 * fm.t + 1.0, method="scipy", samples=False).maxima
    assert fm.t == pytest.approx(float(ref.t[0]), abs=1e-9)
    for name in ("theta", "QR", "QJ", "psi", "phi"):
        assert getattr(fm, name) == pytest.approx(float(getattr(ref, name)[0]), abs=1e-9), name
    y0 = start.to_body_state()
    assert fm.E == float(energy(BODY, y0[0:3], y0[3:6]))


def test_a_start_without_oscillation_is_refused():
    # from rest at the bottom: no motion at all (simulate refuses it, naming the state)
    with pytest.raises(ValueError):
        first_maximum(BODY, EulerState(theta=0.0))
