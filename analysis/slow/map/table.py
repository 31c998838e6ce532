"""Building, fitting, checking and caching the tables of the averaged slow map's coefficient functions: the release
tables of a release from rest at θ0 in ``THETA0_RANGE`` (:func:`build_table`, the kick at Q = 0: :func:`kick_at_rest`),
the fit every first-order table shares (:func:`fit_table` = :func:`fit_reduced` of :func:`reduce_responses`,
:func:`fit_and_check`: continuous branches of W and Δφ, the drift–kick–drift form, the parities in Q, the Chebyshev
series and the check against direct orbits), and the memory and disk cache of every kind of table
(:func:`load_or_build_table` for the release tables, :func:`cached_table` for all).

The coefficient functions of one step of the first-order map (T_θ, W, Δφ and the harmonics 0 and 1 in Θ of the kicks)
are tabulated per (body, θ0) or (body, energy) at the Chebyshev nodes of a chart of the (Q_R, Q_J) plane
(:mod:`rocknroller.analysis.slow.map.chart`); they depend on neither ε nor ψ0.  Release tables cover a strip along the
kick direction at Q = 0, T_θ, W and Δφ from quadratures (:func:`rocknroller.analysis.slow.map.orbit.symmetric_data`),
the kicks from one variational orbit with three ε-responses per node
(:func:`rocknroller.analysis.slow.map.harmonic.harmonic_steps`) on half the nodes, the mirror images −Q following by
the symmetry of ``_MIRROR_SIGNS``; region tables (:mod:`rocknroller.analysis.slow.map.region`) cover the region of an
energy, second-order tables (:mod:`rocknroller.analysis.slow.map.second_order`) hold k₂ on a first-order table's chart.

Drift–kick–drift form.  With the responses ΔX(Q, Θ) of one step (X = Q, Θ, t, φ) tabulated as harmonics in Θ, the
kick is k_Q(Q, Θ') = ΔQ(Q, Θ' − W/2) and k_X(Q, Θ') = ΔX(Q, Θ' − W/2) − ½ ∇F·k_Q(Q, Θ') for X = Θ, t, φ with
F = W, T_θ, Δφ: the part of each response received after the kick is carried by the second half-drift.

Cache.  Each table is cached on disk (``rocknroller.numerics.cache.cache_dir()/averaging``, plain float64 arrays with
their key and checksum, checked on load; a file that fails a check is rebuilt and replaced) and the most recently
used in memory (``TABLE_CACHE_BYTES``).  The key holds the table version, the builder, the body, θ0 or E and the
builder's options.
"""

from __future__ import annotations

import dataclasses
import hashlib
import inspect
import math
import os
import warnings
from typing import Any, Callable

import numpy as np
from numpy.typing import NDArray

from rocknroller.analysis.model.body import Body
from rocknroller.analysis.model.diagnostics import wrap_angle
from rocknroller.analysis.slow.map.chart import (_EVEN, _ODD, CHART_TERMS, TABLE_FUNCTIONS, SlowMapTable, cheb_fit_matrix,
                                             cheb_nodes)
from rocknroller.analysis.slow.map.family import rest_energy
from rocknroller.analysis.slow.map.limits import (K_PERIOD_DOUBLING, AveragingRangeError, AveragingValidityWarning,
                                              check_map_theta0)
from rocknroller.analysis.slow.map.harmonic import harmonic_steps, step_coefficients
from rocknroller.analysis.slow.map.orbit import FIRST_ORDER_NAMES, symmetric_data
from rocknroller.numerics.cache import CacheWarning, MemoryCache, cache_dir, load_arrays, save_arrays, warn_unwritable
from rocknroller.numerics.parallel import check_processes, map_blocks

__all__ = [
    "REGION_TABLE_ACCURACY", "build_table", "check_grid", "kick_at_rest", "fit_table", "fit_and_check",
    "load_or_build_table", "cached_table", "TableNotCachedError", "orbit_data", "is_cached", "node_blocks",
    "reduce_responses", "fit_reduced",
    "assemble_nodes", "node_block", "release_frame", "fit_release_table", "store_table", "mirrored", "nodes_done"
]

