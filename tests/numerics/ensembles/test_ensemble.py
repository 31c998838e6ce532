"""Ensembles of direct runs: the same summaries bit for bit in a loop, in threads and on a dask cluster of two worker
processes (in batches, heyoka's batch integrator); with lanes=1 the summary is simulate()'s own to the bit (the batch
lanes' agreement with simulate is tests/numerics/ensembles/test_batch.py's); inputs are refused before any work, naming the
parameter."""

from __future__ import annotations

import argparse
import dataclasses
import math
import os
import pickle
import sys

import numpy as np
import pytest

import rocknroller as rr
from rocknroller.cli.options import add_cluster_options, cluster_from_args
from rocknroller.numerics.ensembles import ensemble as ens
from rocknroller.numerics.ensembles.ensemble import Job, RunSummary, run_ensemble
from rocknroller.numerics.trajectory import TurningPoints


def _jobs() -> list[Job]:
    """A small atlas: three asymmetries, three spin phases, short runs, and one long enough for a slow period."""
    jobs = [Job(rr.Body.paper(eps), rr.EulerState(0.95 * math.pi, psi=psi0), 20.0)
            for eps in (1e-3, 1e-2, 0.0) for psi0 in (0.0, math.pi / 8, math.pi / 4)]
    return jobs + [Job(rr.Body.paper(1e-2), rr.EulerState.from_omega(0.9 * math.pi, 0.0, 0.3, (0.0, 1e-3, -1e-3)),
                       600.0)]


@pytest.fixture(scope="module")
def jobs() -> list[Job]:
    return _jobs()


@pytest.fixture(scope="module")
def in_process(jobs) -> list[RunSummary]:
    return run_ensemble(jobs, progress=False)


def assert_bit_identical(a: list[RunSummary], b: list[RunSummary]) -> None:
    """Every array equal element for element (np.array_equal, same dtype), every number equal (==, same type)."""
    assert len(a) == len(b)
    for x, y in zip(a, b):
        assert x.maxima.body == y.maxima.body
        for name in [f.name for f in dataclasses.fields(TurningPoints) if f.name != "body"] + ["QR", "QJ"]:
            u, v = getattr(x.maxima, name), getattr(y.maxima, name)
            assert u.dtype == v.dtype and np.array_equal(u, v), name
        for name in [f.name for f in dataclasses.fields(RunSummary)[1:]] + ["QR_extent", "QJ_extent"]:
            u, v = getattr(x, name), getattr(y, name)
            assert type(u) is type(v) and u == v, (name, u, v)


def test_summary_is_simulates_own(jobs):
    """With lanes=1 each summary holds the maxima and diagnostics of simulate(..., samples=False) for its job, to the
    bit, in job order."""
    scalar = run_ensemble(jobs, progress=False, lanes=1)
    assert [s.n_maxima for s in scalar[:3]] == [1, 1, 1] and scalar[-1].n_maxima > 20
    assert scalar[-1].slow_period is not None and scalar[-1].QR_extent > 0.0
    for job, s in zip(jobs, scalar):
        run = rr.simulate(job.body, job.initial, job.t_end, samples=False)
        assert_bit_identical([s], [RunSummary.from_run(run)])
        assert (s.slow_period, s.Phi, s.QR_extent, s.QJ_extent, s.energy_rel_error, s.n_steps) == \
            (run.slow_period, run.Phi, run.QR_extent, run.QJ_extent, run.energy_rel_error, run.n_steps)
    # a run watched step by step (a progress bar: a Python callback per step) takes the same steps to the same bits
    watched = rr.simulate(jobs[-1].body, jobs[-1].initial, jobs[-1].t_end, samples=False, progress=True)
    assert_bit_identical([scalar[-1]], [RunSummary.from_run(watched)])


def test_batches_of_any_width_and_split_give_the_same_bits(jobs, in_process):
    """A job's lane does not depend on its lane mates or on the width (numerics/ensembles/batch.py): batches of 2 and 4 lanes,
    and the jobs in reverse order (so in other batches and lanes), give the default width's results to the bit."""
    assert_bit_identical(run_ensemble(jobs, progress=False, lanes=2), in_process)
    assert_bit_identical(run_ensemble(jobs[::-1], progress=False, lanes=4)[::-1], in_process)
    assert [s.n_maxima for s in in_process[:3]] == [1, 1, 1] and in_process[-1].n_maxima > 20


