"""``rocknroller reproduce``: every figure and table of the paper, computed by the library, with an index page."""

from __future__ import annotations

import argparse
import re
import sys
import time
from pathlib import Path
from typing import Any, Sequence

from rocknroller.cli.options import output_path, prepare_output_dir
from rocknroller.papers.output import PRODUCER


def register(sub: argparse._SubParsersAction) -> None:
    """Add the ``reproduce`` subcommand and its ``--help`` to ``sub``."""
    p = sub.add_parser(
        "reproduce",
        help="reproduce the paper's figures and tables (PNG, PDF, CSV and an index page)",
        description="Run the reproduction of Lynch & Bustamante's figures and tables. Each output is "
        "computed by the library from the paper's stated initial conditions; index.md lists every file "
        "with its caption and the numbers measured.",
    )
    p.add_argument("--out", type=output_path, default=Path("rocknroller-output"), metavar="DIR",
                   help="output directory (default ./rocknroller-output); it must be new or empty unless --force")
    p.add_argument("--force", action="store_true",
                   help="write into an existing, non-empty --out, overwriting the files of the same names")
    p.add_argument("--only", nargs="+", default=None, metavar="NAME", help="run only these (see --list)")
    p.add_argument("--list", action="store_true", help="list the available figures and tables and exit")
    p.add_argument("--quiet", action="store_true", help="no progress bar")
    p.set_defaults(run=run)


def _format(value: object) -> str:
    if isinstance(value, float):
        return f"{value:.6g}"
    return str(value)


#: Characters with a meaning in Markdown text or tables, backslash-escaped so that they show as written.
_MARKDOWN_SPECIAL = re.compile(r"([\\`*_\[\]<>|#])")


def markdown_text(text: str) -> str:
    """``text`` with Markdown's special characters escaped (a ``|`` would split a table cell)."""
    return _MARKDOWN_SPECIAL.sub(r"\\\1", text)


def _section(out: Path, res: Any, seconds: float) -> str:
    """The index section of one output: caption, run time and version, files, and the table of measured numbers."""
    lines = [f"## {res.name}", "", markdown_text(res.caption), "",
             f"Run time: {seconds:.1f} s ({markdown_text(PRODUCER)})", ""]
    for path in res.outputs:
        rel = path.relative_to(out) if path.is_relative_to(out) else path
        lines.append(f"![{res.name}]({rel})" if path.suffix == ".png" else f"- [{rel}]({rel})")
    if res.numbers:
        lines += ["", "| quantity | value |", "| --- | --- |"]
        lines += [f"| {markdown_text(k)} | {markdown_text(_format(v))} |" for k, v in res.numbers.items()]
    return "\n".join(lines) + "\n"


def _sections(text: str) -> dict[str, str]:
    """The sections of an index.md written by :func:`write_index`, by output name (a caption cannot start a line
    with ``## ``: its ``#`` is escaped)."""
    return {part.split("\n", 1)[0].strip(): "## " + part.rstrip("\n") + "\n"
            for part in re.split(r"(?m)^## ", text)[1:]}


def _files_remain(out: Path, section: str) -> bool:
    links = re.findall(r"\]\(([^)]+)\)", section)
    return bool(links) and all((out / link).is_file() for link in links)


def write_index(out: Path, results: list, timings: dict[str, float], names: Sequence[str] | None = None) -> Path:
    """``out/index.md``: per output its caption, files and measured numbers (a two-column table whose cells are
    the escaped :func:`markdown_text` of the quantity and of :func:`_format` of its value).

    Parameters
    ----------
    names : every output the index may list, in its order (default: those of ``results``).  The sections that an
        earlier index.md in ``out`` holds for the others among them stay, while all their files remain: a run of
        ``--only X --force`` updates X's section and keeps the rest listed.
    """
    path = out / "index.md"
    new = {res.name: _section(out, res, timings[res.name]) for res in results}
    earlier = _sections(path.read_text()) if path.is_file() else {}
    order = [*(names or ()), *(n for n in new if n not in (names or ()))]
    kept = {n: earlier[n] for n in order if n not in new and n in earlier and _files_remain(out, earlier[n])}
    lines = ["# rocknroller reproduction of Lynch & Bustamante", "",
             "Every number below is computed by rocknroller from the paper's initial conditions; each section names "
             "the version that computed it.", ""]
    path.write_text("\n".join([*lines, *(new.get(n) or kept[n] for n in order if n in new or n in kept)]))
    return path


def run(args: argparse.Namespace) -> int:
    """Run ``rocknroller reproduce`` with the parsed ``args``; returns the exit status."""
    from tqdm import tqdm

    from rocknroller.papers.lynch_bustamante import registry

    modules = registry()
    if args.list:
        for name, mod in modules.items():
            print(f"{name:28s} {(mod.__doc__ or '').strip().splitlines()[0]}")
        return 0
    names = list(modules) if args.only is None else args.only
    unknown = [n for n in names if n not in modules]
    if unknown:
        raise ValueError(f"unknown name(s) for --only: {', '.join(unknown)}; choose from {', '.join(modules)}")
    prepare_output_dir(args.out, "--out", args.force)
    results, timings = [], {}
    bar = tqdm(names, disable=args.quiet or not sys.stderr.isatty(), file=sys.stderr, unit="output")
    for name in bar:
        bar.set_description(name)
        t0 = time.perf_counter()
        res = modules[name].run(args.out)
        timings[name] = time.perf_counter() - t0
        results.append(res)
        for path in res.outputs:
            print(f"{name}: wrote {path}")
    index = write_index(args.out, results, timings, list(modules))
    print(f"index: {index}")
    return 0
