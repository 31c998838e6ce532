"""Many direct-ODE runs at once: in this process (a loop, or threads), or on a dask.distributed cluster.

Each :class:`Job` (a body, an initial state, a final time, and the integrator's tolerance; nothing else) is run as
:func:`rocknroller.numerics.integrate.simulate` runs it with ``samples=False`` (turning points only) and boiled down to
a :class:`RunSummary` of plain arrays and floats: the θ-maxima and the slow diagnostics that the averaged map is
compared with.  The jobs run in batches, in the lanes of heyoka's batch integrator (:mod:`rocknroller.numerics.ensembles.batch`,
as many lanes as measured fastest on this machine, else as heyoka recommends for the CPU:
:mod:`rocknroller.numerics.ensembles.lanes`), at the job's tolerance (default machine epsilon;
jobs of one tolerance share a batch, :mod:`rocknroller.numerics.run_limits`).  A lane's steps
depend only on its job, so a job's summary is the same bit for bit in whichever lane, batch, process, thread or
machine it runs (provided every worker has the same versions of rocknroller, heyoka and numpy, which
:func:`run_ensemble` checks).  ``lanes=1`` runs each job in the scalar integrator instead, as ``simulate`` does: the
same turning points to the rounding of the integrators (tests/numerics/ensembles/test_batch.py), not to the bit.

Where the jobs run
------------------
* ``run_ensemble(jobs)``: batch after batch in this process.
* ``threads=N``: N threads of this process, each running whole batches with its own copy of the compiled
  integrator (:func:`rocknroller.numerics.ensembles.batch.batch_integrator`); heyoka releases the GIL while it integrates.
* ``workers=N``: a ``distributed.LocalCluster`` of N single-threaded worker processes on this machine, started for
  the call and closed after it.
* ``scheduler="tcp://host:port"``: the workers of an existing dask.distributed cluster (``dask scheduler``, then
  ``dask worker tcp://host:port`` on each machine); the cluster is left running.

dask and distributed are an optional extra: ``python -m pip install -e ".[distributed]"`` in a clone of the
repository (rocknroller is not on PyPI).

Worker environment
------------------
A worker builds the integrator once per process, from heyoka's on-disk compilation cache (``HEYOKA_CACHE_DIR``)
in about 0.1 s when the cache holds it, else by compiling it (≈ 7 s, once per machine).  Before a local cluster
starts, the integrator is built in the calling process, so the cache is filled and the workers, which inherit the
environment (``HEYOKA_CACHE_DIR``, ``ROCKNROLLER_CACHE``), load it instead of each compiling it.  The workers of an
existing cluster use the cache of their own machine: start them with the same ``HEYOKA_CACHE_DIR`` (a shared
directory lets one machine's compilation serve all).
"""

from __future__ import annotations

import re
import sys
from concurrent.futures import ThreadPoolExecutor, as_completed
from dataclasses import dataclass, field
from typing import TYPE_CHECKING, Any, Callable, Sequence

import numpy as np

from rocknroller.analysis.model.body import Body, LoadedSphere
from rocknroller.analysis.model.equations import EulerState
from rocknroller.numerics.ensembles.batch import MAX_LANES, MIN_LANES, batch_integrator, run_batch
from rocknroller.numerics.ensembles.lanes import default_lanes
from rocknroller.numerics.budget import HEYOKA_SECONDS_PER_RADIAN, WORK_BUDGET_SECONDS, check_work
from rocknroller.numerics.integrate import check_run, heyoka_integrator, simulate
from rocknroller.numerics.run_limits import DEFAULT_TOL, check_tol
from rocknroller.numerics.trajectory import MaximaExtents, TurningPointRun, TurningPoints

if TYPE_CHECKING:
    import pandas

__all__ = ["Job", "RunSummary", "run_job", "run_jobs", "run_ensemble", "check_cluster", "cluster_map", "MAX_JOBS", "MAX_WORKERS", "MAX_THREADS",
           "DISTRIBUTED_HINT"]