def test_threads_give_the_loops_results_bit_for_bit(jobs, in_process):
    """Each thread integrates with its own copy of the compiled integrator: the same machine code, the same bits."""
    assert_bit_identical(run_ensemble(jobs, threads=2, progress=False), in_process)
    assert run_ensemble([], progress=False) == []


def test_a_two_worker_local_cluster_gives_the_in_process_results_bit_for_bit(jobs, in_process):
    """The acceptance test of the cluster path: a dask LocalCluster of two worker processes, same bits."""
    pytest.importorskip("distributed")
    assert_bit_identical(run_ensemble(jobs, workers=2, progress=False), in_process)


@pytest.fixture(scope="module")
def cluster():
    """A running dask cluster of two single-threaded worker processes, as `dask scheduler` / `dask worker` make."""
    distributed = pytest.importorskip("distributed")
    with distributed.LocalCluster(n_workers=2, threads_per_worker=1, processes=True, dashboard_address=":0") as c:
        yield c


def test_an_existing_cluster_gives_the_in_process_results_bit_for_bit(jobs, in_process, cluster):
    assert_bit_identical(run_ensemble(jobs, scheduler=cluster.scheduler_address, progress=False), in_process)


def test_workers_with_other_versions_are_refused(cluster, monkeypatch):
    """This process claims another rocknroller version than its workers report: refused before any job runs."""
    real, here = ens._versions, os.getpid()

    def claimed() -> tuple[str, ...]:  # sent to the workers too, where it reports the real versions
        return ("0.0.0-other",) + real()[1:] if os.getpid() == here else real()

    monkeypatch.setattr(ens, "_versions", claimed)
    with pytest.raises(ValueError, match=r"workers run other versions of \(rocknroller, heyoka, numpy\)"):
        run_ensemble(_jobs()[:1], scheduler=cluster.scheduler_address, progress=False)


def test_an_unreachable_scheduler_is_named():
    pytest.importorskip("distributed")
    import dask

    with dask.config.set({"distributed.comm.timeouts.connect": "1s"}):
        with pytest.raises(ValueError, match=r"scheduler='tcp://127.0.0.1:9': cannot connect"):
            run_ensemble(_jobs()[:1], scheduler="tcp://127.0.0.1:9", progress=False)


def test_a_cluster_without_dask_says_how_to_install_it(monkeypatch):
    monkeypatch.setitem(sys.modules, "distributed", None)
    with pytest.raises(ValueError, match=r"workers=2 .*pip install -e \"\.\[distributed\]\" in a clone"):
        run_ensemble(_jobs()[:1], workers=2, progress=False)


def test_jobs_are_plain_picklable_descriptions():
    job = _jobs()[-1]
    assert pickle.loads(pickle.dumps(job)) == job
    assert [f.name for f in dataclasses.fields(Job) if f.init] == ["body", "initial", "t_end", "tol"]
    plan = rr.numerics.integrate.check_run(job.body, job.initial, job.t_end, samples=False)
    assert job.radians == plan.rate * plan.t_end  # the work of the run, for the ensemble's budget
    assert isinstance(Job(rr.Body.paper(), rr.EulerState(3.0), 5).t_end, float)


@pytest.mark.parametrize("kwargs, match", [
    ({"body": "paper"}, r"body must be a rocknroller Body or LoadedSphere"),
    ({"initial": (3.0, 0.0, 0.0)}, r"initial must be a rocknroller.analysis.model.equations.EulerState"),
    ({"t_end": -1.0}, r"t_end must be a finite number > 0"),
    ({"t_end": "long"}, r"t_end must be a finite number > 0"),
    ({"t_end": 1e12}, r"t_end=1000000000000.0 is too long.*MAX_RADIANS"),
    ({"initial": rr.EulerState(math.pi)}, r"no motion"),
])
def test_a_job_is_checked_against_simulates_limits(kwargs, match):
    args = {"body": rr.Body.paper(), "initial": rr.EulerState(3.0), "t_end": 10.0, **kwargs}
    with pytest.raises(ValueError, match=match):
        Job(**args)


