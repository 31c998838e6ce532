"""The documentation reads as documentation (issue 25, item 12: ``docs/averaging.md`` was titled "First-order",
contradicted itself on order 2, spoke of "the issue" nine times and cited the paper's LaTeX labels): the pages cite
the published paper's equation and section numbers (the labels appear only in the one table that maps them), and
``--help`` does too."""

from __future__ import annotations

import re
from pathlib import Path

import numpy as np
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


#: What a development log says and documentation does not (the pages read as theory and evidence).
DEV_LOG = re.compile(r"issue [0-9]+|now fixed|before the fix|was then|before issue")
#: The README and every page of docs/ (as `grep docs/*.md README.md` reads them).
READ = ["README.md", *sorted(p.relative_to(ROOT).as_posix() for p in (ROOT / "docs").glob("*.md"))]


def test_pages_are_not_a_development_log():
    found = [f"{page}:{k}: {ln.strip()}" for page in READ
             for k, ln in enumerate((ROOT / page).read_text().splitlines(), 1) if DEV_LOG.search(ln)]
    assert not found, "\n".join(found)


#: A Markdown link [text](target) and a MyST cross-reference {doc}`text <target>` or {doc}`target`.
MD_LINK = re.compile(r"\[[^\]]*\]\(([^)\s]+)\)")
DOC_ROLE = re.compile(r"\{doc\}`(?:[^`<]*<([^`>]+)>|([^`<]+))`")


def _generated(doc: str) -> bool:
    """Whether ``doc`` (a document name relative to docs/) is a page the docs build writes, by this stated list:
    ``cli`` (docs/conf.py writes cli.md from the parsers), ``auto_examples/NAME`` and ``auto_paper/NAME``
    (sphinx-gallery, from docs/examples/NAME.py and docs/paper/NAME.py), ``auto_examples/index`` and
    ``auto_paper/index`` (from the galleries' README.txt)."""
    if doc == "cli":
        return "cli.md" in (ROOT / "docs" / "conf.py").read_text()
    gallery, _, name = doc.partition("/")
    source = {"auto_examples": "examples", "auto_paper": "paper"}.get(gallery)
    if source is None or "/" in name:
        return False
    return (ROOT / "docs" / source / ("README.txt" if name == "index" else f"{name}.py")).is_file()


def test_links_resolve_in_the_sources():
    """Markdown links to generated pages (cli.md, auto_examples/...) were broken in the sources: every relative
    Markdown link names a file of the repository, and a page that only the docs build writes is reached by a
    {doc} reference to one of the stated generated pages (which the build checks, and which a reader of the source
    does not follow as a link)."""
    pages = [*READ, *sorted(p.relative_to(ROOT).as_posix() for p in (ROOT / "docs").glob("theory/*.md"))]
    broken = []
    for page in pages:
        here = (ROOT / page).parent
        text = (ROOT / page).read_text()
        for m in MD_LINK.finditer(text):
            target = m.group(1).split("#")[0]
            if target and not re.match(r"^[a-z][a-z0-9+.-]*:", target) and not (here / target).exists():
                broken.append(f"{page}: ({m.group(1)})")
        for m in DOC_ROLE.finditer(text):
            target = (m.group(1) or m.group(2)).strip()
            doc = (here / target).resolve().relative_to((ROOT / "docs").resolve()).as_posix()
            if not ((ROOT / "docs" / f"{doc}.md").is_file() or _generated(doc)):
                broken.append(f"{page}: {{doc}}`{target}`")
    assert not broken, "links that do not resolve:\n" + "\n".join(broken)


def test_order_two_gain_is_the_measured_one():
    """`slow --help` said order 2 is "~10-100x" better, the docs "10–1000×": one statement, the medians over the cells of
    the second-order table of docs/slow_validation.md (order 1's largest error over order 2's, at each ε ≤ 3e-3)."""
    text = (ROOT / "docs" / "slow_validation.md").read_text()
    cells = {}
    for line in text.splitlines():
        m = re.match(r"\| (π/8|π/4|3π/8|3\.9π/8) \| ([12]) \| (\d.*)\|$", line)
        if m:
            cells[m.group(1), m.group(2)] = [[float(v) for v in c.split("/")] for c in m.group(3).split("|")[:4]]
    assert len(cells) == 8
    medians = [round(float(np.median([cells[psi, "1"][q][k] / cells[psi, "2"][q][k]
                                      for psi in ("π/8", "π/4", "3π/8", "3.9π/8") for q in range(4)])))
               for k in (1, 2, 3)]  # the columns ε = 3e-3, 1e-3, 3e-4
    help_text = " ".join(help_texts()["slow"].split())
    assert (f"a median {medians[0]}x smaller than order 1's at eps = 3e-3, {medians[1]}x at 1e-3, {medians[2]}x at "
            "3e-4") in help_text
    howto = " ".join((ROOT / "docs" / "slow_howto.md").read_text().split())
    assert f"a median {medians[0]}× smaller than order 1's at ε = 3e-3, {medians[1]}× at 1e-3 and {medians[2]}× at 3e-4" in howto
    assert f"by a median factor of {medians[0]} at ε = 3e-3, {medians[1]} at 1e-3 and {medians[2]} at 3e-4" in " ".join(text.split())