#: Most jobs in one call (each summary holds its θ-maxima: 17 floats, 136 bytes, per maximum).
MAX_JOBS = 100_000
#: Most worker processes of a local cluster started by :func:`run_ensemble` (``workers=``).
MAX_WORKERS = 256
#: Most threads of the in-process path (``threads=``).
MAX_THREADS = 256
#: A scheduler address rocknroller can connect to: TCP, with an optional ``tcp://``, a host name or IPv4 address or a
#: bracketed IPv6 address, and a port.
_TCP_ADDRESS = re.compile(r"(?:tcp://)?(?P<host>\[[0-9A-Fa-f:.]+\]|[^\s/:\[\]@]+):(?P<port>[0-9]{1,5})")
#: How to install the optional dependencies of the cluster path.
DISTRIBUTED_HINT = 'python -m pip install -e ".[distributed]" in a clone of the repository (rocknroller is not on PyPI)'


@dataclass(frozen=True)
class Job:
    """One direct-ODE run to make: the body, the initial state, the final time and the tolerance (nothing else).

    A plain frozen dataclass of floats, picklable and sent as is to the workers of a cluster.  It is checked on
    construction against the limits of :func:`rocknroller.numerics.integrate.simulate` with ``samples=False``, so
    an ensemble fails before any work, not on a worker.

    Parameters
    ----------
    body : Body
        The body (moments, offset, gravity).
    initial : EulerState
        Initial Euler angles and rates (or body-frame ω, :meth:`EulerState.from_omega`).
    t_end : float
        Final time, > 0, within ``MAX_RADIANS`` radians of the run's rate bound (:mod:`rocknroller.numerics.integrate`;
        the default unwrapping grid, one point per ``UNWRAP_RADIANS`` = 1 radian, then stays within
        ``MAX_GRID_POINTS``).
    tol : float
        heyoka's tolerance, in [ε, ``TOL_MAX`` = 1e-6] (default ε, the machine epsilon;
        :mod:`rocknroller.numerics.run_limits`): 1e-11 gives DOP853's best energy error, at a lower Taylor order.

    Raises
    ------
    ValueError
        Naming the parameter and its range.

    Examples
    --------
    >>> import math
    >>> import rocknroller as rr
    >>> body = rr.Body.paper(epsilon=1e-3)
    >>> start = rr.EulerState.from_omega(0.95 * math.pi, 0.0, 0.0, (0.0, 1e-3, -1e-3))
    >>> job = rr.Job(body, start, 60.0)
    >>> try:
    ...     rr.Job(body, start, -1.0)
    ... except ValueError as err:
    ...     print(err)
    ...
    t_end must be a finite number > 0, got t_end=-1.0
    """

    body: Body | LoadedSphere
    initial: EulerState
    t_end: float
    tol: float = DEFAULT_TOL
    #: Λ·t_end of the run, the radians its work scales with (:func:`rocknroller.numerics.integrate.check_run`).
    radians: float = field(init=False, repr=False, compare=False)

    def __post_init__(self) -> None:
        object.__setattr__(self, "tol", check_tol(self.tol))
        plan = check_run(self.body, self.initial, self.t_end, samples=False, tol=self.tol)
        object.__setattr__(self, "t_end", plan.t_end)
        object.__setattr__(self, "radians", plan.rate * plan.t_end)


