"""Regenerate the console examples and the script tables of the documentation from the code.

Run:  python docs/regenerate_examples.py [--slow] [--check] [PAGE ...]      (from the repository's root)

A page marks each piece of output that a command prints, on the line before it:

``<!-- output of: COMMAND -->``
    followed by a ```` ```console ```` block whose first line is ``$ COMMAND`` and whose other lines are lines the
    command prints on stdout, in order; a line ``...`` stands for lines left out (any number, none included).
``<!-- table of: COMMAND -->``
    followed by a Markdown table (its header, rule and rows, the next lines starting with ``|``) that the command
    prints on stdout among its output.

``COMMAND`` is ``rocknroller ...`` (run as ``python -m rocknroller ...``) or ``python SCRIPT ...`` (run with this
interpreter), from the repository's root, in the environment as given (the tables' cache: ``ROCKNROLLER_CACHE``) with
``ROCKNROLLER_ENERGY_TABLES=off``: the pages show what a fresh install prints, on the per-θ0 tables, whether or not
the tables over energy (``rocknroller warm --tables``) are cached here, which would move a chaotic start's numbers.  A
marker written ``output of (slow):`` or ``table of (slow):`` is a command that takes minutes: it is regenerated only
with ``--slow``, and its test is marked slow (run in CI); ``(long)`` marks one that takes many minutes (the
acceptance grids): regenerated with ``--slow --long``, its test is marked ``validation`` and run by hand
(``python -m pytest -m validation``), not in CI, whose slow stage would pass its 30 minutes.  ``(chaotic)`` (alone or
after another flag: ``(slow, chaotic)``) marks a block with numbers of chaotic orbits: MEGNO, Lyapunov exponents,
ensemble fractions and counts taken over thousands of rocks, which the last bits of the tables and of the direct ODE
decide, so that another CPU's vector kernels (numpy's dispatch, OpenBLAS's core type), heyoka's JIT for another CPU
or other versions of the dependencies print other values (measured: MEGNO 45 or 112 for one start with numpy's
AVX-512 kernels or without them and OpenBLAS's Haswell kernels; 117 with the lowest versions pyproject.toml allows).
These blocks are compared digit for digit in the environment that generated the pages (:func:`environment`, recorded in
``docs/examples_environment.json`` by a full run: every page, ``--slow``), and elsewhere with every number masked
(:func:`masked`): the same lines and cells, the same words (a verdict, a method), numbers in the same places.

Without ``--check`` each marked block is rewritten with what its command prints now: a console block keeps its
elisions (each run of lines between two ``...`` is matched to the current output by the longest common prefix of its
first and of its last line, and replaced by the current lines from the one to the other), and a table is replaced by
the table of the output with the same header (else, if the output has one table, by that one).  With ``--check``
nothing is written: the stale blocks are listed and the exit status is 1 if there are any.  The test
``tests/test_docs_examples.py`` checks the same: every line a console block shows (other than ``...``) is a line its
command prints now, in order, and every marked table is the one its command prints (by rerunning the cheap commands,
and the slow ones under ``-m slow``); a table's header and rule are also checked against the script's source.
"""

from __future__ import annotations

import argparse
import hashlib
import json
import os
import platform
import re
import shlex
import subprocess
import sys
from dataclasses import dataclass
from pathlib import Path

ROOT = Path(__file__).resolve().parents[1]
DOCS = ROOT / "docs"
#: Pages written at each build from the code, or pages of other authors' measurements (not marked here).
SKIPPED = ("cli.md", "changelog.md", "errata.md")
MARK = re.compile(r"^<!-- (output|table) of(?: \(([a-z, ]+)\))?: (.+?) -->\s*$")
FLAGS = ("slow", "long", "chaotic")
ELISION = "..."
#: The environment that generated the pages (:func:`environment`), written by a full run.
ENVIRONMENT = DOCS / "examples_environment.json"
#: A number as printed (sign, digits, point, exponent): what :func:`masked` hides.
NUMBER = re.compile(r"[-+]?(?:\d+\.?\d*|\.\d+)(?:[eE][-+]?\d+)?|\b(?:nan|inf)\b")


@dataclass(frozen=True)
class Block:
    """One marked block of a page: its kind (``output`` or ``table``), whether its command is slow, the command, and
    the page's lines ``start:stop`` (0-based, the marker excluded) that it occupies."""
    page: Path
    kind: str
    slow: bool
    command: str
    marker_line: int  # 0-based index of the marker
    start: int
    stop: int
    long: bool = False  # ``(long)``: tens of minutes, checked by hand (``-m validation``), not in CI
    chaotic: bool = False  # ``(chaotic)``: digit for digit only in the environment that generated the pages

    def shown(self, lines: list[str]) -> list[str]:
        """The lines the page shows: a console block's output lines (without the fences and ``$ COMMAND``), or the
        table's lines."""
        body = lines[self.start:self.stop]
        return body[2:-1] if self.kind == "output" else body

    @property
    def where(self) -> str:
        return f"{self.page.relative_to(ROOT).as_posix()}:{self.marker_line + 1}"


