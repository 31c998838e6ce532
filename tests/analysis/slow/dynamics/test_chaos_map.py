"""Chaos indicators of the slow map (issue 23, item 1): the tangent map of one step against central differences of
the step itself, the Lyapunov growth against two nearby map orbits, MEGNO at a regular and a chaotic release, the
errors of the horizon's input (the horizon itself: test_horizon.py).

Releases from rest at θ0 = 0.95π (paper body), the issue's table: ε = 1e-2, ψ0 = π/4 regular, ψ0 = 0.1 chaotic (the
direct ODE's nearby runs separate by ≤ 3.6e-10 and by 3e-3 after 100 rocks).
"""

from __future__ import annotations

import math
import warnings

import numpy as np
import pytest

from rocknroller.analysis.model.body import Body
from rocknroller.analysis.slow.map import _kernel
from rocknroller.analysis.slow.map import compiled_map as slow_map
from rocknroller.analysis.slow import prediction as av
from rocknroller.analysis.slow.dynamics.chaos import map_indicators, tangent_scale
from rocknroller.analysis.slow.map.second_order import load_or_build_second_order_table
from rocknroller.numerics.megno import MEGNO_CHAOTIC, chaos_indicators

THETA0 = 0.95 * math.pi
EPS = 1e-2
REGULAR, CHAOTIC = math.pi / 4, 0.1
#: The kernel's stop of the implicit kick (analysis/slow/map/_kernel.c KICK_RTOL): the step is a smooth function of its
#: start only to this relative accuracy of the kick (plus a few ulp).
KICK_RTOL = 1e-13


@pytest.fixture(scope="module")
def table() -> av.SlowMapTable:
    return av.load_or_build_table(Body.paper(0.0), THETA0)


@pytest.fixture(scope="module")
def second():
    """Built once per cache (~60 s on 2 cores), then read."""
    return load_or_build_second_order_table(Body.paper(0.0), THETA0, workers=2)


def _step(table, second, eps: float, x, w=None):
    """One step of the map from (u, v, Θ) by the kernel itself; with a tangent vector w also M w (the kernel
    renormalises w: M w = w' e^ℓ)."""
    ft = slow_map._fast(table, second)
    tr = slow_map._tangent_rows(ft)
    out = np.empty((1, 5 if w is None else 6))
    extra = () if w is None else (np.array([*w, 0.0]), tr.rows_dw, tr.rows_kt, tr.rows2_kt, tr.scale)
    n, status, *_ = _kernel.iterate(ft.rows, ft.rows_jac, ft.geom, out, ft.U, ft.alpha, ft.beta, ft.dx, ft.nv, eps,
                                    x[0], x[1], x[2], 0.0, 0.0, 1e300, ft.rows2, *extra)
    assert n == 1 and status == slow_map._FULL
    if w is None:
        return out[0, 1:4]
    return out[0, 1:4], extra[0][:3] * math.exp(extra[0][3])


@pytest.mark.parametrize("order", [1, 2])
@pytest.mark.parametrize("psi0", [REGULAR, CHAOTIC])
def test_tangent_map_is_the_derivative_of_the_step(table, second, order, psi0):
    """M e_j (the kernel's tangent map of one step) equals the central differences of the step in u, v, Θ at points
    of a regular and a chaotic orbit, to first and second order, within a derived tolerance.

    Central differences with steps h and h/2: the error of D(h/2) is its truncation, (D(h) − D(h/2))/3 to leading
    order (h²), plus the step's own noise over h/2: the implicit kick stops within KICK_RTOL of the kick (+ a few
    ulp), so each component of the step is smooth only to η_i = KICK_RTOL |x'_i − x_i| + 8 ulp(x'_i).  The tolerance,
    |D(h) − D(h/2)| + 4 η_i/(h/2), is three times the first and twice the second.  A tangent map without the implicit
    midpoint's (I − (ε/2) ∂k/∂m)⁻¹, or without the drifts' ∇W, misses terms of relative size ε|∂k/∂m| ~ 1e-2 or
    more: far above it.
    """
    sec = second if order == 2 else None
    S = tangent_scale(table)
    h = np.array([1e-3 / S, 1e-3 / S, 1e-3])  # a thousandth of the phase scale: Q by 1/S (the twist), Θ by 1
    run = av.iterate_slow_map(table, EPS, psi0, 500.0, second=sec)
    ft = slow_map._fast(table, sec)
    worst = 0.0
    for k in (3, 17):
        Q = np.array([run.QR[k], run.QJ[k]])
        x = np.array([ft.e @ Q, ft.n @ Q, run.Theta[k]])
        xp = _step(table, sec, EPS, x)
        eta = KICK_RTOL * np.abs(xp - x) + 8.0 * np.spacing(np.abs(xp))
        for j in range(3):
            e = np.zeros(3)
            e[j] = 1.0
            _, Mej = _step(table, sec, EPS, x, e)
            D = [(_step(table, sec, EPS, x + s * e) - _step(table, sec, EPS, x - s * e)) / (2.0 * s)
                 for s in (h[j], 0.5 * h[j])]
            tol = np.abs(D[0] - D[1]) + 4.0 * eta / (0.5 * h[j])
            err = np.abs(Mej - D[1])
            assert np.all(err <= tol), (k, j, Mej, D[1], err, tol)
            worst = max(worst, float(np.max(err) / np.max(np.abs(D[1]))))
    assert worst < 1e-5  # measured: ≤ 2.1e-7 of the column (the h/2 differences' truncation: err/tol = 1/3)


