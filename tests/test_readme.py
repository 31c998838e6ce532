"""The README's Python example runs as written, against the public namespace only."""

from __future__ import annotations

import re
from pathlib import Path

README = Path(__file__).resolve().parents[1] / "README.md"


def test_readme_python_example_runs_and_uses_the_public_api(capsys):
    blocks = re.findall(r"```python\n(.*?)```", README.read_text(), flags=re.S)
    assert blocks
    for code in blocks:
        imports = re.findall(r"^\s*(?:from|import) ([\w.]+)", code, flags=re.M)
        assert all(name == "math" or name == "rocknroller" for name in imports), imports
        exec(compile(code, str(README), "exec"), {})
    assert "@software{rocknroller" in capsys.readouterr().out
