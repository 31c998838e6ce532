"""First-order ε-averaging of the slow (Q_R, Q_J) dynamics of the asymmetric rock'n'roller.

The motion is sampled at successive maxima of θ.  The slow variables are Q = (Q_R, Q_J)
(paper eq. JelletandRouth_Qtys) and the phase Θ = 2ψ mod 2π (ψ itself jumps by about ±π at each
passage near θ = 0; 2ψ does not).  The energy E is exact and fixed by the start: the tables
belong to (body, θ0) with E = U(θ0; 0, 0), the energy of the body released from rest at θ0.

One step (maximum n → maximum n+1), to first order in ε = (I2 − I1)/I1 at fixed Q_n:

    Q_{n+1} = Q_n + ε ΔQ(Q_n, Θ_n),     Θ_{n+1} = Θ_n + W(Q_n) + ε ΔΘ(Q_n, Θ_n),
    t_{n+1} = t_n + T_θ(Q_n) + ε Δt(Q_n, Θ_n),   φ_{n+1} = φ_n + Δφ(Q_n) + ε Δφ₁(Q_n, Θ_n),

with T_θ, W = 2(Δψ − π) and Δφ from the symmetric quadratures (``rocknroller.analysis.quadrature``) and the
first-order terms from the symmetric orbit integrated together with its first-order variational
equations in ε (``rocknroller.analysis.slow_orbit``; three orbits per Q give the harmonics 0 and 1 of Θ_n).

Reversible form.  The exact map is reversible under (Q, Θ) → (−Q, Θ) (time reversal).  The same
first-order data are written as drift–kick–drift: a half twist Θ += W(Q)/2, a kick
(Q, Θ) += ε k((x + x')/2) by the implicit midpoint rule, and a half twist W(Q')/2, with

    k_Q(Q, Θ') = ΔQ(Q, Θ' − W/2),   k_Θ(Q, Θ') = ΔΘ(Q, Θ' − W/2) − ½ ∇W·k_Q(Q, Θ'),

k_Q even and k_Θ odd in Q (enforced on the symmetric grid).  The ε ΔΘ term is kept: it is the phase
change of the part of the kick received before the passage near θ = 0, multiplied by the large ∂W/∂Q.

Tables.  The coefficient functions are tabulated once per (body, θ0) on a Chebyshev grid in the
frame (u, v) of the kick direction at Q = 0 (the slow orbit lies close to the line v = 0) and cached
on disk (``rocknroller.numerics.cache.cache_dir()/averaging``, plain arrays with their key and checksum, checked on
load); they depend on neither ε nor ψ0.

Range.  The map is built and validated for releases 0.75π ≤ θ0 ≤ 0.999π (``THETA0_RANGE``;
docs/averaging.md, "Range of θ0"), and one run produces at most ``MAX_MAXIMA`` maxima.
"""

from __future__ import annotations

import dataclasses
import hashlib
import inspect
import math
import os
import warnings
from dataclasses import dataclass, field
from typing import Any, Callable

import numpy as np
from numpy.typing import ArrayLike, NDArray

from rocknroller.analysis.averaging_limits import MAX_MAXIMA, THETA0_RANGE, check_map_theta0, check_t_end, t_end_limit
from rocknroller.analysis.body import Body
from rocknroller.analysis.quadrature import wrap_angle
from rocknroller.analysis.reduction import u_ends
from rocknroller.analysis.slow_diagnostics import azimuth_span, slow_period, span, unwrap_phase
from rocknroller.numerics.cache import CacheWarning, cache_dir, load_arrays, save_arrays, warn_unwritable
from rocknroller.analysis.slow_orbit import (FIRST_ORDER_NAMES, HARMONIC_PSI, _harmonics, first_maximum, first_order_step,
                                             rest_energy, step_coefficients, symmetric_data)
from rocknroller.numerics.equations import EulerState

from rocknroller.analysis import _slow_map_kernel as _kernel

__all__ = [
    "AveragingRangeError",
    "AveragingValidityWarning",
    "THETA0_RANGE",
    "MAX_MAXIMA",
    "check_map_theta0",
    "check_t_end",
    "max_t_end",
    "TABLE_FUNCTIONS",
    "SlowMapTable",
    "build_table",
    "load_or_build_table",
    "SlowSeries",
    "iterate_slow_map",
    "SlowPrediction",
    "predict_slow_motion",
    "line_slope",
    "critical_regions",
    "K_PERIOD_DOUBLING",
    "eps_period_doubling",
    "rocks_per_region",
    "releases_on_region_tables",
    "REGION_TABLE_ACCURACY",
]

#: Bump when the table construction or its file format changes (part of the cache key).
_TABLE_VERSION = "5"
#: Chirikov's standard map I' = I + K sin Θ, Θ' = Θ + I' (the slow map near pure rocking, K = ε κ): the
#: Jacobian at its stable fixed point has trace 2 − K, which reaches −2 (period doubling) at K = 4.
K_PERIOD_DOUBLING = 4.0
_TABLES: dict[str, "SlowMapTable"] = {}


def eps_period_doubling(kappa: float) -> float:
    """ε at which K = ε κ reaches K_PERIOD_DOUBLING (rocking about the stable axis period-doubles)."""
    return K_PERIOD_DOUBLING / abs(kappa)


def rocks_per_region(runs: list[tuple[str, int, float]] | None) -> dict[str, int]:
    """Total number of rocks (maxima) in each critical region, from the runs of :func:`critical_regions`."""
    out: dict[str, int] = {}
    for lab, n, _ in runs or []:
        out[lab] = out.get(lab, 0) + n
    return out


class AveragingRangeError(ValueError):
    """The slow orbit leaves the region where the averaging tables were built."""


class AveragingValidityWarning(UserWarning):
    """The prediction is outside the regime where the first-order theory is expected to hold."""


# ----------------------------------------------------------------------------- small helpers
def max_t_end(body: Body, theta0: float) -> float:
    """Largest t_end accepted by :func:`predict_slow_motion` for (body, θ0): ``MAX_MAXIMA`` · T_θ(0)/2, with T_θ(0)
    the time between maxima of pure rocking (quadrature)."""
    theta0 = check_map_theta0(theta0)
    return t_end_limit(float(symmetric_data(body.symmetric(), rest_energy(body, theta0), 0.0, 0.0)[0]))


