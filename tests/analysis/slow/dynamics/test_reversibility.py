"""Reversibility and the invariant measure of the exact one-step map
(:mod:`rocknroller.analysis.slow.dynamics.reversibility`): the functions on toy maps whose answer is known (the
standard map: det = 1; the dissipative Hénon map: det = −b; the standard map seen through a change of coordinates that
does not keep area: det ≠ 1 pointwise, a coboundary, products 1 around cycles), then on the exact map: the symmetric
fixed points' product, the reversing involution against a mutated one, Routh's sphere, the flow's divergence against
the symbolic one."""

from __future__ import annotations

import math

import numpy as np
import pytest

from rocknroller.analysis.model.body import Body
from rocknroller.analysis.slow.dynamics import flow_volume as fv
from rocknroller.analysis.slow.dynamics import reversibility as rv
from rocknroller.analysis.slow.map.maps import ExactMap, reverse

U = float(np.finfo(float).eps)
#: A toy map's Jacobian: entries of one or two operations on numbers of order K ≤ 2, rounded once each: 8 u.
TOY_RTOL = 8 * U
THETA0 = 0.9 * math.pi


class StandardMap:
    """Chirikov's map (x, p) → (x + p', p'), p' = p + K sin x: det = 1."""

    def __init__(self, K: float) -> None:
        self.K = K

    def __call__(self, z):
        x, p = z
        p1 = p + self.K * math.sin(x)
        return np.array([x + p1, p1])

    def jacobian(self, z):
        k = self.K * math.cos(z[0])
        return np.array([[1.0 + k, 1.0], [k, 1.0]])

    def inverse(self, z):
        x1, p1 = z
        x = x1 - p1
        return np.array([x, p1 - self.K * math.sin(x)])


class Henon:
    """Hénon's map (x, y) → (1 − a x² + y, b x): det = −b everywhere."""

    a, b = 1.4, 0.3

    def __call__(self, z):
        return np.array([1.0 - self.a * z[0] ** 2 + z[1], self.b * z[0]])

    def jacobian(self, z):
        return np.array([[-2.0 * self.a * z[0], 1.0], [self.b, 0.0]])

    def inverse(self, z):
        x = z[1] / self.b
        return np.array([x, z[0] - 1.0 + self.a * x * x])


class Conjugated:
    """h T h⁻¹, T the standard map, h(x, p) = (x, p (1 + c cos x)): invariant density 1/(1 + c cos x), so
    det = (1 + c cos x')/(1 + c cos x), a coboundary."""

    c = 0.5

    def __init__(self, K: float) -> None:
        self.T = StandardMap(K)

    def h(self, z):
        return np.array([z[0], z[1] * (1.0 + self.c * math.cos(z[0]))])

    def h_inv(self, z):
        return np.array([z[0], z[1] / (1.0 + self.c * math.cos(z[0]))])

    def dh(self, z):
        return np.array([[1.0, 0.0], [-self.c * z[1] * math.sin(z[0]), 1.0 + self.c * math.cos(z[0])]])

    def __call__(self, z):
        return self.h(self.T(self.h_inv(z)))

    def jacobian(self, z):
        w = self.h_inv(z)
        return self.dh(self.T(w)) @ self.T.jacobian(w) @ np.linalg.inv(self.dh(w))

    def inverse(self, z):
        return self.h(self.T.inverse(self.h_inv(z)))


def test_standard_map_sums_vanish():
    """Area-preserving and chaotic at K = 1.5: both sums 0 within the bound, the QR sum equal to the direct one."""
    F = StandardMap(1.5)
    for backward in (False, True):
        s = rv.lyapunov_sum(F, [0.1, 0.2], 2000, backward=backward, rtol=TOY_RTOL)
        assert abs(s.value) <= s.error and abs(s.qr_value - s.value) <= s.error
        assert s.exponents[0] > 0.05  # chaotic, so the test is not on a regular orbit


