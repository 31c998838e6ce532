"""The documentation reads as documentation (issue 25, item 12: ``docs/averaging.md`` was titled "First-order",
contradicted itself on order 2, spoke of "the issue" nine times and cited the paper's LaTeX labels): the pages cite
the published paper's equation and section numbers (the labels appear only in the one table that maps them), and
``--help`` does too."""

from __future__ import annotations

import re
from pathlib import Path

import pytest
from cli_help import help_texts

ROOT = Path(__file__).resolve().parents[1]
PAGES = sorted(p.relative_to(ROOT).as_posix() for p in [*(ROOT / "docs").glob("*.md"), *(ROOT / "docs").glob("theory/*.md")]
               if p.name not in ("changelog.md", "cli.md", "performance.md"))
#: "eq. thetadotsq", "eqs. energy, jellett", "§range_X": a LaTeX label where the paper's number belongs.
LABEL = re.compile(r"\beqs?\. (?!\(|[A-Z]\.\d)[A-Za-z_]{3,}|§[A-Za-z_]")


@pytest.mark.parametrize("page", PAGES)
def test_pages_cite_numbers_not_labels(page):
    lines = [(k, ln) for k, ln in enumerate((ROOT / page).read_text().splitlines(), 1) if not ln.startswith("|")]
    found = [f"{page}:{k}: {ln.strip()}" for k, ln in lines if LABEL.search(ln)]
    assert not found, "\n".join(found)
    text = (ROOT / page).read_text()
    assert not re.search(r"\bthe issue\b", text, re.I), f"{page} speaks of 'the issue' (a development log)"


def test_the_slow_map_pages_are_split():
    """Theory, validation (each table with its command) and how-to, the theory page titled for what it is."""
    theory = (ROOT / "docs" / "averaging.md").read_text()
    assert not theory.splitlines()[0].lower().startswith("# first-order")
    assert (ROOT / "docs" / "slow_validation.md").exists() and (ROOT / "docs" / "slow_howto.md").exists()
    assert "| LaTeX label | number |" in theory  # the one table from labels to numbers


def test_help_cites_numbers_not_labels():
    found = [f"{command}: ...{text[max(0, m.start() - 40):m.end() + 10]}"
             for command, text in help_texts().items() for m in LABEL.finditer(text)]
    assert not found, "\n".join(found)
