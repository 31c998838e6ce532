"""The examples in the public docstrings: every public function and class of ``rr`` has a NumPy-style Examples
section, and its ``>>>`` lines run as doctests on the installed package (the cheap ones in the default run, those
that integrate for long, build tables or compile code in the slow stage); no public signature shows a long default
(``help()`` printed a whole module array)."""

from __future__ import annotations

import doctest
import importlib
import inspect
import pkgutil
import re
import types
from collections.abc import Iterator

import pytest

import rocknroller as rr

#: The public functions and classes (the submodules ``analysis``, ``numerics``, ``papers`` are packages, not API).
PUBLIC = sorted(n for n in dir(rr) if not n.startswith("_") and not isinstance(getattr(rr, n), types.ModuleType))

#: Examples that integrate the direct ODE for long, build or load the averaging tables, or compile an integrator:
#: they run in the slow stage (``python -m pytest -m slow``), with the reason.
SLOW = {
    "DirectChaos": "compiles heyoka's variational equations (~45 s on a cold heyoka cache)",
    "direct_chaos_indicators": "compiles heyoka's variational equations (~45 s on a cold heyoka cache)",
    "PeriodDoubling": "the exact map: direct-ODE steps at every ε of the root search (~8 s)",
    "period_doubling": "the exact map: direct-ODE steps at every ε of the root search (~8 s)",
    "bifurcation_diagram": "continues the branches and writes a PNG and a PDF (~8 s)",
    "write_portrait": "writes a PNG and a PDF (~4 s)",
}

#: Longest repr of a default value in a public signature: a scalar, a short string or tuple, a type.
MAX_DEFAULT_REPR = 80


def _examples_section(doc: str) -> bool:
    """True when ``doc`` has a NumPy-style Examples heading (the word, then a line of dashes) followed by ``>>>``."""
    match = re.search(r"^\s*Examples\n\s*-{8,}\n(.*)", doc, re.MULTILINE | re.DOTALL)
    return match is not None and ">>>" in match.group(1)


def test_every_public_object_has_an_examples_section():
    missing = [n for n in PUBLIC if not _examples_section(inspect.getdoc(getattr(rr, n)) or "")]
    assert not missing, f"public names without an Examples section: {missing}"


def test_slow_list_names_public_objects():
    assert set(SLOW) <= set(PUBLIC), sorted(set(SLOW) - set(PUBLIC))


@pytest.mark.parametrize("name", [pytest.param(n, marks=pytest.mark.slow) if n in SLOW else n for n in PUBLIC])
def test_docstring_examples_run(name):
    """The object's own docstring (not its methods': they are examples of their own), each output checked."""
    obj = getattr(rr, name)
    tests = doctest.DocTestFinder(recurse=False).find(obj, f"rocknroller.{name}", globs={})
    examples = sum(len(t.examples) for t in tests)
    assert examples, f"rocknroller.{name} has no doctest"
    runner = doctest.DocTestRunner(optionflags=doctest.ELLIPSIS | doctest.NORMALIZE_WHITESPACE)
    report = _Output()
    for test in tests:
        runner.run(test, out=report)
    assert not runner.failures, f"doctest of rocknroller.{name} failed:\n{report.text}"


class _Output:
    """Collects the runner's report of a failing example, for the assertion message."""

    def __init__(self) -> None:
        self.text = ""

    def __call__(self, s: str) -> None:
        self.text += s


def _modules() -> Iterator[types.ModuleType]:
    """Every module of the installed package (its subpackages install from separate folders: walk each)."""
    packages = [rr] + [importlib.import_module(f"rocknroller.{p}") for p in ("analysis", "numerics", "papers")]
    names = {p.__name__ for p in packages}
    for p in packages:
        names |= {m.name for m in pkgutil.walk_packages(p.__path__, p.__name__ + ".")}
    for name in sorted(names):
        if not name.endswith("__main__"):
            yield importlib.import_module(name)


def _public_callables(module: types.ModuleType) -> Iterator[tuple[str, object]]:
    """The module's public functions and classes (its ``__all__``), and the classes' public methods."""
    for name in getattr(module, "__all__", [n for n in vars(module) if not n.startswith("_")]):
        obj = getattr(module, name)
        yield f"{module.__name__}.{name}", obj
        if inspect.isclass(obj):
            for attr, member in vars(obj).items():
                if not attr.startswith("_"):
                    yield f"{module.__name__}.{name}.{attr}", getattr(member, "__func__", member)


def test_no_public_signature_shows_a_long_default():
    """``help(layer_width)`` printed the 161 values of its default grid: a default is a scalar or None, resolved
    inside."""
    long = []
    for module in _modules():
        for qualname, obj in _public_callables(module):
            if not callable(obj):
                continue
            try:
                signature = inspect.signature(obj)
            except (TypeError, ValueError):  # builtins without a signature
                continue
            long += [f"{qualname}({p.name}=...): {len(repr(p.default))} characters"
                     for p in signature.parameters.values()
                     if p.default is not p.empty and len(repr(p.default)) > MAX_DEFAULT_REPR]
    assert not long, long
