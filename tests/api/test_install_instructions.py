"""Install instructions name what can be installed (issue 25, item 10): rocknroller is not on PyPI, so no document,
docstring or ``--help`` may tell a user to ``pip install rocknroller`` (or ``"rocknroller[extra]"``) by name."""

from __future__ import annotations

import argparse
import re
from pathlib import Path

import pytest

from rocknroller.cli import build_parser

ROOT = Path(__file__).resolve().parents[2]
#: ``pip install`` (pip3, python -m pip, any options) of the name rocknroller, with or without extras or quotes;
#: ``pip install -e ".[extra]"`` and a file name (``dist/rocknroller-....tar.gz``) do not match.
BY_NAME = re.compile(r"\bpip3?\s+install\s+(?:-[-\w]+(?:=\S+)?\s+)*[\"']?rocknroller\b(?![-./\w])")
#: What a user reads: the README, the citation file, the documentation's sources (not its build products; docs/cli.md
#: is written from the parsers, checked below), the package's modules (docstrings, messages), the scripts beside them.
PLACES = ("README.md", "CITATION.cff", "pyproject.toml", "docs", "api", "analysis", "numerics", "papers",
          "benchmarks", "validation", ".ci")
GENERATED = {"_build", "auto_examples", "auto_paper", "generated", "__pycache__"}
GENERATED_FILES = {"cli.md", "api.rst", "sg_execution_times.rst"}


def _texts():
    for place in PLACES:
        path = ROOT / place
        files = [path] if path.is_file() else sorted(path.rglob("*")) if path.is_dir() else []
        for f in files:
            rel = f.relative_to(ROOT)
            if (f.is_file() and not GENERATED & set(rel.parts) and not (rel.parts[0] == "docs" and f.name in
                    GENERATED_FILES) and (f.suffix in {".md", ".rst", ".txt", ".py", ".cff", ".toml"} or
                                          rel.as_posix() == ".ci/run")):
                yield str(rel), f.read_text(encoding="utf-8")


def _help_texts():
    parser = build_parser()
    yield "rocknroller --help", parser.format_help()
    sub = next(a for a in parser._actions if isinstance(a, argparse._SubParsersAction))
    for name, p in sub.choices.items():
        yield f"rocknroller {name} --help", p.format_help()


@pytest.mark.parametrize("text, recommends", [
    ('pip install "rocknroller[distributed]"', True), ("python -m pip install rocknroller", True),
    ("pip install -U 'rocknroller[animation]'", True), ("pip3 install --user rocknroller", True),
    ('python -m pip install -e ".[distributed]"', False), ('pip install "dist/rocknroller-0.1.0.tar.gz[x]"', False),
    ("pip install rocknroller-0.1.0-py3-none-any.whl", False), ('pip install "${wheel}[test]"', False),
])
def test_the_pattern(text, recommends):
    assert bool(BY_NAME.search(text)) == recommends


def test_files_do_not_recommend_installing_by_name():
    texts = dict(_texts())
    assert "README.md" in texts and "docs/install.md" in texts and "api/cli/animate.py" in texts  # the scan reads
    offending = [f"{name}:{text.count(chr(10), 0, m.start()) + 1}: {m.group(0)!r}" for name, text in texts.items()
                 for m in BY_NAME.finditer(text)]
    assert not offending, "install by a name that is not published:\n" + "\n".join(offending)


def test_help_texts_do_not_recommend_installing_by_name():
    helps = dict(_help_texts())
    assert {"rocknroller animate --help", "rocknroller atlas --help"} <= set(helps)
    offending = [f"{name}: {m.group(0)!r}" for name, text in helps.items() for m in BY_NAME.finditer(text)]
    assert not offending, "install by a name that is not published:\n" + "\n".join(offending)


@pytest.mark.parametrize("page, heading", [("README.md", "## Direct runs on a cluster"),
                                           ("docs/install.md", "**Workers and heyoka's cache.**")])
def test_a_shared_heyoka_cache_says_what_it_trusts(page, heading):
    """The cluster recipe shares one writable HEYOKA_CACHE_DIR across workers; heyoka's cache holds machine code that
    the workers run, so the page says whom sharing it trusts and what to do otherwise (issue 25, item 25)."""
    text = (ROOT / page).read_text()
    section = text[text.index(heading):]
    section = " ".join(section[:section.find("\n#", 1) if "\n#" in section[1:] else None].split())
    assert "HEYOKA_CACHE_DIR" in section and "machine code" in section
    assert re.search(r"can write to [^.]* can run code", section) or "trust everyone who can write" in section
    assert "private" in section


def test_build_commands_say_how_to_get_build():
    """docs/install.md said `python -m build`, which no extra installs: a page that uses it says to install `build`
    first (or builds with `pip wheel`, which needs nothing more)."""
    texts = dict(_texts())
    offending = [name for name, text in texts.items() if "python -m build" in text
                 and not re.search(r"pip install build\b[^\n]*python -m build", " ".join(text.split()))]
    assert not offending, "python -m build without installing build first: " + ", ".join(offending)
