"""The tables' charts and series: where a table's nodes lie in (Q_R, Q_J) and how its functions are evaluated.
It holds :class:`SlowMapTable` (one first-order table: its chart and Chebyshev coefficients, with their evaluation,
gradients and range check), :class:`SecondOrderTable` (k₂ on the chart of a first-order table), the tabulated
functions (``TABLE_FUNCTIONS``) with their parities in Q, and the sinh stretch of the chart's coordinates
(:func:`stretch`, :func:`unstretch`, :func:`stretch_slope`).  The tables are built, fitted and cached by
:mod:`rocknroller.analysis.slow.map.table`, :mod:`rocknroller.analysis.slow.map.region` and
:mod:`rocknroller.analysis.slow.map.second_order`.

A table of the slow map holds its coefficient functions (``TABLE_FUNCTIONS``: T_θ, W, Δφ and the harmonics 0 and 1
in Θ of the kicks) as Chebyshev series in the coordinates (ξ, η) of a chart of the (Q_R, Q_J) plane,
Q = x U e + (c(x) + τ w(x)) n with x = stretch(ξ, α) and τ = stretch(η, β): along a line (the kick direction
through Q = 0 for the release tables, Q_J,0^crit or Q_J,π^crit for the region tables of one energy; paper eqs.
QJcrit_0, QJcrit_pi) with a stretch that resolves a layer, and across it between the chart's sides c ± w.
"""

from __future__ import annotations

import math
from dataclasses import dataclass

import numpy as np
from numpy.typing import ArrayLike, NDArray

from rocknroller.analysis.model.body import Body
from rocknroller.analysis.slow.map.limits import (K_PERIOD_DOUBLING, AveragingRangeError, ChartWidthError,
                                                  eps_period_doubling)

__all__ = [
    "TABLE_FUNCTIONS", "CHART_TERMS", "SlowMapTable", "stretch", "unstretch", "stretch_slope", "SecondOrderTable",
    "cheb_nodes", "cheb_basis", "cheb_fit_matrix"
]


#: Functions of the table, in order: symmetric data, then the harmonics (c0, c1, s1) of
#: k_Q (Q_R, Q_J) and k_Θ in the drift–kick–drift form, then of the time and φ responses.
TABLE_FUNCTIONS = ("T", "W", "dphi",
                   "kQR_c0", "kQR_c1", "kQR_s1", "kQJ_c0", "kQJ_c1", "kQJ_s1", "kTh_c0", "kTh_c1", "kTh_s1",
                   "dt_c0", "dt_c1", "dt_s1", "dphi1_c0", "dphi1_c1", "dphi1_s1")


#: Parities in Q of a reversible map (time reversal: Q → −Q, Θ kept, t and φ steps reversed in order/sign).
_ODD = {"W", "dphi", "kTh_c0", "kTh_c1", "kTh_s1", "dphi1_c0", "dphi1_c1", "dphi1_s1"}


_EVEN = {"T", "kQR_c0", "kQR_c1", "kQR_s1", "kQJ_c0", "kQJ_c1", "kQJ_s1", "dt_c0", "dt_c1", "dt_s1"}


def cheb_nodes(n: int) -> NDArray[np.float64]:
    """The n Chebyshev points of the first kind, cos(π(k + ½)/n), k = 0..n−1 (descending): numpy's ``chebpts1``,
    whose sines make them exactly antisymmetric (x_{n−1−k} = −x_k to the bit, which the tables' parity
    symmetrisation F[::-1, ::-1] assumes; the cosines missed it by up to 2.8e-16).

    Examples
    --------
    >>> x = cheb_nodes(4)
    >>> bool((x[::-1] == -x).all()), f"{x[0]:.6f}"
    (True, '0.923880')
    """
    return np.polynomial.chebyshev.chebpts1(n)[::-1].copy()


def cheb_basis(x: ArrayLike, n: int) -> NDArray[np.float64]:
    """T_0..T_{n−1} at x clipped to [−1, 1], shape (n, ...): numpy's ``chebvander`` (the three-term recurrence
    T_k = 2x T_{k−1} − T_{k−2}, stable on [−1, 1]), with the basis index first, as the tables contract it.

    Examples
    --------
    >>> cheb_basis([0.5, 2.0], 3).tolist()  # T_0, T_1, T_2 at 0.5 and at 2 clipped to 1
    [[1.0, 1.0], [0.5, 1.0], [-0.5, 1.0]]
    """
    xc = np.clip(np.asarray(x, float), -1.0, 1.0)
    V = np.polynomial.chebyshev.chebvander(xc, n - 1).reshape(xc.shape + (n,))  # a 0-d x comes back as (1, n)
    return np.moveaxis(V, -1, 0)


