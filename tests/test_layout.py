"""The package's layering: data flows one way, from the model up to the front door, and no two modules need each other.

Every import of a package module counts, at module level or inside a function, and under ``TYPE_CHECKING`` too (an
import inside a function only hides a circle from Python).  The installed package is read (its files, found through
the import system), so the test means the same from the repository, from an unpacked sdist and against a wheel.
"""

from __future__ import annotations

import ast
import importlib
import importlib.util
from pathlib import Path

import pytest

#: The layers, bottom first.  A module may import modules of its own folder (without a circle) and of folders in
#: layers below its own; a package's ``__init__`` that only maps its folder imports nothing.
LAYERS: tuple[tuple[str, ...], ...] = (
    ("rocknroller.analysis", "rocknroller.analysis.model"),  # what a body and a state are
    ("rocknroller.numerics",),                                # integrating the model
    ("rocknroller.numerics.ensembles",),                      # many runs at once: batch lanes, threads, clusters
    ("rocknroller.analysis.routh",),                          # the integrable sphere
    ("rocknroller.analysis.criticality",),                    # critical lines, regions, critical starts
    ("rocknroller.analysis.hierarchy",),                      # the loaded-sphere family: integrals, measures
    ("rocknroller.analysis.slow.map",),                       # the eps-averaged slow map and its tables
    ("rocknroller.analysis.slow.dynamics",),                  # what the map's orbits do: chaos, periodic orbits
    ("rocknroller.analysis.slow",),                           # the slow motion's answers: prediction, atlas, statistics
    ("rocknroller.papers",),                                  # what is drawn or written for people
    ("rocknroller.papers.lynch_bustamante",),                 # the seed paper's figures and tables
    ("rocknroller.cli",),                                     # the command line
    ("rocknroller",),                                         # the public API
)
RANK = {pkg: i for i, layer in enumerate(LAYERS) for pkg in layer}
#: Packages whose ``__init__`` is a map of its folder only.
MAP_ONLY = {"rocknroller.analysis", "rocknroller.numerics", "rocknroller.numerics.ensembles", "rocknroller.papers",
            "rocknroller.analysis.model",
            "rocknroller.analysis.routh", "rocknroller.analysis.criticality", "rocknroller.analysis.hierarchy",
            "rocknroller.analysis.slow",
            "rocknroller.analysis.slow.map", "rocknroller.analysis.slow.dynamics"}
#: A folder past this many modules (its ``__init__`` not counted) is split by stage into subpackages.
MAX_FOLDER_MODULES = 12
#: Folders that are catalogues, one module per item, and may hold more: the command line (one module per
#: subcommand) and the seed paper (one module per figure or table).
CATALOGUES = {"rocknroller.cli", "rocknroller.papers.lynch_bustamante"}
#: A module past about this many lines is split (by stage, into modules of its folder or a subpackage).
MAX_MODULE_LINES = 500


def package_modules() -> dict[str, Path]:
    """Every module of the installed package: name -> source file."""
    mods: dict[str, Path] = {}
    for pkg in RANK:
        package = importlib.import_module(pkg)
        for folder in package.__path__:
            for path in sorted(Path(folder).glob("*.py")):
                name = pkg if path.stem == "__init__" else f"{pkg}.{path.stem}"
                mods[name] = path
    return mods


def imported_modules(source: str, me: str, is_package: bool, known: set[str]) -> set[str]:
    """The package modules a source imports, anywhere in it (absolute or relative)."""
    out: set[str] = set()
    for node in ast.walk(ast.parse(source)):
        if isinstance(node, ast.ImportFrom):
            if node.level:
                base = me if is_package else me.rpartition(".")[0]
                for _ in range(node.level - 1):
                    base = base.rpartition(".")[0]
                mod = f"{base}.{node.module}" if node.module else base
            else:
                mod = node.module or ""
            candidates = [f"{mod}.{a.name}" for a in node.names] + [mod]
        elif isinstance(node, ast.Import):
            candidates = [a.name for a in node.names]
        else:
            continue
        for name in candidates:
            while name and name not in known:
                name = name.rpartition(".")[0]
            if name and name != me:
                out.add(name)
    return out


def folder_of(mod: str, mods: dict[str, Path]) -> str:
    return mod if mods[mod].stem == "__init__" else mod.rpartition(".")[0]