def pages() -> list[Path]:
    """The pages that may hold marked blocks: docs/*.md but the generated ones."""
    return sorted(p for p in DOCS.glob("*.md") if p.name not in SKIPPED)


def blocks(page: Path) -> list[Block]:
    """The marked blocks of ``page``; a marker not followed by what it announces is a ValueError naming the line."""
    lines = page.read_text().splitlines()
    out = []
    for k, line in enumerate(lines):
        m = MARK.match(line)
        if not m:
            continue
        kind, command = m.group(1), m.group(3).strip()
        flags = {f.strip() for f in (m.group(2) or "").split(",")} - {""}
        if m.group(2) is not None and (not flags or not flags <= set(FLAGS)):
            raise ValueError(f"{page.name}:{k + 1}: a marker's flags are among {', '.join(FLAGS)}, got ({m.group(2)})")
        slow, long, chaotic = bool(flags & {"slow", "long"}), "long" in flags, "chaotic" in flags
        start = k + 1
        if kind == "output":
            if start >= len(lines) or lines[start].strip() != "```console":
                raise ValueError(f"{page.name}:{k + 1}: 'output of' must be followed by a ```console block")
            if start + 1 >= len(lines) or lines[start + 1].strip() != f"$ {command}":
                raise ValueError(f"{page.name}:{k + 2}: the console block must open with '$ {command}'")
            stop = next((j for j in range(start + 1, len(lines)) if lines[j].strip() == "```"), None)
            if stop is None:
                raise ValueError(f"{page.name}:{k + 1}: the console block is not closed")
            stop += 1
        else:
            if start >= len(lines) or not lines[start].startswith("|"):
                raise ValueError(f"{page.name}:{k + 1}: 'table of' must be followed by a Markdown table")
            stop = start
            while stop < len(lines) and lines[stop].startswith("|"):
                stop += 1
        out.append(Block(page, kind, slow, command, k, start, stop, long, chaotic))
    return out


def all_blocks() -> list[Block]:
    return [b for p in pages() for b in blocks(p)]


def argv(command: str) -> list[str]:
    """The command as run: ``rocknroller ...`` through this interpreter's ``-m rocknroller``, ``python ...`` with
    this interpreter."""
    words = shlex.split(command)
    if words[0] == "rocknroller":
        return [sys.executable, "-m", "rocknroller", *words[1:]]
    if words[0] == "python":
        return [sys.executable, *words[1:]]
    raise ValueError(f"a marked command starts with 'rocknroller' or 'python', got {command!r}")


def run(command: str, timeout: float | None = None) -> list[str]:
    """What ``command`` prints on stdout now, line by line (trailing blanks removed); a failure is a RuntimeError
    with its stderr's end."""
    done = subprocess.run(argv(command), cwd=ROOT, capture_output=True, text=True, timeout=timeout,
                          env=dict(os.environ, ROCKNROLLER_ENERGY_TABLES="off"))
    if done.returncode != 0:
        raise RuntimeError(f"{command!r} failed ({done.returncode}):\n{done.stderr[-2000:]}")
    return [line.rstrip() for line in done.stdout.splitlines()]


def not_printed(shown: list[str], output: list[str]) -> list[str]:
    """The lines of ``shown`` (other than ``...``) that are not lines of ``output`` in order: each shown line must be
    a line printed after the one matched to the line before it; a console block without ``...`` must be the whole
    output."""
    lines = [s.rstrip() for s in shown]
    if ELISION not in lines:
        if lines == output:
            return []
        return [s for s in lines if s not in output] or ["(the lines differ in order or number; '...' elides lines)"]
    missing, at = [], 0
    for s in lines:
        if s == ELISION:
            continue
        try:
            at = output.index(s, at) + 1
        except ValueError:
            missing.append(s)
    return missing


def tables_in(output: list[str]) -> list[list[str]]:
    """The Markdown tables (runs of lines starting with ``|``) of an output."""
    found: list[list[str]] = []
    for k, line in enumerate(output):
        if line.startswith("|"):
            if k == 0 or not output[k - 1].startswith("|"):
                found.append([])
            found[-1].append(line)
    return found


def table_from(shown: list[str], output: list[str]) -> list[str] | None:
    """The table of ``output`` that replaces ``shown``: the one with the same header, else the only one."""
    tables = tables_in(output)
    same = [t for t in tables if t[0] == shown[0].rstrip()]
    if same:
        return same[0]
    return tables[0] if len(tables) == 1 else None


