"""Version, citation and the records of what wrote an output."""

from __future__ import annotations

import datetime
import json
import re
import subprocess
import sys
from pathlib import Path

import pytest

import rocknroller as rr
from rocknroller.cli import COMMANDS, main
from rocknroller.papers.citation import USES, bibtex_entries, read_cff

ROOT = Path(__file__).resolve().parents[2]


def test_version_everywhere(capsys):
    from importlib.metadata import version

    assert rr.__version__ == version("rocknroller")
    with pytest.raises(SystemExit) as exc:
        main(["--version"])
    assert exc.value.code == 0 and capsys.readouterr().out.strip() == f"rocknroller {rr.__version__}"
    out = subprocess.run([sys.executable, "-m", "rocknroller", "--version"], capture_output=True, text=True, check=True)
    assert out.stdout.strip() == f"rocknroller {rr.__version__}"


@pytest.mark.parametrize("command", [None, *(c for c in COMMANDS if c != "cite")])
def test_cite_is_bibtex_for_what_the_command_uses(command, capsys):
    """``cite`` takes every command of the dispatcher (issue 25, item 9: ``cite atlas`` and ``cite animate`` exited
    2 with "invalid choice")."""
    assert main(["cite"] + ([command] if command else [])) == 0
    text = capsys.readouterr().out
    keys = re.findall(r"^@\w+\{(\w+),", text, flags=re.M)
    assert keys[:2] == ["rocknroller", "LynchBustamante2009"]
    assert len(keys) == len(set(keys)) == len(bibtex_entries(command))
    assert ("BiscaniIzzo2021" in keys) == (command is None or "heyoka" in USES[command])
    assert f"version = {{{rr.__version__}}}" in text
    assert text.count("{") == text.count("}")  # balanced braces: every entry closes
    assert rr.cite(command) == text


@pytest.mark.parametrize("command, methods", [
    ("slow", {"CincottaSimo2000", "Chirikov1979", "Greene1979"}), ("portrait", {"CincottaSimo2000", "Chirikov1979"}),
    ("bifurcation", {"Greene1979", "Chirikov1979"}), ("atlas", {"CincottaSimo2000"}),
    ("simulate", {"CincottaSimo2000"}), ("table", set()), ("hierarchy", set())])
def test_cite_names_the_methods_a_command_uses(command, methods, capsys):
    """MEGNO (Cincotta & Simó 2000), Greene's residue (1979) and the standard map (Chirikov 1979) were cited by no
    command, though slow, portrait, atlas and simulate --chaos report MEGNO and bifurcation Greene's residues."""
    assert main(["cite", command]) == 0
    keys = set(re.findall(r"^@\w+\{(\w+),", capsys.readouterr().out, flags=re.M))
    assert keys & {"CincottaSimo2000", "Greene1979", "Chirikov1979"} == methods
    text = rr.cite(command)
    for key, (journal, volume, page) in {"CincottaSimo2000": ("Astronomy and Astrophysics Supplement Series", 147, 205),
                                         "Greene1979": ("Journal of Mathematical Physics", 20, 1183),
                                         "Chirikov1979": ("Physics Reports", 52, 263)}.items():
        if key in methods:
            entry = text[text.index(f"{{{key},"):]
            entry = entry[:entry.index("\n}")]
            assert journal in entry and f"volume  = {{{volume}}}" in entry and f"pages   = {{{page}--" in entry


def test_cite_refuses_an_unknown_command():
    with pytest.raises(ValueError, match="command must be one of"):
        rr.cite("nope")


def test_cite_knows_exactly_the_commands_of_the_dispatcher():
    from rocknroller.cli.cite import citable_commands

    assert set(USES) == set(citable_commands()) == set(COMMANDS) - {"cite"}


def _bibtex_fields(entry: str) -> dict[str, str]:
    return dict(re.findall(r"^  (\w+)\s*= \{(.*)\},?$", entry, flags=re.M))


def _plain(text: str) -> str:
    """BibTeX text back to plain text: the braces that protect capitals dropped."""
    return re.sub(r"(?<!\\)[{}]", "", text)


