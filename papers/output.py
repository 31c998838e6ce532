"""Writing results: CSV tables whose header records the parameters, and figures as PNG + PDF."""

from __future__ import annotations

import csv
from dataclasses import dataclass, field
from pathlib import Path
from typing import Iterable, Mapping, Sequence

import numpy as np

__all__ = ["write_csv", "save_figure", "Reproduction"]


def write_csv(path: str | Path, columns: Mapping[str, Sequence], header: Iterable[str] = ()) -> Path:
    """Write equal-length ``columns`` to ``path`` with ``# ``-prefixed header lines first.

    Floats are written with ``repr`` precision (17 significant digits); ``None`` becomes an empty cell.
    """
    path = Path(path)
    path.parent.mkdir(parents=True, exist_ok=True)
    names = list(columns)
    cols = [list(columns[n]) for n in names]
    lengths = {len(c) for c in cols}
    if len(lengths) > 1:
        raise ValueError(f"columns must have equal lengths, got {dict(zip(names, map(len, cols)))}")

    def cell(v: object) -> str:
        if v is None:
            return ""
        if isinstance(v, (float, np.floating)):
            return repr(float(v))
        return str(v)

    with path.open("w", newline="") as fh:
        for line in header:
            fh.write(f"# {line}\n")
        w = csv.writer(fh)
        w.writerow(names)
        for row in zip(*cols):
            w.writerow([cell(v) for v in row])
    return path


def save_figure(fig, out_dir: str | Path, name: str, dpi: int = 150) -> list[Path]:
    """Save ``fig`` as ``out_dir/name.png`` and ``out_dir/name.pdf``; returns both paths."""
    import matplotlib.pyplot as plt

    out_dir = Path(out_dir)
    out_dir.mkdir(parents=True, exist_ok=True)
    paths = [out_dir / f"{name}.png", out_dir / f"{name}.pdf"]
    fig.savefig(paths[0], dpi=dpi, bbox_inches="tight")
    fig.savefig(paths[1], bbox_inches="tight")
    plt.close(fig)
    return paths


@dataclass(frozen=True)
class Reproduction:
    """What a figure or table module produced: files, a caption, and the numbers it measured."""

    name: str
    caption: str
    outputs: list[Path] = field(default_factory=list)
    numbers: dict[str, float | int | str] = field(default_factory=dict)