# ----------------------------------------------------------------------------- tables
#: Functions of the table, in order: symmetric data, then the harmonics (c0, c1, s1) of
#: k_Q (Q_R, Q_J) and k_Θ in the drift–kick–drift form, then of the time and φ responses.
TABLE_FUNCTIONS = ("T", "W", "dphi",
                   "kQR_c0", "kQR_c1", "kQR_s1", "kQJ_c0", "kQJ_c1", "kQJ_s1", "kTh_c0", "kTh_c1", "kTh_s1",
                   "dt_c0", "dt_c1", "dt_s1", "dphi1_c0", "dphi1_c1", "dphi1_s1")
#: Parities in Q of a reversible map (time reversal: Q → −Q, Θ kept, t and φ steps reversed in order/sign).
_ODD = {"W", "dphi", "kTh_c0", "kTh_c1", "kTh_s1", "dphi1_c0", "dphi1_c1", "dphi1_s1"}
_EVEN = {"T", "kQR_c0", "kQR_c1", "kQR_s1", "kQJ_c0", "kQJ_c1", "kQJ_s1", "dt_c0", "dt_c1", "dt_s1"}


def _cheb_nodes(n: int) -> NDArray[np.float64]:
    return np.cos(math.pi * (np.arange(n) + 0.5) / n)


def _cheb_basis(x: ArrayLike, n: int) -> NDArray[np.float64]:
    """T_0..T_{n−1} at x ∈ [−1, 1], shape (n, ...), by the three-term recurrence T_k = 2x T_{k−1} − T_{k−2}
    (stable on [−1, 1]: each T_k is within ~k ulps of cos(k arccos x); 10× faster than the cosines)."""
    x = np.clip(np.asarray(x, float), -1.0, 1.0)
    T = np.empty((n,) + x.shape)
    T[0] = 1.0
    if n > 1:
        T[1] = x
    for k in range(2, n):
        T[k] = 2.0 * x * T[k - 1] - T[k - 2]
    return T


def _cheb_fit_matrix(n: int) -> NDArray[np.float64]:
    """A with c = A f for the interpolant at the first-kind nodes."""
    A = (2.0 / n) * _cheb_basis(_cheb_nodes(n), n)
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
    those of a whole region (:func:`rocknroller.analysis.slow_region.build_region_table`) follow the critical
    line Q_J,0^crit and the region's width.

    Attributes
    ----------
    a, I1, I3, g, theta0, E0 : the symmetric body, the release angle (NaN for a region table whose energy is
        not that of a release from rest in (0, π)) and the energy.
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
                from rocknroller.analysis.slow_region import boundary_distance

                delta = float(boundary_distance(self.body, self.E0, Q[0], Q[1]))
                raise AveragingRangeError(
                    f"the slow orbit left the tabulated region at Q=({Q[0]:.4g}, {Q[1]:.4g}), whose distance to "
                    f"steady rolling is (E - min U)/E = {delta:.3g}: the tables of E={self.E0:.6g} cover "
                    f"|u| <= {self.U:.4g} along the critical line Q_J,0^crit and distances >= "
                    f"{self.delta_min:g}; nearer steady rolling the oscillation of theta is too small to average")
            raise AveragingRangeError(
                f"the slow orbit left the tabulated region at Q=({Q[0]:.4g}, {Q[1]:.4g}): the tables cover "
                f"|u| <= {self.U:.4g} along the kick direction e=({self.e[0]:.4f}, {self.e[1]:.4f}) and "
                f"|v| <= {self.w_coef[0]:.3g} across it; the averaging is valid for K = eps*kappa < "
                f"{K_PERIOD_DOUBLING:g} (eps < {eps_period_doubling(self.kappa):.4g}) and orbits near pure rocking")
        nu, nv = self.coef.shape[1:]
        return (self.coef @ _cheb_basis(eta, nv)) @ _cheb_basis(xi, nu)

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
        return self.chart(*np.meshgrid(_cheb_nodes(nu), _cheb_nodes(nv), indexing="ij"))


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


def _table_key(builder: str, sym: Body, where: float, opts: dict[str, Any]) -> str:
    """The cache key of a table: version, builder, body, θ0 or E, and grid options (stored in the file; its SHA-256
    names it)."""
    return f"slowmap|{_TABLE_VERSION}|{builder}|{sym.params!r}|{where!r}|" + "|".join(
        f"{k}={opts[k]!r}" for k in sorted(opts))


def _table_spec(nu: int, nv: int) -> dict[str, tuple[int, ...]]:
    """Fields of a SlowMapTable file in checksum order, each float64 with this shape."""
    shapes = {"e": (2,), "n": (2,), "C0": (2,), "c_coef": (CHART_TERMS,), "w_coef": (CHART_TERMS,),
              "coef": (len(TABLE_FUNCTIONS), nu, nv)}
    return {name: shapes.get(name, ()) for name in SlowMapTable.__dataclass_fields__}


def build_table(body: Body, theta0: float, *, nu: int = 128, nv: int = 6, u_factor: float = 2.5,
                v_ratio: float = 0.002) -> SlowMapTable:
    """Tabulate the reversible first-order slow map of (body, θ0).

    Parameters
    ----------
    body : Body
        Its symmetric part is used (the tables do not depend on ε).
    theta0 : float
        Release angle in ``THETA0_RANGE``; E = U(θ0; 0, 0).
    nu, nv : int
        Chebyshev nodes along and across the kick direction (even, ≥ 4).
    u_factor : float
        U = u_factor · 4/|∂W/∂u|(0): the libration amplitude of the standard map at K = 4, times u_factor.
    v_ratio : float
        V = v_ratio · U.

    Raises
    ------
    ValueError
        θ0 outside ``THETA0_RANGE`` or bad grid options; AveragingRangeError if the energy of the release
        admits no motion somewhere on the table rectangle (possible for bodies other than the paper's).
    """
    theta0 = check_map_theta0(theta0)
    check_grid(nu, nv)
    if not (u_factor > 0 and 0 < v_ratio <= 1):
        raise ValueError(f"u_factor must be > 0 and v_ratio in (0, 1], got {u_factor!r}, {v_ratio!r}")
    sym = body.symmetric()
    E0 = rest_energy(sym, theta0)
    C0 = kick_at_rest(sym, E0)
    e = C0 / np.linalg.norm(C0)
    nvec = np.array([-e[1], e[0]])
    hq = 1e-7
    Wp = symmetric_data(sym, E0, np.array([hq * e[0], -hq * e[0]]), np.array([hq * e[1], -hq * e[1]]))[1]
    dW_du = (Wp[0] - Wp[1]) / (2 * hq)
    U = u_factor * K_PERIOD_DOUBLING / abs(dW_du)
    c_coef, w_coef = np.zeros(CHART_TERMS), np.zeros(CHART_TERMS)
    w_coef[0] = v_ratio * U
    frame = SlowMapTable(a=sym.a, I1=sym.I1, I3=sym.I3, g=sym.g, theta0=theta0, E0=E0, e=e, n=nvec, U=U,
                         c_coef=c_coef, w_coef=w_coef, coef=np.zeros((len(TABLE_FUNCTIONS), nu, nv)), C0=C0,
                         kappa=0.0, interp_error=0.0)
    QRg, QJg = frame.nodes()
    try:
        T, W, dphi, thX = symmetric_data(sym, E0, QRg, QJg)
    except ValueError as exc:
        raise AveragingRangeError(
            f"the averaging tables of theta0={theta0!r} cannot be built for this body ({sym.describe()}): on their "
            f"rectangle |u| <= {U:.4g} (2.5 times the libration amplitude at K = 4) {exc}") from None
    resp = np.empty((len(FIRST_ORDER_NAMES), nu, nv, 3))
    for i in range(nu):
        for j in range(nv):
            steps = [first_order_step(sym, E0, QRg[i, j], QJg[i, j], psi, theta_X=thX[i, j])
                     for psi in HARMONIC_PSI]
            for k, name in enumerate(FIRST_ORDER_NAMES):
                resp[k, i, j] = _harmonics([s.d[name] for s in steps])
    table = fit_table(frame, T, W, dphi, resp)
    err = _interpolation_error(table)
    if err > _INTERP_WARN:
        warnings.warn(f"the averaging tables for theta0={theta0!r} interpolate the coefficients only to {err:.1e} "
                      f"(relative); use more nodes (nu={nu}, nv={nv})", AveragingValidityWarning, stacklevel=2)
    return dataclasses.replace(table, interp_error=err)


