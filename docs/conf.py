"""Sphinx configuration: ``python -m sphinx -W docs docs/_build`` (warnings are errors).

The API reference is generated from the docstrings (autosummary, NumPy style through napoleon); the two
galleries (sphinx-gallery) execute ``docs/examples`` and ``docs/paper`` at every build; the CLI page and the
API page's list of modules are written when this file is read.
"""

from __future__ import annotations

import sys
from pathlib import Path

import rocknroller

DOCS = Path(__file__).resolve().parent
sys.path.insert(0, str(DOCS))  # the gallery scraper (_scraper.py)

project = "rocknroller"
author = "The rocknroller developers"
copyright = "2026, The rocknroller developers"
release = version = rocknroller.__version__

extensions = [
    "sphinx.ext.autodoc",
    "sphinx.ext.autosummary",
    "sphinx.ext.napoleon",
    "sphinx.ext.mathjax",
    "myst_parser",
    "sphinx_gallery.gen_gallery",
]
source_suffix = {".rst": "restructuredtext", ".md": "markdown"}
exclude_patterns = ["_build", "figures", "theory/*_numbers.md", "**/README.txt", "examples/*.py", "paper/*.py"]
myst_enable_extensions = ["dollarmath"]
myst_heading_anchors = 3

autosummary_generate = True
autosummary_imported_members = False
autodoc_default_options = {"members": True, "show-inheritance": True}
autodoc_typehints = "none"  # the NumPy-style docstrings state the types
napoleon_google_docstring = False
napoleon_numpy_docstring = True
napoleon_use_rtype = False
nitpicky = False

from _scraper import RocknrollerScraper  # noqa: E402

sphinx_gallery_conf = {
    "examples_dirs": ["examples", "paper"],
    "gallery_dirs": ["auto_examples", "auto_paper"],
    "filename_pattern": r"/plot_",
    "image_scrapers": (RocknrollerScraper(),),
    "abort_on_example_error": True,
    "only_warn_on_example_error": False,
    "download_all_examples": False,
    "within_subsection_order": "FileNameSortKey",
    "remove_config_comments": True,
}

html_theme = "alabaster"
html_title = f"rocknroller {release}"
html_static_path: list[str] = []


def _write_cli_page() -> None:
    """docs/cli.md: the ``--help`` of the console script and of every subcommand, from the parsers."""
    from rocknroller.cli import build_parser

    parser = build_parser()
    parser.prog = "rocknroller"
    sub = next(a for a in parser._actions if a.__class__.__name__ == "_SubParsersAction")
    parts = ["# Command line", "",
             "Every subcommand of the `rocknroller` console script (also `python -m rocknroller`), with its "
             "`--help`. This page is written from the parsers at each build.", "",
             "```text", parser.format_help().rstrip(), "```", ""]
    for name, sp in sub.choices.items():
        parts += [f"## rocknroller {name}", "", "```text", sp.format_help().rstrip(), "```", ""]
    text = "\n".join(parts)
    page = DOCS / "cli.md"
    if not page.exists() or page.read_text() != text:
        page.write_text(text)


#: The modules of the reference (recursive: every public module below them gets a page).
API_MODULES = ("rocknroller.analysis", "rocknroller.numerics", "rocknroller.papers", "rocknroller.cli")


def _write_api_page() -> None:
    """docs/api.rst: the public namespace (each name linked to where it is defined) and every module."""
    names = [n for n in rocknroller.__all__ if not n.startswith("_")]
    targets = [f"{getattr(rocknroller, n).__module__}.{getattr(rocknroller, n).__qualname__}" for n in names]
    lines = ["API reference", "=============", "",
             "The public namespace", "--------------------", "",
             "``import rocknroller as rr`` gives these names; each links to its documentation in the module that",
             "defines it.", "", ".. autosummary::", "", *(f"   ~{t}" for t in targets), "",
             "Modules", "-------", "", ".. autosummary::", "   :toctree: generated", "   :recursive:", "",
             *(f"   {m}" for m in API_MODULES), ""]
    text = "\n".join(lines)
    page = DOCS / "api.rst"
    if not page.exists() or page.read_text() != text:
        page.write_text(text)


def _plain_text_math(app, what, name, obj, options, lines) -> None:
    """The docstrings write absolute values as |x| (plain-text mathematics); in reST a bar opens a substitution
    reference, so bars are escaped (the docstrings use no reST substitutions or tables)."""
    for i, line in enumerate(lines):
        lines[i] = line.replace("|", "\\|")


# Written when the configuration is read, before autosummary looks for the pages to generate.
_write_cli_page()
_write_api_page()


def setup(app) -> None:
    app.connect("autodoc-process-docstring", _plain_text_math)
