"""The averaged slow map itself: its run-time tables and the compiled drift–kick–drift iteration.  It holds
:func:`iterate_slow_map`, which iterates the reversible map of :mod:`rocknroller.analysis.slow.prediction` from a
maximum, to first order in ε or, given a :class:`rocknroller.analysis.slow.map.chart.SecondOrderTable`, to second order
(kick k₁ + ε k₂), and :class:`SlowSeries`, its samples (t, Q_R, Q_J, Θ = 2ψ, φ) at the θ-maxima.

The map runs on the run-time form of a :class:`rocknroller.analysis.slow.map.chart.SlowMapTable` (values on a fine
grid along the chart, Chebyshev series across it; the most recently used forms are kept in memory,
``RUNTIME_CACHE_BYTES``) in the compiled kernel ``rocknroller.analysis.slow.map._kernel`` (C source ``_kernel.c``).
"""

from __future__ import annotations

import copy
import math
from dataclasses import dataclass, field
from typing import TYPE_CHECKING, Any

import numpy as np
from numpy.typing import ArrayLike, NDArray

from rocknroller.analysis.model.diagnostics import unwrap_phase
from rocknroller.analysis.slow.map import _kernel
from rocknroller.analysis.slow.map.chart import _HARM, _IDX, SecondOrderTable, SlowMapTable, cheb_basis, stretch
from rocknroller.analysis.slow.map.limits import MAX_MAXIMA, AveragingRangeError, check_t_end
from rocknroller.numerics.cache import MemoryCache

if TYPE_CHECKING:
    import pandas

__all__ = ["SlowSeries", "iterate_slow_map", "centre_period", "TANGENT_START", "tangent_start", "chart_step"]

#: The tangent vector w of every run of the map with ``tangent=True``, in the scaled coordinates (S u, S v, Θ) with
#: S = |∇W| at Q = 0 (the table's, per table; a change δQ changes the twist by ≈ S |δQ|, so both parts of w are phases,
#: the standard map's (p, Θ)): the unit vector (1, 1, 1)/√3.  Its norm is √(S²(w_u² + w_v²) + w_Θ²).
TANGENT_START = (1.0, 1.0, 1.0)


@dataclass(frozen=True)
class SlowSeries:
    """Samples of the slow map at the θ-maxima n = 1, 2, ... with t_n ≤ t_end.

    ``Theta`` is unwrapped (continuous); ``phi`` is the accumulated azimuth modulo π-jumps (use mod π).
    ``log_growth`` (a run with ``tangent=True``, else None): ℓ_n = ln(‖w_n‖/‖w_0‖) of the tangent vector carried from
    ``TANGENT_START`` at the start of the run, at each maximum.
    """

    t: NDArray[np.float64]
    QR: NDArray[np.float64]
    QJ: NDArray[np.float64]
    Theta: NDArray[np.float64]
    phi: NDArray[np.float64]
    log_growth: NDArray[np.float64] | None = field(default=None, repr=False)

    @property
    def psi_mod_pi(self) -> NDArray[np.float64]:
        """ψ mod π at the maxima."""
        return np.mod(0.5 * self.Theta, math.pi)

    @property
    def phi_mod_pi(self) -> NDArray[np.float64]:
        """φ mod π at the maxima (the visible half-angle)."""
        return np.mod(self.phi, math.pi)

    def until(self, t_end: float) -> "SlowSeries":
        """The maxima at t ≤ t_end (a run over the chaos indicators' span, cut to the prediction's t_end)."""
        keep = self.t <= t_end
        return SlowSeries(t=self.t[keep], QR=self.QR[keep], QJ=self.QJ[keep], Theta=self.Theta[keep],
                          phi=self.phi[keep], log_growth=None if self.log_growth is None else self.log_growth[keep])

    def to_dataframe(self) -> "pandas.DataFrame":
        """One row per maximum: t, Q_R, Q_J, Θ, φ (needs pandas)."""
        from rocknroller.analysis.model.frames import dataframe

        return dataframe({n: getattr(self, n) for n in ("t", "QR", "QJ", "Theta", "phi")})


