"""Print a pip constraints file pinning every dependency of pyproject.toml (and the given extras) to its lower
bound, for the lowest-versions CI run: ``python .ci/lower_bounds.py test > constraints.txt``."""

from __future__ import annotations

import re
import sys
import tomllib
from pathlib import Path

project = tomllib.loads((Path(__file__).resolve().parents[1] / "pyproject.toml").read_text())["project"]
requirements = list(project["dependencies"])
for extra in sys.argv[1:]:
    requirements += project["optional-dependencies"][extra]
for req in requirements:
    match = re.fullmatch(r"\s*([A-Za-z0-9_.-]+)\s*>=\s*([0-9][0-9A-Za-z.]*)\s*", req)
    if match is None:
        sys.exit(f"every requirement needs a lower bound 'name>=version', got {req!r}")
    print(f"{match[1]}=={match[2]}")
