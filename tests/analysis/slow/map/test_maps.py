"""The slow map and the exact map as objects (issue 32, item 20): their Jacobians against central differences of the
maps themselves (the kernel's tangent; the variational equations of the direct ODE), the inverse by the reversing
symmetry, what the reversor implies for the volume, iterate against repeated calls, the periodic orbits found with
the exact tangents against those found with central differences, and bad input.

Paper body, releases from rest at θ0 = 0.95π; ε = 1e-2 (K = 4.3, past the period doubling: regular and chaotic
orbits side by side), starts taken from the map's own orbits at a regular (ψ0 = π/4) and a chaotic (ψ0 = 0.1)
release (tests/analysis/slow/test_chaos_map.py's cases).
"""

from __future__ import annotations

import math

import numpy as np
import pytest

from rocknroller.analysis.model.body import Body
from rocknroller.analysis.slow.map import maps as mp
from rocknroller.analysis.slow.dynamics import periodic_orbits as po
from rocknroller.analysis.slow.dynamics.chaos import tangent_scale
from rocknroller.analysis.slow.map.limits import MAX_MAXIMA
from rocknroller.analysis.slow.map.maps import EXACT_MAX_STEPS, ExactMap, SlowMap, reverse
from rocknroller.analysis.slow.map.family import _central_difference
from rocknroller.analysis.slow.dynamics.period_doubling import _central_jacobian
from rocknroller.analysis.slow.map.table import load_or_build_table
from tests.roundoff import assert_within, propagated_bound, u

BODY = Body.paper(0.0)
THETA0 = 0.95 * math.pi
EPS = 1e-2
#: Starts off the critical lines inside the release table (|v| ≤ 8e-5 across the kick direction): the first inside the
#: layer of W (width ~2/|∇W(0)| ≈ 3e-3), the second further out.
START = np.array([1e-3, -2e-5, 1.0])
OUTER = np.array([-4e-3, 1e-4, 4.0])
#: The maps' evaluation error (maps.EVALUATION_ULPS ulp of 4π: four times the measured scatter of either map).
ETA = mp.EVALUATION_ULPS * float(np.finfo(float).eps) * 4.0 * math.pi


@pytest.fixture(scope="module")
def slow1() -> SlowMap:
    return SlowMap(BODY, THETA0, EPS, 1)  # order 1 given: the default is 2 (default_order)


@pytest.fixture(scope="module")
def slow2() -> SlowMap:
    """Order 2: the second-order table is built once per cache (~60 s on 2 cores), then read."""
    return SlowMap(BODY, THETA0, EPS, 2, workers=2)


@pytest.fixture(scope="module")
def exact() -> ExactMap:
    return ExactMap(BODY, THETA0, EPS)


def orbit_points(F: SlowMap, psi0: float, picks: tuple[int, ...]) -> list[np.ndarray]:
    """Maxima k of the map's orbit released from rest at ψ0 (Q = 0, Θ = 2ψ0)."""
    orbit = F.iterate([0.0, 0.0, 2.0 * psi0], max(picks))
    return [orbit[k] for k in picks]


def steps() -> np.ndarray:
    """h of the differences: a thousandth of the phase scale, Q by 1/S (S = |∇W(0)|, the twist), Θ by 1."""
    S = tangent_scale(load_or_build_table(BODY, THETA0))
    return np.array([1e-3 / S, 1e-3 / S, 1e-3])


def central(F, x: np.ndarray, j: int, h: float) -> np.ndarray:
    """(F(x + h e_j) − F(x − h e_j))/(2h)."""
    e = np.zeros(3)
    e[j] = h
    return (F(x + e) - F(x - e)) / (2.0 * h)