@pytest.mark.parametrize("kwargs, match", [
    ({"workers": 0}, r"workers must be a whole number in \[1, 256\], got workers 0"),
    ({"workers": ens.MAX_WORKERS + 1}, r"workers must be a whole number in \[1, 256\]"),
    ({"workers": 1.5}, r"workers must be a whole number"),
    ({"workers": True}, r"workers must be a whole number"),
    ({"threads": -1}, r"threads must be a whole number in \[1, 256\]"),
    ({"scheduler": ""}, r"scheduler must be the address of a dask scheduler"),
    ({"scheduler": 8786}, r"scheduler must be the address of a dask scheduler"),
    # protocols rocknroller does not connect with (dask raised a TypeError, or "not enough values to unpack")
    ({"scheduler": "ucx://10.0.0.5:8786"}, r"scheduler must be the address of a dask scheduler over TCP.*got "
                                           r"scheduler 'ucx://10.0.0.5:8786'"),
    ({"scheduler": "tls://10.0.0.5:8786"}, r"over TCP.*tls:// needs security settings"),
    ({"scheduler": "inproc://x"}, r"over TCP.*inproc://"),
    ({"scheduler": "tcp://host"}, r"over TCP, 'tcp://host:port' or 'host:port' with a port in \[1, 65535\]"),
    ({"scheduler": "tcp://host:65536"}, r"with a port in \[1, 65535\]"),
    ({"scheduler": "tcp://h:1", "workers": 2}, r"give either scheduler .* or workers .*, not both"),
    ({"workers": 2, "threads": 2}, r"threads sets the in-process path"),
    ({"lanes": 0}, r"lanes must be 1 \(the scalar integrator\) or a whole number in \[2, 16\]"),
    ({"lanes": ens.MAX_LANES + 1}, r"lanes must be 1 .* or a whole number in \[2, 16\].*got lanes=17"),
    ({"lanes": 4.0}, r"lanes must be 1"),
    ({"lanes": True}, r"lanes must be 1"),
])
def test_where_to_run_is_checked_before_any_work(kwargs, match):
    with pytest.raises(ValueError, match=match):
        run_ensemble(_jobs()[:1], progress=False, **kwargs)


def test_the_jobs_are_checked_before_any_work():
    with pytest.raises(ValueError, match=r"jobs\[1\] must be a rocknroller.numerics.ensembles.ensemble.Job, got tuple"):
        run_ensemble([_jobs()[0], (rr.Body.paper(), rr.EulerState(3.0), 10.0)], progress=False)
    with pytest.raises(ValueError, match=r"jobs: at most MAX_JOBS = 100000 jobs per call, got 100001"):
        run_ensemble(range(ens.MAX_JOBS + 1), progress=False)
    with pytest.raises(ValueError, match=r"jobs must be a sequence"):
        run_ensemble(iter(_jobs()), progress=False)


def test_cluster_options_name_the_option():
    parser = argparse.ArgumentParser()
    add_cluster_options(parser)
    assert cluster_from_args(parser.parse_args([])) == (None, None)
    assert cluster_from_args(parser.parse_args(["--workers", "2"])) == (None, 2)
    assert cluster_from_args(parser.parse_args(["--scheduler", " tcp://10.0.0.5:8786 "])) == ("tcp://10.0.0.5:8786",
                                                                                            None)
    with pytest.raises(ValueError, match=r"--workers must be a whole number in \[1, 256\], got --workers 0"):
        cluster_from_args(parser.parse_args(["--workers", "0"]))
    with pytest.raises(ValueError, match=r"--scheduler must be the address .* over TCP.*got --scheduler 'ucx://h:1'"):
        cluster_from_args(parser.parse_args(["--scheduler", "ucx://h:1"]))
    with pytest.raises(SystemExit):  # argparse: not allowed with argument --scheduler
        parser.parse_args(["--workers", "2", "--scheduler", "tcp://h:1"])


def test_tcp_addresses_are_accepted_as_given():
    """A host name, an IPv4 or a bracketed IPv6 address, with or without tcp://, stripped of spaces."""
    for address in ("10.0.0.5:8786", "tcp://scheduler.example.org:8786", "tcp://[::1]:8786", " tcp://h:1 "):
        assert ens.check_cluster(address) == (address.strip(), None)


def test_scheduler_errors_name_the_option_on_the_command_line():
    """A failure to connect names scheduler='...' in the API; the CLI's message names --scheduler, as given."""
    pytest.importorskip("distributed")
    import dask

    from rocknroller.cli import option_names

    with dask.config.set({"distributed.comm.timeouts.connect": "1s"}):
        with pytest.raises(ValueError) as info:
            run_ensemble(_jobs()[:1], scheduler="tcp://127.0.0.1:9", progress=False)
    message = str(info.value)
    assert message.startswith("scheduler='tcp://127.0.0.1:9': cannot connect")
    assert option_names(message, ["atlas", "--scheduler", "tcp://127.0.0.1:9"]) == "--" + message
