"""One orbit with three turned ε-responses (analysis/slow/map/harmonic.py) against three orbits from the three spin
angles (``first_order_steps``), and the symmetry it rests on, f(S y) = S f(y), as an identity in exact arithmetic."""

from __future__ import annotations

import math
import random
from fractions import Fraction

import numpy as np
import pytest

from rocknroller.analysis.model.body import Body
from rocknroller.analysis.model.equations import body_frame_rhs
from rocknroller.analysis.routh.turning_points import turning_points
from rocknroller.analysis.slow.map.family import rest_energy
from rocknroller.analysis.slow.map.harmonic import _harmonics, harmonic_steps
from rocknroller.analysis.slow.map.orbit import (FIRST_ORDER_NAMES, HARMONIC_PSI, _max_state, first_order_steps,
                                              rotate_about_axis, turn)
from rocknroller.analysis.slow.map.region import region_frame
from rocknroller.analysis.slow.map.table import REGION_TABLE_ACCURACY, release_frame

SYM = Body.paper()
EPS = np.finfo(float).eps
#: The two formulations run different orbits (one turned) and read the responses by fourth-order central differences
#: of step 1e-4 (``directional_derivative``), whose rounding, ~1.5 ε |q| |v| / h, is up to ~1e-10 of a response
#: that is small beside the state; the tables need the responses to ``REGION_TABLE_ACCURACY``, so the two must agree
#: to a hundredth of that, relative to the largest harmonic of each response at each node.
AGREE = 1e-2 * REGION_TABLE_ACCURACY
#: Two runs of one orbit by different systems (here turned, in test_mirror_nodes.py mirrored): each keeps its local
#: error per step within ε of max(1, ‖y‖∞) (≲ 6 on these orbits) over ≲ 100 steps to the next maximum (31 for the
#: motion alone at these energies; the tangent components can only shorten the steps), ≲ 1.3e-13 each, 2.7e-13
#: between the two; the time and the angles read off at the maximum carry that over rates of order one.  1e-12 bounds
#: them with a margin of ~4, and 1e-13 bounds T (≈ 11) relative to itself (measured: 2e-15 relative in T, 8e-15 in
#: Δψ and Δφ).
ORBITS_AGREE = 1e-12


def _nodes(kind: str, count: int, seed: int) -> tuple[float, np.ndarray, np.ndarray]:
    """``count`` random nodes of a band chart (E of a release at 0.95π) or of the release table at 0.9π."""
    if kind == "band":
        E = rest_energy(SYM, 0.95 * math.pi)
        QR, QJ = region_frame(SYM, E, axis="band", nu=16, nv=16).nodes()
    else:
        frame = release_frame(SYM, 0.9 * math.pi, nu=16, nv=6)[0]
        E, (QR, QJ) = frame.E0, frame.nodes()
    pick = np.random.default_rng(seed).choice(QR.size, count, replace=False)
    return E, QR.ravel()[pick], QJ.ravel()[pick]


@pytest.mark.parametrize("kind", ["band", "release"])
def test_one_orbit_gives_the_responses_of_three(kind):
    E, QR, QJ = _nodes(kind, 12, seed=5)
    thX = np.asarray(turning_points(E, QR, QJ, SYM)[1], float)
    steps, resp = harmonic_steps(SYM, E, QR, QJ, thX)
    three = first_order_steps(SYM, E, QR[:, None], QJ[:, None], np.asarray(HARMONIC_PSI)[None, :], thX[:, None])
    shape = (len(QR), len(HARMONIC_PSI))
    ref = np.stack([_harmonics(np.reshape(three.d[name], shape)) for name in FIRST_ORDER_NAMES])
    scale = np.abs(ref).max(axis=-1, keepdims=True)
    assert np.all(np.abs(resp - ref) <= AGREE * scale)
    # the one orbit's own data: the same orbit up to the turn, to its integration's accuracy
    assert np.allclose(steps.T, np.reshape(three.T, shape), rtol=0.1 * ORBITS_AGREE, atol=0.0)
    assert np.allclose(steps.dpsi, np.reshape(three.dpsi, shape), rtol=0.0, atol=ORBITS_AGREE)
    assert np.allclose(steps.dphi, np.reshape(three.dphi, shape), rtol=0.0, atol=ORBITS_AGREE)


def test_the_response_values_follow_from_the_harmonics_at_other_spin_angles():
    """The harmonics of the one orbit predict a start from another spin angle (not one of the three)."""
    E, QR, QJ = _nodes("band", 4, seed=9)
    resp = harmonic_steps(SYM, E, QR, QJ)[1]
    psi = np.array([0.4, 1.1, 2.0, 2.9])
    direct = first_order_steps(SYM, E, QR, QJ, psi)
    Th = 2.0 * psi
    for j, name in enumerate(FIRST_ORDER_NAMES):
        c0, c1, s1 = resp[j].T
        scale = np.abs(resp[j]).max(axis=-1)
        assert np.all(np.abs(c0 + c1 * np.cos(Th) + s1 * np.sin(Th) - direct.d[name]) <= AGREE * scale), name


def test_turning_the_body_is_a_symmetry_of_the_equations_exactly():
    """f(S y) = S f(y) for Routh's sphere (I1 = I2), in exact rational arithmetic at random rational states and a
    rational turn (c, s) = ((1 − t²), 2t)/(1 + t²): the identity the one-orbit harmonics rest on.  With I2 ≠ I1 it
    fails, so the check can fail."""
    rng = random.Random(3)
    p = (Fraction(1, 20), Fraction(7, 20), Fraction(7, 20), Fraction(2, 5), Fraction(987, 100))
    for _ in range(3):
        y = [Fraction(rng.randint(-99, 99), rng.randint(1, 50)) for _ in range(11)]
        t = Fraction(rng.randint(1, 9), rng.randint(10, 20))
        c, s = (1 - t * t) / (1 + t * t), 2 * t / (1 + t * t)
        assert turn(body_frame_rhs(y, p), c, s) == body_frame_rhs(turn(y, c, s), p)
        asym = (p[0], p[1], p[2] * Fraction(11, 10), p[3], p[4])
        assert turn(body_frame_rhs(y, asym), c, s) != body_frame_rhs(turn(y, c, s), asym)


def test_the_start_from_a_spin_angle_is_the_turned_start():
    """S(ψ) y₀(0) = y₀(ψ), the start ``_max_state`` builds at spin angle ψ: each component is a sum of two products
    with cos ψ and sin ψ (rounded), against the same in state_from_euler: a few units of ε of the state's size."""
    E, QR, QJ = _nodes("band", 6, seed=2)
    thX = np.asarray(turning_points(E, QR, QJ, SYM)[1], float)
    y0 = _max_state(SYM, thX, QR, QJ, 0.0)
    for psi in (*HARMONIC_PSI, 0.7):
        turned = np.array(rotate_about_axis(y0, psi))
        assert np.all(np.abs(turned - _max_state(SYM, thX, QR, QJ, psi)) <= 16 * EPS * np.abs(y0).max(axis=0))
    assert np.array_equal(np.array(rotate_about_axis(y0, 0.0)), y0)  # S(0): the identity, exactly