def cheb_fit_matrix(n: int) -> NDArray[np.float64]:
    """A with c = A f for the interpolant at the first-kind nodes: the discrete orthogonality of the T_k there, as
    numpy's ``chebinterpolate`` applies it ((2/n) Vᵀ with the first row halved, V = ``chebvander`` at the nodes).

    Examples
    --------
    >>> import numpy as np
    >>> c = cheb_fit_matrix(4) @ (cheb_nodes(4) ** 2)  # x² = (T_0 + T_2)/2
    >>> np.round(c, 12).tolist()
    [0.5, 0.0, 0.5, 0.0]
    """
    A = np.asarray((2.0 / n) * np.polynomial.chebyshev.chebvander(cheb_nodes(n), n - 1).T, dtype=np.float64)
    A[0] *= 0.5
    return A


#: Chebyshev coefficients of the chart's c(x) and w(x) (:class:`SlowMapTable`), zero-padded.
CHART_TERMS = 48


@dataclass(frozen=True)
class SlowMapTable:
    """Tabulated first-order slow map of one (body, E): Chebyshev series in the chart coordinates (x, τ).

    Q = u e + v n with u = x U and v = c(x) + τ w(x), |x| ≤ 1, |τ| ≤ 1: e and n ⟂ e are unit vectors in
    the (Q_R, Q_J) plane, c(x) (odd) and w(x) > 0 (even) Chebyshev series in x.  The functions are Chebyshev
    series in (ξ, η) with x = :func:`stretch` (ξ, α) and τ = :func:`stretch` (η, β), which put more nodes near
    Q = 0, where W varies on the scale 1/|∇W(0)| (α = β = 0: no stretch).  The tables of a release
    from rest (:func:`build_table`) use the kick direction at Q = 0 for e, c = 0 and w = V (a rectangle);
    those of a whole region (:func:`rocknroller.analysis.slow.map.region.build_region_table`) follow the critical
    line Q_J,0^crit and the region's width.

    Attributes
    ----------
    a, I1, I3, g, theta0, E0 : the symmetric body, the release angle (for a region table that of a release from
        rest with its energy, E0 < 2 g a) and the energy.
    e, n : unit vectors in the (Q_R, Q_J) plane.
    U : half-length of the chart along e.
    c_coef, w_coef : Chebyshev coefficients (``CHART_TERMS``) of c(x) and w(x).
    coef : ndarray (len(TABLE_FUNCTIONS), Nu, Nv), Chebyshev coefficients in (ξ, η).
    kappa : ∇W·C0 at Q = 0 (the standard-map constant, K = ε κ), from the table.
    C0 : the kick ΔQ(0, Θ) = C0 sin Θ, from the variational orbits at Q = 0.
    interp_error : largest relative error of the table against direct coefficients at three
        off-grid points, measured when the table was built.
    delta_min : the region tables' least distance (E − min U)/E to steady rolling (0 for release tables).
    alpha, beta : the stretches of x and τ.
    """

    a: float
    I1: float
    I3: float
    g: float
    theta0: float
    E0: float
    e: NDArray[np.float64]
    n: NDArray[np.float64]
    U: float
    c_coef: NDArray[np.float64]
    w_coef: NDArray[np.float64]
    coef: NDArray[np.float64]
    C0: NDArray[np.float64]
    kappa: float
    interp_error: float
    delta_min: float = 0.0
    alpha: float = 0.0
    beta: float = 0.0

    @property
    def body(self) -> Body:
        """The symmetric body the table was built for."""
        return Body(a=self.a, I1=self.I1, I2=self.I1, I3=self.I3, g=self.g)

    def _sides(self, x: ArrayLike) -> tuple[NDArray[np.float64], ...]:
        """c(x), w(x) and their x-derivatives over U."""
        cheb = np.polynomial.chebyshev
        x = np.clip(x, -1.0, 1.0)  # the series are the chart's only on [−1, 1]; beyond it Q is outside anyway
        return (cheb.chebval(x, self.c_coef), cheb.chebval(x, self.w_coef),
                cheb.chebval(x, cheb.chebder(self.c_coef)) / self.U, cheb.chebval(x, cheb.chebder(self.w_coef)) / self.U)

    def same_chart(self, other: "SlowMapTable") -> bool:
        """True if ``other`` has this table's chart and grid (the frame e, n, U, the sides c, w, the stretches and
        the number of terms), bit for bit: tables tabulated on one table's chart (the second-order k₂) fit it."""
        return (self.coef.shape == other.coef.shape
                and (self.U, self.alpha, self.beta) == (other.U, other.alpha, other.beta)
                and all(np.array_equal(getattr(self, k), getattr(other, k)) for k in ("e", "n", "c_coef", "w_coef")))

    def chart(self, xi: ArrayLike, eta: ArrayLike) -> tuple[NDArray[np.float64], NDArray[np.float64]]:
        """(Q_R, Q_J) at the chart coordinates (ξ, η) ∈ [−1, 1]² (those of the Chebyshev series)."""
        xi, eta = np.asarray(xi, float), np.asarray(eta, float)
        x = stretch(xi, self.alpha)
        u = x * self.U
        c, w = self._sides(x)[:2]
        v = c + stretch(eta, self.beta) * w
        return u * self.e[0] + v * self.n[0], u * self.e[1] + v * self.n[1]

    def coordinates(self, Q: ArrayLike) -> tuple[float, float]:
        """The chart coordinates (ξ, η) of Q = (Q_R, Q_J) (outside [−1, 1]² if Q is outside the table)."""
        Q = np.asarray(Q, float)
        u, v = float(self.e @ Q), float(self.n @ Q)
        x = u / self.U
        xi = float(unstretch(x, self.alpha))
        c, w = (float(s) for s in self._sides(x)[:2])
        return xi, float(unstretch((v - c) / w, self.beta))

    def inverse_jacobian(self, xi: ArrayLike, eta: ArrayLike) -> tuple[NDArray[np.float64], ...]:
        """(∂ξ/∂u, ∂η/∂u, ∂η/∂v) at (ξ, η), for the chain rule ∂F/∂u = F_ξ ∂ξ/∂u + F_η ∂η/∂u, ∂F/∂v = F_η ∂η/∂v."""
        xi, eta = np.asarray(xi, float), np.asarray(eta, float)
        x = stretch(xi, self.alpha)
        dxi_du = 1.0 / (self.U * stretch_slope(xi, self.alpha))
        c, w, dc, dw = self._sides(x)
        tau = stretch(eta, self.beta)
        deta_dv = 1.0 / (stretch_slope(eta, self.beta) * w)
        return dxi_du, -(dc + tau * dw) * deta_dv, deta_dv

    def evaluate(self, Q: ArrayLike) -> NDArray[np.float64]:
        """All ``TABLE_FUNCTIONS`` at Q = (Q_R, Q_J); raises AveragingRangeError outside the table."""
        Q = np.asarray(Q, float)
        xi, eta = self.coordinates(Q)
        if not (abs(xi) <= 1.0 and abs(eta) <= 1.0):
            if self.delta_min > 0.0:
                from rocknroller.analysis.routh.steady_rolling import boundary_distance

                delta = float(boundary_distance(self.body, self.E0, Q[0], Q[1]))
                raise AveragingRangeError(
                    f"the slow orbit left the tabulated region at Q=({Q[0]:.4g}, {Q[1]:.4g}), whose distance to "
                    f"steady rolling is (E - min U)/E = {delta:.3g}: the tables of E={self.E0:.6g} cover "
                    f"|u| <= {self.U:.4g} along their chart's line e=({self.e[0]:.4f}, {self.e[1]:.4f}) (Q_J,0^crit for "
                    f"the spindle chart, Q_J,pi^crit for the band) and distances >= {self.delta_min:g}; nearer "
                    f"steady rolling the oscillation of theta is too small to average, and the band does not reach "
                    f"the spindle's tips (axis='spindle' covers them where it is accurate)")
            across = abs(xi) <= 1.0 and not abs(eta) <= 1.0
            raise (ChartWidthError if across else AveragingRangeError)(
                f"the slow orbit left the tabulated region at Q=({Q[0]:.4g}, {Q[1]:.4g}): the tables cover "
                f"|u| <= {self.U:.4g} along the kick direction e=({self.e[0]:.4f}, {self.e[1]:.4f}) and "
                f"|v| <= {self.w_coef[0]:.3g} across it; the averaging is valid for K = eps*kappa < "
                f"{K_PERIOD_DOUBLING:g} (eps < {eps_period_doubling(self.kappa):.4g}) and orbits near pure rocking"
                + (f"; the orbit's spread across the kick direction grows like eps^2 and passes this width at large "
                   f"eps (from K ~ 3 at 0.85pi; docs/averaging.md): the region tables of the release's energy "
                   f"cover it (an explicit zero rate, --theta-dot0 0, or the EulerState(theta0, 0, psi0))"
                   if across else ""))
        nu, nv = self.coef.shape[1:]
        return (self.coef @ cheb_basis(eta, nv)) @ cheb_basis(xi, nu)

    def gradient(self, name: str, Q: ArrayLike) -> NDArray[np.float64]:
        """(∂F/∂u, ∂F/∂v) of the table function ``name`` at Q (Q = u e + v n), by the chain rule through the chart."""
        self.evaluate(Q)  # the range check
        xi, eta = self.coordinates(Q)
        cheb = np.polynomial.chebyshev
        c = self.coef[TABLE_FUNCTIONS.index(name)]
        f_xi, f_eta = (cheb.chebval2d(xi, eta, cheb.chebder(c, axis=k)) for k in (0, 1))
        dxi_du, deta_du, deta_dv = self.inverse_jacobian(xi, eta)
        return np.array([f_xi * dxi_du + f_eta * deta_du, f_eta * deta_dv])

    def nodes(self) -> tuple[NDArray[np.float64], NDArray[np.float64]]:
        """(Q_R, Q_J) at the table's Chebyshev nodes (ξ_i, η_j), arrays (Nu, Nv)."""
        nu, nv = self.coef.shape[1:]
        return self.chart(*np.meshgrid(cheb_nodes(nu), cheb_nodes(nv), indexing="ij"))


