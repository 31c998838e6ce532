"""Writing results: CSV tables whose header records the parameters, and figures as PNG + PDF.

Every CSV starts with lines beginning with ``#`` (the package version first, then the parameters): read it with
``pandas.read_csv(path, comment="#")`` or ``numpy.genfromtxt(path, delimiter=",", names=True)``.  Figures carry
the package version in their metadata and embed TrueType fonts in the PDF (``pdf.fonttype = 42``), as journals ask.
"""

from __future__ import annotations

import csv
import math
from dataclasses import dataclass, field
from pathlib import Path
from typing import TYPE_CHECKING, Any, Iterable, Mapping, Sequence

import numpy as np

from rocknroller.numerics.provenance import __version__

if TYPE_CHECKING:
    import matplotlib.figure

__all__ = ["angle_text", "write_csv", "CsvStream", "new_figure", "save_figure", "Reproduction", "PRODUCER"]

#: Who wrote an output: the first header line of every CSV, the ``Creator`` of every figure.
PRODUCER = f"rocknroller {__version__}"


def angle_text(angle: float) -> str:
    """An angle in radians as the command line reads it back, in the shorter of two exact forms: ``0.93pi`` when
    ``float("0.93") * pi`` is the angle (how ``0.93pi`` is read), else ``repr`` of the float (``0.1``), so that an
    angle given as ``0.93pi`` is echoed so, not as 2.9216811678385075."""
    x = float(angle)
    plain = repr(x)
    if math.isfinite(x) and x != 0.0:
        for digits in range(1, 18):
            d = float(f"{x / math.pi:.{digits}g}")
            if d * math.pi == x:
                return min(plain, f"{d!r}pi", key=len)
    return plain


def _cell(v: object) -> str:
    if v is None:
        return ""
    if isinstance(v, (float, np.floating)):
        return repr(float(v))
    return str(v)


class CsvStream:
    """A CSV file written in pieces: header lines starting with ``#`` (:data:`PRODUCER` first), the column names,
    then rows as they come.

    Use as a context manager; :meth:`write` takes equal-length columns.  Floats are written with ``repr``
    precision (17 significant digits); ``None`` becomes an empty cell.
    """

    def __init__(self, path: str | Path, names: Sequence[str], header: Iterable[str] = ()) -> None:
        self.path, self.names = Path(path), list(names)
        self.path.parent.mkdir(parents=True, exist_ok=True)
        self._fh = self.path.open("w", newline="")
        for line in (PRODUCER, *header):
            self._fh.write(f"# {line}\n")
        self._writer = csv.writer(self._fh)
        self._writer.writerow(self.names)

    def write(self, columns: Mapping[str, Iterable[Any]]) -> None:
        """Append the rows of ``columns`` (keys: the column names, in any order)."""
        cols = [list(columns[n]) for n in self.names]
        lengths = {len(c) for c in cols}
        if len(lengths) > 1:
            raise ValueError(f"columns must have equal lengths, got {dict(zip(self.names, map(len, cols)))}")
        self._writer.writerows([_cell(v) for v in row] for row in zip(*cols))
        self._fh.flush()

    def __enter__(self) -> "CsvStream":
        return self

    def __exit__(self, *exc: object) -> None:
        self._fh.close()


def write_csv(path: str | Path, columns: Mapping[str, Iterable[Any]], header: Iterable[str] = ()) -> Path:
    """Write equal-length ``columns`` to ``path`` with header lines starting with ``#`` first (:class:`CsvStream`)."""
    with CsvStream(path, list(columns), header) as stream:
        stream.write(columns)
    return stream.path


def new_figure(**kwargs) -> "matplotlib.figure.Figure":
    """A matplotlib figure outside pyplot's state machine (keyword arguments as for
    :class:`matplotlib.figure.Figure`): it needs no GUI backend, is never shown and is freed with its last
    reference, so the package never chooses the user's backend (no ``matplotlib.use``)."""
    from matplotlib.figure import Figure

    return Figure(**kwargs)


def save_figure(fig, out_dir: str | Path, name: str, dpi: int = 150) -> list[Path]:
    """Save ``fig`` as ``out_dir/name.png`` and ``out_dir/name.pdf``; returns both paths."""
    out_dir = Path(out_dir)
    out_dir.mkdir(parents=True, exist_ok=True)
    paths = [out_dir / f"{name}.png", out_dir / f"{name}.pdf"]
    import matplotlib

    with matplotlib.rc_context({"pdf.fonttype": 42, "ps.fonttype": 42}):  # TrueType, not Type 3
        fig.savefig(paths[0], dpi=dpi, bbox_inches="tight", metadata={"Software": PRODUCER})
        fig.savefig(paths[1], bbox_inches="tight", metadata={"Creator": PRODUCER})
    return paths


@dataclass(frozen=True)
class Reproduction:
    """What a figure or table module produced: files, a caption, and the numbers it measured."""

    name: str
    caption: str
    outputs: list[Path] = field(default_factory=list)
    numbers: Mapping[str, float | int | str] = field(default_factory=dict)

    def summary(self) -> str:
        """The caption, then one line per number measured (``quantity: value``)."""
        return "\n".join([self.caption, *(f"{k}: {v}" for k, v in self.numbers.items())])