def derivative_check(F, x: np.ndarray, J: np.ndarray, eta: np.ndarray) -> None:
    """|J − D(h)| within the error of D(h), column by column: D(h) = f' + (h²/6) f''' + O(h⁴) + noise, the noise of a
    difference of two evaluations each within η (componentwise) over 2h being ≤ η/h.  The truncation (h²/6) f''' is
    measured from the same differences: D(h) − D(h/2) = (h²/8) f''' + O(h⁴), so (h²/6) f''' = (4/3)(D(h) − D(h/2)),
    up to the noise of both, ≤ 3η/h.  Bound: twice the measured truncation (the O(h⁴) rest and f''' varying over
    [x − h, x + h]) plus η/h plus the measurement's own noise (4/3)·3η/h·2 = 8η/h: 2·(4/3)|D(h) − D(h/2)| + 9η/h.
    The check has teeth: the bound is below 1e-4 of the column."""
    for j, h in enumerate(steps()):
        D, D2 = central(F, x, j, h), central(F, x, j, 0.5 * h)
        bound = 2.0 * (4.0 / 3.0) * np.abs(D - D2) + 9.0 * eta / h
        assert_within(J[:, j] - D, bound, f"column {j}", value=D)
        assert np.max(bound) < 1e-4 * np.max(np.abs(D))  # a tangent off by 1e-4 of its column fails


def slow_eta(F: SlowMap, x: np.ndarray) -> np.ndarray:
    """The slow step's noise as a function of its start, componentwise: the implicit kick stops within 1e-13 of the
    kick (analysis/slow/_kernel.c KICK_RTOL; the kick is ≤ |F(x) − x|) plus a few ulp, and the chart's rotation adds
    2 ulp of |Q| each way; 8 ulp in all."""
    y = F(x)
    return 1e-13 * np.abs(y - x) + 8.0 * np.spacing(np.maximum(np.abs(y), np.abs(x)))


@pytest.mark.parametrize("order", [1, 2])
@pytest.mark.parametrize("psi0", [math.pi / 4, 0.1])
def test_slow_jacobian_is_the_derivative_of_the_map(slow1, slow2, order, psi0):
    """The kernel's tangent map of one step, turned into (Q_R, Q_J, Θ), against central differences of ``__call__`` at
    two points of a regular and of a chaotic orbit, first and second order (:func:`derivative_check`)."""
    F = slow1 if order == 1 else slow2
    for x in orbit_points(F, psi0, (3, 17)):  # measured: |J − D(h)| ≤ 1.6e-6 of the column, D(h)'s truncation
        derivative_check(F, x, F.jacobian(x), slow_eta(F, x))


def test_exact_jacobian_by_variational_equations(exact):
    """The exact map's Jacobian (the variational equations through the rock, with the start's and the event's
    dependence on x) against central differences of the exact map, whose evaluations are within ETA
    (:func:`derivative_check`): at a start off the critical lines, inside the layer of W."""
    x = START.copy()
    derivative_check(exact, x, exact.jacobian(x), np.full(3, ETA))  # measured ≤ 1.1e-7 of the column (D's own)


def inverse_bound(F, y: np.ndarray) -> np.ndarray:
    """|F⁻¹(F(x)) − x| for F⁻¹(y) = R F(R y): F(x) is within η of the exact image, and R F(R ·) carries that error by
    |DF(R y)| and adds its own η: η + |DF(R y)| η (componentwise, to first order), η = ETA on every component."""
    eta = np.full(3, ETA)
    return eta + np.abs(F.jacobian(reverse(y))) @ eta


@pytest.mark.parametrize("kind", ["slow", "exact"])
def test_inverse_by_the_reversing_symmetry(slow1, exact, kind):
    """inverse(F(x)) = x (and F(inverse(x)) = x) to the first-order bound :func:`inverse_bound`, at a start inside
    the layer and one further out; and the inverse is no identity: it undoes a step of ~1 rad in Θ."""
    F = slow1 if kind == "slow" else exact
    for x in (START.copy(), OUTER.copy()):
        y = F(x)
        assert_within(F.inverse(y) - x, inverse_bound(F, y), "inverse(F(x))", value=x)
        assert_within(F(F.inverse(x)) - x, inverse_bound(F, x), "F(inverse(x))", value=x)
        assert abs(y[2] - x[2]) > 0.1


#: Steps of the fourth-order differences that bound a Jacobian's error (period_doubling's: in Q well inside the layer
#: of W, so the h⁴ truncation is ~1e-12 relative; in Θ).
H4 = np.array([1e-6, 1e-6, 1e-5])