def test_package_entry_is_citation_cff():
    """The package's BibTeX entry has CITATION.cff's title, authors, licence and release year, the running version,
    and CITATION.cff's address when it gives one (issue 25, item 9: one source, with a year)."""
    cff = read_cff((ROOT / "CITATION.cff").read_text())
    fields = _bibtex_fields(bibtex_entries()[0])
    assert bibtex_entries()[0].startswith("@software{rocknroller,")
    assert _plain(fields["title"]) == cff["title"]
    assert [_plain(a) for a in fields["author"].split(" and ")] == [a["name"] for a in cff["authors"]]
    assert fields["license"] == cff["license"]
    assert fields["year"] == str(datetime.date.fromisoformat(cff["date-released"]).year)
    assert fields["version"] == rr.__version__
    assert fields.get("url") == (cff.get("url") or cff.get("repository-code"))
    # the paper's and heyoka's entries are CITATION.cff's references
    refs = {r["doi"]: r for r in cff["references"]}
    for entry in bibtex_entries()[1:3]:
        f = _bibtex_fields(entry)
        ref = refs[f["doi"]]
        assert _plain(f["title"]) == ref["title"] and f["journal"] == ref["journal"] and f["year"] == str(ref["year"])
        assert f["author"] == " and ".join(f"{a['family-names']}, {a['given-names']}" for a in ref["authors"])
        assert f["pages"] == "--".join(str(ref[k]) for k in ("start", "end") if k in ref)


def test_cff_reader_agrees_with_pyyaml():
    """The package's own reader (PyYAML is not a dependency of the package, only of its tests: the [test] extra) gives
    what PyYAML gives for CITATION.cff, scalars compared as written.  Imported, not skipped when missing: the test
    skipped on every install that lacked it."""
    import yaml

    def as_written(x):
        if isinstance(x, dict):
            return {k: as_written(v) for k, v in x.items()}
        if isinstance(x, list):
            return [as_written(v) for v in x]
        return x.isoformat() if isinstance(x, datetime.date) else (x if x is None or isinstance(x, str) else str(x))

    text = (ROOT / "CITATION.cff").read_text()
    assert read_cff(text) == as_written(yaml.safe_load(text))


def test_cff_reader_reads_the_block_subset():
    text = ("# a comment\ntitle: \"a # b: c\"  # comment\nname: 'it''s'\nplain: 2026-11-23#x\nempty:\n"
            "list:\n- one\n- key: 1\n  other: two\n- - x\n  - y\nsame-indent:\n  - z\n")
    assert read_cff(text) == {"title": "a # b: c", "name": "it's", "plain": "2026-11-23#x", "empty": None,
                              "list": ["one", {"key": "1", "other": "two"}, ["x", "y"]], "same-indent": ["z"]}


@pytest.mark.parametrize("text, fragment", [
    ("a: [1, 2]", "line 1: cannot read '[1, 2]'"),
    ("a: {b: 1}", "line 1: cannot read"),
    ("a: |\n  text", "line 1: cannot read '|'"),
    ("a: >\n  text", "line 1: cannot read '>'"),
    ("a: &anchor b", "line 1: cannot read"),
    ("a: !!str b", "line 1: cannot read"),
    ("a:\n\t- b", "line 2: a tab in the indentation"),
    ("a: b\na: c", "line 2: the key 'a' is given twice"),
    ("a: b: c", "line 1: cannot read 'b: c'"),
    ("a: first\n  continued", "line 2: unexpected indentation"),
    ("  a: b", "line 1: the file must be a mapping"),
    ("- a", "line 1: the file must be a mapping"),
    ('a: "open', "line 1: cannot read the double-quoted scalar"),
    ("a: 'open", "line 1: cannot read the single-quoted scalar"),
    ("a:\n  -\nb: c", "line 2: an empty sequence item"),
])
def test_cff_reader_refuses_what_it_does_not_read(text, fragment):
    with pytest.raises(ValueError, match=re.escape(fragment)):
        read_cff(text)


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


def test_citation_and_changelog_agree_on_the_release():
    """CITATION.cff's version and release date are those of the CHANGELOG's entry for that version (they differed:
    2026-11-23 against 2026-11-22), and the installed package carries the same CITATION.cff."""
    cff = read_cff((ROOT / "CITATION.cff").read_text())
    entry = re.search(r"^## \[" + re.escape(str(cff["version"])) + r"\] - (\d{4}-\d{2}-\d{2})$",
                      (ROOT / "CHANGELOG.md").read_text(), re.M)
    assert entry, f"CHANGELOG.md has no entry for version {cff['version']}"
    assert str(cff["date-released"]) == entry.group(1)
    from importlib import resources

    assert resources.files("rocknroller.papers").joinpath("CITATION.cff").read_text() == (ROOT / "CITATION.cff").read_text()