#: Points of the fine uniform grid in u used at run time per Chebyshev term along it (6-point Lagrange
#: interpolation between them; 64 nu + 1 = 8193 for the release tables' nu = 128), and their most: the run-time form
#: holds points × (18 + 48 + 25 for order 2) functions × nv doubles, ≤ 8193 × 91 × 128 × 8 B = 0.76 GB whatever nu
#: (≤ 4096) is; a run with a tangent vector adds its rows (``_TangentRows``: 3 + 27 + 45 for order 2 functions,
#: ≤ 0.63 GB more, cached under their own key).
_FINE_PER_TERM = 64
_FINE_MAX = 8193
#: Run-time functions: 0-8 the harmonics (c0, c1, s1) of k_u = e·k_Q, k_v = n·k_Q and k_Θ (solved for
#: implicitly), 9-14 those of the time and φ kicks, 15-17 the drifts T_θ, W, Δφ.
_N_KICK = 15
#: Bytes of run-time forms this process keeps (the most recently used): 1 GiB, four region tables' (~250 MB each)
#: or forty release tables' (~25 MB).  A form dropped is rebuilt from its table when used again (0.1–1 s).
RUNTIME_CACHE_BYTES = 1 << 30
_FAST = MemoryCache(RUNTIME_CACHE_BYTES)
#: Kernel statuses (analysis/slow/map/_kernel.c).
_DONE, _FULL, _LEFT_TABLE, _NO_CONVERGENCE = range(4)
#: Largest number of output rows the kernel fills per call.
_CHUNK = 1 << 16


def _at_points(coef: NDArray[np.float64], basis: NDArray[np.float64]) -> NDArray[np.float64]:
    """Σ_k coef[f, k, j] basis[k, i] as an array (i, f, j): Chebyshev series in x at the points of ``basis``
    (one BLAS product; an einsum without optimisation loops in C one term at a time, ~25× slower here)."""
    return np.tensordot(basis, coef, axes=([0], [1]))


def _kick_and_drift(table: SlowMapTable) -> tuple[NDArray[np.float64], NDArray[np.float64]]:
    """The Chebyshev coefficients of the run-time functions (``_N_KICK``): the 15 kick functions (the harmonics of
    k_u = e·k_Q, k_v = n·k_Q, k_Θ, then of the time and φ kicks) and the 3 drifts (T_θ, W, Δφ)."""
    c, e, n = table.coef, table.e, table.n
    rows = []
    for h in _HARM:
        qr, qj = c[_IDX[f"kQR_{h}"]], c[_IDX[f"kQJ_{h}"]]
        rows.append((e[0] * qr + e[1] * qj, n[0] * qr + n[1] * qj))
    kick = [rows[m][0] for m in range(3)] + [rows[m][1] for m in range(3)]
    kick += [c[_IDX[f"{pre}_{h}"]] for pre in ("kTh", "dt", "dphi1") for h in _HARM]
    drift = [c[_IDX[name]] for name in ("T", "W", "dphi")]
    return np.array(kick), np.array(drift)