@dataclass(frozen=True)
class RunSummary(MaximaExtents):
    """A direct-ODE run reduced to what the slow-map comparison needs: its θ-maxima and its slow diagnostics.

    The diagnostics are those of :class:`rocknroller.numerics.trajectory.TurningPointRun` (and of
    :class:`rocknroller.analysis.slow.prediction_result.SlowPrediction`), computed where the job ran.  A worker's warnings
    (an :class:`rocknroller.numerics.integrate.AccuracyWarning`) stay on the worker: ``energy_rel_error`` and
    ``n_steps`` let the caller check the accuracy (:func:`rocknroller.numerics.run_limits.energy_error_bound`).

    Attributes
    ----------
    maxima : rocknroller.numerics.trajectory.TurningPoints
        Time, Euler angles (φ and ψ unwrapped), Q_R, Q_J and body-frame state at each θ-maximum.
    slow_period : float or None
        Period of Θ = 2ψ at the maxima; None if not measurable within the run.
    Phi : float
        Azimuth span of φ mod π at the maxima.
    QR_extent, QJ_extent : float
        max − min of Q_R and Q_J at the maxima (the paper's quantities: a ValueError for a
        :class:`~rocknroller.analysis.model.body.LoadedSphere`).
    energy_rel_error : float
        Largest relative energy error of the run.
    n_steps : int
        Integration steps taken.

    The fraction of the maxima in each critical region, by the package's classifier ``region``:
    ``rr.region_fractions(run.maxima.QR, run.maxima.QJ, body)``
    (:func:`rocknroller.analysis.criticality.lines.region_fractions`).

    Examples
    --------
    >>> import math
    >>> import rocknroller as rr
    >>> body = rr.Body.paper(epsilon=1e-3)
    >>> run, = rr.run_ensemble([rr.Job(body, rr.EulerState(theta=0.95 * math.pi, psi=math.pi / 4), 200.0)])
    >>> print(type(run).__name__, len(run.maxima.t), run.energy_rel_error < 1e-12)
    RunSummary 15 True
    >>> print(f"Phi = {run.Phi:.4f}")
    Phi = 1.5094
    """

    maxima: TurningPoints
    slow_period: float | None
    Phi: float
    energy_rel_error: float
    n_steps: int

    @classmethod
    def from_run(cls, run: TurningPointRun) -> "RunSummary":
        """The summary of a run of ``simulate(..., samples=False)``."""
        return cls(maxima=run.maxima, slow_period=run.slow_period, Phi=run.Phi,
                   energy_rel_error=run.energy_rel_error, n_steps=run.n_steps)

    @property
    def n_maxima(self) -> int:
        """Number of θ-maxima in the run."""
        return len(self.maxima)

    def to_dataframe(self) -> "pandas.DataFrame":
        """One row per θ-maximum: t, θ, φ, ψ, Q_R, Q_J (:meth:`TurningPoints.to_dataframe`; needs pandas)."""
        return self.maxima.to_dataframe()

    def plot(self, ax: Any = None, kind: str = "orbit") -> Any:
        """Draw the θ-maxima on ``ax`` (a new pyplot figure without one): ``"orbit"`` their (Q_R, Q_J), ``"phi"`` φ
        against time (paper fig. 5).  Returns the axes."""
        from rocknroller.numerics import trajectory_plots as tp

        plots: dict[str, Callable[..., Any]] = {"orbit": tp.plot_invariant_orbit, "phi": tp.plot_phi_at_maxima}
        if kind not in plots:
            raise ValueError(f"kind must be one of {list(plots)}, got kind={kind!r}")
        return plots[kind](self, ax=ax)


def run_job(job: Job) -> RunSummary:
    """Run one job: :func:`rocknroller.numerics.integrate.simulate` with ``samples=False``, then its summary."""
    run = simulate(job.body, job.initial, job.t_end, samples=False, tol=job.tol)
    return RunSummary.from_run(run)


def run_jobs(jobs: Sequence[Job], lanes: int) -> list[RunSummary]:
    """Run jobs of one tolerance in one batch of ``lanes`` lanes (:func:`rocknroller.numerics.ensembles.batch.run_batch`;
    ``lanes=1`` runs each by :func:`run_job`, the scalar integrator), then their summaries."""
    if lanes == 1:
        return [run_job(job) for job in jobs]
    tols = {job.tol for job in jobs}
    if len(tols) > 1:
        raise ValueError(f"jobs: one batch runs at one tolerance, got tol in {sorted(tols)}")
    return [RunSummary.from_run(run) for run in run_batch([(j.body, j.initial, j.t_end) for j in jobs], lanes,
                                                          tol=jobs[0].tol)]


def _batches(jobs: list[Job], lanes: int) -> list[list[int]]:
    """The jobs' indices in batches of ``lanes`` of one tolerance and one kind of body (Body, LoadedSphere) each, the longest jobs (in radians Λ·t_end)
    together so that few lanes idle while the others finish.  Which jobs share a batch does not change any job's
    result (:mod:`batch`)."""
    batches = []
    for kind in sorted({(job.tol, len(job.body.params)) for job in jobs}):  # one tolerance, one kind of body each
        order = sorted((i for i in range(len(jobs)) if (jobs[i].tol, len(jobs[i].body.params)) == kind),
                       key=lambda i: -jobs[i].radians)
        batches += [order[k:k + lanes] for k in range(0, len(order), lanes)]
    return batches


