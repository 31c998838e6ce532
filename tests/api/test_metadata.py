"""Version, citation and the records of what wrote an output."""

from __future__ import annotations

import json
import re
import subprocess
import sys

import pytest

import rocknroller as rr
from rocknroller.cli import main
from rocknroller.papers.citation import USES, bibtex_entries


def test_version_everywhere(capsys):
    from importlib.metadata import version

    assert rr.__version__ == version("rocknroller")
    with pytest.raises(SystemExit) as exc:
        main(["--version"])
    assert exc.value.code == 0 and capsys.readouterr().out.strip() == f"rocknroller {rr.__version__}"
    out = subprocess.run([sys.executable, "-m", "rocknroller", "--version"], capture_output=True, text=True, check=True)
    assert out.stdout.strip() == f"rocknroller {rr.__version__}"


@pytest.mark.parametrize("command", [None, *USES])
def test_cite_is_bibtex_for_what_the_command_uses(command, capsys):
    assert main(["cite"] + ([command] if command else [])) == 0
    text = capsys.readouterr().out
    keys = re.findall(r"^@\w+\{(\w+),", text, flags=re.M)
    assert keys[:2] == ["rocknroller", "LynchBustamante2009"]
    assert len(keys) == len(set(keys)) == len(bibtex_entries(command))
    assert ("BiscaniIzzo2021" in keys) == (command is None or "heyoka" in USES[command])
    assert f"version = {{{rr.__version__}}}" in text
    assert text.count("{") == text.count("}")  # balanced braces: every entry closes
    assert rr.cite(command) == text


def test_cite_refuses_an_unknown_command():
    with pytest.raises(ValueError, match="command must be one of"):
        rr.cite("nope")


def test_outputs_record_the_version(tmp_path, capsys):
    assert main(["table", "--QR", "0.01", "--QJ", "0.01", "--out", str(tmp_path / "t.csv"), "--quiet"]) == 0
    first = (tmp_path / "t.csv").read_text().splitlines()[0]
    assert first == f"# rocknroller {rr.__version__}"
    capsys.readouterr()
    assert main(["table", "--QR", "0.01", "--QJ", "0.01", "--json", "--quiet", "--out", str(tmp_path / "u.csv")]) == 0
    assert json.loads(capsys.readouterr().out)["rocknroller_version"] == rr.__version__


def test_figures_embed_truetype_and_name_their_producer(tmp_path):
    from rocknroller.papers.output import PRODUCER, new_figure, save_figure

    fig = new_figure(figsize=(2, 2))
    fig.subplots().set_title("θ, φ, ψ")
    png, pdf = save_figure(fig, tmp_path, "f")
    data = pdf.read_bytes()
    assert b"/FontFile2" in data and b"/Type3" not in data  # TrueType embedded, no Type 3 fonts
    assert PRODUCER.encode() in data
    from PIL import Image

    assert Image.open(png).info["Software"] == PRODUCER


def test_local_modules_named_like_the_folders_do_not_shadow_the_package(tmp_path):
    """The folders install as rocknroller.analysis, .numerics and .papers: a user's own analysis.py (or
    numerics.py, papers.py) in the working directory cannot replace them."""
    for name in ("analysis", "numerics", "papers"):
        (tmp_path / f"{name}.py").write_text("raise ImportError('the user module was imported')\n")
    code = "import rocknroller, rocknroller.cli, rocknroller.papers.output; print(rocknroller.Body.paper().a)"
    out = subprocess.run([sys.executable, "-c", code], cwd=tmp_path, capture_output=True, text=True)
    assert out.returncode == 0, out.stderr
    assert out.stdout.strip() == "0.05"