class _FastTable:
    """Run-time form of a SlowMapTable: values on a fine uniform grid in x = u/U, Chebyshev series in τ.

    Each row of ``rows`` holds the 18 run-time functions (see ``_N_KICK``) at one grid point as
    Chebyshev coefficients in τ; 6-point Lagrange interpolation in x on 8193 points reproduces the
    Chebyshev interpolant to ~1e-13 relative.  ``geom`` holds the chart there (c, w, c'/U, w'/U).
    ``rows_jac`` adds the x- (over U) and τ-derivatives of the
    Chebyshev series of the kick functions 0-14, for the Jacobian of the implicit kick and a
    first-order correction of ε k_t, ε k_φ by less than the kick tolerance (they set the speed of
    convergence, not the converged value).  The rows are evaluated, and the map stepped, by the
    compiled kernel ``rocknroller.analysis.slow.map._kernel`` (about 1 µs a step).
    """

    def __init__(self, table: SlowMapTable, second: SecondOrderTable | None = None) -> None:
        c = table.coef
        e, n = table.e, table.n
        kick, drift = _kick_and_drift(table)
        self.U, self.nv = float(table.U), c.shape[2]
        self.e, self.n = e, n
        self.n_fine = min(_FINE_PER_TERM * c.shape[1] + 1, _FINE_MAX)
        xi = np.linspace(-1.0, 1.0, self.n_fine)
        self.dx = float(xi[1] - xi[0])
        self.alpha, self.beta = float(table.alpha), float(table.beta)
        self.geom = np.ascontiguousarray(np.stack(table._sides(stretch(xi, self.alpha)), axis=1))
        Bu = cheb_basis(xi, c.shape[1])                                  # (nu, Nf)
        kick_d = self._values_and_derivatives(kick).reshape(self.n_fine, 3 * _N_KICK, self.nv)  # values, ∂ξ/U, ∂τ
        fine = np.concatenate([kick_d[:, :_N_KICK], _at_points(drift, Bu)], axis=1)  # (Nf, 18, nv)
        self.rows = np.ascontiguousarray(fine.reshape(self.n_fine, -1))
        self.rows_jac = np.ascontiguousarray(np.concatenate([fine, kick_d[:, _N_KICK:]], axis=1).reshape(self.n_fine,
                                                                                                       -1))
        self.table = table
        self.second = second
        self.rows2 = None if second is None else self._second_order_rows(second)

    def with_second(self, second: SecondOrderTable) -> "_FastTable":
        """This run-time form with the second-order rows of ``second`` added; the first-order rows are shared (they
        do not depend on ``second``: the same arrays as ``_FastTable(table, second)`` builds)."""
        ft = copy.copy(self)
        ft.second, ft.rows2 = second, self._second_order_rows(second)
        return ft

    def _values_and_derivatives(self, coef: NDArray[np.float64]) -> NDArray[np.float64]:
        """Run-time rows (Nf, 3 F · nv) of F Chebyshev series (F, nu, nv) on this chart: their values, then their
        ξ-derivatives over U and their τ-derivatives (the kernel turns these into ∂/∂u, ∂/∂v)."""
        xi = np.linspace(-1.0, 1.0, self.n_fine)
        B = cheb_basis(xi, coef.shape[1])
        du = np.asarray(np.polynomial.chebyshev.chebder(coef, axis=1), float) / self.U  # (F, nu − 1, nv)
        dv = np.asarray(np.polynomial.chebyshev.chebder(coef, axis=2), float)            # (F, nu, nv − 1), d/dτ
        dv = np.concatenate([dv, np.zeros(dv.shape[:2] + (1,))], axis=2)
        fine = np.concatenate([_at_points(coef, B), _at_points(du, B[: du.shape[1]]), _at_points(dv, B)], axis=1)
        return np.ascontiguousarray(fine.reshape(self.n_fine, -1))

    def _second_order_coef(self, second: "SecondOrderTable") -> NDArray[np.float64]:
        """k₂_u = e·k₂_Q, k₂_v = n·k₂_Q, k₂_Θ, k₂_t, k₂_φ, five harmonics each: Chebyshev coefficients (25, nu₂, nv)
        in τ padded to this table's nv terms."""
        c2 = np.asarray(second.coef, float).reshape(5, 5, *second.coef.shape[1:])  # (component, harmonic, ξ, η)
        nu2, nv2 = c2.shape[2:]
        if nv2 > self.nv:
            raise ValueError(f"the second-order table ({nu2} x {nv2} terms) does not fit the run-time form of this "
                             f"table ({self.nv} terms across)")
        e, n = self.e, self.n
        comps = [e[0] * c2[0] + e[1] * c2[1], n[0] * c2[0] + n[1] * c2[1], c2[2], c2[3], c2[4]]
        coef = np.zeros((25, nu2, self.nv))
        coef[:, :, :nv2] = np.concatenate(comps).reshape(25, nu2, nv2)
        return coef

    def _second_order_rows(self, second: "SecondOrderTable") -> NDArray[np.float64]:
        """The run-time rows (Nf, 25 · nv) of a :class:`rocknroller.analysis.slow.map.chart.SecondOrderTable` on this
        table's chart: k₂_u = e·k₂_Q, k₂_v = n·k₂_Q, k₂_Θ, k₂_t, k₂_φ, five harmonics each, Chebyshev in τ (its
        series padded to this table's nv terms)."""
        coef = self._second_order_coef(second)
        xi = np.linspace(-1.0, 1.0, self.n_fine)
        fine = _at_points(coef, cheb_basis(xi, coef.shape[1]))  # (Nf, 25, nv)
        return np.ascontiguousarray(fine.reshape(self.n_fine, -1))

    def _evaluate(self, rows: NDArray[np.float64], u: float, v: float) -> list[float]:
        out = _kernel.evaluate(rows, self.geom, rows.shape[1] // self.nv, self.nv, self.U, self.alpha, self.beta,
                               self.dx, u, v)
        if out is None:
            self.table.evaluate(u * self.e + v * self.n)  # raises AveragingRangeError with the explanation
        assert out is not None, "the kernel left the table where the table's own evaluate did not"
        return out

    def values(self, u: float, v: float) -> list[float]:
        """The 18 run-time functions at Q = u e + v n."""
        return self._evaluate(self.rows, u, v)

    def values_and_jacobian(self, u: float, v: float) -> list[float]:
        """The 18 functions, then ∂/∂u and ∂/∂v of the kick functions (0-14): 48 values."""
        return self._evaluate(self.rows_jac, u, v)

    def iterate(self, eps: float, u: float, v: float, Th: float, phi: float, t_end: float,
                n_steps: int | None, tangent: "_TangentRows | None" = None
                ) -> tuple[NDArray[np.float64], tuple[int, int]]:
        """Rows (t, u, v, Θ, φ) of the maxima after the start with t ≤ t_end (at most ``n_steps``),
        and the numbers of table evaluations with and without the Jacobian rows.  With ``tangent`` (the tangent rows
        of this form) a tangent vector is carried along from ``TANGENT_START`` and each row gains ℓ, the logarithm of
        its growth since the start (:func:`iterate_slow_map`)."""
        # room for t_end / (T_θ(0)/2) maxima, at most _CHUNK rows at a time
        cap = min(int(t_end / (0.5 * abs(self.values(0.0, 0.0)[_N_KICK]))) + 8, _CHUNK)
        cap = cap if n_steps is None else min(int(n_steps), cap)
        chunks, t, counts = [], 0.0, [0, 0]
        width = 5 if tangent is None else 6
        extra: tuple[Any, ...] = ()
        if tangent is not None:
            w = np.array([*tangent_start(tangent.scale), 0.0])  # (w_u, w_v, w_Θ, ℓ), carried from chunk to chunk
            extra = (w, tangent.rows_dw, tangent.rows_kt, tangent.rows2_kt, tangent.scale)
        while True:
            out = np.empty((max(cap, 1), width))
            n, status, ub, vb, n_jac, n_plain = _kernel.iterate(self.rows, self.rows_jac, self.geom, out, self.U,
                                                                 self.alpha, self.beta, self.dx, self.nv, eps, u, v,
                                                                 Th, t, phi, t_end, self.rows2, *extra)
            counts[0] += n_jac
            counts[1] += n_plain
            chunks.append(out[:n])
            done = sum(len(c) for c in chunks)
            if status in (_LEFT_TABLE, _NO_CONVERGENCE):
                raise _failure(self, eps, status, ub, vb)
            if status == _DONE or (n_steps is not None and done >= n_steps):
                break
            if done > MAX_MAXIMA:  # t_end was checked against T_θ(0)/2 per maximum; T_θ ≥ 0.7 T_θ(0) on the tables
                raise ValueError(f"t_end={t_end!r} gives more than MAX_MAXIMA = {MAX_MAXIMA} maxima")
            assert status == _FULL
            t, u, v, Th, phi = (float(x) for x in out[n - 1, :5])  # out was full: go on from the last maximum
            cap = _CHUNK if n_steps is None else min(_CHUNK, n_steps - done)
        return np.concatenate(chunks), (counts[0], counts[1])

    def steps(self, eps: float, u: float, v: float, Th: float, out: NDArray[np.float64]) -> AveragingRangeError | None:
        """Fill ``out`` (n, 5), C-contiguous, with the rows (t, u, v, Θ, φ) of the n maxima after the start (t and φ
        from 0) in one kernel call, and None; or, if the orbit leaves the table (or its implicit kick fails), the rows
        before that (the rest untouched) and that error, unraised."""
        if not len(out):
            return None
        _, status, ub, vb, _, _ = _kernel.iterate(self.rows, self.rows_jac, self.geom, out, self.U, self.alpha,
                                                  self.beta, self.dx, self.nv, eps, u, v, Th, 0.0, 0.0, math.inf,
                                                  self.rows2)
        return None if status == _FULL else _failure(self, eps, status, ub, vb)