def _check_count(value: Any, name: str, limit: int) -> int | None:
    if value is None:
        return None
    if isinstance(value, bool) or not isinstance(value, (int, np.integer)) or not 1 <= value <= limit:
        raise ValueError(f"{name} must be a whole number in [1, {limit}], got {name} {value!r}")
    return int(value)


def check_cluster(scheduler: Any = None, workers: Any = None, threads: Any = None, *,
                  prefix: str = "") -> tuple[str | None, int | None]:
    """Check where an ensemble is to run, before any work.

    Parameters
    ----------
    scheduler : str, optional
        TCP address of an existing dask scheduler, ``"tcp://host:port"`` or ``"host:port"``, such as
        ``"tcp://10.0.0.5:8786"`` (the only protocol rocknroller connects with).
    workers : int, optional
        Number of worker processes of a local cluster, in [1, ``MAX_WORKERS``].
    threads : int, optional
        Number of threads of the in-process path, in [1, ``MAX_THREADS``]; not with a cluster.
    prefix : str
        Put before the parameter names in error messages (``"--"`` for command-line options).

    Returns
    -------
    (scheduler, workers)
        As given (``scheduler`` stripped, ``workers`` an int); both None for the in-process path.

    Raises
    ------
    ValueError
        Naming the parameter: a scheduler that is not a TCP address, a count out of range, or two of them given.
    """
    s_name, w_name, t_name = (prefix + name for name in ("scheduler", "workers", "threads"))
    if scheduler is not None:
        match = _TCP_ADDRESS.fullmatch(scheduler.strip()) if isinstance(scheduler, str) else None
        if match is None or not 1 <= int(match["port"]) <= 65535:
            raise ValueError(f"{s_name} must be the address of a dask scheduler over TCP, 'tcp://host:port' or "
                             f"'host:port' with a port in [1, 65535], such as 'tcp://10.0.0.5:8786' (rocknroller "
                             f"connects over TCP only: tls:// needs security settings, ucx:// the ucx-py package, "
                             f"inproc:// a scheduler in this process, none of which it passes), got {s_name} "
                             f"{scheduler!r}")
        scheduler = scheduler.strip()
    workers = _check_count(workers, w_name, MAX_WORKERS)
    threads = _check_count(threads, t_name, MAX_THREADS)
    if scheduler is not None and workers is not None:
        raise ValueError(f"give either {s_name} (an existing cluster) or {w_name} (a local cluster), not both")
    if threads is not None and (scheduler is not None or workers is not None):
        raise ValueError(f"{t_name} sets the in-process path (a cluster runs one job per single-threaded worker): "
                         f"give {t_name} without {s_name} or {w_name}")
    return scheduler, workers