#: Bump when the table construction or its file format changes (part of the cache key).
_TABLE_VERSION = "11"  # 6: exactly antisymmetric nodes; 7: batch terminal events; 8: k₂ in batch lanes; 9: one orbit
# a node, mirrored grids; 10: a node's T from its orbit; 11: k₂'s drift Hessians exact (they left charts past 0.97π)


class TableNotCachedError(ValueError):
    """The tables asked for with ``build=False`` are neither in memory nor in the disk cache."""


#: Bytes of tables this process keeps in memory (the most recently used; each is also on disk): 256 MiB, ~250
#: region tables or ~2500 release tables.
TABLE_CACHE_BYTES = 1 << 28
_TABLES = MemoryCache(TABLE_CACHE_BYTES)

#: Largest interpolation error of a region table for which its predictions are given without a warning: the
#: map's own error is O(ε) of the slow motion, and a table error δ adds ~N δ over N rocks (N ≲ 10³ in 10⁴ t.u.).
REGION_TABLE_ACCURACY = 1e-6


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


def node_block(sym: Body, E: float, nodes: list[tuple[float, float, float]]) -> NDArray[np.float64]:
    """Rows (T, W mod 2π, Δφ mod π, the harmonics of the ε-responses) at nodes (Q_R, Q_J, θ_X): one orbit with
    three ε-responses each (:func:`~rocknroller.analysis.slow.map.harmonic.harmonic_steps`), all run through the
    batch integrator's lanes."""
    QR, QJ, thX = np.array(nodes, float).T
    steps, resp = harmonic_steps(sym, E, QR, QJ, thX)
    out = np.empty((len(nodes), 3 + 3 * len(FIRST_ORDER_NAMES)))
    # a batch's fields: arrays (N, 3), the one orbit's T, Δψ, Δφ in each column
    out[:, 0] = np.asarray(steps.T)[:, 0]
    out[:, 1] = wrap_angle(2.0 * np.asarray(steps.dpsi)[:, 0])
    out[:, 2] = np.asarray(steps.dphi)[:, 0]
    out[:, 3:] = np.moveaxis(resp, 0, 1).reshape(len(nodes), -1)
    return out


#: Nodes per task of a table build (a step of its progress bar; a task of its processes).
_BLOCK_NODES = 64

#: Signs of a node's row (T, W, Δφ, then the harmonics (c0, c1, s1) of each response of ``FIRST_ORDER_NAMES``) at −Q
#: relative to those at Q.  Routh's sphere is symmetric under a reflection in a vertical plane, which takes
#: (Q, ψ, φ) to (−Q, −ψ, −φ) and keeps θ and t: T_θ and the time response are even, W, Δφ and the responses of
#: Q_R, Q_J, Θ and φ odd under (Q, Θ) → (−Q, −Θ), so c0 and c1 take the response's sign and s1 the opposite one.
#: (tests/analysis/slow/map/test_mirror_nodes.py checks it against orbits run from −Q.)
_RESPONSE_PARITY = {"QR": -1.0, "QJ": -1.0, "Theta": -1.0, "t": 1.0, "phi": -1.0}
_MIRROR_SIGNS = np.concatenate([[1.0, -1.0, -1.0],
                                *(_RESPONSE_PARITY[name] * np.array([1.0, 1.0, -1.0]) for name in FIRST_ORDER_NAMES)])


def mirrored(QR: NDArray, QJ: NDArray) -> bool:
    """Whether the nodes come in pairs Q, −Q to the bit, the second of each pair at the reversed place in C order:
    every chart's grid of Chebyshev points (even in number, exactly antisymmetric) is, so only the first half of its
    nodes needs orbits (``_MIRROR_SIGNS``)."""
    q, j = np.ravel(QR), np.ravel(QJ)
    return q.size % 2 == 0 and bool(np.array_equal(q[::-1], -q) and np.array_equal(j[::-1], -j))


