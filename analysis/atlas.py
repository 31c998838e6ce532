"""Recession atlas: the averaged slow map over a plane of releases from rest, (ψ0, θ0), and its ODE confirmation.

For each release angle θ0 the map runs on one table (``averaging.load_or_build_table`` in ``THETA0_RANGE``, the
region tables of the release's energy below it, :mod:`rocknroller.analysis.slow_region`), so a row of ψ0 costs
one table and ~1 ms a point once the tables are cached.  Each point gives the slow period of Θ = 2ψ, the azimuth
span Φ, the Q_R and Q_J extents and the numbers of full-angle (Q_J,0^crit) and visible-angle (Q_J,π^crit)
reversals per 1000 time units: crossings of the critical lines by the maxima's (Q_R, Q_J), as
``averaging.critical_regions`` counts them for the map and the ODE alike.

A sample of the points (and any the caller names) is run by the direct ODE as an ensemble
(:func:`rocknroller.numerics.ensemble.run_ensemble`: in process, threads, or a dask cluster, the same numbers bit for
bit), and the map's relative errors there are returned beside the atlas.
"""

from __future__ import annotations

import warnings
from dataclasses import dataclass, field
from typing import Any, Sequence

import numpy as np
from numpy.typing import ArrayLike, NDArray

from rocknroller.analysis import averaging as av
from rocknroller.analysis.body import Body

__all__ = ["ATLAS_OBSERVABLES", "MAX_ATLAS_POINTS", "MAX_ATLAS_WORKERS", "Atlas", "AtlasCheck", "reversal_counts", "atlas_from_rest",
           "confirm_atlas"]

#: What the atlas maps, per point: the map's diagnostics and the reversals per 1000 time units.
ATLAS_OBSERVABLES = ("slow_period", "Phi", "QR_extent", "QJ_extent", "full_reversals", "visible_reversals")
#: Most points of one atlas (≈ 1 ms and 48 bytes each once the tables are cached).
MAX_ATLAS_POINTS = 250_000


def reversal_counts(crossings: Sequence[tuple[float, str, str, str]] | None, t_end: float) -> tuple[float, float]:
    """(full-angle, visible-angle) reversals per 1000 time units: crossings of Q_J,0^crit and of Q_J,π^crit."""
    lines = [c[3] for c in crossings or []]
    scale = 1000.0 / t_end
    return (scale * sum("QJ0crit" in s for s in lines), scale * sum("QJpicrit" in s for s in lines))


def _values(pred: Any, t_end: float) -> list[float | None]:
    full, visible = reversal_counts(pred.crossings, t_end)
    return [pred.slow_period, pred.Phi, pred.QR_extent, pred.QJ_extent, full, visible]


@dataclass(frozen=True)
class Atlas:
    """The averaged map's diagnostics over a grid of releases from rest.

    Attributes
    ----------
    eps, t_end : the body's asymmetry and the time span of each prediction.
    theta0, psi0 : the grid's release angles (rows) and spin angles (columns).
    values : dict
        For each of ``ATLAS_OBSERVABLES``, a masked array (len(theta0), len(psi0)); masked where the quantity is
        undefined (the slow period of a run with fewer than two crossings of its mean).
    warnings : the distinct validity warnings of the predictions (e.g. K = ε κ > 4, coarse region tables).
    """

    eps: float
    t_end: float
    theta0: NDArray[np.float64]
    psi0: NDArray[np.float64]
    values: dict[str, np.ma.MaskedArray] = field(repr=False)
    warnings: tuple[str, ...] = ()


def _check_grid(name: str, values: ArrayLike, lo: float, hi: float) -> NDArray[np.float64]:
    a = np.atleast_1d(np.asarray(values, float))
    if a.ndim != 1 or a.size == 0 or not np.all(np.isfinite(a)) or np.any((a < lo) | (a > hi)):
        raise ValueError(f"{name} must be a non-empty 1-D grid of finite values in [{lo:.6g}, {hi:.6g}], got {values!r}")
    return a