def run_ensemble(jobs: Sequence[Job], *, scheduler: str | None = None, workers: int | None = None,
                 threads: int | None = None, progress: bool | None = None,
                 budget: float | None = WORK_BUDGET_SECONDS, lanes: int | None = None) -> list[RunSummary]:
    """Run every job and return their summaries in job order.

    The jobs run in batches in the lanes of heyoka's batch integrator (:func:`run_jobs`), the longest together;
    each thread or worker runs whole batches.  The result is the same bit for bit whichever way the jobs are
    batched or run (see the module docstring).

    Parameters
    ----------
    jobs : sequence of Job
        At most ``MAX_JOBS``; each already checked against the limits of ``simulate``.
    scheduler : str, optional
        Address of an existing dask.distributed scheduler (``"tcp://host:port"``) to run the jobs on its workers.
    workers : int, optional
        Start a local dask.distributed cluster of this many single-threaded worker processes for the call, in
        [1, ``MAX_WORKERS``].  Not with ``scheduler``.
    threads : int, optional
        Without a cluster: run the jobs in this many threads of this process, in [1, ``MAX_THREADS``] (default 1,
        a plain loop).
    progress : bool or None
        A tqdm bar over the completed jobs on stderr (None: only if stderr is a terminal).
    budget : float or None
        CPU seconds the jobs may take together (:mod:`rocknroller.numerics.budget`; None: no limit), estimated before
        any work from their radians Λ·t_end; however many processes share them.
    lanes : int, optional
        Lanes per batch, in [``MIN_LANES``, ``MAX_LANES``] (default :func:`rocknroller.numerics.ensembles.lanes.default_lanes`: the
        width measured fastest on this machine by ``rocknroller warm``, else the one heyoka recommends for the CPU; the
        results do not depend on it); 1 runs each job by itself in the scalar integrator (:func:`run_job`), as
        ``simulate`` does, whose results differ from the lanes' in the last bits (:mod:`rocknroller.numerics.ensembles.batch`).

    Returns
    -------
    list of RunSummary
        One per job, in the order of ``jobs``.

    Raises
    ------
    ValueError
        Naming the parameter: too many jobs, an element that is not a :class:`Job`, a bad ``scheduler``,
        ``workers`` or ``threads`` (:func:`check_cluster`); a cluster requested without dask.distributed installed
        (``python -m pip install -e ".[distributed]"`` in a clone), a scheduler that cannot be reached, or workers
        whose versions of rocknroller, heyoka or numpy differ from this process's.

    Examples
    --------
    >>> import math
    >>> import rocknroller as rr
    >>> body = rr.Body.paper(epsilon=1e-3)
    >>> jobs = [rr.Job(body, rr.EulerState(theta=0.95 * math.pi, psi=psi0), 200.0) for psi0 in (0.5, 1.0)]
    >>> runs = rr.run_ensemble(jobs)
    >>> print([len(r.maxima.t) for r in runs])
    [15, 15]
    """
    scheduler, workers = check_cluster(scheduler, workers, threads)
    if lanes is not None and (isinstance(lanes, bool) or not isinstance(lanes, (int, np.integer))
                              or not (lanes == 1 or MIN_LANES <= lanes <= MAX_LANES)):
        raise ValueError(f"lanes must be 1 (the scalar integrator) or a whole number in [{MIN_LANES}, {MAX_LANES}] "
                         f"(MIN_LANES, MAX_LANES), got lanes={lanes!r}")
    lanes = default_lanes() if lanes is None else int(lanes)
    if isinstance(jobs, (str, bytes)) or not isinstance(jobs, Sequence):
        raise ValueError(f"jobs must be a sequence (list or tuple) of Job, got {type(jobs).__name__}")
    if len(jobs) > MAX_JOBS:
        raise ValueError(f"jobs: at most MAX_JOBS = {MAX_JOBS} jobs per call, got {len(jobs)}; split the ensemble")
    for i, job in enumerate(jobs):
        if not isinstance(job, Job):
            raise ValueError(f"jobs[{i}] must be a rocknroller.numerics.ensembles.ensemble.Job, got {type(job).__name__}")
    jobs = list(jobs)
    if not jobs:
        return []
    check_work(sum(job.radians for job in jobs) * HEYOKA_SECONDS_PER_RADIAN,
               f"{len(jobs)} direct run{'s' if len(jobs) > 1 else ''} (Λ t_end up to "
               f"{max(job.radians for job in jobs):.3g} radians)", budget)
    batches = _batches(jobs, lanes)
    if scheduler is None and workers is None:
        done = _run_in_process(jobs, batches, lanes, threads or 1, progress)
    else:
        done = _run_on_cluster(jobs, batches, lanes, scheduler, workers, progress)
    results: list[RunSummary | None] = [None] * len(jobs)
    for batch, summaries in zip(batches, done, strict=True):
        for i, summary in zip(batch, summaries, strict=True):
            results[i] = summary
    return [r for r in results if r is not None]


def _bar(total: int, enabled: bool | None, unit: str = "run") -> Any:
    from tqdm import tqdm

    if enabled is None:
        enabled = sys.stderr.isatty()
    return tqdm(total=total, disable=not enabled, unit=unit, leave=False, file=sys.stderr)