def node_blocks(sym: Body, E: float, QR: NDArray, QJ: NDArray,
                theta_X: NDArray) -> list[tuple[Body, float, list[tuple[float, float, float]]]]:
    """The arguments of :func:`node_block` for the nodes (Q_R, Q_J) with their θ_X, in blocks of ``_BLOCK_NODES``
    in node order (C order of ``QR``'s shape): the first half of the nodes if they are :func:`mirrored`, all of them
    otherwise."""
    nodes = list(zip(np.ravel(QR).tolist(), np.ravel(QJ).tolist(), np.ravel(theta_X).tolist()))
    if mirrored(QR, QJ):
        nodes = nodes[:len(nodes) // 2]
    return [(sym, E, nodes[i:i + _BLOCK_NODES]) for i in range(0, len(nodes), _BLOCK_NODES)]


def nodes_done(blocks: list[tuple[Body, float, list[tuple[float, float, float]]]], size: int) -> list[int]:
    """The nodes of the table that each of :func:`node_blocks`' blocks (for a table of ``size`` nodes) provides:
    twice its own on a mirrored grid (the progress bars count the table's nodes)."""
    per = size // sum(len(b[2]) for b in blocks)
    return [per * len(b[2]) for b in blocks]


def assemble_nodes(rows: list[NDArray], shape: tuple[int, ...]) -> tuple[NDArray, NDArray, NDArray, NDArray]:
    """T, W mod 2π, Δφ mod π (each of ``shape``) and the harmonics of the ε-responses (shape
    ``(len(FIRST_ORDER_NAMES), *shape, 3)``) from the rows of :func:`node_block` of :func:`node_blocks`' blocks; rows
    for half the nodes (a :func:`mirrored` grid) are completed by the mirror symmetry (``_MIRROR_SIGNS``)."""
    data = np.concatenate(rows)
    if 2 * len(data) == math.prod(shape):
        data = np.concatenate([data, data[::-1] * _MIRROR_SIGNS])
    data = data.reshape(shape + (-1,))
    resp = np.moveaxis(data[..., 3:].reshape(shape + (len(FIRST_ORDER_NAMES), 3)), -2, 0)
    return data[..., 0], data[..., 1], data[..., 2], resp


def orbit_data(sym: Body, E: float, QR: NDArray, QJ: NDArray, theta_X: NDArray, *, progress: bool | None = None,
               workers: int = 1, desc: str = "tables") -> tuple[NDArray, NDArray, NDArray, NDArray]:
    """T, W mod 2π, Δφ mod π (each shaped like QR) and the harmonics of the ε-responses (shape
    ``(len(FIRST_ORDER_NAMES), *QR.shape, 3)``) at nodes (Q_R, Q_J) with their θ_X: one variational orbit with three ε-responses
    per node, for the first half of the nodes of a :func:`mirrored` grid (the rest by the symmetry), in blocks of
    ``_BLOCK_NODES`` shared by ``workers`` processes, under a tqdm bar named ``desc`` (``progress`` None: only if
    stderr is a terminal).  Each node's numbers depend on neither the blocks nor the processes (the batch
    integrator's lanes are independent)."""
    blocks = node_blocks(sym, E, QR, QJ, theta_X)
    rows = map_blocks(node_block, blocks, nodes_done(blocks, np.size(QR)), processes=workers, desc=desc, unit="node",
                      progress=progress)
    return assemble_nodes(rows, np.shape(QR))


def build_table(body: Body, theta0: float, *, nu: int = 128, nv: int = 6, u_factor: float = 2.5,
                v_ratio: float = 0.002, progress: bool | None = None, workers: int = 1) -> SlowMapTable:
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
    progress : bool or None
        A tqdm bar on stderr over the nodes (one variational orbit each), naming the table and showing the time
        left; None: only if stderr is a terminal.
    workers : int
        Processes that share the nodes, 1 ≤ workers ≤ ``parallel.MAX_PROCESSES``; the table does not depend on it.

    Raises
    ------
    ValueError
        θ0 outside ``THETA0_RANGE`` or bad grid options; AveragingRangeError if the energy of the release
        admits no motion somewhere on the table rectangle (possible for bodies other than the paper's).
    """
    workers = check_processes(workers, "workers")
    frame, T, W, dphi, thX = release_frame(body, theta0, nu=nu, nv=nv, u_factor=u_factor, v_ratio=v_ratio)
    QRg, QJg = frame.nodes()
    resp = orbit_data(frame.body, frame.E0, QRg, QJg, thX, progress=progress, workers=workers,
                      desc=f"release tables, theta0={frame.theta0 / math.pi:.6g}pi")[3]
    return fit_release_table(frame, T, W, dphi, resp)


def release_frame(body: Body, theta0: float, *, nu: int = 128, nv: int = 6, u_factor: float = 2.5,
                  v_ratio: float = 0.002,
                  C0: NDArray | None = None) -> tuple[SlowMapTable, NDArray, NDArray, NDArray, NDArray]:
    """The release table of (body, θ0) without its coefficients (its chart: ``frame.nodes()``), and T, W mod 2π,
    Δφ mod π and θ_X of the symmetric orbits at its nodes (quadratures): :func:`build_table` up to the nodes'
    variational orbits, its parameters checked as there.  ``C0``: the kick at rest if known (the tables over energy
    interpolate it), else :func:`kick_at_rest` (one variational orbit)."""
    body.require_gravity("the averaged slow map (its release tables)")
    theta0 = check_map_theta0(theta0)
    check_grid(nu, nv)
    if not (u_factor > 0 and 0 < v_ratio <= 1):
        raise ValueError(f"u_factor must be > 0 and v_ratio in (0, 1], got {u_factor!r}, {v_ratio!r}")
    sym = body.symmetric()
    E0 = rest_energy(sym, theta0)
    C0 = kick_at_rest(sym, E0) if C0 is None else np.asarray(C0, float)
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
    return frame, T, W, dphi, thX


def fit_release_table(frame: SlowMapTable, T: NDArray, W: NDArray, dphi: NDArray, resp: NDArray) -> SlowMapTable:
    """The release table on ``frame`` (:func:`release_frame`) from the data at its nodes: :func:`fit_and_check`."""
    return fit_and_check(frame, T, W, dphi, resp, _interpolation_error, _INTERP_WARN,
                         f"the averaging tables for theta0={frame.theta0!r} interpolate the coefficients only to "
                         f"{{err:.1e}} (relative); use more nodes (nu={T.shape[0]}, nv={T.shape[1]})")


def check_grid(nu: int, nv: int) -> None:
    """ValueError unless nu and nv are even integers ≥ 4 (and nv ≤ 128, the compiled kernel's limit)."""
    for name, val, top in (("nu", nu, 4096), ("nv", nv, 128)):
        if int(val) != val or not 4 <= val <= top or val % 2:
            raise ValueError(f"{name} must be an even integer in [4, {top}], got {name}={val!r}")


def kick_at_rest(sym: Body, E: float) -> NDArray[np.float64]:
    """C0 with ΔQ(0, Θ) = C0 sin Θ: the kick at Q = 0 from the variational orbit with three ε-responses at energy E."""
    resp = harmonic_steps(sym, E, 0.0, 0.0)[1]
    return np.array([resp[FIRST_ORDER_NAMES.index(k), 0, 2] for k in ("QR", "QJ")])


def fit_table(frame: SlowMapTable, T: NDArray, W: NDArray, dphi: NDArray, resp: NDArray) -> SlowMapTable:
    """The table on ``frame``'s chart (all but ``coef`` and ``kappa``) from T, W, Δφ (mod π) of the symmetric orbit
    and ``resp`` (len(FIRST_ORDER_NAMES), nu, nv, 3), the harmonics of the ε-responses, at its Chebyshev nodes
    (x_i, τ_j): :func:`fit_reduced` of :func:`reduce_responses`."""
    return fit_reduced(frame, T, W, dphi, reduce_responses(frame, T, W, dphi, resp))


def _drifts(frame: SlowMapTable, T: NDArray, W: NDArray,
            dphi: NDArray) -> tuple[dict[str, NDArray], dict[str, tuple[NDArray, NDArray]], NDArray]:
    """T, W, Δφ at the nodes (W and Δφ on continuous branches, :func:`_lift`), their gradients (∂/∂u, ∂/∂v) there
    (each fitted with its parity in Q, by the chain rule through the chart), and W/2 made odd."""
    nu, nv = T.shape
    xu, xv = cheb_nodes(nu), cheb_nodes(nv)  # ξ, η
    W, dphi = _lift(W, 2.0 * math.pi), _lift(dphi, math.pi)
    Au, Av = cheb_fit_matrix(nu), cheb_fit_matrix(nv)
    cheb = np.polynomial.chebyshev
    dxi_du, deta_du, deta_dv = frame.inverse_jacobian(*np.meshgrid(xu, xv, indexing="ij"))
    grads = {}
    for name, F, kind in (("W", W, "odd"), ("T", T, "even"), ("dphi", dphi, "odd")):
        c = Au @ _parity(F, kind) @ Av.T
        f_xi, f_eta = (cheb.chebgrid2d(xu, xv, cheb.chebder(c, axis=k)) for k in (0, 1))
        grads[name] = (f_xi * dxi_du + f_eta * deta_du, f_eta * deta_dv)
    return {"T": T, "W": W, "dphi": dphi}, grads, 0.5 * _parity(W, "odd")


def _parity(F: NDArray, kind: str) -> NDArray:
    """F made even or odd under (x, τ) → (−x, −τ) (its grid reversed), or as it is."""
    flipped = F[::-1, ::-1]
    return 0.5 * (F + flipped) if kind == "even" else 0.5 * (F - flipped) if kind == "odd" else F


def reduce_responses(frame: SlowMapTable, T: NDArray, W: NDArray, dphi: NDArray, resp: NDArray) -> NDArray:
    """``resp`` with the part of the Θ, t and φ responses that the second half-drift carries taken out: X − ½ ∇F·ΔQ
    for X = Θ, t, φ, F = W, T_θ, Δφ (module docstring; before the turn by W/2, which commutes with it).  Near θ0 = π
    the two parts cancel to a small remainder (∇W ~ 10⁶ at 0.999π): it is the remainder that is interpolated over
    energy (:mod:`rocknroller.analysis.slow.map.tables_at_once`)."""
    _, grads, _ = _drifts(frame, T, W, dphi)
    e, nvec = frame.e, frame.n
    dQu = e[0] * resp[0] + e[1] * resp[1]
    dQv = nvec[0] * resp[0] + nvec[1] * resp[1]
    out = np.array(resp, float)
    for k, name in ((2, "W"), (3, "T"), (4, "dphi")):
        gu, gv = grads[name]
        out[k] = resp[k] - 0.5 * (gu[..., None] * dQu + gv[..., None] * dQv)
    return out


def fit_reduced(frame: SlowMapTable, T: NDArray, W: NDArray, dphi: NDArray, reduced: NDArray) -> SlowMapTable:
    """The table on ``frame``'s chart from T, W, Δφ at its nodes and the reduced ε-responses
    (:func:`reduce_responses`): the kicks are the responses turned by the half-twist, k(Q, Θ') = ΔX(Q, Θ' − W/2)
    (the drift–kick–drift form); each function gets its parity in Q ((x, τ) → (−x, −τ)) and its Chebyshev series."""
    nu, nv = T.shape
    drifts, _, half = _drifts(frame, T, W, dphi)
    Au, Av = cheb_fit_matrix(nu), cheb_fit_matrix(nv)
    cw, sw = np.cos(half), np.sin(half)

    def rotate(h: NDArray) -> NDArray:  # harmonics of F(Θ' − W/2) from those of F(Θ)
        c0, c1, s1 = h[..., 0], h[..., 1], h[..., 2]
        return np.stack([c0, c1 * cw - s1 * sw, c1 * sw + s1 * cw], axis=-1)

    data = dict(drifts)
    for pre, arr in zip(("kQR", "kQJ", "kTh", "dt", "dphi1"), reduced):
        kick = rotate(arr)
        for m, suf in enumerate(("c0", "c1", "s1")):
            data[f"{pre}_{suf}"] = kick[..., m]
    coef = np.empty((len(TABLE_FUNCTIONS), nu, nv))
    for k, name in enumerate(TABLE_FUNCTIONS):
        kind = "odd" if name in _ODD else "even" if name in _EVEN else "none"
        coef[k] = Au @ _parity(np.asarray(data[name], float), kind) @ Av.T
    table = dataclasses.replace(frame, coef=coef)
    gu, gv = (float(g) for g in table.gradient("W", (0.0, 0.0)))
    return dataclasses.replace(table, kappa=float(gu * frame.C0 @ frame.e + gv * frame.C0 @ frame.n))


def fit_and_check(frame: SlowMapTable, T: NDArray, W: NDArray, dphi: NDArray, resp: NDArray,
                  error_of: Callable[[SlowMapTable], float], limit: float, message: str) -> SlowMapTable:
    """:func:`fit_table`, then its interpolation error ``error_of(table)`` recorded in the table; above ``limit`` an
    :class:`AveragingValidityWarning` with ``message`` (``{err:.1e}`` in it replaced by the error)."""
    finite = np.isfinite(T) & np.isfinite(W) & np.isfinite(dphi) & np.all(np.isfinite(resp), axis=(0, -1))
    if not finite.all():
        raise AveragingRangeError(f"the orbits of {np.count_nonzero(~finite)} of the {finite.size} nodes of the tables "
                                  f"of E={frame.E0!r} gave non-finite data; the tables are not built")
    table = fit_table(frame, T, W, dphi, resp)
    err = error_of(table)
    if not math.isfinite(err):
        raise AveragingRangeError(f"the check of the tables of E={frame.E0!r} against direct orbits gave {err!r}; "
                                  "the tables are not used")
    if err > limit:
        warnings.warn(message.format(err=err), AveragingValidityWarning, stacklevel=3)
    return dataclasses.replace(table, interp_error=err)


def _lift(F: NDArray, period: float) -> NDArray:
    """F (mod ``period`` at the nodes) on a continuous branch: along τ, then the middle column along x, shifted by
    the multiple of ``period`` that makes it odd under (x, τ) → (−x, −τ)."""
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
        worst = float(np.max([worst, *errs]))  # a NaN propagates (max() would drop it)
    return float(worst)


def load_or_build_table(body: Body, theta0: float, *, build: bool = True, use_cache: bool = True,
                        **grid: Any) -> SlowMapTable:
    """The tables of (body, θ0): from memory, from the disk cache, or built (and cached).

    The cache file holds plain float64 arrays, the key and a SHA-256 checksum (``rocknroller.numerics.cache``; read with
    ``allow_pickle=False``).  A file that fails any check is never used: it is rebuilt and replaced, with a
    ``CacheWarning``; an unwritable cache directory gives one ``CacheWarning`` per process (docs/slow_howto.md, "Tables
    and cache").

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


_RUN_OPTIONS = ("progress", "workers")  # a builder's options that change how it runs, not the table (not in the key)


def _table_location(builder: Callable[..., Any], body: Body, where: float,
                    grid: dict[str, Any]) -> tuple[str, str, str, dict[str, Any], dict[str, Any]]:
    """(key, cache folder, file, the builder's table options with defaults filled in, its run options) of the table
    ``builder(body.symmetric(), where, **grid)``."""
    params = inspect.signature(builder).parameters
    opts = {name: p.default for name, p in params.items() if p.kind is p.KEYWORD_ONLY and name not in _RUN_OPTIONS}
    unknown = set(grid) - set(opts) - set(_RUN_OPTIONS)
    if unknown:
        raise ValueError(f"unknown table options {sorted(unknown)}; allowed: {sorted(opts)}")
    grid = dict(grid)
    run = {name: grid.pop(name) for name in _RUN_OPTIONS if name in grid and name in params}
    opts.update(grid)
    key = _table_key(builder.__name__, body.symmetric(), where, opts)
    directory = os.path.join(str(cache_dir()), "averaging")
    return key, directory, os.path.join(directory, f"slowmap-{hashlib.sha256(key.encode()).hexdigest()[:20]}.npz"), \
        opts, run


def is_cached(builder: Callable[..., Any], body: Body, where: float, **grid: Any) -> bool:
    """Whether the table ``builder(body.symmetric(), where, **grid)`` is in memory or has a file in the disk cache
    (not read or checked here: for estimating the work of a call before it starts)."""
    key, _, path, _, _ = _table_location(builder, body, where, grid)
    return _TABLES.get(key) is not None or os.path.lexists(path)


def cached_table(builder: Callable[..., Any], body: Body, where: float, what: str, *, build: bool = True,
                 use_cache: bool = True, table_type: type = SlowMapTable,
                 spec_of: Callable[[dict[str, Any]], dict[str, tuple[int, ...]]] | None = None,
                 unstored: dict[str, float] | None = None, **grid: Any) -> Any:
    """``builder(body.symmetric(), where, **grid)`` from memory, from the disk cache, or built (and cached).

    ``what`` names ``where`` in messages.  The key holds the table version, the builder, the body, ``where`` and every
    keyword-only option of the builder (defaults filled in); see :func:`load_or_build_table`.  ``table_type`` is the
    frozen dataclass built, whose fields ``spec_of(options)`` lists with their shapes (default: a SlowMapTable's); the
    file holds those fields only, each finite (``load_arrays`` refuses any other), and ``unstored`` gives the value
    every table of this builder has in each remaining field (a region's second-order table: θ0 = NaN).
    """
    sym = body.symmetric()
    key, directory, path, opts, run = _table_location(builder, body, where, grid)
    table = _TABLES.get(key)
    if table is not None:
        return table
    spec = spec_of(opts) if spec_of is not None else _table_spec(opts["nu"], opts["nv"])
    table = None
    if use_cache and os.path.lexists(path):
        arrays, reason = load_arrays(path, key, spec)
        if arrays is None:
            warnings.warn(f"the cached averaging table {path} is not used ({reason}); it is rebuilt", CacheWarning,
                          stacklevel=3)
        else:
            table = table_type(**{k: (a if a.ndim else float(a)) for k, a in arrays.items()}, **(unstored or {}))
    if table is None:
        if not build:
            raise TableNotCachedError(
                f"no averaging tables for {what} and this body ({sym.describe()}); they are built "
                "on first use: call without build=False / --cached-only")
        table = builder(sym, where, **opts, **run)
        _store(table, key, directory, path, spec, what, use_cache)
    _TABLES[key] = table
    return table


def store_table(builder: Callable[..., Any], body: Body, where: float, what: str, table: Any, *,
                use_cache: bool = True, spec_of: Callable[[dict[str, Any]], dict[str, tuple[int, ...]]] | None = None,
                **grid: Any) -> None:
    """Keep ``table``, built as ``builder(body.symmetric(), where, **grid)`` builds it (elsewhere: by
    :mod:`rocknroller.analysis.slow.map.tables_at_once`), in memory and, with ``use_cache``, in the disk cache, as
    :func:`cached_table` keeps the tables it builds (``spec_of`` as there)."""
    key, directory, path, opts, _ = _table_location(builder, body, where, grid)
    spec = spec_of(opts) if spec_of is not None else _table_spec(opts["nu"], opts["nv"])
    _store(table, key, directory, path, spec, what, use_cache)
    _TABLES[key] = table


def _store(table: Any, key: str, directory: str, path: str, spec: dict[str, tuple[int, ...]], what: str,
           use_cache: bool) -> None:
    """Write the fields ``spec`` of ``table`` to the cache file ``path`` (one CacheWarning per process if the
    folder is unwritable)."""
    if use_cache:
        try:
            save_arrays(path, key, {k: getattr(table, k) for k in spec})
        except OSError as exc:
            warn_unwritable(directory, exc, f"the averaging tables are rebuilt in every process (for each body "
                            f"and {what.split('=')[0]})")