def _rows(body: Body, theta0: NDArray[np.float64], psi0: NDArray[np.float64], t_end: float,
          build: bool) -> tuple[NDArray[np.float64], NDArray[np.bool_], list[str]]:
    """The observables (len(ATLAS_OBSERVABLES), len(theta0), len(psi0)), where they are undefined, and the validity
    warnings, for some rows of the atlas (in this process)."""
    out = np.zeros((len(ATLAS_OBSERVABLES), theta0.size, psi0.size))
    mask = np.zeros_like(out, dtype=bool)
    with warnings.catch_warnings(record=True) as caught:
        warnings.simplefilter("always", av.AveragingValidityWarning)
        for i, t0 in enumerate(theta0):
            table = None if av.releases_on_region_tables(t0) else av.load_or_build_table(body, t0, build=build)
            for j, p0 in enumerate(psi0):
                pred = av.predict_slow_motion(body, float(t0), float(p0), t_end, table=table, build=build)
                for k, v in enumerate(_values(pred, t_end)):
                    mask[k, i, j] = v is None
                    out[k, i, j] = 0.0 if v is None else v
    return out, mask, [str(w.message) for w in caught if issubclass(w.category, av.AveragingValidityWarning)]


#: Most processes :func:`atlas_from_rest` shares the rows among.
MAX_ATLAS_WORKERS = 64


def atlas_from_rest(body: Body, theta0: ArrayLike, psi0: ArrayLike, t_end: float = 1000.0, *,
                    progress: bool | None = None, build: bool = True, workers: int = 1) -> Atlas:
    """Map the slow motion over the releases from rest at every (θ0, ψ0) of the grid (module docstring).

    Parameters
    ----------
    body : Body
        The asymmetric body (ε = body.epsilon).
    theta0 : array_like
        Release tilts, 0 < θ0 ≤ ``THETA0_RANGE[1]`` (0.999π).
    psi0 : array_like
        Spin angles (any finite values; ψ0 and ψ0 + π give the same motion).
    t_end : float
        Time span of each prediction (``predict_slow_motion``'s limits).
    progress : bool or None
        A tqdm bar over the rows (None: only on a terminal).
    build : bool
        Build the tables that are not cached (else ValueError).
    workers : int
        Processes that share the rows, 1 ≤ workers ≤ ``MAX_ATLAS_WORKERS`` (each point is computed the same way
        wherever it runs; more than one starts "spawn" processes, which import the calling script: guard a script's
        top level with ``if __name__ == "__main__":``).

    Raises
    ------
    ValueError
        A grid out of range or larger than ``MAX_ATLAS_POINTS`` (before anything is built), naming it.
    """
    from tqdm.auto import tqdm

    th = _check_grid("theta0", theta0, np.nextafter(0.0, 1.0), av.THETA0_RANGE[1])
    ps = _check_grid("psi0", psi0, -1e6, 1e6)
    if th.size * ps.size > MAX_ATLAS_POINTS:
        raise ValueError(f"the atlas has {th.size} x {ps.size} = {th.size * ps.size} points, more than "
                         f"MAX_ATLAS_POINTS = {MAX_ATLAS_POINTS}")
    if int(workers) != workers or not 1 <= workers <= MAX_ATLAS_WORKERS:
        raise ValueError(f"workers must be an integer in [1, {MAX_ATLAS_WORKERS}], got workers={workers!r}")
    blocks = np.array_split(np.arange(th.size), min(int(workers), th.size) if workers > 1 else th.size)
    parts: list[Any] = []
    with tqdm(total=th.size, desc="atlas rows", unit="theta0", disable=None if progress is None else not progress) as bar:
        if workers == 1:
            for rows in blocks:
                parts.append(_rows(body, th[rows], ps, t_end, build))
                bar.update(rows.size)
        else:
            import multiprocessing
            from concurrent.futures import ProcessPoolExecutor

            with ProcessPoolExecutor(len(blocks), mp_context=multiprocessing.get_context("spawn")) as pool:
                futures = [pool.submit(_rows, body, th[rows], ps, float(t_end), build) for rows in blocks]
                for fut, rows in zip(futures, blocks):
                    fut.add_done_callback(lambda _, n=rows.size: bar.update(n))
                parts = [fut.result() for fut in futures]
    out = np.concatenate([p[0] for p in parts], axis=1)
    mask = np.concatenate([p[1] for p in parts], axis=1)
    caught_all = [msg for p in parts for msg in p[2]]
    return Atlas(eps=body.epsilon, t_end=float(t_end), theta0=th, psi0=ps,
                 values={name: np.ma.MaskedArray(out[k], mask[k]) for k, name in enumerate(ATLAS_OBSERVABLES)},
                 warnings=tuple(dict.fromkeys(caught_all)))