def _run_in_process(jobs: list[Job], batches: list[list[int]], lanes: int, threads: int,
                    progress: bool | None) -> list[list[RunSummary]]:
    with _bar(len(jobs), progress) as bar:
        if threads == 1:
            results = []
            for batch in batches:
                results.append(run_jobs([jobs[i] for i in batch], lanes))
                bar.update(len(batch))
            return results
        with ThreadPoolExecutor(max_workers=min(threads, len(batches))) as pool:
            futures = {pool.submit(run_jobs, [jobs[i] for i in batch], lanes): len(batch) for batch in batches}
            try:
                for future in as_completed(futures):
                    future.result()  # the first failure stops the call: the batches not yet started are dropped
                    bar.update(futures[future])
            except BaseException:
                pool.shutdown(cancel_futures=True)
                raise
        return [future.result() for future in futures]


def _versions() -> tuple[str, str, str]:
    """The versions that decide a job's result: rocknroller, heyoka, numpy."""
    import heyoka

    from rocknroller.numerics.provenance import __version__

    return __version__, heyoka.__version__, np.__version__


def _import_distributed(what: str) -> Any:
    try:
        import distributed
    except ImportError:
        raise ValueError(f"{what} runs the jobs on dask.distributed, which is not installed: "
                         f"{DISTRIBUTED_HINT}") from None
    return distributed


def _run_on_cluster(jobs: list[Job], batches: list[list[int]], lanes: int, scheduler: str | None,
                    workers: int | None, progress: bool | None) -> list[list[RunSummary]]:
    _import_distributed(f"scheduler={scheduler!r}" if scheduler is not None else f"workers={workers}")
    # fill heyoka's disk cache (if empty) before any worker needs the integrator
    for tol in {job.tol for job in jobs}:
        heyoka_integrator("double", tol) if lanes == 1 else batch_integrator(lanes, tol)
    return cluster_map(run_jobs, [([jobs[i] for i in batch], lanes) for batch in batches], [len(b) for b in batches],
                       scheduler=scheduler, workers=workers, progress=progress)


def cluster_map(fn: Callable[..., Any], tasks: Sequence[tuple[Any, ...]], sizes: Sequence[int], *,
                scheduler: str | None = None, workers: int | None = None, progress: bool | None = None,
                unit: str = "run") -> list[Any]:
    """``[fn(*task) for task in tasks]`` on a dask.distributed cluster: the one at ``scheduler`` (an address checked by
    :func:`check_cluster`), or a local one of ``workers`` single-threaded processes started for the call.  A tqdm bar
    advances by ``sizes[i]`` as task i completes.  Workers whose versions of (rocknroller, heyoka, numpy) differ from
    this process's are refused (ValueError), as is a missing dask.distributed or an unreachable scheduler."""
    what = f"scheduler={scheduler!r}" if scheduler is not None else f"workers={workers}"
    distributed = _import_distributed(what)
    if workers is not None:  # the scheduler's HTTP server on a free port: never a clash with another cluster's
        with distributed.LocalCluster(n_workers=workers, threads_per_worker=1, processes=True,
                                      dashboard_address=":0") as cluster, distributed.Client(cluster) as client:
            return _submit(client, fn, tasks, sizes, what, progress, unit)
    try:
        client = distributed.Client(scheduler)
    except (OSError, TimeoutError) as exc:
        raise ValueError(f"scheduler={scheduler!r}: cannot connect to the dask scheduler ({exc})") from None
    with client:
        return _submit(client, fn, tasks, sizes, what, progress, unit)


def _submit(client: Any, fn: Callable[..., Any], tasks: Sequence[tuple[Any, ...]], sizes: Sequence[int], what: str,
            progress: bool | None, unit: str) -> list[Any]:
    import distributed

    here = _versions()
    odd = {addr: v for addr, v in client.run(_versions).items() if v != here}
    if odd:
        raise ValueError(f"{what}: workers run other versions of (rocknroller, heyoka, numpy) than {here}, so their "
                         f"results could differ: {odd}")
    futures = [client.submit(fn, *task, pure=False) for task in tasks]
    size_of = {future.key: n for future, n in zip(futures, sizes)}
    with _bar(sum(sizes), progress, unit) as bar:
        for future in distributed.as_completed(futures):
            if future.status == "error":
                future.result()  # re-raises the task's exception here; leaving the client drops the other tasks
            bar.update(size_of[future.key])
    return client.gather(futures)
