"""Rocking period and precession of Routh's sphere by quadrature (paper §2.5, eq. Delta_phi).

Conventions (DESIGN §2).  T_θ = 2∫_{θ_N}^{θ_X} dθ/√F is the time between successive maxima of
θ; the paper's τ = 4∫ = 2 T_θ.  Δφ and Δψ are the increments of the full (unwrapped) angles,
given per T_θ and per τ; the visible angle is Δφ mod 2π, the visible half-angle Δφ mod π (both
returned in the symmetric ranges (−π, π] and (−π/2, π/2], so that their sign is the apparent
sense of precession).

Substitution.  With c = cos θ, dθ/√F = dc/√(P/D) (reduction: P = s² D F is regular), and the
turning points are simple roots of P.  Writing x = 1 − c = x_N + H sin²(v/2) and
y = 1 + c = y_X + H cos²(v/2), H = c_N − c_X, v ∈ [0, π], removes both inverse square roots:

    ∫_{θ_N}^{θ_X} dθ/√F = ∫_0^π J dv,   J = H sin(v/2) cos(v/2) √(D/P) = √(D/Q),

Q = P/((c − c_X)(c_N − c)) analytic and positive.  This is the variable of the mpmath reference
(tanh-sinh on [0, π/2] and [π/2, π], each from its own end).

Shadow roots.  When θ_X → π with Q_J near Q_J,π^crit (the paper's rocking regime), P has a second
root y_s ≤ 0 just beyond θ = π, at a distance ~y_X from the turning point: in v that is a branch
point at distance ~√(y_X) from the real axis, and a Gauss–Chebyshev rule in v would need ~1/√(y_X)
nodes.  The double backend therefore splits [c_X, c_N] in the middle and uses on each half
z − z_end = Δ sinh²t (z = y near θ_X, z = x near θ_N), with Δ ≈ z_end − z_s estimated from P
(:func:`_end_scale`, Δ = H/2 when there is no close shadow root).  This removes both square-root
branch points: the integrands are even and analytic in t with singularities no closer than ~π/2 to
the real axis, and Gauss–Legendre in t converges geometrically, with a rate that degrades only
like log(1/y_X).

Poles.  V_φ = u/(I1 x y) (u = Q_J − I3 f ρ Q_R) has poles at x = 0 and y = 0 (θ = 0, π); when
θ_N → 0 the integrand V_φ J becomes a Lorentzian of width √(x_N/H) in v.  Its residues give an
exact closed form: with A = sgn(u₀) √(x_N x_X)/2 and B = sgn(u_π) √(y_N y_X)/2,

    ∫_0^π (A/x + B/y) dv = (π/2)(sgn u₀ + sgn u_π),

and V_φ J − A/x − B/y is analytic at θ = 0 and π.  (A = Res of V_φ J at x = 0 follows from
Q(x=0) = u₀² α/(x_N x_X), α = (f₀² + I1)/I1², D(0) = I1 + f₀².)  This is the ±π jump of φ
at a passage near the vertical, exact for every θ_N.  For ψ, V_ψ = ρ Q_R − c V_φ (paper eq.
anglesdot) gives the singular part (π/2)(sgn u_π − sgn u₀).

Backends: :func:`precession` here (double precision, vectorised, node count doubled until the change
is below ``rtol``) and :func:`rocknroller.analysis.routh.quadrature_mp.precession_mp` (mpmath, any ``dps``,
tanh-sinh without the residue subtraction, turning points by ``mpmath.findroot``): the reference.
"""

from __future__ import annotations

from dataclasses import dataclass, fields
from functools import lru_cache
from typing import TYPE_CHECKING, Any, cast

import numpy as np
from numpy.typing import ArrayLike, NDArray