def jacobian_error(F, x: np.ndarray, J: np.ndarray) -> np.ndarray:
    """A bound on |J − DF(x)| entrywise, from an independent determination: fourth-order central differences D₄(h)
    err by ≤ 1.5 η/h (the stencil's weights 18/12 over h, evaluations within η = ETA) plus their truncation, which the
    same stencil at 2h measures: D₄(2h) − D₄(h) ≈ 15 c h⁴, so |D₄(2h) − D₄(h)| is 15 times that; then
    |J − DF| ≤ |J − D₄(h)| + 1.5 η/h + |D₄(2h) − D₄(h)|."""
    def d4(h: np.ndarray) -> np.ndarray:
        return np.stack([_central_difference(lambda s: F(x + s * np.eye(3)[j]), 0.0, h[j]) for j in range(3)], axis=1)

    D = d4(H4)
    return np.abs(J - D) + 1.5 * ETA / H4[None, :] + np.abs(d4(2.0 * H4) - D)


@pytest.mark.parametrize("kind", ["slow", "exact"])
def test_volume_along_the_reversor(slow1, exact, kind):
    """What the reversible 3-d map preserves.  R F R = F⁻¹ gives DF(x) R DF(R F(x)) R = 1, so with det R = 1:
    det DF(x) · det DF(R F(x)) = 1 — but not det DF = 1: neither map preserves volume in (Q_R, Q_J, Θ) (det DF ≈ 1.001
    at the start, far outside the error of the determinant).  That error, to first order: |δ det J| ≤ Σ|adj(J)ᵀ||δJ|,
    |δJ| from :func:`jacobian_error`."""
    F = slow1 if kind == "slow" else exact
    x = START.copy()
    A, B = F.jacobian(x), F.jacobian(reverse(F(x)))

    def det_error(J: np.ndarray, at: np.ndarray) -> float:
        adj = np.linalg.det(J) * np.linalg.inv(J).T
        return float(np.sum(np.abs(adj) * jacobian_error(F, at, J)))

    dA, dB = np.linalg.det(A), np.linalg.det(B)
    eA, eB = det_error(A, x), det_error(B, reverse(F(x)))
    assert abs(dA * dB - 1.0) <= eA * abs(dB) + eB * abs(dA) + eA * eB
    assert abs(dA - 1.0) > 10.0 * eA


def test_slow_iterate_equals_repeated_calls(slow1, slow2):
    """``iterate`` (the kernel in one call, in the chart) against n calls (each through the chart's rotation and the
    Θ continuation): each call differs from the kernel's step by the rotation's round-off, ≤ 4 u |Q| per component
    (two two-term dot products) and 2 ulp of Θ; carried along the orbit by the Jacobians (tests.roundoff's
    propagated_bound, first order) with a margin of 2.  Regular and chaotic, 12 steps; n = 0 is the start alone."""
    for F in (slow1, slow2):
        for psi0 in (math.pi / 4, 0.1):
            x = np.array([0.0, 0.0, 2.0 * psi0])
            orbit = F.iterate(x, 12)
            calls = [x]
            for _ in range(12):
                calls.append(F(calls[-1]))
            calls = np.array(calls)
            J = np.array([F.jacobian(p) for p in calls[:-1]])
            q = np.max(np.abs(calls[:, :2]), axis=1)
            local = np.stack([4 * u * q[1:], 4 * u * q[1:], 2 * np.spacing(np.abs(calls[1:, 2]))], axis=1)
            assert_within(orbit[1:] - calls[1:], 2.0 * propagated_bound(J, local), "iterate vs calls",
                          value=calls[1:])
            assert orbit.shape == (13, 3) and np.array_equal(orbit[0], x)
    assert np.array_equal(slow1.iterate(x, 0), x[None, :])


def test_exact_iterate_equals_repeated_calls(exact):
    """The exact map's iterate is its calls, bit for bit (one direct run per step)."""
    x = START.copy()
    orbit = exact.iterate(x, 2)
    assert np.array_equal(orbit, np.array([x, exact(x), exact(exact(x))]))