@dataclass(frozen=True)
class AtlasCheck:
    """The direct ODE at some points of an atlas, and the map's relative errors there.

    Attributes
    ----------
    index : ndarray (n, 2) of int, the (row, column) of each point.
    ode : dict, for each of ``ATLAS_OBSERVABLES``, the ODE's values (masked where undefined).
    rel_error : dict, the map's value / the ODE's − 1 (masked where either is undefined or the ODE's is 0);
        for the reversal counts, the difference map − ODE (per 1000 time units) instead.
    """

    index: NDArray[np.int64]
    ode: dict[str, np.ma.MaskedArray] = field(repr=False)
    rel_error: dict[str, np.ma.MaskedArray] = field(repr=False)


def confirm_atlas(atlas: Atlas, body: Body, *, every: int | None = 50, points: Sequence[tuple[int, int]] = (),
                  scheduler: str | None = None, workers: int | None = None, threads: int | None = None,
                  progress: bool | None = None) -> AtlasCheck:
    """Run the direct ODE at 1 point in ``every`` (row-major, starting at the first; None: none) and at ``points``
    (row, column),
    as an ensemble (:func:`rocknroller.numerics.ensemble.run_ensemble`; where it runs does not change the numbers).

    Raises
    ------
    ValueError
        ``every`` not an integer ≥ 1, a point outside the grid, or the ensemble's own limits, naming them.
    """
    from rocknroller.numerics.ensemble import Job, run_ensemble
    from rocknroller.numerics.equations import EulerState

    n_t, n_p = atlas.theta0.size, atlas.psi0.size
    if every is not None and (int(every) != every or every < 1):
        raise ValueError(f"every must be an integer >= 1 or None, got every={every!r}")
    chosen = [] if every is None else list(range(0, n_t * n_p, int(every)))
    for i, j in points:
        if not (0 <= i < n_t and 0 <= j < n_p):
            raise ValueError(f"points must lie on the {n_t} x {n_p} grid, got {(i, j)!r}")
        chosen.append(int(i) * n_p + int(j))
    flat = sorted(set(chosen))
    if not flat:
        raise ValueError("nothing to confirm: give every or points")
    index = np.array([divmod(f, n_p) for f in flat], dtype=np.int64).reshape(-1, 2)
    jobs = [Job(body, EulerState(float(atlas.theta0[i]), 0.0, float(atlas.psi0[j])), atlas.t_end) for i, j in index]
    runs = run_ensemble(jobs, scheduler=scheduler, workers=workers, threads=threads, progress=progress)
    ode = {name: np.zeros(len(runs)) for name in ATLAS_OBSERVABLES}
    undefined = {name: np.zeros(len(runs), bool) for name in ATLAS_OBSERVABLES}
    sym = body.symmetric()
    for r, run in enumerate(runs):
        m = run.maxima
        crossings = av.critical_regions(m.QR, m.QJ, m.t, sym)[2]
        full, visible = reversal_counts(crossings, atlas.t_end)
        for name, v in zip(ATLAS_OBSERVABLES, (run.slow_period, run.Phi, run.QR_extent, run.QJ_extent, full, visible)):
            undefined[name][r] = v is None
            ode[name][r] = 0.0 if v is None else v
    rel: dict[str, np.ma.MaskedArray] = {}
    for name in ATLAS_OBSERVABLES:
        mv = atlas.values[name][index[:, 0], index[:, 1]]
        ov = np.ma.MaskedArray(ode[name], undefined[name])
        if name.endswith("reversals"):
            rel[name] = mv - ov
        else:
            with np.errstate(divide="ignore", invalid="ignore"):
                rel[name] = np.ma.masked_invalid(mv / np.ma.masked_equal(ov, 0.0) - 1.0)
    return AtlasCheck(index=index, ode={k: np.ma.MaskedArray(ode[k], undefined[k]) for k in ATLAS_OBSERVABLES},
                      rel_error=rel)
