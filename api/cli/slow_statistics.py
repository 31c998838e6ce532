"""``rocknroller slow --statistics``: the statistical prediction beside the point prediction.

Past the predictability horizon the map's point predictions hold statistically only
(:meth:`rocknroller.analysis.slow.prediction_result.SlowPrediction.horizon`).  Beside them ``slow`` then gives the
statistical prediction: the map's ensemble over a stated small ball of releases
(:class:`rocknroller.analysis.slow.ensemble_statistics.StartBall`: ψ0 uniform in ±δ about the release's, seeded;
:func:`~rocknroller.analysis.slow.ensemble_statistics.map_ensemble` at the point prediction's order and span), the mean, standard deviation (ddof = 1) and standard error of each of
:data:`~rocknroller.analysis.slow.ensemble_statistics.STATISTICS` (region fractions, reversals per 1000 time units,
extents) over its members, each beside the point prediction's own value of it
(:func:`~rocknroller.analysis.slow.ensemble_statistics.member_statistics` of the predicted maxima), labelled
"statistical (map ensemble of N starts within ±δ)".  The ensemble runs by default (``AUTO_MEMBERS`` members) when
t_end lies past the horizon, on request (``--statistics N``) for any release from rest, never with
``--statistics 0``; it costs about N point predictions (~ms each per 1000 time units once the tables are cached).
"""

from __future__ import annotations

import argparse
from pathlib import Path
from typing import Any

from rocknroller.cli.options import add_budget_option, budget_from_args

__all__ = ["AUTO_MEMBERS", "DELTA_DEFAULT", "STATISTICS_CSV", "add_statistics_options", "check_statistics_options",
           "check_statistics_work", "statistics_summary", "statistics_lines", "write_statistics_csv"]

#: Members of the ensemble run by default past the horizon.
AUTO_MEMBERS = 32
#: Default half-width δ of the ball in ψ0 (rad): that of the validation's ensembles (docs/chaos_statistics.md).
DELTA_DEFAULT = 1e-3
#: The file written beside ``slow_maxima.csv`` by ``--csv`` when the ensemble ran.
STATISTICS_CSV = "slow_statistics.csv"


def add_statistics_options(p: argparse.ArgumentParser) -> None:
    """Add ``--statistics``, ``--statistics-delta`` and ``--statistics-seed`` to ``slow``'s parser."""
    from rocknroller.analysis.slow.ensemble_statistics import MAX_MEMBERS

    g = p.add_argument_group("statistical prediction (past the predictability horizon)")
    g.add_argument("--statistics", type=int, default=None, metavar="N",
                   help=f"releases from rest: beside the point prediction, the statistical one: the map's ensemble "
                        f"of N releases with psi0 uniform within +-DELTA (seeded), the mean +- standard deviation of "
                        f"the fractions of rocks per critical region, the reversals per 1000 time units and the "
                        f"extents, labelled 'statistical (map ensemble of N starts within +-DELTA)'; 2 <= N <= "
                        f"{MAX_MEMBERS} (about N point predictions' cost), 0: never (default: {AUTO_MEMBERS} members "
                        f"when t_end lies past the predictability horizon, none otherwise)")
    g.add_argument("--statistics-delta", type=float, default=DELTA_DEFAULT, metavar="DELTA",
                   help=f"half-width of the ensemble's ball in psi0, 0 < DELTA <= pi/2 (rad; default "
                        f"{DELTA_DEFAULT:g})")
    g.add_argument("--statistics-seed", type=int, default=0, metavar="SEED",
                   help="seed of the ball's random starts (numpy default_rng; default 0)")
    add_budget_option(p, "the statistical ensemble")


def check_statistics_options(args: argparse.Namespace, release: bool) -> None:
    """Refuse a bad ``--statistics`` (before any table is built), or one asked for a start that is not a release
    from rest."""
    from rocknroller.analysis.slow.ensemble_statistics import MAX_MEMBERS

    n = args.statistics
    if n is not None and n != 0 and not 2 <= n <= MAX_MEMBERS:
        raise ValueError(f"--statistics must be 0 (none) or a number of members in [2, {MAX_MEMBERS}], got "
                         f"--statistics {n!r}")
    if not 0.0 < args.statistics_delta <= 1.5707963267948966:
        raise ValueError(f"--statistics-delta must be a half-width in (0, pi/2] (rad), got --statistics-delta "
                         f"{args.statistics_delta!r}")
    if args.statistics_seed < 0:
        raise ValueError(f"--statistics-seed must be >= 0, got --statistics-seed {args.statistics_seed!r}")
    if n and not release:
        raise ValueError("--statistics applies to releases from rest in the release tables' range (its ensemble "
                         "is a ball of release angles psi0): leave out the rate options and --critical-line")


def check_statistics_work(args: argparse.Namespace, body: Any, theta0: float, order: int) -> None:
    """Refuse an ensemble of ``--statistics N`` members whose estimated CPU time exceeds ``--budget`` (before any
    table is built; :func:`rocknroller.analysis.slow.work.check_map_work`).  The default ensemble past the horizon
    (``AUTO_MEMBERS``) is checked by ``map_ensemble`` itself."""
    from rocknroller.analysis.slow.work import check_map_work

    if args.statistics:
        check_map_work(body, [theta0], args.statistics, args.t_end, order,
                       f"--statistics {args.statistics} ({args.statistics} map runs of {args.t_end:g} time units each)", budget_from_args(args))


