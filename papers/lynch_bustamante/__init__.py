"""Lynch & Bustamante, "Precession and recession of the rock'n'roller": one module per figure or table.

Each module defines ``NAME`` and ``run(out: Path) -> rocknroller.papers.output.Reproduction``; it computes with the
library, writes PNG + PDF and the data as CSV into ``out``, and returns a caption with the numbers it
measured.  ``MODULES`` lists them in the order ``rocknroller reproduce`` runs them.  Beside them: ``reversals``
(the runs and three-panel plots shared by figs. 7–11) and ``ERRATA.md`` (what the paper gets wrong, with the
checks; ``rocknroller verify`` runs them, :mod:`rocknroller.papers.verification`).
"""

from __future__ import annotations

import importlib
import tempfile
from pathlib import Path
from types import ModuleType

from rocknroller.papers.output import Reproduction

MODULES = (
    "fig4_regions",
    "fig5_symmetry_breaking",
    "fig6_contact_tracks",
    "fig7_rest_start",
    "fig8_visible_reversal",
    "fig9_full_reversal",
    "fig10_combined",
    "fig11_high_QR",
    "table_polar_cap",
    "table_small_amplitude",
    "table_periodic_orbit",
    "fig_azimuth_span",
    "fig_slow_period",
)


def load(module: str) -> ModuleType:
    """Import one reproduction module by its file name."""
    return importlib.import_module(f"{__name__}.{module}")


def registry() -> dict[str, ModuleType]:
    """NAME -> module, in run order."""
    mods = [load(m) for m in MODULES]
    return {m.NAME: m for m in mods}


def reproduce(name: str, out: str | Path | None = None) -> Reproduction:
    """Run the reproduction ``name`` (a key of :func:`registry`) into ``out`` (a new temporary directory if None),
    as ``rocknroller reproduce --only name`` does."""
    modules = registry()
    if name not in modules:
        raise ValueError(f"name must be one of {', '.join(modules)}, got name={name!r}")
    return modules[name].run(Path(tempfile.mkdtemp(prefix=f"rocknroller-{name}-") if out is None else out))
