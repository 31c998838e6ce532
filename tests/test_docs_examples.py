"""The pages show what the code prints today: every console example and script table of docs/*.md that is marked with
the command that prints it (``<!-- output of: COMMAND -->`` before a ```` ```console ```` block, ``<!-- table of:
COMMAND -->`` before a Markdown table; ``docs/regenerate_examples.py`` rewrites them) is checked against that
command's current output.  The pages had drifted: a console example of ``rocknroller slow`` showed a MEGNO and a
horizon line the command no longer printed, and a table of ``validation/chaos_map_table.py`` a horizon of 6.538e+19
where the script gives none.

Cheap commands (a few seconds) run in the default suite; those marked ``(slow)`` (minutes) under ``-m slow`` (CI);
those marked ``(long)`` (the acceptance grids, many minutes) under ``-m validation``, by hand.  A
table's header and rule are also checked, without running anything, against the script's source: a literal string
there, or a module-level string constant of the script.
"""

from __future__ import annotations

import ast
import importlib.util
import re
import shlex
import sys
from pathlib import Path

import pytest

ROOT = Path(__file__).resolve().parents[1]
_spec = importlib.util.spec_from_file_location("regenerate_examples", ROOT / "docs" / "regenerate_examples.py")
assert _spec is not None and _spec.loader is not None
regen = importlib.util.module_from_spec(_spec)
sys.modules["regenerate_examples"] = regen
_spec.loader.exec_module(regen)

BLOCKS = regen.all_blocks()
#: Seconds a cheap command may take (it runs in the default suite; they take 2–3 s here).
CHEAP_TIMEOUT = 120.0
_outputs: dict[str, list[str]] = {}


def _output(command: str, timeout: float | None) -> list[str]:
    """The command's current stdout, run once per session for all the blocks that show it."""
    if command not in _outputs:
        _outputs[command] = regen.run(command, timeout=timeout)
    return _outputs[command]


def _params(kind: str) -> list:
    return [pytest.param(b, id=f"{b.where}", marks=([pytest.mark.slow] if b.slow else [])
                         + ([pytest.mark.validation] if b.long else []))
            for b in BLOCKS if b.kind == kind]


def test_the_examples_are_marked():
    """Every console block of docs/*.md names the command it is the output of (else nothing would check it), and the
    known examples and tables are marked: the slow command's console example and the chaos table of the how-to."""
    unmarked = []
    for page in regen.pages():
        lines = page.read_text().splitlines()
        for k, line in enumerate(lines):
            if line.strip() == "```console" and not (k and regen.MARK.match(lines[k - 1])):
                unmarked.append(f"{page.name}:{k + 1}")
    assert not unmarked, f"console blocks without '<!-- output of: COMMAND -->' on the line before: {unmarked}"
    commands = {(b.page.name, b.kind, b.command) for b in BLOCKS}
    assert ("slow_howto.md", "output", "rocknroller slow --eps 5e-3 --psi0 0.05 --t-end 2000") in commands
    assert ("slow_howto.md", "table", "python validation/chaos_map_table.py") in commands


@pytest.mark.parametrize("block", _params("output"))
def test_console_example_is_what_the_command_prints(block):
    """Every line the block shows (other than ``...``) is a line the command prints now, in order (a chaotic block's
    numbers masked outside the environment that generated the pages)."""
    shown = block.shown(block.page.read_text().splitlines())
    assert [s for s in shown if s.strip() != regen.ELISION], f"{block.where}: the block shows no output"
    missing = regen.stale(block, _output(block.command, None if block.slow else CHEAP_TIMEOUT))
    assert not missing, (f"{block.where}: `{block.command}` no longer prints these lines (run python "
                         f"docs/regenerate_examples.py{' --slow' if block.slow else ''}):\n" + "\n".join(missing))


@pytest.mark.parametrize("block", _params("table"))
def test_table_is_what_the_script_prints(block):
    """The table is, row for row, the table with its header that the command prints now."""
    missing = regen.stale(block, _output(block.command, None if block.slow else CHEAP_TIMEOUT))
    assert not missing, (f"{block.where}: `{block.command}` no longer prints these rows (run python "
                         f"docs/regenerate_examples.py{' --slow' if block.slow else ''}):\n" + "\n".join(missing))