class _TangentRows:
    """The run-time rows a tangent vector needs beside a :class:`_FastTable` (kept in the same memory cache, under
    their own key): ``rows_dw`` (W, ∂W/∂u, ∂W/∂v), ``rows_kt`` (the kick functions 0-8 and
    their ∂/∂u, ∂/∂v), ``rows2_kt`` (k₂'s u, v, Θ harmonics and their ∂/∂u, ∂/∂v; order 2 only) and ``scale``, the
    norm's weight of (u, v): ``TANGENT_SCALE``."""

    def __init__(self, ft: _FastTable) -> None:
        self.table, self.second = ft.table, ft.second
        kick, drift = _kick_and_drift(ft.table)
        self.rows_dw = ft._values_and_derivatives(drift[1:2])
        self.rows_kt = ft._values_and_derivatives(kick[:9])
        self.rows2_kt = None if ft.second is None else ft._values_and_derivatives(ft._second_order_coef(ft.second)[:15])
        out = _kernel.evaluate(self.rows_dw, ft.geom, 3, ft.nv, ft.U, ft.alpha, ft.beta, ft.dx, 0.0, 0.0)
        assert out is not None, "Q = 0 lies on every table"
        self.scale = math.hypot(out[1], out[2])
        if not (math.isfinite(self.scale) and self.scale > 0.0):
            raise ValueError(f"the averaging table gives |grad W| = {self.scale!r} at Q = 0, not a positive number: it "
                             "is damaged or not a table of this version")