@pytest.mark.parametrize("period, eps_factor, start", [(1, 0.8, (1e-4, 0.0, math.pi + 0.05)), (2, 1.2, None)])
def test_periodic_orbits_agree_with_central_differences(monkeypatch, period, eps_factor, start):
    """Newton with the kernel's exact tangent finds the orbits that Newton with fourth-order central differences
    (the method before; steps 1e-6 in u, v and 1e-5 in Θ) finds, at test_periodic_orbits' cases: the points within
    ‖(DG)⁻¹‖∞ (DG = DF + 1) times the two residuals (both Newton solutions have ‖G‖ ≤ their residual), the residues
    within what the differences' error allows: each entry within 1.5 η/h (the stencil's weights, 18/12, over h; its
    h⁴ truncation is ~1e-12 relative) and R = (3 − tr M)/4 with M = J or J²: |δR| ≤ Σ|δJ|/4 (period 1), and
    |δ tr J²| = |tr(J δJ + δJ J)| ≤ 2 max|J| Σ|δJ| (period 2).  Newton needs no more iterations with the exact
    tangent."""
    eps = eps_factor * 4.0 / abs(SlowMap(BODY, THETA0, EPS).kappa)
    new = po.periodic_orbit(BODY, THETA0, eps, period, start=start)
    monkeypatch.setattr(po._Problem, "jacobian", lambda self, x: _central_jacobian(self.step, x))
    old = po.periodic_orbit(BODY, THETA0, eps, period, start=start)
    P = po._Problem(BODY, THETA0, eps, "slow", 1, 1)
    J = P.B.T @ P.F.jacobian(P.B @ new.points[0]) @ P.B
    cond = np.abs(np.linalg.inv(J + np.eye(3))).sum(axis=1).max()
    d = new.points[0] - old.points[0]
    assert np.max(np.abs(d)) <= cond * (new.residual + old.residual)
    dJ = np.sum(1.5 * ETA / np.array([1e-6, 1e-6, 1e-5]) * np.ones((3, 3)))
    dR = dJ / 4.0 if period == 1 else 2.0 * np.abs(J).max() * dJ / 4.0
    assert abs(new.residue - old.residue) <= dR
    assert new.iterations <= old.iterations


def test_bad_input(slow1, exact):
    for F in (slow1, exact):
        for x in ([1.0, 2.0], [[0.0, 0.0]], [0.0, math.nan, 1.0], "abc"):  # an array (..., 3): test_map_arrays.py
            with pytest.raises(ValueError, match=r"x must be three finite numbers \(Q_R, Q_J, Theta\)"):
                F(x)
            with pytest.raises(ValueError, match="x must be"):
                F.jacobian(x)
            with pytest.raises(ValueError, match="x must be"):
                F.inverse(x)
        for n in (-1, 1.5, True, "3"):
            with pytest.raises(ValueError, match=r"n must be an integer in \[0, "):
                F.iterate([0.0, 0.0, 1.0], n)
    with pytest.raises(ValueError, match=rf"n must be an integer in \[0, {MAX_MAXIMA}\] \(MAX_MAXIMA\)"):
        slow1.iterate([0.0, 0.0, 1.0], MAX_MAXIMA + 1)
    with pytest.raises(ValueError, match=rf"n must be an integer in \[0, {EXACT_MAX_STEPS}\] \(EXACT_MAX_STEPS\)"):
        exact.iterate([0.0, 0.0, 1.0], EXACT_MAX_STEPS + 1)
    top = BODY.I3 / BODY.I1 - 1.0
    for cls in (SlowMap, ExactMap):
        for eps in (-1e-3, math.nan, top, 1.0, "x"):
            with pytest.raises(ValueError, match=r"eps must lie in \[0, "):
                cls(BODY, THETA0, eps)
    with pytest.raises(ValueError, match="order must be 1 or 2"):
        SlowMap(BODY, THETA0, EPS, 3)
    with pytest.raises(ValueError, match="theta0 must lie in"):
        SlowMap(BODY, 0.5 * math.pi, EPS)
    with pytest.raises(ValueError, match="theta0 must lie in"):
        ExactMap(BODY, math.pi, EPS)


