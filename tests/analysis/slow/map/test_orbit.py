"""The start of the slow map: any initial state carried to its first maximum of θ (``slow.family.first_maximum``)."""

from __future__ import annotations

import math

import pytest

from rocknroller.analysis.model.body import Body
from rocknroller.analysis.model.equations import EulerState
from rocknroller.analysis.model.invariants import energy
from rocknroller.analysis.slow.map.family import first_maximum, rest_energy
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


def test_maximum_located_when_a_step_ends_where_the_event_function_is_flat():
    """A node of the spindle tables of a release from 0.03π (θ between 0.02 and 0.054 rad): the Taylor step that
    passes the maximum ends where dγ3/dt is nearly flat, and Newton from the step's end left the step (the dense
    output, a polynomial, extrapolated to 1e17: NaN in 76 of the table's 8192 nodes).  Kept inside the step's
    bracket, the orbit ends at the next maximum: T_θ and Δψ mod π as the quadrature (paper eqs. T_theta,
    Delta_psi) gives them within its tolerance DEFAULT_RTOL, and finite ε-responses."""
    import numpy as np

    from rocknroller.analysis.model.diagnostics import wrap_angle
    from rocknroller.analysis.routh.quadrature import DEFAULT_RTOL, precession
    from rocknroller.analysis.slow.map.orbit import first_order_steps

    sym = Body.paper(0.0)
    E, QR, QJ = rest_energy(sym, 0.03 * math.pi), 0.09587927499116591, 0.03078631520695371
    step = first_order_steps(BODY, E, QR, QJ, [0.0, 1.0, 2.0])
    ref = precession(E, QR, QJ, sym)
    np.testing.assert_allclose(step.T, float(ref.T_theta), rtol=DEFAULT_RTOL, atol=0.0)
    assert np.all(np.abs(wrap_angle(step.dpsi - float(ref.delta_psi), math.pi)) <= DEFAULT_RTOL * abs(ref.delta_psi))
    assert all(np.all(np.isfinite(v)) for v in step.d.values())


def test_a_release_whose_energy_is_zero_is_refused_as_no_motion():
    """θ0 = 1e-9: g a (1 − cos θ0) is 0 in double precision (the range check of test_cli_slow passes it)."""
    from rocknroller.analysis.slow import prediction as av

    with pytest.raises(ValueError, match="no motion to average over"):
        av.predict_slow_motion(BODY, 1e-9, 0.3, 100.0)


def test_a_start_near_steady_rolling_is_refused_with_its_distance():
    """Steady rolling at 0.4π (paper eq. om2om3) nudged by θ̇0 = 0.05: θ oscillates, but within (E − min U)/E =
    2.5e-3 of steady rolling, where the double quadrature of the first-maximum search is unresolved (its mpmath
    reference takes over) and the region tables (δ ≥ 0.05) do not reach: refused with that distance before any
    table is built (build=False would otherwise fail for want of one)."""
    from rocknroller.analysis.routh.steady_rolling import boundary_distance, steady_rolling_omega3
    from rocknroller.analysis.slow import prediction as av
    from rocknroller.analysis.slow.map.region import DELTA_MIN_DEFAULT

    theta0, phi_dot = 0.4 * math.pi, 0.5
    omega3 = steady_rolling_omega3(BODY.symmetric(), theta0, math.sin(theta0) * phi_dot)
    start = EulerState(theta0, 0.0, 0.0, 0.05, phi_dot, omega3 - math.cos(theta0) * phi_dot)
    fm = first_maximum(BODY, start)
    delta = float(boundary_distance(BODY, fm.E, fm.QR, fm.QJ))
    assert fm.t > 0.0 and 0.0 < delta < 0.1 * DELTA_MIN_DEFAULT
    with pytest.raises(av.AveragingRangeError, match=rf"distance \(E - min U\)/E = {delta:.3g} from steady rolling"
                                                     rf".* cover distances >= {DELTA_MIN_DEFAULT:g}"):
        av.predict_slow_motion(BODY, start, t_end=100.0, build=False)


def test_t_end_over_the_maps_limit_is_refused_before_any_table_is_built():
    """A start with velocity and t_end = 1e12: the map's limit (MAX_MAXIMA maxima) is checked before its tables are
    built (build=False: with none cached the refusal is the t_end's, not the missing table's)."""
    from rocknroller.analysis.slow import prediction as av

    start = EulerState(0.9 * math.pi, 0.0, 0.3, 0.0, 0.01, 0.0)
    with pytest.raises(ValueError, match=r"^t_end must be a finite number in \(0, "):
        av.predict_slow_motion(BODY, start, t_end=1e12, build=False)