def check_grid(nu: int, nv: int) -> None:
    """ValueError unless nu and nv are even integers ≥ 4 (and nv ≤ 64, the compiled kernel's limit)."""
    for name, val, top in (("nu", nu, 4096), ("nv", nv, 64)):
        if int(val) != val or not 4 <= val <= top or val % 2:
            raise ValueError(f"{name} must be an even integer in [4, {top}], got {name}={val!r}")


def kick_at_rest(sym: Body, E: float) -> NDArray[np.float64]:
    """C0 with ΔQ(0, Θ) = C0 sin Θ: the kick at Q = 0 from the three variational orbits at energy E."""
    at0 = [first_order_step(sym, E, 0.0, 0.0, psi) for psi in HARMONIC_PSI]
    return np.array([_harmonics([s.d[k] for s in at0])[2] for k in ("QR", "QJ")])


def fit_table(frame: SlowMapTable, T: NDArray, W: NDArray, dphi: NDArray, resp: NDArray) -> SlowMapTable:
    """The table on ``frame``'s chart from the data at its Chebyshev nodes (x_i, τ_j).

    T, W, Δφ (mod π) of the symmetric orbit and ``resp`` (len(FIRST_ORDER_NAMES), nu, nv, 3), the harmonics of
    the ε-responses.  W and Δφ are lifted to continuous branches (along τ, then along x through the middle of
    the chart, odd in Q); the kick is put in drift–kick–drift form (module docstring) with ∇F by the chain
    rule through the chart; each function gets its parity in Q ((x, τ) → (−x, −τ)) and its Chebyshev series.
    ``frame`` supplies everything but ``coef`` and ``kappa``.
    """
    nu, nv = T.shape
    xu, xv = _cheb_nodes(nu), _cheb_nodes(nv)  # ξ, η
    W, dphi = _lift(W, 2.0 * math.pi), _lift(dphi, math.pi)
    Au, Av = _cheb_fit_matrix(nu), _cheb_fit_matrix(nv)
    cheb = np.polynomial.chebyshev
    e, nvec = frame.e, frame.n
    dxi_du, deta_du, deta_dv = frame.inverse_jacobian(*np.meshgrid(xu, xv, indexing="ij"))

    def parity(F: NDArray, kind: str) -> NDArray:
        flipped = F[::-1, ::-1]
        return 0.5 * (F + flipped) if kind == "even" else 0.5 * (F - flipped) if kind == "odd" else F

    def fit(F: NDArray) -> NDArray:
        return Au @ F @ Av.T

    half = 0.5 * parity(W, "odd")
    cw, sw = np.cos(half), np.sin(half)

    def rotate(h: NDArray) -> NDArray:  # harmonics of F(Θ' − W/2) from those of F(Θ)
        c0, c1, s1 = h[..., 0], h[..., 1], h[..., 2]
        return np.stack([c0, c1 * cw - s1 * sw, c1 * sw + s1 * cw], axis=-1)

    kQR, kQJ = rotate(resp[0]), rotate(resp[1])

    def gradient(F: NDArray, kind: str) -> tuple[NDArray, NDArray]:
        """(∂F/∂u, ∂F/∂v) at the nodes, F a symmetric-orbit function fitted on the grid."""
        c = fit(parity(F, kind))
        f_xi, f_eta = (cheb.chebgrid2d(xu, xv, cheb.chebder(c, axis=k)) for k in (0, 1))
        return f_xi * dxi_du + f_eta * deta_du, f_eta * deta_dv

    def half_grad_dot_kQ(F: NDArray, kind: str) -> NDArray:
        """½ ∇F·k_Q at the nodes (harmonics)."""
        gu, gv = gradient(F, kind)
        return 0.5 * (gu[..., None] * (e[0] * kQR + e[1] * kQJ) + gv[..., None] * (nvec[0] * kQR + nvec[1] * kQJ))

    # the part of each response received after the kick is carried by the second half-drift
    kTh = rotate(resp[2]) - half_grad_dot_kQ(W, "odd")
    kT = rotate(resp[3]) - half_grad_dot_kQ(T, "even")
    kP = rotate(resp[4]) - half_grad_dot_kQ(dphi, "odd")
    data = {"T": T, "W": W, "dphi": dphi}
    for pre, arr in (("kQR", kQR), ("kQJ", kQJ), ("kTh", kTh), ("dt", kT), ("dphi1", kP)):
        for m, suf in enumerate(("c0", "c1", "s1")):
            data[f"{pre}_{suf}"] = arr[..., m]
    coef = np.empty((len(TABLE_FUNCTIONS), nu, nv))
    for k, name in enumerate(TABLE_FUNCTIONS):
        kind = "odd" if name in _ODD else "even" if name in _EVEN else "none"
        coef[k] = fit(parity(np.asarray(data[name], float), kind))
    table = dataclasses.replace(frame, coef=coef)
    gu, gv = (float(g) for g in table.gradient("W", (0.0, 0.0)))
    return dataclasses.replace(table, kappa=gu * frame.C0 @ e + gv * frame.C0 @ nvec)


