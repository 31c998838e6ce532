"""Performance figures are stated once (issue 25, item 17: a band-table build was "6–7 s" in one page, "15–20 s" in
``slow --help`` and "≈ 15 s" in a docstring, while a rerun measured 26 s; README's map-vs-ODE ratio and memory of 10⁵
rocks disagreed with reruns): on ``docs/performance.md``, the output of one run of ``benchmarks/performance.py``
that states the machine and its load.  README, the other pages and every ``--help`` point there and state no time or
memory of their own.  (The validation page's tables are its scripts' output, and may carry their build times.)"""

from __future__ import annotations

import re
from pathlib import Path

import pytest
from cli_help import help_texts

ROOT = Path(__file__).resolve().parents[1]
#: A duration or an amount of memory: "8 s", "60–75 s", "0.17 ms", "~0.4 GB", "347 MB" (a limit's value, "= 1 GiB",
#: is a setting, not a measurement).
FIGURE = re.compile(r"(?<!= )(?<![\w.])\d(?:[\d.,–-]*\d)?\s?(?:ms|µs|s|min|h|kB|MB|GB|MiB|GiB)\b")
PAGES = ["README.md", "docs/index.md", "docs/install.md", "docs/slow_howto.md", "docs/averaging.md",
         "docs/slow_validation.md", "docs/errata.md", "docs/order_and_chaos.md", "docs/theory/reduction.md", "docs/theory/criticality.md"]


#: The one paragraph of the README that states figures, those no benchmark measures: the one-off compilations and
#: the duration of the test suite; they are stated there only.
ONE_OFF = "**One-off costs.**"


def _prose(path: Path) -> list[tuple[int, str]]:
    """The lines of a page outside tables, code blocks and the README's one-off costs."""
    out, code, one_off = [], False, False
    for k, line in enumerate(path.read_text().splitlines(), 1):
        one_off = (one_off or line.startswith(ONE_OFF)) and bool(line.strip())
        if line.startswith("```"):
            code = not code
        elif not code and not one_off and not line.lstrip().startswith("|"):
            out.append((k, line))
    return out


def test_one_off_costs_are_stated_once():
    """The README states the one-off compilations and the suite's duration in one paragraph, and no other page does."""
    readme = (ROOT / "README.md").read_text()
    paragraph = readme[readme.index(ONE_OFF):].split("\n\n")[0]
    figures = FIGURE.findall(paragraph)
    assert len(figures) >= 4 and "verify" in paragraph and "direct_chaos_indicators" in paragraph
    assert "python -m pytest" in paragraph
    stated = re.findall(r"\d+(?:\.\d+)? s of CPU", paragraph)
    assert stated
    for page in [*PAGES[1:], "docs/performance.md"]:
        text = (ROOT / page).read_text()
        assert not [f for f in stated if f in text], page


@pytest.mark.parametrize("page", [p for p in PAGES if (ROOT / p).exists()])
def test_pages_state_no_performance_figure_of_their_own(page):
    found = [f"{page}:{k}: {line.strip()}" for k, line in _prose(ROOT / page) if FIGURE.search(line)]
    assert not found, "performance figures belong on docs/performance.md:\n" + "\n".join(found)


def test_help_states_no_performance_figure():
    found = [f"{command}: ...{text[max(0, m.start() - 60):m.end()]}"
             for command, text in help_texts().items() for m in FIGURE.finditer(text)]
    assert not found, "\n".join(found)


def test_the_performance_page_is_the_script_output():
    """docs/performance.md exists, names the script that writes it and the load of every benchmark it ran."""
    text = (ROOT / "docs" / "performance.md").read_text()
    assert "python benchmarks/performance.py" in text and "load average" in text
    script = (ROOT / "benchmarks" / "performance.py").read_text()
    for name in re.findall(r'\("(bench_\w+\.py)"', script):
        assert f"benchmarks/{name}" in text, name


#: What the page states of the first uses and of the ensembles at equal error, by the benchmark that prints it: the
#: second-order table (k₂ per node by the scalar path beside the batched one), the region tables, each command's first
#: run from an empty table cache beside its rerun, the first chaos call with heyoka's cache warm and cold, and the
#: ensembles' lanes against CyRK at equal energy error and against the scalar loop.
FIRST_USES = {
    "bench_tables.py": ["k2 per node, scalar / batched:", "its second-order table (1 process)",
                        "region tables, spindle chart", "region tables, band chart"],
    "bench_commands.py": [f"slow --order {n} (theta0 0.93pi, 1 process): {when}" for n in (1, 2)
                          for when in ("first, empty table cache", "again, tables cached")]
                         + [f"{command}, its defaults: first, empty table cache"
                            for command in ("portrait", "bifurcation")]
                         + ["reproduce (every figure and table): first", "slow --statistics 32, tables cached",
                            "first chaos call, new process, heyoka cache warm",
                            "first chaos call, new process, heyoka cache cold", "first / again"],
    "bench_ensemble.py": ["ratio CyRK / lanes at tol", "ratio scalar loop / lanes at tol = eps"],
}


@pytest.mark.parametrize("script", FIRST_USES)
def test_the_page_states_the_first_uses_and_the_ensembles_at_equal_error(script):
    """Each of those rows is in the section of its benchmark, which ran to the end."""
    sections = re.split(r"(?m)^## ", (ROOT / "docs" / "performance.md").read_text())
    section = next((s for s in sections if f"`python benchmarks/{script}`" in s), "")
    assert section and "[exit status" not in section, script
    missing = [row for row in FIRST_USES[script] if row not in section]
    assert not missing, f"{script}: {missing}"