def stretch(s: ArrayLike, a: float) -> NDArray[np.float64]:
    """z = sinh(a s)/sinh(a) on [−1, 1] (z = s for a = 0): nodes uniform in s crowd near z = 0 at the scale
    1/sinh(a) (Tee & Trefethen's sinh map for an interior layer, SIAM J. Sci. Comput. 28, 2006)."""
    s = np.asarray(s, float)
    return s if a == 0.0 else np.sinh(a * s) / math.sinh(a)


def unstretch(z: ArrayLike, a: float) -> NDArray[np.float64]:
    """The inverse of :func:`stretch`."""
    z = np.asarray(z, float)
    return z if a == 0.0 else np.arcsinh(z * math.sinh(a)) / a


def stretch_slope(s: ArrayLike, a: float) -> NDArray[np.float64]:
    """dz/ds of :func:`stretch`."""
    s = np.asarray(s, float)
    return np.ones_like(s) if a == 0.0 else a * np.cosh(a * s) / math.sinh(a)


def _basis(theta_a: ArrayLike) -> NDArray[np.float64]:
    th = np.asarray(theta_a, float)
    return np.stack([np.ones_like(th), np.cos(th), np.sin(th), np.cos(2 * th), np.sin(2 * th)], axis=-1)


@dataclass(frozen=True)
class SecondOrderTable:
    """k₂ over the chart of a first-order release table (θ0, E0), or of a region table (E0; θ0 is then NaN):
    Chebyshev series in its (ξ, η), ``coef`` of shape (len(K2_FUNCTIONS), nu, nv); ``interp_error`` as checked when
    built."""

    theta0: float
    E0: float
    coef: NDArray[np.float64]
    interp_error: float = math.nan

    def harmonics(self, first: SlowMapTable, Q: ArrayLike) -> NDArray[np.float64]:
        """(5 components, 5 harmonics) of k₂ at Q (``first``: the release table whose chart this one uses)."""
        xi, eta = first.coordinates(np.asarray(Q, float))
        nu, nv = self.coef.shape[1:]
        vals = (self.coef @ cheb_basis(eta, nv)) @ cheb_basis(xi, nu)
        return np.asarray(vals, float).reshape(5, 5)

    def kick(self, first: SlowMapTable, Q: ArrayLike, theta_a: float) -> NDArray[np.float64]:
        """k₂ at (Q, Θ_a) for the components of ``STEP_NAMES``."""
        return self.harmonics(first, Q) @ _basis(theta_a)


_IDX = {name: i for i, name in enumerate(TABLE_FUNCTIONS)}


_HARM = ("c0", "c1", "s1")
