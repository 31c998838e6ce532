"""The README's Python example runs as written, against the public namespace only."""

from __future__ import annotations

import re
from pathlib import Path

ROOT = Path(__file__).resolve().parents[1]
README = ROOT / "README.md"


def test_readme_python_example_runs_and_uses_the_public_api(capsys):
    blocks = re.findall(r"```python\n(.*?)```", README.read_text(), flags=re.S)
    assert blocks
    for code in blocks:
        imports = re.findall(r"^\s*(?:from|import) ([\w.]+)", code, flags=re.M)
        assert all(name == "math" or name == "rocknroller" for name in imports), imports
        exec(compile(code, str(README), "exec"), {})
    assert "@software{rocknroller" in capsys.readouterr().out


def test_readme_on_order_and_chaos_and_what_is_bit_identical():
    """The README never mentioned order and chaos nor linked its pages, and said the scalar integrator's turning
    points (lanes=1) "agree to the integrators' rounding", which on a chaotic start grows to the whole extent."""
    text = (ROOT / "README.md").read_text()
    assert re.search(r"^## Order and chaos$", text, re.M)
    for word in ("MEGNO", "chaos", "horizon"):
        assert word in text
    for page in ("docs/order_and_chaos.md", "docs/slow_howto.md", "docs/chaos_statistics.md"):
        assert f"]({page})" in text and (ROOT / page).is_file()
    flat = " ".join(text.split())
    assert "agree with the lanes' to the integrators' rounding" not in flat
    assert "Bit-identical: every batch width from 2 to 16" in flat and "Not bit-identical: `lanes=1`" in flat