def tangent_start(scale: float) -> tuple[float, float, float]:
    """The tangent vector every run starts from, ``TANGENT_START`` normalised in the scaled coordinates
    (S u, S v, Θ), S = ``scale``, and given in (u, v, Θ)."""
    wu, wv, wt = TANGENT_START
    c = 1.0 / math.sqrt(wu * wu + wv * wv + wt * wt)
    return c * wu / scale, c * wv / scale, c * wt


def chart_step(table: SlowMapTable, eps: float, x: NDArray[np.float64], second: SecondOrderTable | None = None,
               jacobian: bool = False, failures: dict[int, ValueError] | None = None
               ) -> tuple[NDArray[np.float64], NDArray[np.float64] | None]:
    """One step of the map in the table's chart, x = (u, v, Θ) → x' (Θ' the kernel's own continued value: no
    wrapping), and with ``jacobian`` its derivative ∂x'/∂x: the kernel's tangent map of the step as implemented
    (:func:`iterate_slow_map`, ``tangent=True``), applied to the three unit vectors (one kernel step each; the kernel
    renormalises w, so M e_j = w' e^ℓ in the norm with weight 1).  No argument checks: the callers check theirs.

    x may be an array (N, 3) of starts: then x' is (N, 3) and M (N, 3, 3), each row the kernel's step from that row
    alone (a loop of kernel calls, each as for one start, so each row is what the start alone gives, bit for bit).
    With ``failures`` (a dict) a start whose step fails is recorded there (its row index → its error, unraised) and
    its rows of x' and M are NaN; without it the first failure is raised.

    Raises
    ------
    AveragingRangeError
        The step leaves the table, or the implicit kick does not converge (without ``failures``).
    """
    ft = _fast(table, second)
    starts = np.asarray(x, float).reshape(-1, 3)
    columns, width = (3, 6) if jacobian else (1, 5)
    out = np.empty((len(starts), columns, width))
    rows = out.reshape(-1, width)  # row k: the kernel's one row of output for start k // columns, column k % columns
    tr, eps = (_tangent_rows(ft) if jacobian else None), float(eps)
    bad: dict[int, ValueError] = {}
    w = np.zeros((len(starts), columns, 4))  # with jacobian the tangent vectors (w_u, w_v, w_Θ, ℓ), e_j to start with
    w.reshape(len(starts), 4 * columns)[:, ::5] = 1.0  # w[i, j, j]
    ws = w.reshape(-1, 4)
    fixed = (ft.U, ft.alpha, ft.beta, ft.dx, ft.nv, eps)
    for i, (u, v, th) in enumerate(starts.tolist()):
        for k in range(i * columns, (i + 1) * columns):
            extra = () if tr is None else (ws[k], tr.rows_dw, tr.rows_kt, tr.rows2_kt, 1.0)
            n, status, ub, vb, _, _ = _kernel.iterate(ft.rows, ft.rows_jac, ft.geom, rows[k], *fixed, u, v, th, 0.0,
                                                      0.0, math.inf, ft.rows2, *extra)
            if status != _FULL:
                bad[i] = _failure(ft, eps, status, ub, vb)
                break
            assert n == 1, "one step fills the one row"
    step, M = out[:, -1, 1:4].copy(), None
    if tr is not None:
        growth = np.array([math.exp(g) for g in w[..., 3].ravel().tolist()]).reshape(w.shape[:2])
        M = np.ascontiguousarray(np.swapaxes(w[..., :3] * growth[..., None], 1, 2))
    if bad:
        if failures is None:
            raise bad[min(bad)]
        failures.update(bad)
        step[list(bad)] = np.nan
        if M is not None:
            M[list(bad)] = np.nan
    if np.ndim(x) == 1:
        return step[0], None if M is None else M[0]
    return step, M