def _script(command: str) -> Path | None:
    words = shlex.split(command)
    return ROOT / words[1] if words[0] == "python" and words[1].endswith(".py") else None


def _printed_texts(script: Path) -> set[str]:
    """The strings the script's source spells out, and each of their lines: its string literals (adjacent literals
    joined, as Python joins them) and the constant parts of its f-strings."""
    found = {node.value for node in ast.walk(ast.parse(script.read_text()))
             if isinstance(node, ast.Constant) and isinstance(node.value, str)}
    return found | {line for text in found for line in text.splitlines()}


_STATIC = [b for b in BLOCKS if b.kind == "table" and _script(b.command) is not None]


@pytest.mark.parametrize("block", [pytest.param(b, id=b.where) for b in _STATIC])
def test_table_header_is_the_scripts(block):
    """Without running the script: the table's header and rule are strings its source prints (a literal, or a
    module-level string constant such as ``HEADER``).  A header the script builds at run time is checked by the
    rerun above (slow for the slow scripts)."""
    script = _script(block.command)
    assert script is not None and script.is_file(), f"{block.where}: no script {block.command!r}"
    header, rule = block.shown(block.page.read_text().splitlines())[:2]
    assert re.fullmatch(r"\|(?:-{3,}\|)+", rule) and rule.count("|") == header.count("|"), (
        f"{block.where}: the rule does not match the header's columns")
    texts = _printed_texts(script)
    if header not in texts:
        spec = importlib.util.spec_from_file_location(f"_docs_script_{script.stem}", script)
        assert spec is not None and spec.loader is not None
        module = importlib.util.module_from_spec(spec)
        spec.loader.exec_module(module)  # the scripts run only under __main__
        texts |= {v for v in vars(module).values() if isinstance(v, str)}
    if header not in texts:
        if block.slow:  # a cheap script's header is checked by the rerun in the default suite
            pytest.skip(f"{block.where}: the header is built at run time (checked by rerunning `{block.command}`)")
        return
    assert rule in texts, f"{block.where}: the script prints another rule"


def test_chaos_table_horizons_follow_the_stated_rule():
    """The horizon column of the how-to's chaos table is printed as `rocknroller slow` prints a horizon: two
    significant digits, "≥" before an extrapolated one (a lower bound), "infinite" for none (a growth not resolved, or
    past the longest run)."""
    block = next(b for b in BLOCKS if b.command == "python validation/chaos_map_table.py")
    rows = block.shown(block.page.read_text().splitlines())
    head = [c.strip() for c in rows[0].strip("|").split("|")]
    h, m = head.index("horizon"), head.index("method")
    for row in rows[2:]:
        cells = [c.strip() for c in row.strip("|").split("|")]
        horizon, method = cells[h], cells[m]
        if method in ("unresolved", "beyond"):
            assert horizon == "infinite", row
            continue
        value = horizon.removeprefix("≥ ")
        assert (horizon != value) == (method in ("exponential", "linear")), row
        assert value == f"{float(f'{float(value):.2g}'):g}", f"not two significant digits: {row}"


def test_regeneration_keeps_the_elisions():
    """A block with ``...`` is rewritten run by run (each run's first and last lines matched by their common prefix),
    and a line that changed is reported."""
    shown = ["...", "a: 1", "b: 2", "...", "  z 9"]
    output = ["head", "a: 10", "b: 20", "c", "  y 1", "  z 90"]
    assert regen.regenerated(shown, output) == ["...", "a: 10", "b: 20", "...", "  z 90"]
    assert regen.not_printed(shown, output) == ["a: 1", "b: 2", "  z 9"]
    assert regen.not_printed(["...", "a: 10", "...", "  z 90"], output) == []
    assert regen.not_printed(["  z 90", "...", "a: 10"], output) == ["a: 10"]  # in order
    assert regen.not_printed(["a: 10"], output)  # without '...' the block is the whole output


