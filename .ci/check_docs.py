"""After ``python -m sphinx -W docs docs/_build``: every public function and class of every rocknroller module is in
the API reference (the built inventory), every name of ``rocknroller.__all__`` too, and every gallery example ran
(its page exists and shows its output).  Exit status 1 with the missing names otherwise."""

from __future__ import annotations

import importlib
import inspect
import pkgutil
import sys
from pathlib import Path

from sphinx.util.inventory import InventoryFile

import rocknroller

build = Path(sys.argv[1] if len(sys.argv) > 1 else "docs/_build")
with open(build / "objects.inv", "rb") as fh:
    inventory = InventoryFile.load(fh, str(build), lambda base, uri: uri)
documented = {name for kind in inventory.values() for name in kind}


def modules() -> list[str]:
    """Every module of the package.  The folders install under one name (setuptools package-dir), so each top
    package is walked on its own path: an editable install's ``rocknroller.__path__`` holds only the front door."""
    names = {"rocknroller"}
    for top in ("rocknroller", "rocknroller.analysis", "rocknroller.numerics", "rocknroller.papers"):
        names.add(top)
        names.update(info.name for info in pkgutil.walk_packages(importlib.import_module(top).__path__, top + "."))
    return sorted(n for n in names if not any(part.startswith("_") for part in n.split(".")))


missing = []
for name in modules():
    module = importlib.import_module(name)
    for name, obj in vars(module).items():
        if name.startswith("_") or not (inspect.isfunction(obj) or inspect.isclass(obj)):
            continue
        if getattr(obj, "__module__", None) != module.__name__:
            continue  # imported from elsewhere: documented where it is defined
        if f"{module.__name__}.{name}" not in documented:
            missing.append(f"{module.__name__}.{name}")
for name in rocknroller.__all__:
    obj = getattr(rocknroller, name)
    if (inspect.isfunction(obj) or inspect.isclass(obj)) and f"{obj.__module__}.{obj.__qualname__}" not in documented:
        missing.append(f"rocknroller.{name} ({obj.__module__}.{obj.__qualname__})")

docs = Path(__file__).resolve().parents[1] / "docs"
from rocknroller.papers.lynch_bustamante import MODULES  # noqa: E402

for name in MODULES:
    if not list((docs / "paper").glob(f"plot_*_{name}.py")):
        missing.append(f"paper gallery script for {name}")
for gallery, out in (("examples", "auto_examples"), ("paper", "auto_paper")):
    for script in sorted((docs / gallery).glob("plot_*.py")):
        page = build / out / f"{script.stem}.html"
        if not page.exists() or "sphx-glr-script-out" not in page.read_text():
            missing.append(f"gallery page with output: {page}")

if missing:
    print("not in the documentation:\n  " + "\n  ".join(missing))
    sys.exit(1)
print(f"documentation complete: {len(documented)} objects in the inventory, every gallery example ran")
