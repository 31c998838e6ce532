"""K(m) and sn, cn, dn by the AGM (analysis/slow/dynamics/elliptic_functions.py), which replace scipy.special's in the
pendulum's closed form: against mpmath at 30 digits, against scipy.special (Cephes' ellpj, the same algorithm), by
their identities, and on bad input.

Tolerances (the module's error analysis): K within 2 u_r per AGM step (N ≤ 8 here: 16 u_r, relative); sn and cn
within (N + 4)(1 + |u|) u_r per rounding of the amplitude, doubled for the sine and arcsine of the descending steps:
2 (8 + 4) = 24 (1 + |u|) u_r; dn within that over its least value √(1 − m).  Measured: at most 1 u_r for K and
8.7 (1 + |u|) u_r for cn at m = 1 − 1e-12.
"""

from __future__ import annotations

import mpmath as mp
import numpy as np
import pytest
import scipy.special as sc

from rocknroller.analysis.slow.dynamics.elliptic_functions import ellipj, ellipk

U_R = np.finfo(float).eps / 2
MS = [0.0, 1e-20, 1e-12, 1e-6, 0.1, 0.5, 0.9, 0.99, 1 - 1e-6, 1 - 1e-12]


def _arguments(m: float) -> np.ndarray:
    """Four quarter-periods finely (sn = 1, cn = 0 at u = K: dn's switch to √(1 − m sn²)), then out to 3e4."""
    return np.concatenate([np.linspace(0.0, 4.0 * ellipk(m), 37), np.linspace(-300.0, 300.0, 41), [1e4, 3e4]])


@pytest.mark.parametrize("m", MS)
def test_against_mpmath_at_30_digits(m):
    with mp.workdps(30):
        assert abs(ellipk(m) / float(mp.ellipk(m)) - 1.0) <= 16 * U_R
        u = _arguments(m)
        ref = np.array([[float(mp.ellipfun(f, mp.mpf(float(x)), m=mp.mpf(m))) for x in u] for f in ("sn", "cn", "dn")])
    sn, cn, dn = ellipj(u, m)
    bound = 24 * (1.0 + np.abs(u)) * U_R
    assert np.all(np.abs(sn - ref[0]) <= bound) and np.all(np.abs(cn - ref[1]) <= bound)
    assert np.all(np.abs(dn - ref[2]) <= bound / np.sqrt(1.0 - m))


@pytest.mark.parametrize("m", [1e-6, 0.1, 0.5, 0.9, 0.99])
def test_as_scipy_special_gives_them(m):
    """The same algorithm as scipy.special's (Cephes' ellpj): within the rounding of the two libraries' sine and
    arcsine (scipy's K is a polynomial approximation: within 2 u_r of ours)."""
    u = _arguments(m)
    ours, theirs = ellipj(u, m), sc.ellipj(u, m)[:3]
    for a, b in zip(ours, theirs):
        assert np.all(np.abs(a - b) <= 24 * (1.0 + np.abs(u)) * U_R / np.sqrt(1.0 - m))
    assert abs(ellipk(m) / float(sc.ellipk(m)) - 1.0) <= 4 * U_R


@pytest.mark.parametrize("m", MS)
def test_their_identities(m):
    """sn² + cn² = 1 and dn² + m sn² = 1, to a few roundings; sn(K) = 1, cn(0) = 1, sn odd and cn, dn even."""
    u = _arguments(m)
    sn, cn, dn = ellipj(u, m)
    assert np.all(np.abs(sn ** 2 + cn ** 2 - 1.0) <= 4 * U_R)
    assert np.all(np.abs(dn ** 2 + m * sn ** 2 - 1.0) <= 48 * (1.0 + np.abs(u)) * U_R / np.sqrt(1.0 - m))
    s, c, d = ellipj(-u, m)
    assert np.array_equal(s, -sn) and np.array_equal(c, cn) and np.array_equal(d, dn)
    sK, cK, dK = ellipj([ellipk(m)], m)
    assert abs(sK[0] - 1.0) <= 8 * U_R and abs(dK[0] - np.sqrt(1.0 - m)) <= 64 * U_R


@pytest.mark.parametrize("m", [-0.1, 1.0, 1.5, float("nan")])
def test_a_parameter_outside_0_1_is_named(m):
    with pytest.raises(ValueError, match=r"the parameter m = k\^2 must lie in \[0, 1\)"):
        ellipk(m)
    with pytest.raises(ValueError, match=r"the parameter m = k\^2 must lie in \[0, 1\)"):
        ellipj([0.5], m)


def test_arguments_must_be_finite():
    with pytest.raises(ValueError, match="the arguments u must be finite"):
        ellipj([0.0, np.inf], 0.5)


def test_the_closed_form_and_the_quadratures_of_a_release_import_no_scipy():
    """What a first prediction at a new release angle runs besides the tables (the pendulum's closed form, the
    precession quadratures of the release chart's drifts) loads neither scipy.special nor scipy.linalg (0.2 s of CPU
    each to import)."""
    import subprocess
    import sys

    code = ("import math, sys; import rocknroller as rr\n"
            "from rocknroller.analysis.slow.dynamics.pendulum import pendulum_prediction\n"
            "from rocknroller.analysis.routh.quadrature import precession\n"
            "b = rr.Body.paper(1e-3); pendulum_prediction(b, 0.9 * math.pi, 0.3, 500.0)\n"
            "from rocknroller.analysis.slow.map.family import rest_energy\n"
            "precession(rest_energy(rr.Body.paper(), 0.9 * math.pi), [0.0, 1e-4], [0.0, 2e-5], rr.Body.paper())\n"
            "print(sorted(m for m in sys.modules if m.startswith('scipy')))")
    out = subprocess.run([sys.executable, "-c", code], capture_output=True, text=True, check=True).stdout
    assert out.strip() == "[]"