def _lift(F: NDArray, period: float) -> NDArray:
    """F (given modulo ``period`` on the nodes) on a continuous branch: along τ (axis 1), then the middle
    column along x, and the multiple of ``period`` that makes F odd under (x, τ) → (−x, −τ)."""
    F = np.unwrap(F, axis=1, period=period)
    mid = F[:, F.shape[1] // 2]
    F = F + (np.unwrap(mid, period=period) - mid)[:, None]
    return F - period * np.round(np.mean(F + F[::-1, ::-1]) / (2.0 * period))


#: Off-grid points (u/U, v/V) at which a new table is checked against direct coefficients.
_CHECK_POINTS = ((0.37, 0.3), (-0.81, -0.55), (0.93, 0.8))
_INTERP_WARN = 1e-7


def _interpolation_error(table: SlowMapTable) -> float:
    """Largest relative error of the table against :func:`step_coefficients` at ``_CHECK_POINTS``."""
    sym, worst = table.body, 0.0
    for x, y in _CHECK_POINTS:
        Q = np.array(table.chart(x, y))
        sc = step_coefficients(sym, table.E0, float(Q[0]), float(Q[1]))
        vals = dict(zip(TABLE_FUNCTIONS, table.evaluate(Q)))
        w = 0.5 * vals["W"]
        errs = [abs(vals["T"] / sc.T - 1.0), abs(float(wrap_angle(vals["W"] - sc.W))) / max(abs(sc.W), 1e-300)]
        for name in ("QR", "QJ"):  # k_Q is ΔQ with its phase advanced by W/2; relative to the largest harmonic
            c0, c1, s1 = (vals[f"k{name}_{h}"] for h in ("c0", "c1", "s1"))
            scale = max(abs(v) for v in sc.harmonics[name])
            back = (c0, c1 * math.cos(w) + s1 * math.sin(w), -c1 * math.sin(w) + s1 * math.cos(w))
            errs += [abs(b - a) / scale for b, a in zip(back, sc.harmonics[name])]
        worst = max(worst, *errs)
    return float(worst)


def load_or_build_table(body: Body, theta0: float, *, build: bool = True, use_cache: bool = True,
                        **grid: Any) -> SlowMapTable:
    """The tables of (body, θ0): from memory, from the disk cache, or built (and cached).

    The cache file holds plain float64 arrays, the key and a SHA-256 checksum (``rocknroller.numerics.cache``; read with
    ``allow_pickle=False``).  A file that fails any check is never used: it is rebuilt and replaced, with a
    ``CacheWarning``; an unwritable cache directory gives one ``CacheWarning`` per process (docs/averaging.md).

    Parameters
    ----------
    body : Body
        Its symmetric part is used.
    theta0 : float
        Release angle in ``THETA0_RANGE``.
    build : bool
        If False and no valid cached table exists, raise ValueError instead of building.
    use_cache : bool
        Read and write the disk cache (``rocknroller.numerics.cache.cache_dir()/averaging``).
    grid : keyword arguments of :func:`build_table`.
    """
    theta0 = check_map_theta0(theta0)
    return cached_table(build_table, body, theta0, f"theta0={theta0!r}", build=build, use_cache=use_cache, **grid)


#: Options of a table builder that change how it runs, not the table (not part of the cache key).
_RUN_OPTIONS = ("progress", "workers")


def cached_table(builder: Callable[..., SlowMapTable], body: Body, where: float, what: str, *, build: bool = True,
                 use_cache: bool = True, **grid: Any) -> SlowMapTable:
    """``builder(body.symmetric(), where, **grid)`` from memory, from the disk cache, or built (and cached).

    ``what`` names ``where`` in messages.  The key holds the table version, the builder, the body, ``where`` and every
    keyword-only option of the builder (defaults filled in); see :func:`load_or_build_table`.
    """
    sym = body.symmetric()
    params = inspect.signature(builder).parameters
    opts = {name: p.default for name, p in params.items() if p.kind is p.KEYWORD_ONLY and name not in _RUN_OPTIONS}
    unknown = set(grid) - set(opts) - set(_RUN_OPTIONS)
    if unknown:
        raise ValueError(f"unknown table options {sorted(unknown)}; allowed: {sorted(opts)}")
    run = {name: grid.pop(name) for name in _RUN_OPTIONS if name in grid and name in params}
    opts.update(grid)
    key = _table_key(builder.__name__, sym, where, opts)
    if key in _TABLES:
        return _TABLES[key]
    directory = os.path.join(str(cache_dir()), "averaging")
    path = os.path.join(directory, f"slowmap-{hashlib.sha256(key.encode()).hexdigest()[:20]}.npz")
    spec = _table_spec(opts["nu"], opts["nv"])
    table = None
    if use_cache and os.path.lexists(path):
        arrays, reason = load_arrays(path, key, spec)
        if arrays is None:
            warnings.warn(f"the cached averaging table {path} is not used ({reason}); it is rebuilt", CacheWarning,
                          stacklevel=3)
        else:
            table = SlowMapTable(**{k: (a if a.ndim else float(a)) for k, a in arrays.items()})
    if table is None:
        if not build:
            raise ValueError(
                f"no averaging tables for {what} and this body ({sym.describe()}); they are built "
                "on first use: call without build=False / --cached-only")
        table = builder(sym, where, **opts, **run)
        if use_cache:
            try:
                save_arrays(path, key, {k: getattr(table, k) for k in spec})
            except OSError as exc:
                warn_unwritable(directory, exc, f"the averaging tables are rebuilt in every process (for each body "
                                f"and {what.split('=')[0]})")
    _TABLES[key] = table
    return table


# ----------------------------------------------------------------------------- the map
@dataclass(frozen=True)
class SlowSeries:
    """Samples of the slow map at the θ-maxima n = 1, 2, ... with t_n ≤ t_end.

    ``Theta`` is unwrapped (continuous); ``phi`` is the accumulated azimuth modulo π-jumps (use mod π).
    """

    t: NDArray[np.float64]
    QR: NDArray[np.float64]
    QJ: NDArray[np.float64]
    Theta: NDArray[np.float64]
    phi: NDArray[np.float64]

    @property
    def psi_mod_pi(self) -> NDArray[np.float64]:
        """ψ mod π at the maxima."""
        return np.mod(0.5 * self.Theta, math.pi)

    @property
    def phi_mod_pi(self) -> NDArray[np.float64]:
        """φ mod π at the maxima (the visible half-angle)."""
        return np.mod(self.phi, math.pi)

    def to_dataframe(self) -> "pandas.DataFrame":  # noqa: F821
        """One row per maximum: t, Q_R, Q_J, Θ, φ (needs pandas)."""
        from rocknroller.analysis.frames import dataframe

        return dataframe({n: getattr(self, n) for n in ("t", "QR", "QJ", "Theta", "phi")})


_IDX = {name: i for i, name in enumerate(TABLE_FUNCTIONS)}
_HARM = ("c0", "c1", "s1")
#: Points of the fine uniform grid in u used at run time (6-point Lagrange interpolation between them).
_FINE_POINTS = 8193
#: Run-time functions: 0-8 the harmonics (c0, c1, s1) of k_u = e·k_Q, k_v = n·k_Q and k_Θ (solved for
#: implicitly), 9-14 those of the time and φ kicks, 15-17 the drifts T_θ, W, Δφ.
_N_KICK = 15
_FAST: dict[int, "_FastTable"] = {}
#: Kernel statuses (analysis/_slow_map_kernel.c).
_DONE, _FULL, _LEFT_TABLE, _NO_CONVERGENCE = range(4)
#: Largest number of output rows the kernel fills per call.
_CHUNK = 1 << 16


def _at_points(coef: NDArray[np.float64], basis: NDArray[np.float64]) -> NDArray[np.float64]:
    """Σ_k coef[f, k, j] basis[k, i] as an array (i, f, j): Chebyshev series in x at the points of ``basis``
    (one BLAS product; an einsum without optimisation loops in C one term at a time, ~25× slower here)."""
    return np.tensordot(basis, coef, axes=([0], [1]))


class _FastTable:
    """Run-time form of a SlowMapTable: values on a fine uniform grid in x = u/U, Chebyshev series in τ.

    Each row of ``rows`` holds the 18 run-time functions (see ``_N_KICK``) at one grid point as
    Chebyshev coefficients in τ; 6-point Lagrange interpolation in x on 8193 points reproduces the
    Chebyshev interpolant to ~1e-13 relative.  ``geom`` holds the chart there (c, w, c'/U, w'/U).
    ``rows_jac`` adds the x- (over U) and τ-derivatives of the
    Chebyshev series of the kick functions 0-14, for the Jacobian of the implicit kick and a
    first-order correction of ε k_t, ε k_φ by less than the kick tolerance (they set the speed of
    convergence, not the converged value).  The rows are evaluated, and the map stepped, by the
    compiled kernel ``rocknroller.analysis._slow_map_kernel`` (about 1 µs a step).
    """

    def __init__(self, table: SlowMapTable) -> None:
        c = table.coef
        e, n = table.e, table.n
        rows = []
        for h in _HARM:
            qr, qj = c[_IDX[f"kQR_{h}"]], c[_IDX[f"kQJ_{h}"]]
            rows.append((e[0] * qr + e[1] * qj, n[0] * qr + n[1] * qj))
        kick = [rows[m][0] for m in range(3)] + [rows[m][1] for m in range(3)]
        kick += [c[_IDX[f"{pre}_{h}"]] for pre in ("kTh", "dt", "dphi1") for h in _HARM]
        drift = [c[_IDX[name]] for name in ("T", "W", "dphi")]
        self.U, self.nv = float(table.U), c.shape[2]
        self.e, self.n = e, n
        xi = np.linspace(-1.0, 1.0, _FINE_POINTS)
        self.dx = float(xi[1] - xi[0])
        self.alpha, self.beta = float(table.alpha), float(table.beta)
        self.geom = np.ascontiguousarray(np.stack(table._sides(stretch(xi, self.alpha)), axis=1))
        Bu = _cheb_basis(xi, c.shape[1])                                  # (nu, Nf)
        fine = np.concatenate([_at_points(np.array(kick), Bu),
                               _at_points(np.array(drift), Bu)], axis=1)  # (Nf, 18, nv)
        kick = np.array(kick)
        du = np.polynomial.chebyshev.chebder(kick, axis=1) / self.U                 # (15, nu − 1, nv)
        dv = np.polynomial.chebyshev.chebder(kick, axis=2)                          # (15, nu, nv − 1), d/dτ
        dv = np.concatenate([dv, np.zeros(dv.shape[:2] + (1,))], axis=2)
        fine_d = np.concatenate([_at_points(du, Bu[: du.shape[1]]),
                                 _at_points(dv, Bu)], axis=1)         # (Nf, 30, nv)
        self.rows = np.ascontiguousarray(fine.reshape(_FINE_POINTS, -1))
        self.rows_jac = np.ascontiguousarray(np.concatenate([fine, fine_d], axis=1).reshape(_FINE_POINTS, -1))
        self.table = table

    def _evaluate(self, rows: NDArray[np.float64], u: float, v: float) -> list[float]:
        out = _kernel.evaluate(rows, self.geom, rows.shape[1] // self.nv, self.nv, self.U, self.alpha, self.beta,
                               self.dx, u, v)
        if out is None:
            self.table.evaluate(u * self.e + v * self.n)  # raises AveragingRangeError with the explanation
        return out

    def values(self, u: float, v: float) -> list[float]:
        """The 18 run-time functions at Q = u e + v n."""
        return self._evaluate(self.rows, u, v)

    def values_and_jacobian(self, u: float, v: float) -> list[float]:
        """The 18 functions, then ∂/∂u and ∂/∂v of the kick functions (0-14): 48 values."""
        return self._evaluate(self.rows_jac, u, v)

    def iterate(self, eps: float, u: float, v: float, Th: float, phi: float, t_end: float,
                n_steps: int | None) -> tuple[NDArray[np.float64], tuple[int, int]]:
        """Rows (t, u, v, Θ, φ) of the maxima after the start with t ≤ t_end (at most ``n_steps``),
        and the numbers of table evaluations with and without the Jacobian rows."""
        # room for t_end / (T_θ(0)/2) maxima, at most _CHUNK rows at a time
        cap = min(int(t_end / (0.5 * abs(self.values(0.0, 0.0)[_N_KICK]))) + 8, _CHUNK)
        cap = cap if n_steps is None else min(int(n_steps), cap)
        chunks, t, counts = [], 0.0, [0, 0]
        while True:
            out = np.empty((max(cap, 1), 5))
            n, status, ub, vb, n_jac, n_plain = _kernel.iterate(self.rows, self.rows_jac, self.geom, out, self.U,
                                                                 self.alpha, self.beta, self.dx, self.nv, eps, u, v,
                                                                 Th, t, phi, t_end)
            counts[0] += n_jac
            counts[1] += n_plain
            chunks.append(out[:n])
            done = sum(len(c) for c in chunks)
            if status == _LEFT_TABLE:
                self.table.evaluate(ub * self.e + vb * self.n)  # raises AveragingRangeError with the explanation
            if status == _NO_CONVERGENCE:
                raise AveragingRangeError(
                    f"the implicit kick did not converge at eps={eps!r}: eps is too large for the first-order map")
            if status == _DONE or (n_steps is not None and done >= n_steps):
                break
            if done > MAX_MAXIMA:  # t_end was checked against T_θ(0)/2 per maximum; T_θ ≥ 0.7 T_θ(0) on the tables
                raise ValueError(f"t_end={t_end!r} gives more than MAX_MAXIMA = {MAX_MAXIMA} maxima")
            assert status == _FULL
            t, u, v, Th, phi = (float(x) for x in out[n - 1])  # out was full: go on from the last maximum
            cap = _CHUNK if n_steps is None else min(_CHUNK, n_steps - done)
        return np.concatenate(chunks), (counts[0], counts[1])


def _fast(table: SlowMapTable) -> _FastTable:
    ft = _FAST.get(id(table))
    if ft is None or ft.table is not table:
        ft = _FastTable(table)
        _FAST[id(table)] = ft
    return ft


def iterate_slow_map(table: SlowMapTable, eps: float, psi0: float, t_end: float, *,
                     Q0: ArrayLike = (0.0, 0.0), phi0: float = 0.0, n_steps: int | None = None) -> SlowSeries:
    """Iterate the reversible drift–kick–drift slow map from a maximum at t = 0.

    One step: Θ += W(Q)/2; (Q, Θ) += ε k(midpoint) (implicit midpoint, solved by simplified Newton
    to 1e-13 of the kick, + 4 ulp, or until the observed contraction η puts the remaining error
    η/(1 − η) × change below 1e-3 of that; Hairer & Wanner, Solving ODEs II, §IV.8); Θ += W(Q')/2;
    t += ½[T_θ(Q) + T_θ(Q')] + ε k_t(midpoint); φ += ½[Δφ(Q) + Δφ(Q')] + ε k_φ(midpoint).
    The loop runs in the compiled kernel ``rocknroller.analysis._slow_map_kernel``.

    Parameters
    ----------
    table : SlowMapTable
    eps : float
        Asymmetry ε ≥ 0.
    psi0 : float
        ψ at the starting maximum (Θ0 = 2ψ0).
    t_end : float
        Last time, 0 < t_end ≤ MAX_MAXIMA · T_θ(0)/2 (at most ``MAX_MAXIMA`` maxima; unbounded if n_steps is given).
    Q0 : (Q_R, Q_J) at the start (default: released from rest, Q = 0).
    phi0 : φ at the start.
    n_steps : int, optional
        Stop after this many steps (even before t_end), 1 ≤ n_steps ≤ ``MAX_MAXIMA``.

    Raises
    ------
    ValueError
        Bad input, naming the parameter and its range.
    AveragingRangeError
        If the orbit leaves the tabulated region, or the implicit kick does not converge.
    """
    eps, t_end, psi0 = float(eps), float(t_end), float(psi0)
    if not math.isfinite(eps) or eps < 0.0:
        raise ValueError(f"eps must be a finite number >= 0, got eps={eps!r}")
    if not math.isfinite(psi0):
        raise ValueError(f"psi0 must be finite, got psi0={psi0!r}")
    if n_steps is not None and (int(n_steps) != n_steps or not 1 <= n_steps <= MAX_MAXIMA):
        raise ValueError(f"n_steps must be an integer in [1, {MAX_MAXIMA}] (MAX_MAXIMA), got n_steps={n_steps!r}")
    ft = _fast(table)
    if n_steps is None:
        check_t_end(t_end, ft.values(0.0, 0.0)[_N_KICK])
    elif not (math.isfinite(t_end) and t_end > 0.0):
        raise ValueError(f"t_end must be a finite number > 0, got t_end={t_end!r}")
    Q0 = np.asarray(Q0, float)
    if Q0.shape != (2,) or not np.all(np.isfinite(Q0)) or not math.isfinite(float(phi0)):
        raise ValueError(f"Q0 must be two finite numbers (Q_R, Q_J) and phi0 finite, got Q0={Q0!r}, phi0={phi0!r}")
    arr, _ = ft.iterate(eps, float(ft.e @ Q0), float(ft.n @ Q0), 2.0 * psi0, float(phi0), t_end, n_steps)
    Q = np.outer(arr[:, 1], ft.e) + np.outer(arr[:, 2], ft.n)
    return SlowSeries(t=arr[:, 0], QR=Q[:, 0], QJ=Q[:, 1], Theta=unwrap_phase(arr[:, 3]), phi=arr[:, 4])


def line_slope(QR: ArrayLike, QJ: ArrayLike) -> float | None:
    """Slope dQ_J/dQ_R of the straight line through turning-point samples (total least squares).

    The line's direction is the principal axis of the samples' 2×2 scatter matrix S, at the angle
    α = ½ atan2(2 S_RJ, S_RR − S_JJ); the slope is tan α.  None (undefined) for fewer than two samples or
    samples that all coincide (S = 0: no line, e.g. pure rocking at Q = 0).
    """
    x, y = np.asarray(QR, float), np.asarray(QJ, float)
    if x.size < 2:
        return None
    x, y = x - x.mean(), y - y.mean()
    sxx, syy, sxy = float(x @ x), float(y @ y), float(x @ y)
    if sxx == 0.0 and syy == 0.0:
        return None
    return math.tan(0.5 * math.atan2(2.0 * sxy, sxx - syy))


@dataclass(frozen=True)
class SlowPrediction:
    """Averaged prediction of the slow motion of a body released from rest at (θ0, ψ0).

    Attributes
    ----------
    eps, theta0, psi0, t_end : inputs (θ0 and ψ0 of the initial state, for a start with velocity).
    K : ε κ, the standard-map parameter near pure rocking.
    slow_period : period of Θ = 2ψ at the maxima; None if undefined (pure rocking) or not measurable
        within t_end (fewer than two crossings of the mean).
    QR_extent, QJ_extent : max − min of Q_R, Q_J at the maxima within t_end.
    Phi : span of φ mod π at the maxima within t_end.
    line_slope : dQ_J/dQ_R of the line through the samples; None if undefined (:func:`line_slope`).
    series : SlowSeries.
    regions, region_runs, crossings : critical region of each sample, runs of consecutive rocks in
        one region, and the crossings of the critical lines (:func:`critical_regions`).
    pure_rocking : True for ε = 0 (Routh's sphere released from rest): Q_R = Q_J = 0 exactly at every
        maximum, the intersection of both critical lines, and Θ, φ mod π are constant.  Then every
        sample's region is ``criticality.ON_BOTH``, there are no region runs or crossings, the extents
        and Φ are 0 and the slow period and line slope are None.
    start : the initial state of a start with velocity (None for a release from rest).
    """

    eps: float
    theta0: float
    psi0: float
    t_end: float
    K: float
    slow_period: float | None
    QR_extent: float
    QJ_extent: float
    Phi: float
    line_slope: float | None
    series: SlowSeries = field(repr=False)
    regions: Any = field(default=None, repr=False)
    region_runs: list[tuple[str, int, float]] | None = field(default=None, repr=False)
    crossings: list[tuple[float, str, str, str]] | None = field(default=None, repr=False)
    pure_rocking: bool = False
    start: EulerState | None = field(default=None, repr=False)

    @property
    def rocks_per_region(self) -> dict[str, int]:
        """Total number of rocks (maxima) in each critical region within t_end."""
        return rocks_per_region(self.region_runs)

    def to_dataframe(self) -> "pandas.DataFrame":  # noqa: F821
        """The series at the maxima (:meth:`SlowSeries.to_dataframe`) with each maximum's critical region."""
        frame = self.series.to_dataframe()
        if self.regions is not None:
            frame["region"] = np.asarray(self.regions)
        return frame

    def plot(self, ax: Any = None) -> Any:
        """Draw the predicted (Q_R, Q_J) at the θ-maxima on ``ax`` (a new pyplot figure without one); returns
        the axes.  Over the critical lines: :func:`rocknroller.papers.plotting.draw_critical_lines`."""
        if ax is None:
            import matplotlib.pyplot as plt

            _, ax = plt.subplots(figsize=(5, 4))
        ax.plot(self.series.QR, self.series.QJ, ".", ms=3, color="k", label="averaged map (maxima)")
        ax.set_xlabel("$Q_R$")
        ax.set_ylabel("$Q_J$")
        return ax


def predict_slow_motion(body: Body, theta0: float | EulerState, psi0: float | None = None,
                        t_end: float = 1000.0, *,
                        table: SlowMapTable | None = None, build: bool = True) -> SlowPrediction:
    """Predict the slow (Q_R, Q_J) motion of ``body`` released from rest at θ0 with spin angle ψ0, or from any
    initial state.

    Parameters
    ----------
    body : Body
        The asymmetric body (ε = body.epsilon ≥ 0).
    theta0 : float or EulerState
        Release tilt, 0 < θ0 ≤ 0.999π: in ``THETA0_RANGE`` = [0.75π, 0.999π] the release tables (validated
        against the direct ODE, docs/averaging.md); below, the region tables of the release's energy (as for an
        EulerState from rest); other values are refused (ValueError).
        Or an initial state (the one ``simulate`` takes): it is carried to its first θ-maximum by a short
        direct integration (:func:`rocknroller.analysis.slow_orbit.first_maximum`) and the map is iterated from
        there on the region tables of its energy (:mod:`rocknroller.analysis.slow_region`); then ``psi0`` is
        not given and ``table`` is a region table of that energy, if given.
    psi0 : float
        Release spin angle (Θ0 = 2ψ0).
    t_end : float
        Time span, 0 < t_end ≤ ``MAX_MAXIMA`` · T_θ(0)/2 (:func:`max_t_end`; 6.6e6 at θ0 = 0.95π): checked
        before anything is built.
    table : SlowMapTable, optional
        Precomputed tables of (body, θ0); by default :func:`load_or_build_table`.
    build : bool
        Build the tables if they are not cached (else ValueError).

    Returns
    -------
    SlowPrediction
        For ε = 0 (Routh's sphere) the exact pure rocking (``pure_rocking``): no slow motion, Q = 0 on
        both critical lines, no region runs; the slow period and line slope are None.

    Raises
    ------
    ValueError
        θ0, ψ0 or t_end out of range (naming it), or a table for another (body, θ0).

    Warns
    -----
    AveragingValidityWarning
        If K = ε κ > 4 (pure rocking about the stable axis has period-doubled).
    """
    if isinstance(theta0, EulerState):
        if psi0 is not None:
            raise ValueError("psi0 is part of the initial state: give either (theta0, psi0) or an EulerState")
        return _predict_from_state(body, theta0, t_end, table=table, build=build)
    if psi0 is None:
        raise ValueError("psi0 must be given with a release angle theta0")
    if table is None and releases_on_region_tables(theta0):
        return _predict_from_state(body, EulerState(float(theta0), 0.0, float(psi0)), t_end, table=None, build=build)
    theta0 = check_map_theta0(theta0)
    eps, psi0 = body.epsilon, float(psi0)
    if not math.isfinite(psi0):
        raise ValueError(f"psi0 must be finite, got psi0={psi0!r}")
    if table is None:
        check_t_end(t_end, float(symmetric_data(body.symmetric(), rest_energy(body, theta0), 0.0, 0.0)[0]))
        table = load_or_build_table(body, theta0, build=build)
    elif abs(table.theta0 - theta0) > 1e-15:
        raise ValueError(f"the table is for theta0={table.theta0!r}, not {theta0!r}")
    elif table.body != body.symmetric():
        raise ValueError(f"the table is for the body {table.body.describe()}, not {body.symmetric().describe()}")
    K = eps * table.kappa
    _warn_validity(eps, table)
    if eps == 0.0:  # Routh's sphere from rest: rocking in a fixed vertical plane, Q ≡ 0, ψ and φ mod π fixed
        from rocknroller.analysis.criticality import ON_BOTH

        T0 = _fast(table).values(0.0, 0.0)[_N_KICK]
        t = T0 * np.arange(1, int(check_t_end(t_end, T0) // T0) + 1)
        zero = np.zeros_like(t)
        return SlowPrediction(
            eps=eps, theta0=theta0, psi0=psi0, t_end=float(t_end), K=0.0, slow_period=None, QR_extent=0.0,
            QJ_extent=0.0, Phi=0.0, line_slope=None,
            series=SlowSeries(t=t, QR=zero, QJ=zero.copy(), Theta=np.full_like(t, 2.0 * psi0), phi=zero.copy()),
            regions=np.full(t.size, ON_BOTH, dtype=object), region_runs=[], crossings=[], pure_rocking=True)
    return _prediction(eps, theta0, psi0, t_end, K, iterate_slow_map(table, eps, psi0, t_end), table.body)


#: Largest interpolation error of a region table for which its predictions are given without a warning: the
#: map's own error is O(ε) of the slow motion, and a table error δ adds ~N δ over N rocks (N ≲ 10³ in 10⁴ t.u.).
REGION_TABLE_ACCURACY = 1e-6


def _warn_validity(eps: float, table: SlowMapTable) -> None:
    """AveragingValidityWarning if K = ε κ exceeds 4 or a region table interpolates worse than its accuracy."""
    K = eps * table.kappa
    if abs(K) > K_PERIOD_DOUBLING:
        warnings.warn(
            f"K = eps*kappa = {K:.3g} > {K_PERIOD_DOUBLING:g}: pure rocking about the stable principal axis is "
            f"unstable (period doubling at eps = {eps_period_doubling(table.kappa):.4g}); the first-order "
            f"averaging is expected to hold for K < {K_PERIOD_DOUBLING:g}", AveragingValidityWarning, stacklevel=3)
    if table.delta_min > 0.0 and table.interp_error > REGION_TABLE_ACCURACY:
        warnings.warn(
            f"the region tables of E={table.E0:.6g} interpolate the map's coefficients only to {table.interp_error:.1e} "
            f"(> {REGION_TABLE_ACCURACY:g}): near Q = 0, W turns by ~2 pi over 1/|grad W(0)|, which their Chebyshev "
            "grid resolves up to the energy of a release from about 0.7 pi (docs/averaging.md, 'Starts with "
            "velocity'); the prediction carries that error", AveragingValidityWarning, stacklevel=3)


def releases_on_region_tables(theta0: float) -> bool:
    """True for release angles 0 < θ0 < ``THETA0_RANGE[0]``, which the region tables serve (the release tables'
    rectangle would leave the region of motion there)."""
    return isinstance(theta0, (int, float)) and 0.0 < float(theta0) < THETA0_RANGE[0]


def _prediction(eps: float, theta0: float, psi0: float, t_end: float, K: float, series: SlowSeries,
                sym: Body, start: EulerState | None = None) -> SlowPrediction:
    """The diagnostics of a series of maxima."""
    regions, runs, crossings = critical_regions(series.QR, series.QJ, series.t, sym)
    return SlowPrediction(
        eps=eps, theta0=theta0, psi0=float(psi0), t_end=float(t_end), K=K,
        slow_period=slow_period(series.t, series.Theta) if series.t.size >= 3 else None,
        QR_extent=span(series.QR), QJ_extent=span(series.QJ), Phi=azimuth_span(series.phi),
        line_slope=line_slope(series.QR, series.QJ),
        series=series, regions=regions, region_runs=runs, crossings=crossings, start=start)


def _predict_from_state(body: Body, start: EulerState, t_end: float, *, table: SlowMapTable | None,
                        build: bool) -> SlowPrediction:
    """predict_slow_motion from an initial state: its first maximum, then the map on the region tables."""
    from rocknroller.analysis.slow_region import load_or_build_region_table

    t_end = float(t_end)
    if not (math.isfinite(t_end) and t_end > 0.0):
        raise ValueError(f"t_end must be a finite number > 0, got t_end={t_end!r}")
    fm = first_maximum(body, start)
    if fm.t >= t_end:
        raise ValueError(f"t_end={t_end!r} ends before the first maximum of theta (t = {fm.t:.6g})")
    if table is None:
        table = load_or_build_region_table(body, fm.E, build=build)
    elif abs(table.E0 - fm.E) > 8.0 * math.ulp(fm.E) or table.delta_min == 0.0:  # E from two formulas: rounding
        raise ValueError(f"the table is not the region table of this start's energy E={fm.E!r}")
    elif table.body != body.symmetric():
        raise ValueError(f"the table is for the body {table.body.describe()}, not {body.symmetric().describe()}")
    eps = body.epsilon
    _warn_validity(eps, table)
    rest = iterate_slow_map(table, eps, fm.psi, t_end - fm.t, Q0=(fm.QR, fm.QJ), phi0=fm.phi)
    first = [fm.t > 0.0]  # a start that is itself a maximum is not a sample (the ODE reports none at t = 0)
    series = SlowSeries(t=np.concatenate([[fm.t][: sum(first)], fm.t + rest.t]),
                        QR=np.concatenate([[fm.QR][: sum(first)], rest.QR]),
                        QJ=np.concatenate([[fm.QJ][: sum(first)], rest.QJ]),
                        Theta=unwrap_phase(np.concatenate([[2.0 * fm.psi][: sum(first)], rest.Theta])),
                        phi=np.concatenate([[fm.phi][: sum(first)], rest.phi]))
    return _prediction(eps, float(start.theta), float(start.psi), t_end, eps * table.kappa, series, table.body,
                       start=start)


def critical_regions(QR: ArrayLike, QJ: ArrayLike, t: ArrayLike, body: Body):
    """Critical region of each turning-point sample, the runs of consecutive rocks in one region, and
    the crossings of the critical lines.

    Returns
    -------
    (regions, runs, crossings)
        regions: array of "I".."IV"; runs: list of (region, number of rocks, time of the first);
        crossings: list of (t, from, to, line) with line "QJ0crit" (full-angle reversal) and/or
        "QJpicrit" (visible-angle reversal).  A sample exactly on a line (u = 0) counts as above it.
    """
    from rocknroller.analysis.criticality import region_from_offsets, side_code  # imported here: it loads sympy

    u0, upi = u_ends(QR, QJ, body.symmetric())
    regions = region_from_offsets(u0, upi).astype(object)
    side = side_code(u0, upi)
    starts = np.flatnonzero(np.concatenate([[True], side[1:] != side[:-1]]))[: side.size].tolist()
    labels, sides, times = regions.tolist(), side.tolist(), np.asarray(t, float).tolist()
    runs = [(labels[i], j - i, times[i]) for i, j in zip(starts, starts[1:] + [len(labels)])]
    crossings = []
    for i in starts[1:]:
        flip = sides[i] ^ sides[i - 1]  # the lines crossed (bits of side_code)
        lines = "+".join(name for name, bit in (("QJ0crit", 2), ("QJpicrit", 1)) if flip & bit)
        crossings.append((times[i], labels[i - 1], labels[i], lines))
    return regions, runs, crossings