def test_henon_contracts_and_fails_the_test():
    """The dissipative control: value = log b forward and backward (det constant), far outside the bound from 0; the
    fixed point's log det = log b."""
    F = Henon()
    for backward, n in ((False, 500), (True, 5)):  # backward orbits leave to infinity: a few steps
        s = rv.lyapunov_sum(F, [0.1, 0.1], n, backward=backward, rtol=TOY_RTOL)
        assert abs(s.value - math.log(F.b)) <= s.error + 2 * U
        assert abs(s.value) > 1e6 * s.error
    cycle = rv.find_cycle(F, [0.6, 0.2], 1, angles=(), reversors={}, tol=8 * U)
    d = rv.log_det_product(F, cycle.points, angles=(), rtol=TOY_RTOL)
    assert abs(d.log_product - math.log(F.b)) <= d.error and abs(d.log_product) > 1e6 * d.error


def test_coboundary_products_vanish_where_det_does_not():
    """Conservative with a non-uniform density: log det of single steps is far from 0, yet every cycle's product
    is 0 within its bound and the mean over n steps is bounded by the density's range over n."""
    F = Conjugated(1.5)
    cycle = rv.find_cycle(F, [1.0, 2.0], 2, angles=(0,), reversors={}, tol=8 * U)
    steps = [abs(np.linalg.slogdet(F.jacobian(x))[1]) for x in cycle.points]
    d = rv.log_det_product(F, cycle.points, angles=(0,), rtol=TOY_RTOL)
    assert min(steps) > 1e6 * d.error and abs(d.log_product) <= d.error
    s = rv.lyapunov_sum(F, [0.1, 0.2], 1000, rtol=TOY_RTOL)
    assert abs(s.value) <= math.log((1 + F.c) / (1 - F.c)) / s.n + s.error


def test_find_cycle_refuses_where_there_is_none():
    """x → x + 1 has no fixed point: Newton's step cannot lower the residual."""

    class Shift:
        def __call__(self, x):
            return np.asarray(x, float) + 1.0

        def jacobian(self, x):
            return np.eye(1)

        inverse = None

    with pytest.raises(rv.CycleError):
        rv.find_cycle(Shift(), [0.0], 1, angles=(), reversors={})


@pytest.mark.parametrize("theta_star", [0.0, math.pi])
def test_symmetric_fixed_points_product_is_one(theta_star):
    """The control on the exact map: pure rocking about either axis (R- and RS-symmetric) has log det = 0 within
    its derived bound."""
    F = ExactMap(Body.paper(0.0), THETA0, 0.03)
    c = rv.find_cycle(F, [0.0, 0.0, theta_star], 1)
    assert c.symmetry == "R" and c.residual <= rv.CYCLE_TOL
    d = rv.log_det_product(F, c.points)
    assert abs(d.log_product) <= d.error < 1e-9


def test_reversor_defect_detects_a_mutated_involution():
    """det DP(x) det DP(G P x) = 1 for both reversors, within 2 d η; a wrong involution (Q_J's sign kept) breaks it
    by far more."""
    F = ExactMap(Body.paper(0.0), THETA0, 0.03)
    x = [0.02, 5e-4, 1.0]
    for G in rv.REVERSORS.values():
        defect, bound = rv.reversor_defect(F, x, G)
        assert abs(defect) <= bound
    defect, bound = rv.reversor_defect(F, x, lambda y: np.array([-y[0], y[1], y[2]]))
    assert abs(defect) > 1e3 * bound


def test_backward_sum_is_forward_sum_from_the_reversed_start():
    """By reversibility the orbit of P⁻¹ from x is R of P's orbit from R x, so the backward sum (P's orientation) is
    minus the forward one from R x, within the two bounds."""
    F = ExactMap(Body.paper(0.0), THETA0, 0.03)
    x0 = np.array([0.02, 5e-4, 1.0])
    back = rv.lyapunov_sum(F, x0, 4, backward=True)
    fwd = rv.lyapunov_sum(F, reverse(x0), 4)
    assert abs(back.value + fwd.value) <= back.error + fwd.error
    assert abs(fwd.value) > 1e3 * fwd.error  # the identity is not 0 = 0


def test_routh_sphere_keeps_volume():
    """The positive control, ε = 0: det DP = 1 (Q conserved, Θ' − Θ a function of Q) and ∫ div f = 0 at the maxima
    (Routh's density depends on θ alone, the same at every maximum)."""
    F = ExactMap(Body.paper(0.0), THETA0, 0.0)
    s = rv.lyapunov_sum(F, [0.02, 5e-4, 1.0], 3)
    assert abs(s.value) <= s.error
    run = fv.divergence_run(F, [0.02, 5e-4, 1.0], 500)
    assert run.max_abs() <= run.error