from rocknroller.analysis.model.body import Body, float_or_nan
from rocknroller.analysis.model.diagnostics import wrap_angle
from rocknroller.analysis.model.invariants import rho_inv
from rocknroller.analysis.routh.precession_plots import precession_figure
from rocknroller.analysis.routh.reduction import (E_MAX, NO_MOTION, OK, STATUS_TEXT, STEADY, D_coefficient,
                                                  NoMotionError, SteadyRollingError, _f, _P_and_terms, _P_xy, _U_xy,
                                                  check_invariants, require_open_tilt, theta_from_xy, tilt_xy,
                                                  u_numerator, where_defined)
from rocknroller.analysis.routh.turning_points import TurningPoints, solve_turning_points

if TYPE_CHECKING:
    import pandas

__all__ = ["UNRESOLVED", "QUADRATURE_STATUS_TEXT", "Precession", "precession", "precession_from_turning_point",
           "check_rtol"]

#: Extra status of the double-precision quadrature: the rule did not converge, or its estimated rounding
#: error exceeds 1e-12 (near-steady rolling: E − U(θ) is a small difference everywhere); use precession_mp.
UNRESOLVED = 3
QUADRATURE_STATUS_TEXT = {**STATUS_TEXT, UNRESOLVED: "unresolved: not resolved to full accuracy in double "
                          "precision (near-steady rolling, E close to min U); use the mpmath backend (dps=)"}

_N_START = 16
_EPS = float(np.finfo(float).eps)
#: Largest estimated rounding error of a result in double precision; above it the point is UNRESOLVED
#: (near-steady rolling, where E − U(θ) is a small difference over the whole interval).  The estimate
#: adds |rounding| node by node, so it lies 10–100× above the actual error (≲ 1e-14 for ordinary points).
_MAX_ROUNDING = 1e-12
_N_MAX = 1024
#: Largest ``max_nodes`` accepted.  The rule costs O(n) memory and O(n²) time to build (:func:`_gauss_legendre`; 16384
#: nodes: ~4 s, ~1 MB) and O(n) per point; more nodes cannot help, since a rule's own rounding grows like n·u
#: (measured: ~1e-11 relative on ∫cos 40t at 4096 nodes), above the smallest tolerance 1e-14 · (sum) long before.
MAX_NODES_LIMIT = 1 << 14
#: Points × nodes evaluated at once (≈ 16 MB per work array): larger inputs are done in blocks.
_BLOCK_ELEMENTS = 1 << 21
#: Default tolerance on the change between n/2 and n nodes (see :func:`precession`).
DEFAULT_RTOL = 1e-9
#: Allowed tolerances: below 1e-14 the change between the two rules is their round-off (sums of up to thousands of
#: terms, each to a unit round-off 1.1e-16: a few 1e-15 relative), which the doubling does not reliably bring under
#: the tolerance (3e-15 is missed at θ_X = 0.95π, 1e-14 met at every point tried).
RTOL_RANGE = (1e-14, 1e-3)