def test_tangent_to_maximum_bad_input():
    from rocknroller.numerics.variational import tangent_to_maximum

    y0 = np.array([0.0, 0.1, 0.99498743710662, 0.0, 0.0, 0.0])
    with pytest.raises(ValueError, match="y0 and w0 must be 6 finite numbers"):
        tangent_to_maximum(BODY, y0[:5], np.ones(6), 0.0, 1.0)
    with pytest.raises(ValueError, match="t_after"):
        tangent_to_maximum(BODY, y0, np.ones(6), 2.0, 1.0)


@pytest.mark.parametrize("body", ["body", None, 3.0, Body.chaplygin_ball(0.3, 0.35, 0.4),
                                  Body.paper(1e-3).as_loaded_sphere()])
@pytest.mark.parametrize("cls", [SlowMap, ExactMap])
def test_a_map_refuses_what_is_not_a_body_in_one_clear_error(cls, body):
    """rr.SlowMap('body', ...) gave an AttributeError traceback; a LoadedSphere would have been read as the paper's
    body (its `a` refused deep inside): both are ValueErrors naming what was given."""
    with pytest.raises(ValueError, match="body must be a rocknroller Body"):
        cls(body, 0.95 * math.pi, 1e-3)


def test_a_complex_point_is_refused_not_cast():
    """A complex x was cast to its real part with only a ComplexWarning."""
    m = SlowMap(Body.paper(1e-3), 0.95 * math.pi, 1e-3, order=1)
    with pytest.raises(ValueError, match="x must be three finite numbers"):
        m(np.array([1e-3, 0.0, 0.3 + 1e-3j]))


def test_huge_angles_are_refused_past_a_stated_bound(capsys):
    """slow --psi0 1e14 flipped the verdict, 1e15 gave an empty prediction with exit 0, and the maps returned
    Theta = 1e17 unchanged: past ANGLE_MAX an angle is refused, in the API and on the command line."""
    from rocknroller.analysis.slow.map.limits import ANGLE_MAX
    from rocknroller.analysis.slow.prediction import predict_slow_motion
    from rocknroller.cli import main

    body = Body.paper(1e-3)
    m = SlowMap(body, 0.95 * math.pi, 1e-3, order=1)
    with pytest.raises(ValueError, match="Theta must be a finite angle within"):
        m(np.array([1e-3, 0.0, 1e17]))
    with pytest.raises(ValueError, match="psi0 must be a finite angle within"):
        predict_slow_motion(body, 0.95 * math.pi, 2 * ANGLE_MAX, 100.0, order=1)
    assert predict_slow_motion(body, 0.95 * math.pi, ANGLE_MAX, 100.0, order=1).series.t.size > 0
    assert main(["slow", "--order", "1", "--psi0", "1e15"]) == 2
    assert "--psi0 must be a finite angle within [-1e+06, 1e+06]" in capsys.readouterr().err


@pytest.mark.parametrize("order", [1, 2])
def test_a_releases_prediction_gives_its_map_and_start(order):
    """pred.start was None for a release and nothing said how to get the map's start: SlowMap.from_prediction gives
    the map and x0, whose orbit is the prediction's series (iterate includes x0, run and the series do not)."""
    from rocknroller.analysis.slow.prediction import predict_slow_motion

    pred = predict_slow_motion(Body.paper(1e-3), 0.95 * math.pi, 0.3, 100.0, order=order)
    F, x0 = SlowMap.from_prediction(pred)
    assert F.order == order and x0[2] == 0.6 and not x0[:2].any()
    n = pred.series.t.size
    orbit = F.iterate(x0, n)
    np.testing.assert_array_equal(orbit[1:, :2], np.column_stack([pred.series.QR, pred.series.QJ]))
    run = F.run(x0, 100.0)
    np.testing.assert_array_equal(run.QR, pred.series.QR)
    assert "max_steps" not in {n for n in dir(SlowMap) if not n.startswith("_")}


def test_from_prediction_refuses_a_start_with_velocity():
    from rocknroller.analysis.model.equations import EulerState
    from rocknroller.analysis.slow.prediction import predict_slow_motion

    pred = predict_slow_motion(Body.paper(1e-3), EulerState(0.95 * math.pi, 0.0, 0.3, 0.0, 0.01, 0.0), t_end=100.0)
    with pytest.raises(ValueError, match="a start with velocity is predicted on the region tables"):
        SlowMap.from_prediction(pred)
