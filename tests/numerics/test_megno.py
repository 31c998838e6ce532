"""MEGNO and the finite-time Lyapunov exponent from samples (numerics/megno.py): the limits the definitions give in
closed form, and Chirikov's standard map, whose chaotic Lyapunov exponent at large K is known (ln(K/2), Chirikov 1979)."""

from __future__ import annotations

import math

import numpy as np
import pytest

from rocknroller.numerics.megno import MEGNO_CHAOTIC, chaos_indicators, megno_series


def test_linear_growth_gives_two():
    # ‖w‖ = 1 + t: Y_n = (2/n) Σ k ln((k+1)/k) = 2 + O(ln n / n), so ⟨Y⟩ = 2 + O(ln² n / n): within 0.05 at n = 10⁴
    # (the O(.) constant is ≤ 1: Σ k ln(1 + 1/k) ≤ n + ½ ln n).
    t = np.arange(1.0, 10_001.0)
    ind = chaos_indicators(t, np.log1p(t))
    assert abs(ind.megno - 2.0) < 0.05 and ind.regular
    assert ind.lyapunov < 1e-3  # the slope of ln(1 + t) over [5000, 10000] is ≈ 1.4e-4


def test_exponential_growth_gives_lambda_t_over_two():
    # ℓ = λ t exactly: Y(t_n) = λ (t_n + T) for spacing T, ⟨Y⟩ = λ (t_n + 3T)/2 in closed form; slope λ exactly.
    lam, T = 0.037, 2.5
    t = T * np.arange(1, 401)
    Y, mean_Y = megno_series(t, lam * t)
    np.testing.assert_allclose(Y, lam * (t + T), rtol=1e-12)
    np.testing.assert_allclose(mean_Y, lam * (t + 3 * T) / 2, rtol=1e-12)
    ind = chaos_indicators(t, lam * t)
    assert ind.lyapunov == pytest.approx(lam, rel=1e-12)
    assert ind.lyapunov_per_rock == pytest.approx(lam * T, rel=1e-12)
    assert not ind.regular and ind.megno > MEGNO_CHAOTIC


def test_bounded_growth_gives_zero():
    # a stable periodic orbit: ‖w‖ oscillates, ℓ bounded by 1, so |Y| ≤ 4 max|ℓ| / ... → ⟨Y⟩ = O(1/n) → 0.
    t = np.arange(1.0, 5001.0)
    ind = chaos_indicators(t, np.sin(0.7 * t))
    assert abs(ind.megno) < 0.01 and ind.regular


def _standard_map_growth(K: float, x: float, p: float, n: int) -> np.ndarray:
    """ln‖w_k‖ along Chirikov's map p' = p + K sin x, x' = x + p', its tangent map by hand, renormalised each step."""
    w = np.array([1.0, 0.0])
    ell, total = np.empty(n), 0.0
    for k in range(n):
        c = K * math.cos(x)
        p = p + K * math.sin(x)
        x = x + p
        dp = w[1] + c * w[0]
        w = np.array([w[0] + dp, dp])
        norm = math.hypot(*w)
        total += math.log(norm)
        w /= norm
        ell[k] = total
    return ell


def test_standard_map_chaotic_and_regular():
    n = 2000
    t = np.arange(1.0, n + 1.0)
    # K = 10: λ = ln(K/2) + O(1/K²) per step (Chirikov 1979, eq. 5.9): ln 5 = 1.609; finite-time estimates over
    # 1000 steps scatter by ~ σ/√1000 with σ ~ 1, so within 10 %.
    chaotic = chaos_indicators(t, _standard_map_growth(10.0, 0.3, 0.2, n))
    assert chaotic.lyapunov == pytest.approx(math.log(5.0), rel=0.1)
    assert not chaotic.regular
    # K = 0.5, a start inside the resonance island about the elliptic point (π, 0), (x, p) = (π + 1, 0): a KAM
    # torus, regular (⟨Y⟩ approaches 2 from below as the twist spreads the tangent vector; 1.93 after 2000 steps);
    # a start at (0.2, 0), beside the hyperbolic point, lies in the separatrix's chaotic layer.
    regular = chaos_indicators(t, _standard_map_growth(0.5, math.pi + 1.0, 0.0, n))
    assert regular.regular and abs(regular.megno - 2.0) < 0.2
    layer = chaos_indicators(t, _standard_map_growth(0.5, 0.2, 0.0, n))
    assert not layer.regular and layer.lyapunov > 10 * regular.lyapunov


@pytest.mark.parametrize("t, ell, word", [
    ([1.0, 2.0], [0.0, 0.1], "MIN_SAMPLES"),
    (np.arange(1.0, 11.0), np.zeros(9), "shapes"),
    (np.arange(0.0, 10.0), np.zeros(10), "positive and strictly increasing"),
    (np.arange(1.0, 11.0)[::-1], np.zeros(10), "strictly increasing"),
    (np.arange(1.0, 11.0), np.full(10, np.nan), "finite"),
])
def test_bad_samples(t, ell, word):
    with pytest.raises(ValueError, match=word):
        chaos_indicators(t, ell)