@dataclass(frozen=True)
class Precession:
    """Rocking period and precession angles of Routh's sphere (arrays, or mpf for precession_mp).

    Attributes
    ----------
    E, QR, QJ : energy and the two invariants.
    theta_N, theta_X : turning points (θ_N ≤ θ_X).
    T_theta : time between successive maxima of θ, 2∫ dθ/√F.
    tau : paper's rocking period τ = 4∫ dθ/√F = 2 T_θ.
    delta_phi, delta_psi : full (unwrapped) increments of φ and ψ per T_θ.
    delta_phi_tau, delta_psi_tau : the same per τ (paper eq. Delta_phi).
    visible_phi : Δφ per T_θ mod 2π in (−π, π].
    visible_half_phi : Δφ per T_θ mod π in (−π/2, π/2].
    status : OK, NO_MOTION, STEADY or UNRESOLVED (QUADRATURE_STATUS_TEXT).  In the double backend the
        numeric fields of array input are masked arrays, masked where the status is not OK (never NaN);
        a single point (0-d input) gives 0-d arrays, or, if it is not OK, raises the ValueError that says why.
    n_nodes : Gauss–Legendre nodes per point (double backend), 0 for mpmath.
    rounding_error : estimated rounding error of the double backend (relative for T_θ, radians for the
        angles per T_θ), from the cancellation in P at the nodes, summed in absolute value (an upper
        bound in practice); above 1e-12 the point is UNRESOLVED (this happens near steady rolling,
        E − min U ≲ 1e-2 |U|).  None for mpmath.

    Examples
    --------
    >>> import math
    >>> import rocknroller as rr
    >>> body = rr.Body.paper()
    >>> p, _ = rr.precession_from_turning_point(0.95 * math.pi, [0.01, 0.02], [-0.002, 0.0], body)
    >>> print(p.status)
    [0 0]
    >>> print(p.tau / p.T_theta)
    [2.0 2.0]
    """

    E: Any
    QR: Any
    QJ: Any
    theta_N: Any
    theta_X: Any
    T_theta: Any
    tau: Any
    delta_phi: Any
    delta_psi: Any
    delta_phi_tau: Any
    delta_psi_tau: Any
    visible_phi: Any
    visible_half_phi: Any
    status: Any
    n_nodes: Any
    rounding_error: Any = None

    def status_text(self) -> NDArray[np.str_]:
        """Explanatory text of each status code."""
        return np.vectorize(QUADRATURE_STATUS_TEXT.get, otypes=[str])(np.asarray(self.status))

    def to_dataframe(self) -> "pandas.DataFrame":
        """One row per point, one column per field (masked entries are missing values; needs pandas)."""
        from rocknroller.analysis.model.frames import dataframe

        names = [f.name for f in fields(self) if getattr(self, f.name) is not None]
        return dataframe({**{n: getattr(self, n) for n in names}, "status_text": self.status_text()})

    def plot(self, fig: Any = None) -> Any:
        """T_θ, Δφ and Δψ per T_θ over the (Q_R, Q_J) plane on ``fig`` (a new pyplot figure without one), as
        ``rocknroller table --plot`` draws them (:func:`~rocknroller.analysis.routh.precession_plots.precession_figure`).

        Examples
        --------
        >>> import math, matplotlib.figure, rocknroller as rr
        >>> p, _ = rr.precession_from_turning_point(0.95 * math.pi, [0.01, 0.02], [-0.002, 0.0], rr.Body.paper())
        >>> print(p.plot(matplotlib.figure.Figure(figsize=(13, 4))).axes[3].get_ylabel())
        $T_\\theta$ (time units)
        """
        return precession_figure(self.QR, self.QJ, self.T_theta, self.delta_phi, self.delta_psi, fig=fig)


# ----------------------------------------------------------------------------- double precision
#: Largest Gauss–Legendre rule whose companion matrix is diagonalised dense (numpy) rather than tridiagonal (scipy).
_DENSE_UP_TO = 512