def _setup_py() -> dict:
    import runpy

    return runpy.run_path(str(ROOT / "setup.py"))  # run_name is not "__main__": setup() is not called


def test_dev_version_scheme():
    """A build of the release commit is the release; any other build a PEP 440 development build of the next patch
    release that names its commit (issue 25, item 11: every build said 0.1.0)."""
    dev_version = _setup_py()["dev_version"]
    assert dev_version("0.1.0", 0, "2315f86", dirty=False) == "0.1.0"
    assert dev_version("0.1.0", 0, "2315f86", dirty=True) == "0.1.1.dev0+g2315f86.dirty"
    assert dev_version("0.1.0", 77, "219d0ff", dirty=False) == "0.1.1.dev77+g219d0ff"
    assert dev_version("1.2.9", None, "abcdef0", dirty=False) == "1.2.10.dev0+gabcdef0"
    assert dev_version("0.1.0", None, None, dirty=False) == "0.1.1.dev0+unknown"
    pep440 = r"\d+\.\d+\.\d+(\.dev\d+\+[a-z0-9]+(\.[a-z0-9]+)*)?"
    for case in ("0.1.0", "0.1.1.dev0+g2315f86.dirty", "0.1.1.dev0+unknown", rr.__version__):
        assert re.fullmatch(pep440, case), case


def test_citation_names_the_release_commit():
    """CITATION.cff records the release with its full commit, and that commit is in this history where there is one."""
    release, commit = _setup_py()["cff_release"]((ROOT / "CITATION.cff").read_text())
    assert release == read_cff((ROOT / "CITATION.cff").read_text())["version"]
    if (ROOT / ".git").exists():
        out = subprocess.run(["git", "-C", str(ROOT), "cat-file", "-t", commit], capture_output=True, text=True)
        if out.returncode == 0:  # absent from a shallow clone
            assert out.stdout.strip() == "commit"


def test_installed_version_tells_a_development_build():
    """The installed version is the release only for a build of the release commit: built from a later checkout it
    is ``X.Y.(Z+1).devN+g<commit>``, and a wheel built from the sdist alone keeps the sdist's version."""
    setup_py = _setup_py()
    pkg_info = ROOT / "PKG-INFO"
    if pkg_info.exists():  # the unpacked sdist: its wheel carries its version
        assert rr.__version__ == setup_py["version"]()
        return
    if not (ROOT / ".git").exists():
        pytest.skip("neither a git checkout nor an unpacked sdist")
    release, commit = setup_py["cff_release"]((ROOT / "CITATION.cff").read_text())
    head = subprocess.run(["git", "-C", str(ROOT), "rev-parse", "HEAD"], capture_output=True, text=True, check=True)
    if head.stdout.strip() != commit:
        assert rr.__version__ != release and ".dev" in rr.__version__ and "+" in rr.__version__, rr.__version__


@pytest.mark.parametrize("command, keys", [
    ("hierarchy", {"Chaplygin1903", "BorisovMamaev2002"}),
    ("simulate", {"BorisovMamaev2002", "BorisovKazakovSataev2014"}), ("slow", set())])
def test_cite_names_the_literature_of_the_loaded_spheres(command, keys):
    """Chaplygin (1903), Borisov and Mamaev (2002) and Borisov, Kazakov and Sataev (2014) where a command works with
    the family of loaded spheres: `hierarchy` its integrals and measures, `simulate --offset` Chaplygin's top."""
    found = set(re.findall(r"^@\w+\{(\w+),", rr.cite(command), flags=re.M))
    assert found & {"Chaplygin1903", "BorisovMamaev2002", "BorisovKazakovSataev2014"} == keys


def test_changelog_speaks_to_users_not_to_the_tracker():
    """The CHANGELOG's headings and entries cited the project's internal issue numbers ("### Added (issue 31)"),
    which mean nothing to a reader of the release: each entry says what changed instead."""
    text = (ROOT / "CHANGELOG.md").read_text()
    cited = [line for line in text.splitlines() if re.search(r"\b(issues?|items?) \d", line, re.I)]
    assert not cited, cited