def _failure(ft: _FastTable, eps: float, status: int, ub: float, vb: float) -> AveragingRangeError:
    """The error of a kernel run that stopped with ``status``: the implicit kick did not converge, or the orbit left
    the table at (u, v) = (ub, vb), explained by the table's own evaluate there."""
    if status == _NO_CONVERGENCE:
        return AveragingRangeError(f"the implicit kick did not converge at eps={eps!r}: eps is too large for the "
                                   "first-order map")
    assert status == _LEFT_TABLE, f"a kernel run that neither finished nor failed (status {status})"
    try:
        ft.table.evaluate(ub * ft.e + vb * ft.n)
    except AveragingRangeError as err:
        return err
    raise AssertionError("the kernel left the table where the table's own evaluate did not")


def centre_period(table: SlowMapTable) -> float:
    """T_θ at the centre of the table's chart (Q = 0: pure rocking), from the table itself.

    Raises
    ------
    ValueError
        If it is not a positive finite time: the table is damaged or not one of this code's (a tampered cache file
        whose coefficients are finite but absurd blamed ``t_end`` for it).
    """
    T0 = float(_fast(table).values(0.0, 0.0)[_N_KICK])
    if not (math.isfinite(T0) and 0.0 < T0 < math.inf):
        raise ValueError(f"the averaging table gives T_theta = {T0!r} at Q = 0, not a positive time: it is damaged or "
                         "not a table of this version (a cached file: delete it, or point ROCKNROLLER_CACHE at another "
                         "folder, and it is rebuilt)")
    return T0


def _fast(table: SlowMapTable, second: SecondOrderTable | None = None) -> _FastTable:
    """The run-time form of (table, second), cached; one with second-order rows shares the first-order one's rows
    (a prediction asks for both: :func:`centre_period`, then the map's run), which are built once."""
    key = (id(table), id(second))
    ft = _FAST.get(key)
    if ft is None or ft.table is not table or ft.second is not second:
        ft = _FastTable(table) if second is None else _fast(table).with_second(second)
        _FAST[key] = ft
    return ft