def _page(tmp_path: Path, marker: str, body: list[str]) -> Path:
    page = tmp_path / "page.md"
    page.write_text("\n".join(["intro", marker, *body, "", "after"]) + "\n")
    return page


def test_chaotic_blocks_are_compared_digit_for_digit_only_where_they_were_generated(tmp_path):
    """A block marked ``(chaotic)`` is compared exactly in the pages' environment and with its numbers masked
    elsewhere (another CPU's kernels or other dependency versions move a chaotic orbit's MEGNO: 45 or 112 for one
    start); the words (a verdict, a method) and the cells' places still count.  An unmarked block is always exact."""
    rows = ["| ε | MEGNO | verdict |", "|---|---|---|", "| 0.01 | 45 | chaotic |"]
    moved = ["| ε | MEGNO | verdict |", "|---|---|---|", "| 0.01 | 112 | chaotic |"]
    turned = ["| ε | MEGNO | verdict |", "|---|---|---|", "| 0.01 | 112 | regular |"]
    (block,) = regen.blocks(_page(tmp_path, "<!-- table of (slow, chaotic): python x.py -->", rows))
    assert block.chaotic and block.slow and not block.long
    assert regen.stale(block, moved, exact=False) == []
    assert regen.stale(block, moved, exact=True) == ["| 0.01 | 45 | chaotic |"]
    assert regen.stale(block, turned, exact=False) == ["| 0.01 | 45 | chaotic |"]
    assert regen.stale(block, moved[:2], exact=False) == ["(the rows differ in number)"]
    (plain,) = regen.blocks(_page(tmp_path, "<!-- table of: python x.py -->", rows))
    assert not plain.chaotic and regen.stale(plain, moved, exact=False) == ["| 0.01 | 45 | chaotic |"]
    console = ["```console", "$ rocknroller slow", "CHAOTIC (MEGNO = 99.1; 0.0155 per unit time)", "...",
               "  fraction_I  0.25974  0.531967 +- 0.193", "```"]
    (out,) = regen.blocks(_page(tmp_path, "<!-- output of (chaotic): rocknroller slow -->", console))
    now = ["CHAOTIC (MEGNO = 74.9; 0.0121 per unit time)", "other", "  fraction_I      0.5    0.4 +- 0.2"]
    assert regen.stale(out, now, exact=False) == []
    assert regen.stale(out, now, exact=True) == [console[2], console[4]]
    assert regen.stale(out, ["REGULAR (MEGNO = 2.0; 1e-05 per unit time)", *now[1:]], exact=False) == [console[2]]
    assert regen.masked("| 8 | 11/20 | nan | 1.574 |") == regen.masked("| 8 | 12/20 | 1.6 | inf |") == "| # | #/# | # | # |"


def test_a_marker_names_known_flags(tmp_path):
    """Flags in a marker are among slow, long and chaotic; ``(long)`` is also slow; anything else is refused, naming
    the line."""
    (block,) = regen.blocks(_page(tmp_path, "<!-- table of (long): python x.py -->", ["| a |", "|---|", "| 1 |"]))
    assert block.slow and block.long and not block.chaotic
    with pytest.raises(ValueError, match=r"page.md:2: a marker's flags are among slow, long, chaotic, got \(fast\)"):
        regen.blocks(_page(tmp_path, "<!-- table of (fast): python x.py -->", ["| a |", "|---|", "| 1 |"]))


def test_the_pages_record_the_environment_that_generated_them():
    """docs/examples_environment.json holds what :func:`environment` measures (the same keys), written by a full run;
    and the chaotic blocks are the ones whose numbers another CPU's kernels move (the how-to's chaos table and console
    example, the chaos acceptance's part (c) table)."""
    import json

    recorded = json.loads(regen.ENVIRONMENT.read_text())
    assert set(recorded) == set(regen.environment())
    chaotic = {(b.page.name, b.command) for b in BLOCKS if b.chaotic}
    assert chaotic >= {("slow_howto.md", "python validation/chaos_map_table.py"),
                       ("slow_howto.md", "rocknroller slow --eps 5e-3 --psi0 0.05 --t-end 2000"),
                       ("order_and_chaos.md", "python validation/chaos_acceptance.py --parts c")}