@lru_cache(maxsize=32)
def _gauss_legendre(n: int) -> tuple[NDArray[np.float64], NDArray[np.float64]]:
    """The positive half of the n-point Gauss–Legendre rule on [−1, 1] (n even).

    numpy's ``leggauss`` algorithm (the eigenvalues of the symmetric Legendre companion matrix, Newton steps on P_n,
    the weights from P_{n−1} and P_n', symmetrised and normalised), with the companion matrix's eigenvalues from its
    tridiagonal form (``scipy.linalg.eigvalsh_tridiagonal``): ``leggauss`` forms the dense n × n matrix, O(n²)
    memory and O(n³) time (4096 nodes: 3.2 s and 290 MB; 65536: ~70 GB), where this needs O(n) and O(n²).  The
    nodes agree with ``leggauss``'s to 0.5 ulp and the rules integrate alike (tests/analysis/routh/test_quadrature.py).
    Up to ``_DENSE_UP_TO`` nodes the eigenvalues come from numpy's dense solver instead (≤ 2 MB, a few ms), which
    spares a first prediction the import of scipy.linalg (0.2 s CPU); the Newton steps make the two agree.
    """
    leg = np.polynomial.legendre
    k = np.arange(1.0, n)
    off = k / np.sqrt(4.0 * k * k - 1.0)  # legcompanion's off-diagonal
    if n <= _DENSE_UP_TO:
        x = np.linalg.eigvalsh(np.diag(off, 1) + np.diag(off, -1))
    else:
        from scipy.linalg import eigvalsh_tridiagonal

        # LAPACK's sterf (QR, eigenvalues only) in O(n) memory: scipy < 1.15's 'auto' took stemr, which allocated an
        # n × n array (2 GB at 16384 nodes, seen with scipy 1.13.1)
        x = eigvalsh_tridiagonal(np.zeros(n), off, lapack_driver="sterf")
    c = np.zeros(n + 1)
    c[-1] = 1.0
    dc = leg.legder(c)
    for _ in range(2):  # Newton on P_n: the eigenvalues' error (LAPACK's, which varies between builds) polished away
        x -= leg.legval(x, c) / leg.legval(x, dc)
    df = leg.legval(x, dc)  # at the polished nodes (leggauss takes P_n' at the eigenvalues themselves)
    fm = leg.legval(x, c[1:])
    w = 1.0 / ((fm / np.abs(fm).max()) * (df / np.abs(df).max()))
    w, x = 0.5 * (w + w[::-1]), 0.5 * (x - x[::-1])
    w *= 2.0 / w.sum()
    return x[n // 2:], w[n // 2:]


def _end_scale(z_end, H, P_at):
    """Distance Δ from a turning point to the nearest other root of P beyond it (a "shadow" root).

    Near θ = π with θ_X → π, P(y) ≈ P2 (y − y_X)(y − y_s) with a second root y_s ≤ 0 close by;
    the stretch z − z_end = Δ sinh²t then removes both square-root branch points (module
    docstring).  P1, P2 come from P at z_end + h and z_end + 2h, h = ½ min(z_end, H/4); without a close
    shadow root (P2 ≤ 0 or Δ ≥ H/2) the stretch degenerates to the plain square-root map, Δ = H/2.
    """
    h = 0.5 * np.minimum(z_end, 0.25 * H)
    with np.errstate(invalid="ignore", divide="ignore", over="ignore"):
        p1, p2 = P_at(h), P_at(2.0 * h)
        P2 = (p2 - 2.0 * p1) / (2.0 * h * h)
        P1 = (4.0 * p1 - p2) / (2.0 * h)
        delta = P1 / P2
    good = (h > 0.0) & (P2 > 0.0) & (P1 > 0.0) & np.isfinite(delta)
    return np.where(good, np.clip(delta, z_end, 0.5 * H), 0.5 * H)


def _half_integrals(xN, yN, xX, yX, E, QR, QJ, u0, upi, body: Body, n: int):
    """Integrals over the half-oscillation θ_N → θ_X: an n-point Gauss–Legendre rule on each half.

    The interval in c is split at its middle (x − x_N = y − y_X = H/2).  On the half next to
    θ_X, y = y_X + Δ_X sinh²t; on the half next to θ_N, x = x_N + Δ_N sinh²t (Δ from
    :func:`_end_scale`); the integrands are even in t, so each half is ½∫_{−t_m}^{t_m} and needs
    n/2 evaluations (n per point in all).  Returns, per point: ∫ dt (the half period), the
    remainder integrals of φ̇ and ψ̇ after their residue parts (module docstring), the L1 norm of
    those two integrands (the scale of the convergence test), whether P > 0 at every node, and the
    estimated rounding errors of the half period and of the two angle integrals (from the
    cancellation in P at the nodes).
    """
    col = lambda a: a[:, None]  # noqa: E731
    H = np.where(xX <= 1.0, xX - xN, np.where(xN >= 1.0, yN - yX, xX - xN))
    E_, QR_, QJ_ = col(E), col(QR), col(QJ)
    A = col(np.sign(u0) * 0.5 * np.sqrt(xN * xX))
    B = col(np.sign(upi) * 0.5 * np.sqrt(yN * yX))
    tg, wg = _gauss_legendre(n)
    out = np.zeros((6, xN.size))
    positive = np.ones(xN.size, dtype=bool)
    for near_X in (True, False):
        if near_X:
            z_end = yX
            P_at = lambda e: _P_xy(xX - e, yX + e, E, QR, QJ, body)  # noqa: E731
        else:
            z_end = xN
            P_at = lambda e: _P_xy(xN + e, yN - e, E, QR, QJ, body)  # noqa: E731
        delta = _end_scale(z_end, H, P_at)
        t_m = np.arcsinh(np.sqrt(0.5 * H / delta))
        t = col(t_m) * tg
        w = col(t_m) * wg
        sh = np.sinh(t)
        e = col(delta) * sh * sh  # distance from this turning point, in x (or y)
        if near_X:
            x, y = col(xX) - e, col(yX) + e
        else:
            x, y = col(xN) + e, col(yN) - e
        dc_dt = 2.0 * col(delta) * sh * np.cosh(t)
        with np.errstate(invalid="ignore", divide="ignore"):
            P, terms = _P_and_terms(x, y, E_, QR_, QJ_, body)
            j = np.sqrt(D_coefficient(x, body) / P) * dc_dt  # dt/dθ-measure in t
            m = dc_dt / np.sqrt(e * (col(H) - e))  # dv/dt
            u = u_numerator(x, y, QR_, QJ_, body)
            Rphi = u * j / (body.I1 * x * y) - (A / x + B / y) * m
            c = np.where(x <= 1.0, 1.0 - x, y - 1.0)
            f = _f(x, y, body)
            omega3 = QR_ / rho_inv(body, x * y, f)  # ω3' = ρ Q_R (paper eq. routh)
            Rpsi = omega3 * j - c * Rphi + (A - B) * m
            # rounding of P (relative ε·terms/|P|) enters √(1/P) halved: the integrands' rounding error
            cond = 0.5 * _EPS * terms / np.abs(P)
            vphi_j = np.abs(u * j / (body.I1 * x * y))
        out[0] += (w * j).sum(1)
        out[1] += (w * Rphi).sum(1)
        out[2] += (w * Rpsi).sum(1)
        out[3] += (w * (np.abs(Rphi) + np.abs(Rpsi))).sum(1)
        out[4] += (w * np.abs(j) * cond).sum(1)
        out[5] += (w * (vphi_j + np.abs(omega3 * j) + vphi_j) * cond).sum(1)
        positive &= np.all(P > 0.0, axis=1)
    return out[0], out[1], out[2], out[3], positive, out[4], out[5]


#: The per-point arguments of :func:`_half_integrals`: x_N, y_N, x_X, y_X, E, Q_R, Q_J, u0, u_pi.
_Points = tuple[NDArray, NDArray, NDArray, NDArray, NDArray, NDArray, NDArray, NDArray, NDArray]


def _rows(args: _Points, i: int, j: int) -> _Points:
    """Points i to j − 1 of each array."""
    return cast(_Points, tuple(a[i:j] for a in args))  # nine arrays in, nine out (a generator's length is not typed)


def _blocked_half_integrals(args: _Points, body: Body, n: int) -> tuple[NDArray, ...]:
    """:func:`_half_integrals` over blocks of at most ``_BLOCK_ELEMENTS // n`` points (bounded memory)."""
    size = max(1, _BLOCK_ELEMENTS // n)
    m = args[0].size
    if m <= size:
        return _half_integrals(*args, body, n)
    parts = [_half_integrals(*_rows(args, i, i + size), body, n) for i in range(0, m, size)]
    return tuple(np.concatenate([p[k] for p in parts]) for k in range(len(parts[0])))


def check_rtol(rtol: float, name: str = "rtol") -> float:
    """The quadrature tolerance as a float, or a ValueError naming ``name`` unless it lies in ``RTOL_RANGE``."""
    lo, hi = RTOL_RANGE
    value = float_or_nan(rtol)
    if not lo <= value <= hi:  # also NaN
        raise ValueError(f"{name} must lie in [{lo:g}, {hi:g}] (below {lo:g} the change between the Gauss-Legendre "
                         f"rules is round-off, and points would stay unresolved), got {name}={rtol!r}")
    return value


def _precession_from_tp(tp: TurningPoints, body: Body, rtol: float, max_nodes: int) -> Precession:
    rtol = check_rtol(rtol)
    if isinstance(max_nodes, bool) or int(max_nodes) != max_nodes or not 2 * _N_START <= max_nodes <= MAX_NODES_LIMIT:
        raise ValueError(f"max_nodes must be an integer in [{2 * _N_START}, {MAX_NODES_LIMIT}] (the rule's work and "
                         f"memory grow with it), got max_nodes={max_nodes!r}")
    shape = tp.E.shape
    status = tp.status.copy().ravel()
    flat = lambda a: np.asarray(a, float).ravel()  # noqa: E731
    xN, yN, xX, yX, E, QR, QJ, u0, upi = map(flat, (tp.x_N, tp.y_N, tp.x_X, tp.y_X, tp.E, tp.QR, tp.QJ,
                                                    tp.u0, tp.upi))
    m = status.size
    T = np.full(m, np.nan)
    Iphi = np.full(m, np.nan)
    Ipsi = np.full(m, np.nan)
    nodes = np.zeros(m, dtype=np.int64)
    err = np.full(m, np.nan)
    active = np.flatnonzero(status == OK)
    prev = None
    n = _N_START
    while active.size and n <= max_nodes:
        args = (xN[active], yN[active], xX[active], yX[active], E[active], QR[active], QJ[active],
                u0[active], upi[active])
        cur = _blocked_half_integrals(args, body, n)
        if prev is None:
            prev = cur
            n *= 2
            continue
        positive = cur[4]
        dT = np.abs(cur[0] - prev[0]) <= rtol * np.abs(cur[0])
        dA = (np.abs(cur[1] - prev[1]) + np.abs(cur[2] - prev[2])) <= rtol * cur[3]
        # P ≤ 0 at a node: the roots are not separated from the rounding of P (near-steady rolling);
        # more nodes would only come closer to them, so such points stop here, unresolved
        done = (dT & dA) | ~positive
        # estimated rounding error: relative for T_θ, in radians (per T_θ) for the angles
        with np.errstate(invalid="ignore", divide="ignore"):
            rounding = np.where(positive, np.maximum(cur[5] / cur[0], 2.0 * cur[6]), np.inf)
        resolved = done & (rounding <= _MAX_ROUNDING)
        idx = active[resolved]
        T[idx], Iphi[idx], Ipsi[idx] = cur[0][resolved], cur[1][resolved], cur[2][resolved]
        nodes[idx] = n
        err[active[done]] = rounding[done]
        status[active[done & ~resolved]] = UNRESOLVED
        keep = ~done
        active = active[keep]
        prev = tuple(p[keep] for p in cur)
        n *= 2
    status[active] = UNRESOLVED
    ok = status == OK
    sg0, sgpi = np.sign(u0), np.sign(upi)
    kphi = np.where(ok, sg0 + sgpi, 0.0)  # Δφ per T_θ = kphi π + 2 Iphi
    kpsi = np.where(ok, sgpi - sg0, 0.0)
    if ok.size == 1 and not ok[0] and len(shape) == 0:
        _raise_for_status(int(status[0]), tp)
    T_theta = 2.0 * np.where(ok, T, 0.0)
    dphi = kphi * np.pi + 2.0 * np.where(ok, Iphi, 0.0)
    dpsi = kpsi * np.pi + 2.0 * np.where(ok, Ipsi, 0.0)
    # visible angles from the remainder, the integer multiple of π being reduced exactly
    odd = np.remainder(kphi, 2.0)
    vis = wrap_angle(2.0 * np.where(ok, Iphi, 0.0) + odd * np.pi)
    vis_half = wrap_angle(2.0 * np.where(ok, Iphi, 0.0), np.pi)
    def defined(a: NDArray) -> Any:  # a single point was OK (else it raised): a plain 0-d array
        a = np.asarray(a).reshape(shape)
        return a if len(shape) == 0 else where_defined(a, ok.reshape(shape))

    with np.errstate(invalid="ignore"):  # θ of the masked (zero) roots is never used
        theta_N, theta_X = theta_from_xy(xN, yN), theta_from_xy(xX, yX)
    return Precession(
        E=tp.E, QR=tp.QR, QJ=tp.QJ,
        theta_N=defined(theta_N), theta_X=defined(theta_X),
        T_theta=defined(T_theta), tau=defined(2.0 * T_theta),
        delta_phi=defined(dphi), delta_psi=defined(dpsi), delta_phi_tau=defined(2.0 * dphi),
        delta_psi_tau=defined(2.0 * dpsi), visible_phi=defined(vis), visible_half_phi=defined(vis_half),
        status=status.reshape(shape), n_nodes=nodes.reshape(shape), rounding_error=defined(np.where(ok, err, 0.0)),
    )


def _raise_for_status(status: int, tp: TurningPoints) -> None:
    """A single point without a result: the ValueError that says why (the vectorised form reports a status)."""
    where = f"E={float(tp.E)!r}, QR={float(tp.QR)!r}, QJ={float(tp.QJ)!r}"
    if status == NO_MOTION:
        raise NoMotionError(f"no motion: F(theta) < 0 on all of (0, pi) for {where}; E must be >= min U = "
                            f"{float(tp.U_min)!r}")
    if status == STEADY:
        raise SteadyRollingError(f"double root at {where}: steady circular rolling at theta={float(tp.theta_min)!r}, "
                                 "not a rocking motion", where_defined(tp.theta_min, True))
    raise ValueError(f"{where} is too close to steady rolling for the double-precision quadrature (estimated "
                     f"rounding error above {_MAX_ROUNDING:g}); use precession_mp")


def precession(E: ArrayLike, QR: ArrayLike, QJ: ArrayLike, body: Body, *, rtol: float = DEFAULT_RTOL,
               max_nodes: int = _N_MAX) -> Precession:
    """T_θ, τ, Δφ, Δψ and the visible angles in double precision, vectorised over (E, Q_R, Q_J).

    Paper §2.5 and eq. Delta_phi; method in the module docstring.  The node count of the
    Gauss–Legendre rules is doubled from 16 until the change of every integral from n/2 to n nodes
    is at most ``rtol`` relative (of T_θ, and of the L1 norm of the angle integrands).  The rules
    converge geometrically, error(n) ≈ error(n/2)², so the n-node result is then accurate to
    round-off: against 40-digit mpmath, ≤ 3e-14 on 200 points for every rtol from 1e-12 to 1e-7
    (tests/analysis/routh/test_quadrature.py; a tighter rtol only adds nodes and round-off).

    Parameters
    ----------
    E, QR, QJ : array_like
        Energy and invariants, broadcast together.
    body : Body
        Symmetric body.
    rtol : float
        Convergence tolerance on the change between n/2 and n nodes, in (0, 1e-3] (default 1e-9).
    max_nodes : int
        Largest rule tried, in [32, MAX_NODES_LIMIT = 16384]; points not converged get status UNRESOLVED.

    Returns
    -------
    Precession
        Points without motion (NO_MOTION), steady rolling (STEADY, double root) or not converged
        (UNRESOLVED) carry that status and are masked in the numeric fields (masked arrays, never NaN).

    Raises
    ------
    ValueError
        Asymmetric body, non-finite input, rtol outside (0, 1e-3], or a single point (0-d input) that is
        not OK (NoMotionError, SteadyRollingError, or too close to steady rolling: use precession_mp).

    Examples
    --------
    >>> import math
    >>> import rocknroller as rr
    >>> body = rr.Body.paper()
    >>> E, QR, QJ = rr.invariants_from_euler(body, 0.95 * math.pi, 0.0, 0.15, 0.15)
    >>> p = rr.precession(E, QR, QJ, body)
    >>> print(f"T_theta = {p.T_theta:.10f}, tau = {p.tau:.10f}, delta_phi = {p.delta_phi:.10f}")
    T_theta = 13.1496523760, tau = 26.2993047520, delta_phi = -2.6333667605
    """
    tp = solve_turning_points(E, QR, QJ, body)
    return _precession_from_tp(tp, body, rtol, max_nodes)


def precession_from_turning_point(theta0: ArrayLike, QR: ArrayLike, QJ: ArrayLike, body: Body, *,
                                  rtol: float = DEFAULT_RTOL, max_nodes: int = _N_MAX) -> tuple[Precession, NDArray]:
    """Precession for motions with a turning point at θ0 (θ̇ = 0 there) and given (Q_R, Q_J).

    E = U(θ0) (reduction.state_from_turning_point); the root at θ0 is set to θ0 exactly.

    Returns
    -------
    (Precession, is_upper)
        ``is_upper`` is True where θ0 is the upper turning point θ_X, False where U'(θ0) < 0 makes
        it the lower one θ_N.

    Raises
    ------
    ValueError
        θ0 outside (0, π), asymmetric body, rtol outside (0, 1e-3].

    Examples
    --------
    >>> import math
    >>> import rocknroller as rr
    >>> body = rr.Body.paper()
    >>> p, is_upper = rr.precession_from_turning_point(0.95 * math.pi, 0.01, -0.002, body)
    >>> print(f"T_theta = {p.T_theta:.10f}, visible half-angle per T_theta = {p.visible_half_phi:.10f}", is_upper)
    T_theta = 13.1551952337, visible half-angle per T_theta = 0.4650514197 True
    """
    body.require_symmetric("the precession quadratures")
    theta0 = require_open_tilt(theta0)
    theta0, QR, QJ = np.broadcast_arrays(theta0, *check_invariants(QR=QR, QJ=QJ))
    x0, y0 = tilt_xy(theta0)
    E = _U_xy(x0, y0, QR, QJ, body)
    if np.any(~(np.abs(E) <= E_MAX)):
        i = np.flatnonzero(~(np.abs(E) <= E_MAX))[0]
        raise ValueError(f"theta0={float(theta0.flat[i])!r} with QR={float(QR.flat[i])!r}, QJ={float(QJ.flat[i])!r} "
                         f"gives the energy E = U(theta0) = {float(E.flat[i]):.3g}, beyond E_MAX = {E_MAX:g}: move "
                         "theta0 away from the vertical or reduce QR, QJ")
    tp = solve_turning_points(E, QR, QJ, body)
    with np.errstate(divide="ignore", invalid="ignore"):  # only the OK entries are used
        upper = np.abs(np.log(tp.x_X / x0)) <= np.abs(np.log(tp.x_N / x0))
    upper = np.where(tp.status == OK, upper, True)
    ok = tp.status == OK

    def pin(cond: NDArray[np.bool_], a: NDArray[np.float64], b: NDArray[np.float64]) -> NDArray[np.float64]:
        return np.where(ok & cond, a, b)

    tp = TurningPoints(
        E=tp.E, QR=tp.QR, QJ=tp.QJ,
        x_N=pin(~upper, x0, tp.x_N), y_N=pin(~upper, y0, tp.y_N),
        x_X=pin(upper, x0, tp.x_X), y_X=pin(upper, y0, tp.y_X),
        U_min=tp.U_min, theta_min=tp.theta_min, u0=tp.u0, upi=tp.upi, status=tp.status,
    )
    return _precession_from_tp(tp, body, rtol, max_nodes), upper