def _prefix(a: str, b: str) -> int:
    n = 0
    for x, y in zip(a, b):
        if x != y:
            break
        n += 1
    return n


def _best(line: str, output: list[str], start: int) -> int | None:
    """The index ≥ ``start`` of the output line with the longest common prefix with ``line`` (the first such), or None
    if none shares its first word (its indent, then its first word without trailing punctuation)."""
    if start >= len(output) or not line.strip():
        return None
    k = max(range(start, len(output)), key=lambda j: (_prefix(line, output[j]), -j))
    indent = len(line) - len(line.lstrip())
    word = indent + len(line.split()[0].rstrip(":;,.=(")) or 1
    return k if _prefix(line, output[k]) >= min(word, len(line)) else None


def regenerated(shown: list[str], output: list[str]) -> list[str] | None:
    """The console lines that replace ``shown``, keeping its elisions: each run of shown lines between two ``...`` is
    replaced by the current output from the line that best matches its first line to the one that best matches its
    last; None if a run cannot be placed."""
    lines = [s.rstrip() for s in shown]
    if ELISION not in lines:
        return list(output)
    runs: list[list[str] | None] = []
    for s in lines:
        if s == ELISION:
            runs.append(None)
        elif runs and runs[-1] is not None:
            runs[-1].append(s)
        else:
            runs.append([s])
    new: list[str] = []
    at = 0
    for r in runs:
        if r is None:
            new.append(ELISION)
            continue
        first = _best(r[0], output, at)
        if first is None:
            return None
        last = first if len(r) == 1 else _best(r[-1], output, first + 1)
        if last is None:
            return None
        new += output[first:last + 1]
        at = last + 1
    return new


def environment() -> dict[str, str]:
    """What the last bits of a chaotic orbit's numbers depend on, besides the code: the versions of Python and of the
    numerical dependencies, the CPU's vector extensions that heyoka's JIT compiles for, the variables that choose
    numpy's and OpenBLAS's kernels, and a digest of what those kernels return on fixed inputs (numpy's transcendental
    functions and sums, BLAS products and LAPACK solves), which tells their dispatch apart.

    Examples
    --------
    >>> import sys; sys.path.insert(0, "docs"); import regenerate_examples as regen
    >>> import numpy
    >>> env = regen.environment()
    >>> env["numpy"] == numpy.__version__, len(env["numpy and BLAS kernels"])
    (True, 16)
    """
    from importlib.metadata import version

    import numpy as np

    x = np.linspace(-20.0, 20.0, 4099)
    a = np.random.default_rng(0).standard_normal((96, 96))
    probes = [np.sin(x), np.cos(x), np.exp(x / 7.0), np.log1p(np.abs(x)), np.arctan2(x, 1.3), np.sqrt(np.abs(x)),
              np.tanh(x), np.abs(x) ** 1.7, np.cumsum(x), np.array([np.sum(np.sin(x)), np.dot(x, np.cos(x))]), a @ a,
              np.linalg.solve(a, a[:, 0]), np.linalg.lstsq(a[:, :40], a[:, 0], rcond=None)[0], np.linalg.eigvalsh(a + a.T)]
    digest = hashlib.sha256(b"".join(np.ascontiguousarray(p, float).tobytes() for p in probes)).hexdigest()[:16]
    flags: set[str] = set()
    cpuinfo = Path("/proc/cpuinfo")
    if cpuinfo.is_file():
        line = next((ln for ln in cpuinfo.read_text().splitlines() if ln.startswith("flags")), "")
        flags = set(line.split()) & {"avx", "avx2", "fma", "avx512f", "avx512dq", "avx512vl", "avx512bw"}
    env = {name: os.environ.get(name, "") for name in ("NPY_DISABLE_CPU_FEATURES", "NPY_ENABLE_CPU_FEATURES",
                                                       "OPENBLAS_CORETYPE")}
    return {"python": platform.python_version(), "machine": platform.machine(),
            "cpu vector extensions": " ".join(sorted(flags)) or platform.processor(),
            **{name: version(name) for name in ("numpy", "scipy", "heyoka", "mpmath", "sympy")},
            **env, "numpy and BLAS kernels": digest}


def reference_environment() -> bool:
    """Whether this is the environment that generated the pages (``ENVIRONMENT``)."""
    return ENVIRONMENT.is_file() and json.loads(ENVIRONMENT.read_text()) == environment()


def masked(line: str) -> str:
    """``line`` with each number (``nan`` and ``inf`` included: a chaotic orbit may leave the tables in one environment
    and not in another) replaced by ``#`` and each run of blanks by one (numbers of other lengths realign the
    columns): what a chaotic block is compared by outside the environment that generated it.

    Examples
    --------
    >>> import sys; sys.path.insert(0, "docs"); import regenerate_examples as regen
    >>> regen.masked("| 0.01 | 0.3 | chaotic | 1.326e+04 | ≥ 610 | 3/20 | nan |")
    '| # | # | chaotic | # | ≥ # | #/# | # |'
    >>> regen.masked("  fraction_I      0.25974      0.531967 +- 0.193") == regen.masked("  fraction_I    0.5   0.4 +- 0.2")
    True
    """
    return " ".join(NUMBER.sub("#", line).split())


