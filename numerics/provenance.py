"""The package version, read from the installed distribution's metadata (one source: ``pyproject.toml``).

It lives here, low in the package, because the layers that record what produced a result need it: the ensembles
check that a cluster's workers run the caller's versions (:mod:`rocknroller.numerics.ensembles.ensemble`), and every CSV and
figure written for people carries it (:mod:`rocknroller.papers.output`); the front door re-exports it as
``rocknroller.__version__``.
"""

from __future__ import annotations

from importlib.metadata import PackageNotFoundError, version

try:
    __version__: str = version("rocknroller")
except PackageNotFoundError:  # pragma: no cover - a source tree that was never installed
    __version__ = "0+unknown"
