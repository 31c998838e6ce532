"""``rocknroller warm``: compile every integrator the package uses, ahead of time, into heyoka's disk cache; with
``--tables``, build the slow map's tables over energy of a body too."""

from __future__ import annotations

import argparse
import math
import sys
import time
import warnings
from typing import Any, Callable

from rocknroller.analysis.model.body import Body
from rocknroller.cli.options import add_body_options, body_from_args


def integrators() -> list[tuple[str, Callable[[], Any]]]:
    """(what, build) for every compiled integrator of the package: the direct ODE in double and extended precision,
    the ensembles' batch integrator at each lane count the ensembles may use (``LANE_CANDIDATES`` and heyoka's
    recommendation, :mod:`rocknroller.numerics.ensembles.lanes`), the chaos indicators' variational integrator (each of
    these three also for the general loaded sphere, Chaplygin's top), and the
    averaging tables' variational integrators of order 1 and 2 and of the three harmonics.  Each build loads from heyoka's disk cache when it
    holds the integrator, and compiles it into that cache otherwise."""
    from rocknroller.analysis.slow.map.orbit import _variational_integrator
    from rocknroller.numerics.ensembles.batch import batch_integrator, batch_width
    from rocknroller.numerics.ensembles.lanes import LANE_CANDIDATES
    from rocknroller.numerics.integrate import heyoka_integrator
    from rocknroller.numerics.variational import variational_integrator

    widths = sorted({*LANE_CANDIDATES, batch_width()})
    return [("direct ODE (double precision)", lambda: heyoka_integrator("double")),
            ("direct ODE (extended precision)", lambda: heyoka_integrator("extended")),
            *((f"ensembles' batch integrator ({w} lanes)", lambda w=w: batch_integrator(w)) for w in widths),
            ("chaos indicators' variational integrator", variational_integrator),
            ("direct ODE of the general loaded sphere (double precision)", lambda: heyoka_integrator("double", n_par=7)),
            *((f"ensembles' batch integrator, general loaded sphere ({w} lanes)",
               lambda w=w: batch_integrator(w, n_par=7)) for w in widths),
            ("chaos indicators' variational integrator, general loaded sphere", lambda: variational_integrator(7)),
            ("averaging tables' variational integrator, order 1", lambda: _variational_integrator(1)),
            ("averaging tables' variational integrator, order 2", lambda: _variational_integrator(2)),
            ("averaging tables' variational integrator, three harmonics",
             lambda: _variational_integrator("harmonic"))]


def register(sub: argparse._SubParsersAction) -> None:
    """Add the ``warm`` subcommand and its ``--help`` to ``sub``."""
    p = sub.add_parser(
        "warm",
        help="compile every integrator ahead of time into heyoka's disk cache (once per machine)",
        description="Compile the package's integrators (the direct ODE in double and extended precision, the "
        "ensembles' batch integrator, the chaos indicators' and the averaging tables' variational integrators) into "
        "heyoka's disk cache (HEYOKA_CACHE_DIR), so that no later command waits for a compilation: one that is "
        "already there loads in a fraction of a second. Compiling all of them takes about two minutes of CPU. "
        "Then it times the ensembles' batch integrator at 4 and 8 lanes side by side (a few seconds) and records the "
        "faster for run_ensemble (the results do not depend on it). "
        "Prints each integrator, whether it was compiled and cached or loaded from the cache, and the seconds it "
        "took; exits 1, saying why, when heyoka's disk cache cannot be used (nothing is then kept for later "
        "processes). With --tables it then builds the slow map's tables over energy of the body (first and second "
        "order at every release angle from 0.75pi to 0.999pi, once per body, shared by --processes; cached in "
        "ROCKNROLLER_CACHE; the cost: docs/performance.md), after which the first prediction at any release angle takes "
        "no table build.",
    )
    p.add_argument("--tables", action="store_true",
                   help="also build the slow map's tables over energy of the body given by the body options (once "
                   "per body)")
    p.add_argument("--processes", type=int, default=2, metavar="N",
                   help="processes of this machine that build the tables (default 2; the tables do not depend on it)")
    p.add_argument("--quiet", action="store_true", help="no progress bars (the tables' build)")
    add_body_options(p)
    p.set_defaults(run=run)


def run(args: argparse.Namespace) -> int:
    """Run ``rocknroller warm`` with the parsed ``args``; returns the exit status: 1 when heyoka's disk cache cannot be
    used, so that the integrators compiled here are not kept for later processes."""
    import heyoka as hy

    from rocknroller.numerics.backends import check_diskcache
    from rocknroller.numerics.cache import CacheWarning, warming
    from rocknroller.numerics.ensembles.lanes import measure_lanes
    from rocknroller.numerics.parallel import check_processes

    processes = check_processes(args.processes, "--processes")
    body = body_from_args(args, gravity=True) if args.tables else None  # bad body options refused before any work
    with warnings.catch_warnings(record=True) as caught:
        warnings.simplefilter("always", CacheWarning)
        check_diskcache()  # an unusable cache is switched off here, with a CacheWarning that says why
    why = [str(w.message) for w in caught if issubclass(w.category, CacheWarning)]
    cached = bool(hy.llvm_state.get_diskcache_enabled())
    with warming():
        for what, build in integrators():
            size = hy.llvm_state.get_diskcache_size() if cached else 0
            start = time.perf_counter()
            build()
            seconds = time.perf_counter() - start
            if not cached:
                status = "compiled, not cached"
            elif hy.llvm_state.get_diskcache_size() > size:
                status = "compiled and cached"
            else:
                status = "loaded from heyoka's disk cache"
            print(f"{what}: {status} in {seconds:.1f} s", flush=True)
        choice = measure_lanes()
        print(f"ensembles' lanes, measured side by side: {choice.describe()}", flush=True)
    if body is not None:
        _tables(body, processes, None if not args.quiet else False)
    if not cached:
        reason = why[0] if why else "heyoka's disk cache is switched off (hy.llvm_state.set_diskcache_enabled)"
        print(f"rocknroller warm: nothing was cached, so every process compiles again: {reason}", file=sys.stderr)
        return 1
    return 0


def _tables(body: Body, processes: int, progress: bool | None) -> None:
    """Build (or find cached) the tables over energy of ``body`` and print what was done, the CPU seconds and the
    errors measured at the build's off-node checks."""
    import resource

    from rocknroller.analysis.slow.map.tables_at_once import energy_tables_cached, load_energy_tables

    def cpu() -> float:
        own, kids = resource.getrusage(resource.RUSAGE_SELF), resource.getrusage(resource.RUSAGE_CHILDREN)
        return own.ru_utime + own.ru_stime + kids.ru_utime + kids.ru_stime

    cached, start = energy_tables_cached(body), cpu()
    span = load_energy_tables(body, workers=processes, progress=progress)
    status = "loaded from the cache" if cached else f"built and cached in {cpu() - start:.0f} s of CPU"
    print(f"tables over energy, theta0 in [{span.theta0_lo / math.pi:.4g}pi, "
          f"{span.theta0_hi / math.pi:.4g}pi], {body.describe()}: {status}; interpolation error at the "
          f"build's checks {span.first_error:.1e} (first order), {span.second_error:.1e} (k2)", flush=True)
