"""The package's version, computed when it is built (everything else is in ``pyproject.toml``).

A release is the commit that ``CITATION.cff`` names (its ``version``, ``date-released`` and ``commit``: one record of
the release, which the CHANGELOG's heading repeats and ``tests/api/test_metadata.py`` checks). A build of that
commit is the release; a build of any later commit, or of a tree with uncommitted changes, is a development build
of the next patch release, PEP 440 ``X.Y.(Z+1).devN+g<commit>[.dirty]`` with N the commits since the release (0
where the history is too shallow to count them). So every output that records the version (CSV and figure headers,
JSON, ``--version``, the BibTeX entry) tells a release from a development build.

The release is recorded in the repository rather than as a git tag because a clone of the main branch need not
carry tags; ``setuptools-scm`` reads only tags, so it would call every such build ``0.1.devN``, which sorts before the
release 0.1.0. An sdist carries the version it was built with in its ``PKG-INFO``, so a wheel built from the sdist
alone (no git history) has the same version.
"""

from __future__ import annotations

import re
import subprocess
from pathlib import Path

from setuptools import setup

ROOT = Path(__file__).resolve().parent


def cff_release(text: str) -> tuple[str, str]:
    """The release's version and commit from the text of ``CITATION.cff`` (its top-level ``version`` and ``commit``)."""
    fields = dict(re.findall(r'^(version|commit):\s*"?([^"\s]+)"?\s*$', text, flags=re.M))
    if not re.fullmatch(r"\d+\.\d+\.\d+", fields.get("version", "")):
        raise ValueError(f"CITATION.cff: version must be a release X.Y.Z, got {fields.get('version')!r}")
    if not re.fullmatch(r"[0-9a-f]{40}", fields.get("commit", "")):
        raise ValueError(f"CITATION.cff: commit must be a full 40-digit hash, got {fields.get('commit')!r}")
    return fields["version"], fields["commit"]


def dev_version(release: str, since: int | None, commit: str | None, dirty: bool) -> str:
    """The PEP 440 version of a build ``since`` commits after ``release``, at ``commit`` (a short hash).

    The release itself when ``since`` is 0 and the tree is clean; otherwise a development build of the next patch
    release, ``X.Y.(Z+1).dev<since>+g<commit>``, with ``.dirty`` appended for uncommitted changes. ``since`` is None
    where the history does not reach the release (a shallow clone; written as dev0), ``commit`` None where there is
    no git checkout (``+unknown``).
    """
    if since == 0 and not dirty:
        return release
    major, minor, patch = (int(p) for p in release.split("."))
    local = "unknown" if commit is None else f"g{commit}" + (".dirty" if dirty else "")
    return f"{major}.{minor}.{patch + 1}.dev{since or 0}+{local}"


def _git(*args: str) -> str:
    return subprocess.run(["git", "-C", str(ROOT), *args], capture_output=True, text=True, check=True).stdout.strip()


def version() -> str:
    """This tree's version: from ``PKG-INFO`` in an unpacked sdist, else from ``CITATION.cff`` and git."""
    pkg_info = ROOT / "PKG-INFO"
    if pkg_info.exists():
        found = re.search(r"^Version:\s*(\S+)\s*$", pkg_info.read_text(encoding="utf-8"), flags=re.M)
        if found is None:
            raise ValueError(f"{pkg_info}: no Version line")
        return found.group(1)
    release, release_commit = cff_release((ROOT / "CITATION.cff").read_text(encoding="utf-8"))
    try:
        head = _git("rev-parse", "HEAD")
        dirty = bool(_git("status", "--porcelain", "--untracked-files=no"))
    except (OSError, subprocess.CalledProcessError):  # no git, or not a checkout: not known to be the release
        return dev_version(release, None, None, dirty=False)
    try:
        since: int | None = int(_git("rev-list", "--count", f"{release_commit}..HEAD"))
    except subprocess.CalledProcessError:  # a shallow clone without the release commit
        since = None
    return dev_version(release, since, head[:7], dirty)

if __name__ == "__main__":
    setup(version=version())