def statistics_summary(args: argparse.Namespace, body: Any, pred: Any, summary: dict[str, Any],
                       release: bool, off_tables: str | None = None) -> dict[str, Any]:
    """The summary's ``statistics`` entry (null with ``statistics_note`` where none was made): the ball, the label
    and, per statistic, the point prediction's value and the ensemble's mean, standard deviation and standard
    error.  ``release``: a release from rest on the release tables; ``off_tables``: why a release from rest that is
    not on them has none (else the start is not a release from rest)."""
    import warnings

    import numpy as np

    from rocknroller.analysis.slow.ensemble_statistics import (STATISTIC_UNITS, STATISTICS, StartBall, map_ensemble,
                                                               member_statistics)
    from rocknroller.analysis.slow.map.limits import AveragingRangeError, AveragingValidityWarning

    n = args.statistics
    if n is None:
        n = AUTO_MEMBERS if summary.get("beyond_horizon") else 0
        why = "t_end lies within the predictability horizon" if summary.get("horizon") else "no horizon"
    else:
        why = "--statistics 0"
    if n and release and pred.series.t.size == 0:
        return {"statistics": None, "statistics_note": "no statistical prediction: the run ends before the first "
                                                       "theta-maximum (no samples to compare; give a longer --t-end)"}
    if n == 0 or not release:
        reason = why if release else off_tables or ("not a release from rest (the ensemble is a ball of release "
                                                    "angles psi0)")
        return {"statistics": None, "statistics_note": f"no statistical prediction: {reason}"}
    ball = StartBall(summary["theta0"], summary["psi0"], args.statistics_delta, n, seed=args.statistics_seed)
    with warnings.catch_warnings():  # the members' tables and K are the point prediction's: its warnings say it
        warnings.simplefilter("ignore", AveragingValidityWarning)
        try:
            ens = map_ensemble(body, ball, args.t_end, order=pred.order, progress=False,
                               budget=budget_from_args(args))
        except AveragingRangeError as exc:  # fewer than two members stayed on the tables
            return {"statistics": None, "statistics_note": f"no statistical prediction: {exc}"}
    s = pred.series
    point = member_statistics(body, s.t, s.QR, s.QJ, args.t_end)
    values = {name: {"point": point[name], "mean": ens.mean(name), "std": float(np.std(ens.values[name], ddof=1)),
                     "standard_error": ens.standard_error(name), "unit": STATISTIC_UNITS.get(name, "")}
              for name in STATISTICS}
    label = f"statistical (map ensemble of {n} starts within +-{args.statistics_delta:g} in psi0)"
    return {"statistics": {"label": label, "ball": ball.describe(), "members": n, "delta": args.statistics_delta,
                           "seed": args.statistics_seed, "order": ens.order, "t_end": args.t_end,
                           "members_left": len(ens.left), "psi0_left": list(ens.left), "values": values}}


def statistics_lines(s: dict[str, Any]) -> list[str]:
    """The text lines of the statistical prediction (:func:`statistics_summary`): one per statistic, the point
    prediction's value beside the ensemble's mean +- standard deviation."""
    st = s.get("statistics")
    if st is None:
        return [s["statistics_note"]] if "statistics_note" in s else []
    point = "point prediction" + (" (past the horizon)" if s.get("beyond_horizon") else "")
    lines = [f"{st['label']}: {st['ball']}, map of order {st['order']}, over t_end = {st['t_end']:g}"]
    if st["members_left"]:
        lines.append(f"  {st['members_left']} of the {st['members']} members left the tables before t_end (psi0 = "
                     f"{', '.join(f'{p:.6g}' for p in st['psi0_left'])}); the statistics are over the other "
                     f"{st['members'] - st['members_left']}")
    lines.append(f"  {'statistic':<18}  {point:>33}  {'ensemble mean +- std':>26}")
    for name, v in st["values"].items():
        lines.append(f"  {name:<18}  {v['point']:>33.6g}  {v['mean']:>12.6g} +- {v['std']:<10.3g} {v['unit']}".rstrip())
    return lines


def write_statistics_csv(path: Path, body: Any, s: dict[str, Any]) -> Path:
    """``slow_statistics.csv``: per statistic the point prediction's value, the ensemble's mean, standard deviation
    and standard error; the header records the run, the ball and the label."""
    from rocknroller.papers.output import angle_text, write_csv

    st = s["statistics"]
    header = [f"rocknroller slow: body {body.describe()}; eps={body.epsilon_text()}; "
              f"theta0={angle_text(s['theta0'])}; psi0={angle_text(s['psi0'])}; t_end={s['t_end']!r}",
              f"{st['label']}: {st['ball']}; map of order {st['order']}; {st['members_left']} members left the tables "
              f"before t_end (left out)",
              "point: the point prediction's own value" + (" (past the predictability horizon: statistical only)"
                                                          if s.get("beyond_horizon") else "")
              + "; mean, std (ddof 1), standard_error: over the ensemble's members; reversals per 1000 time units"]
    names = list(st["values"])
    return write_csv(path, {"statistic": names, **{k: [st["values"][n][k] for n in names]
                                                   for k in ("point", "mean", "std", "standard_error", "unit")}},
                     header)