def _tangent_rows(ft: _FastTable) -> _TangentRows:
    key = (id(ft.table), id(ft.second), "tangent")
    tr = _FAST.get(key)
    if tr is None or tr.table is not ft.table or tr.second is not ft.second:
        tr = _TangentRows(ft)
        _FAST[key] = tr
    return tr


def iterate_slow_map(table: SlowMapTable, eps: float, psi0: float, t_end: float, *,
                     Q0: ArrayLike = (0.0, 0.0), phi0: float = 0.0, n_steps: int | None = None,
                     second: SecondOrderTable | None = None, tangent: bool = False) -> SlowSeries:
    """Iterate the reversible drift–kick–drift slow map from a maximum at t = 0.

    One step: Θ += W(Q)/2; (Q, Θ) += ε k(midpoint) (implicit midpoint, solved by simplified Newton
    to 1e-13 of the kick, + 4 ulp, or until the observed contraction η puts the remaining error
    η/(1 − η) × change below 1e-3 of that; Hairer & Wanner, Solving ODEs II, §IV.8; an iterate outside the table,
    such as an explicit first iterate that overshoots its edge, is moved halfway back towards the last one inside);
    Θ += W(Q')/2;
    t += ½[T_θ(Q) + T_θ(Q')] + ε k_t(midpoint); φ += ½[Δφ(Q) + Δφ(Q')] + ε k_φ(midpoint).
    The loop runs in the compiled kernel ``rocknroller.analysis.slow.map._kernel``.

    With ``tangent=True`` a tangent vector w of (u, v, Θ) (Q = u e + v n) is carried along by the tangent map of the
    step as implemented (the drifts' ∇W; the implicit midpoint's derivative by the implicit function theorem,
    dm = (I − (ε/2) ∂k/∂m)⁻¹ da at the converged midpoint m, with ∂k/∂m from the tables' derivatives and the analytic
    Θ-derivative of the harmonics; second order: of k₁ + ε k₂), starting from ``TANGENT_START``, renormalised every
    step in the norm √(S²(w_u² + w_v²) + w_Θ²) (S = |∇W(0)|) and the logarithms of the norms summed: the series'
    ``log_growth``, the samples of :func:`rocknroller.numerics.megno.chaos_indicators`.  It costs ~1.5× the map
    alone (benchmarks/bench_chaos_map.py).

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
    second : SecondOrderTable, optional
        The second-order kick k₂ on this table's chart (:mod:`rocknroller.analysis.slow.map.second_order`): the kick
        function becomes k₁ + ε k₂, the map second order in ε and still reversible.
    tangent : bool
        Carry a tangent vector along (above) and return its ``log_growth``.

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
    ft = _fast(table, second)
    if n_steps is None:
        check_t_end(t_end, centre_period(table))
    elif not (math.isfinite(t_end) and t_end > 0.0):
        raise ValueError(f"t_end must be a finite number > 0, got t_end={t_end!r}")
    Q0 = np.asarray(Q0, float)
    if Q0.shape != (2,) or not np.all(np.isfinite(Q0)) or not math.isfinite(float(phi0)):
        raise ValueError(f"Q0 must be two finite numbers (Q_R, Q_J) and phi0 finite, got Q0={Q0!r}, phi0={phi0!r}")
    arr, _ = ft.iterate(eps, float(ft.e @ Q0), float(ft.n @ Q0), 2.0 * psi0, float(phi0), t_end, n_steps,
                        _tangent_rows(ft) if tangent else None)
    Q = np.outer(arr[:, 1], ft.e) + np.outer(arr[:, 2], ft.n)
    return SlowSeries(t=arr[:, 0], QR=Q[:, 0], QJ=Q[:, 1], Theta=unwrap_phase(arr[:, 3]), phi=arr[:, 4],
                      log_growth=arr[:, 5] if tangent else None)