def violations(graph: dict[str, set[str]], mods: dict[str, Path]) -> list[str]:
    """Upward or sideways imports between folders, imports from a map-only ``__init__``, and module circles."""
    bad = []
    for mod, targets in sorted(graph.items()):
        here = folder_of(mod, mods)
        if mod in MAP_ONLY and targets:
            bad.append(f"{mod} is a map of its folder and imports {sorted(targets)}")
        for t in sorted(targets):
            there = folder_of(t, mods)
            if there != here and RANK[there] >= RANK[here]:
                bad.append(f"{mod} (layer {RANK[here]}) imports {t} (layer {RANK[there]}): upward")
    bad += [f"module circle: {' -> '.join(c)}" for c in circles(graph)]
    return bad


def circles(graph: dict[str, set[str]]) -> list[list[str]]:
    """Strongly connected components with more than one module (Tarjan)."""
    index: dict[str, int] = {}
    low: dict[str, int] = {}
    stack: list[str] = []
    on: set[str] = set()
    out: list[list[str]] = []

    def visit(v: str) -> None:
        index[v] = low[v] = len(index)
        stack.append(v)
        on.add(v)
        for w in graph.get(v, ()):
            if w not in index:
                visit(w)
                low[v] = min(low[v], low[w])
            elif w in on:
                low[v] = min(low[v], index[w])
        if low[v] == index[v]:
            comp = []
            while True:
                w = stack.pop()
                on.discard(w)
                comp.append(w)
                if w == v:
                    break
            if len(comp) > 1:
                out.append(sorted(comp))

    for v in sorted(graph):
        if v not in index:
            visit(v)
    return out


def import_graph(mods: dict[str, Path], sources: dict[str, str] | None = None) -> dict[str, set[str]]:
    known = set(mods)
    return {m: imported_modules((sources or {}).get(m) or p.read_text(), m, p.stem == "__init__", known)
            for m, p in mods.items()}


@pytest.fixture(scope="module")
def modules() -> dict[str, Path]:
    return package_modules()


def test_every_package_has_a_layer(modules):
    packages = {folder_of(m, modules) for m in modules}
    assert packages == set(RANK), f"place these in LAYERS: {sorted(packages ^ set(RANK))}"
    assert len(modules) > 60  # the whole package was read, not an empty folder


def test_data_flows_one_way(modules):
    assert violations(import_graph(modules), modules) == []


@pytest.mark.parametrize("planted, added", [
    # an upward import inside a function (the kind Python does not notice)
    ("rocknroller.analysis.model.body", "def f():\n    from rocknroller.analysis.slow.prediction import predict_slow_motion\n"),
    # a circle inside one folder
    ("rocknroller.analysis.slow.map.limits", "from rocknroller.analysis.slow import prediction\n"),
    # a relative import out of the model into the integrators
    ("rocknroller.analysis.model.invariants", "from ...numerics import integrate\n"),
])
def test_the_check_catches_a_planted_import(modules, planted, added):
    """The same check fails when one import that breaks the layering is added to today's sources."""
    sources = {planted: modules[planted].read_text() + "\n" + added}
    bad = violations(import_graph(modules, sources), modules)
    assert bad and all(planted in b or "circle" in b for b in bad), bad


def folder_sizes(mods: dict[str, Path]) -> dict[str, int]:
    """Modules per folder, the ``__init__`` not counted."""
    sizes = {folder_of(m, mods): 0 for m in mods}
    for m, path in mods.items():
        if path.stem != "__init__":
            sizes[folder_of(m, mods)] += 1
    return sizes


def test_folders_and_modules_stay_small(modules):
    """No folder holds more than ``MAX_FOLDER_MODULES`` modules (catalogues aside), no module more than about
    ``MAX_MODULE_LINES`` lines (5 % over, for a docstring that grows by a line or two)."""
    crowded = {f: n for f, n in folder_sizes(modules).items() if n > MAX_FOLDER_MODULES and f not in CATALOGUES}
    assert crowded == {}, f"split these folders by stage into subpackages: {crowded}"
    long = {m: n for m, p in modules.items() if (n := len(p.read_text().splitlines())) > 1.05 * MAX_MODULE_LINES}
    assert long == {}, f"split these modules by stage: {long}"


def test_the_size_check_catches_a_crowded_folder(modules):
    """The count sees a folder of 13 modules (today's analysis/slow had 16 in one folder)."""
    crowded = {f"rocknroller.analysis.slow.x{i}": Path(f"/x/x{i}.py") for i in range(MAX_FOLDER_MODULES + 1)}
    assert folder_sizes(crowded) == {"rocknroller.analysis.slow": MAX_FOLDER_MODULES + 1}