def stale(block: Block, output: list[str], exact: bool | None = None) -> list[str]:
    """What of ``block`` its command's ``output`` no longer prints (empty if the block is current).  A chaotic block
    is compared with its numbers :func:`masked` unless ``exact`` (default: in the environment that generated the
    pages, :func:`reference_environment`); the lines reported are the page's."""
    if block.chaotic and not (reference_environment() if exact is None else exact):
        page = block.shown(block.page.read_text().splitlines())
        keys = {masked(s.rstrip()): s for s in page}
        plain = _stale(block.kind, [masked(s) for s in page], [masked(s) for s in output])
        return [keys.get(s, s) for s in plain]
    return _stale(block.kind, block.shown(block.page.read_text().splitlines()), output)


def _stale(kind: str, shown: list[str], output: list[str]) -> list[str]:
    if kind == "output":
        return not_printed(shown, output)
    table = table_from(shown, output)
    if table is None:
        return ["(the output has no table with this header)"]
    return [s for s, t in zip(shown, table) if s.rstrip() != t] + (["(the rows differ in number)"]
                                                                  if len(shown) != len(table) else [])


def rewrite(block: Block, index: int, output: list[str]) -> bool:
    """Write ``block``, the ``index``-th marked block of its page, as its command's ``output`` gives it; whether the
    page changed.  The page is read again here, so that only the block's lines change (edits elsewhere in the page
    while the command ran are kept)."""
    lines = block.page.read_text().splitlines(keepends=True)
    found = blocks(block.page)
    current = found[index] if index < len(found) else None
    if current is None or current.command != block.command or current.kind != block.kind:
        raise RuntimeError(f"{block.where}: the page's marked blocks changed under the run; run again")
    plain = [ln.rstrip("\n") for ln in lines]
    shown = current.shown(plain)
    if block.kind == "output":
        new = regenerated(shown, output)
        if new is None:
            raise RuntimeError(f"{block.where}: a shown line matches nothing the command prints now; edit the block")
        body = ["```console", f"$ {block.command}", *new, "```"]
    else:
        table = table_from(shown, output)
        if table is None:
            raise RuntimeError(f"{block.where}: the command prints no table with the page's header")
        body = table
    if plain[current.start:current.stop] == body:
        return False
    lines[current.start:current.stop] = [f"{ln}\n" for ln in body]
    block.page.write_text("".join(lines))
    return True


def main(args: list[str] | None = None) -> int:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("pages", nargs="*", type=Path, help="pages to regenerate (default: every page of docs/)")
    parser.add_argument("--slow", action="store_true", help="also the commands marked slow")
    parser.add_argument("--long", action="store_true", help="also those marked long (with --slow: all of them)")
    parser.add_argument("--check", action="store_true", help="write nothing; list the stale blocks (exit 1 if any)")
    a = parser.parse_args(args)
    chosen = [p.resolve() for p in a.pages] or pages()
    full, elsewhere = not a.pages and a.slow, not reference_environment()
    n_stale = 0
    outputs: dict[str, list[str]] = {}  # a command run once for all the blocks that show it
    for page in chosen:
        for index in range(len(blocks(page))):
            block = blocks(page)[index]  # read again: a rewritten block before it may have moved it
            if block.slow and not a.slow or block.long and not a.long:
                print(f"{block.where}: skipped ({'long; --slow --long' if block.long else 'slow; --slow'} runs it): "
                      f"{block.command}")
                continue
            if block.chaotic and elsewhere and not (full or a.check):
                print(f"{block.where}: skipped (chaotic, generated in another environment: a full run, every page with "
                      f"--slow, regenerates it and records this one in {ENVIRONMENT.name}): {block.command}")
                continue
            if block.command not in outputs:
                outputs[block.command] = run(block.command)
            output = outputs[block.command]
            if a.check:
                missing = stale(block, output)
                n_stale += bool(missing)
                print(f"{block.where}: {'STALE' if missing else 'current'}: {block.command}")
                for s in missing:
                    print(f"    not printed now: {s}")
            else:
                changed = rewrite(block, index, output)
                print(f"{block.where}: {'rewritten' if changed else 'current'}: {block.command}")
    if full and not a.check:
        ENVIRONMENT.write_text(json.dumps(environment(), indent=1) + "\n")
        print(f"the pages' environment recorded in {ENVIRONMENT.relative_to(ROOT)}")
    return 1 if n_stale else 0


if __name__ == "__main__":
    sys.exit(main())