def test_lyapunov_growth_equals_the_separation_of_nearby_orbits(table, second):
    """At the chaotic release two map orbits started 1e-10 apart in Θ separate, in the tangent vector's norm
    √(S²|ΔQ|² + ΔΘ²), as the tangent vector grows: over the window where their distance d lies in [1e-8, 1e-4] (past
    the first rocks, where the two vectors turn towards the unstable direction; before the orbits' nonlinearity
    matters) ln(d) and ℓ rise by the same amount within 0.05.  That bound: the nonlinear terms change the growth of d
    relative to a tangent vector by ≲ d ≤ 1e-4 per rock, ≲ 1e-2 over the ≤ 100 rocks of the window, and the kick's
    tolerance adds ~S KICK_RTOL ε|k| ≲ 1e-12 per rock to d ≥ 1e-8; 0.05 is five times their sum.  Both rise by 6 or
    more, i.e. the check resolves λ to 1 %."""
    S = tangent_scale(table)
    for sec in (None, second):
        a = av.iterate_slow_map(table, EPS, CHAOTIC, 4000.0, second=sec, tangent=True)
        b = av.iterate_slow_map(table, EPS, CHAOTIC + 0.5e-10, 4000.0, second=sec)
        n = min(a.t.size, b.t.size)
        dQ2 = (a.QR[:n] - b.QR[:n]) ** 2 + (a.QJ[:n] - b.QJ[:n]) ** 2
        d = np.sqrt(S * S * dQ2 + (a.Theta[:n] - b.Theta[:n]) ** 2)
        inside = np.flatnonzero((d > 1e-8) & (d < 1e-4))
        i, j = inside[0], inside[-1]
        assert np.all((d[i:j + 1] > 1e-9) & (d[i:j + 1] < 1e-3))  # one window of exponential growth
        rise_d, rise_l = math.log(d[j] / d[i]), a.log_growth[j] - a.log_growth[i]
        assert rise_d > 6.0 and abs(rise_d - rise_l) < 0.05, (rise_d, rise_l)
        assert a.log_growth is not None and b.log_growth is None


def test_megno_at_a_regular_and_a_chaotic_release(table, second):
    """ε = 1e-2, θ0 = 0.95π, 3000 time units (the indicators over their span of ~1000 rocks): ψ0 = π/4 regular with
    ⟨Y⟩ within 0.1 of 2 (a regular orbit's ⟨Y⟩ is 2 + O(ln N/N), ln 1000/1000 = 0.007); ψ0 = 0.1 chaotic (⟨Y⟩ > 3), both orders, as the direct ODE's
    nearby runs say (the issue's table); the indicators are the package's one formula on the series' samples."""
    body = Body.paper(EPS)
    with warnings.catch_warnings():
        warnings.simplefilter("ignore", av.AveragingValidityWarning)  # K = 4.26 > 4 here: the case
        for order in (1, 2):
            reg = av.predict_slow_motion(body, THETA0, REGULAR, 3000.0, order=order)
            cha = av.predict_slow_motion(body, THETA0, CHAOTIC, 3000.0, order=order)
            assert reg.regular and abs(reg.chaos.megno - 2.0) < 0.1, reg.chaos
            assert not cha.regular and cha.chaos.megno > MEGNO_CHAOTIC, cha.chaos
            assert cha.chaos.lyapunov_per_rock > 10.0 * reg.chaos.lyapunov_per_rock
            again = chaos_indicators(cha.chaos.t, cha.chaos.log_growth)  # over the span; the series stops at t_end
            assert again.megno == cha.chaos.megno and again.lyapunov == cha.chaos.lyapunov
            assert np.array_equal(cha.chaos.log_growth[: cha.series.t.size], cha.series.log_growth)


def test_indicators_do_not_change_the_orbit(table, second):
    """The tangent vector rides along: the orbit with it is the orbit without it, bit for bit, and a run split
    over output chunks carries the tangent vector across them."""
    for sec in (None, second):
        plain = av.iterate_slow_map(table, EPS, CHAOTIC, 2000.0, second=sec)
        tan = av.iterate_slow_map(table, EPS, CHAOTIC, 2000.0, second=sec, tangent=True)
        for name in ("t", "QR", "QJ", "Theta", "phi"):
            assert np.array_equal(getattr(plain, name), getattr(tan, name)), name
    whole = av.iterate_slow_map(table, EPS, CHAOTIC, 2000.0, tangent=True)
    mp = pytest.MonkeyPatch()
    mp.setattr(slow_map, "_CHUNK", 7)
    try:
        chunked = av.iterate_slow_map(table, EPS, CHAOTIC, 2000.0, tangent=True)
    finally:
        mp.undo()
    assert whole.t.size > 3 * 7 and np.array_equal(whole.log_growth, chunked.log_growth)


def test_bad_input(table):
    """ε = 0, indicators off, a bad fraction: clear ValueErrors, never NaN."""
    pure = av.predict_slow_motion(Body.paper(0.0), THETA0, 0.3, 1000.0)
    assert pure.pure_rocking and pure.chaos is None and pure.regular is None
    with pytest.raises(ValueError, match="eps = 0"):
        pure.horizon()
    off = av.predict_slow_motion(Body.paper(1e-3), THETA0, REGULAR, 1000.0, indicators=False)
    assert off.chaos is None and off.series.log_growth is None
    with pytest.raises(ValueError, match="indicators=True"):
        off.horizon()
    p = av.predict_slow_motion(Body.paper(1e-3), THETA0, REGULAR, 1000.0)
    for bad in (0.0, -0.1, 1.5, math.nan):
        with pytest.raises(ValueError, match="fraction"):
            p.horizon(bad)
    assert map_indicators(np.arange(1.0, 8.0), np.zeros(7)) is None
