"""What to cite for a run: BibTeX for the package, the paper it builds on and the codes a command used
(after REBOUND's ``sim.cite()``).  No physics here.

The package's own entry is generated from ``CITATION.cff`` (one source: its title, authors, release date, licence and
address), read by :func:`read_cff`, a reader of the small part of YAML that file uses; the version is the running
package's.

>>> import rocknroller as rr
>>> print(rr.cite("simulate"))  # doctest: +SKIP
"""

from __future__ import annotations

import json
import re
from importlib import resources
from typing import Any

from rocknroller.numerics.provenance import __version__

__all__ = ["USES", "cite", "bibtex_entries", "read_cff", "citation_file"]

# ----------------------------------------------------------------------------- CITATION.cff, read
#: A ``key: value`` line of a block mapping.
_KEY = re.compile(r"^([A-Za-z0-9][\w.-]*):(?:\s+(.*))?$")
#: First characters of the YAML this reader refuses: flow collections, block scalars, anchors, aliases, tags,
#: directives and reserved indicators.
_UNREAD = "[]{}|>&*!%@`"


def _cff_error(number: int, what: str) -> ValueError:
    return ValueError(f"CITATION.cff, line {number}: {what} (rocknroller reads the plain subset of YAML that "
                      "CITATION.cff needs: block mappings and sequences, one-line plain or quoted scalars)")


def _uncomment(line: str) -> str:
    """``line`` without its ``# comment`` (a ``#`` at the start or after a space, outside quotes)."""
    quote, i = None, 0
    while i < len(line):
        ch = line[i]
        if quote == '"' and ch == "\\":
            i += 2  # an escape: the next character cannot close the scalar
            continue
        if quote == "'" and line.startswith("''", i):
            i += 2  # a quote doubled inside a single-quoted scalar
            continue
        if quote is not None:
            quote = None if ch == quote else quote
        elif ch in "\"'" and (i == 0 or line[i - 1] == " "):
            quote = ch
        elif ch == "#" and (i == 0 or line[i - 1] == " "):
            return line[:i].rstrip()
        i += 1
    return line.rstrip()


def _scalar(text: str, number: int) -> str:
    """A one-line scalar: plain (as written), ``'single'`` (``''`` is a quote) or ``"double"`` quoted (JSON's
    escapes, which YAML's include)."""
    if text[0] == '"':
        try:
            value = json.loads(text)
        except json.JSONDecodeError:
            value = None
        if not isinstance(value, str):
            raise _cff_error(number, f"cannot read the double-quoted scalar {text}")
        return value
    if text[0] == "'":
        inner = text[1:-1]
        if len(text) < 2 or text[-1] != "'" or "'" in inner.replace("''", ""):
            raise _cff_error(number, f"cannot read the single-quoted scalar {text}")
        return inner.replace("''", "'")
    if text[0] in _UNREAD or ": " in text or text.endswith(":"):
        raise _cff_error(number, f"cannot read {text!r}")
    return text


def _lines(text: str) -> list[tuple[int, int, str]]:
    """(line number, indentation, content) of the lines with content; a sequence item's content that starts a
    mapping or another sequence (``- name: x``) is split off as its own line, indented where it starts."""
    out = []
    for number, raw in enumerate(text.splitlines(), 1):
        body = _uncomment(raw)
        content = body.lstrip(" ")
        if not content:
            continue
        if content[0] == "\t" or "\t" in body[:len(body) - len(content)]:
            raise _cff_error(number, "a tab in the indentation")
        indent = len(body) - len(content)
        while content.startswith("- ") and (content[2:].lstrip().startswith("- ") or _KEY.match(content[2:].lstrip())):
            rest = content[2:].lstrip()
            out.append((number, indent, "-"))
            indent, content = indent + len(content) - len(rest), rest
        out.append((number, indent, content))
    return out


def _block(lines: list[tuple[int, int, str]], i: int) -> tuple[Any, int]:
    """The block mapping or sequence whose first line is ``lines[i]`` (its indentation is the block's); returns the
    value and the index of the first line after it."""
    indent = lines[i][1]
    if lines[i][2] == "-" or lines[i][2].startswith("- "):
        items: list[Any] = []
        while i < len(lines) and lines[i][1] == indent and (lines[i][2] == "-" or lines[i][2].startswith("- ")):
            number, _, content = lines[i]
            if content == "-":
                if i + 1 == len(lines) or lines[i + 1][1] <= indent:
                    raise _cff_error(number, "an empty sequence item")
                value, i = _block(lines, i + 1)
            else:
                value, i = _scalar(content[2:].lstrip(), number), i + 1
            items.append(value)
        return items, i
    mapping: dict[str, Any] = {}
    while i < len(lines) and lines[i][1] == indent:
        number, _, content = lines[i]
        match = _KEY.match(content)
        if match is None:
            raise _cff_error(number, f"expected 'key: value', got {content!r}")
        key, value = match.groups()
        if key in mapping:
            raise _cff_error(number, f"the key {key!r} is given twice")
        i += 1
        if value:
            mapping[key] = _scalar(value, number)
        elif i < len(lines) and (lines[i][1] > indent or (lines[i][1] == indent and lines[i][2].startswith("-"))):
            mapping[key], i = _block(lines, i)  # a sequence may sit at its key's indentation
        else:
            mapping[key] = None
    return mapping, i


def read_cff(text: str) -> dict[str, Any]:
    """The content of a ``CITATION.cff`` file: a mapping of its keys to text, lists and mappings.

    Reads the plain subset of YAML that CITATION.cff files use (block mappings and sequences, ``#`` comments,
    one-line plain, single- or double-quoted scalars); plain scalars are kept as written (``2026-11-23``, ``42``).
    The package has no YAML dependency; this reader refuses what it does not read rather than guess.

    Raises
    ------
    ValueError
        Naming the line: flow collections (``[a, b]``), block scalars (``|``, ``>``), anchors, tags, tabs in the
        indentation, a multi-line scalar or a key given twice.
    """
    lines = _lines(text)
    if not lines or lines[0][1] != 0:
        raise _cff_error(lines[0][0] if lines else 1, "the file must be a mapping starting in the first column")
    value, i = _block(lines, 0)
    if i != len(lines):
        raise _cff_error(lines[i][0], f"unexpected indentation of {lines[i][2]!r}")
    if not isinstance(value, dict):
        raise _cff_error(1, "the file must be a mapping of keys to values")
    return value


def citation_file() -> str:
    """The text of the package's ``CITATION.cff``, installed in ``rocknroller.papers`` (in the repository
    ``papers/CITATION.cff`` is a link to the one at the root, so there is one source)."""
    packaged = resources.files("rocknroller.papers").joinpath("CITATION.cff")
    if not packaged.is_file():
        raise RuntimeError(f"CITATION.cff is not installed with this copy of rocknroller (looked for {packaged}); "
                           "reinstall the package")
    return packaged.read_text(encoding="utf-8")


# ----------------------------------------------------------------------------- BibTeX, written
#: Characters with a meaning in BibTeX/LaTeX, and how text from CITATION.cff writes them.
_LATEX = {"\\": r"\textbackslash{}", "{": r"\{", "}": r"\}", "&": r"\&", "%": r"\%", "$": r"\$", "#": r"\#",
          "_": r"\_", "~": r"\textasciitilde{}", "^": r"\textasciicircum{}"}


def _latex(text: str) -> str:
    return "".join(_LATEX.get(ch, ch) for ch in str(text))


def _title(text: str) -> str:
    """A title whose capitalised words after the first keep their capitals in styles that lower-case titles."""
    first, *rest = _latex(text).split(" ")
    return " ".join([first, *(f"{{{w}}}" if w[:1].isupper() else w for w in rest)])


def _person(author: dict[str, Any]) -> str:
    """One CFF author as BibTeX: ``Family, Given`` (with a particle and a suffix) or ``{Entity name}``."""
    if "family-names" in author:
        family = " ".join(_latex(author[k]) for k in ("name-particle", "family-names") if author.get(k))
        return ", ".join([family, *(_latex(author[k]) for k in ("name-suffix", "given-names") if author.get(k))])
    if "name" in author:
        return f"{{{_latex(author['name'])}}}"
    raise ValueError(f"CITATION.cff: an author needs family-names or name, got {author!r}")


def _authors(work: dict[str, Any]) -> list[dict[str, Any]]:
    authors = work.get("authors")
    if not (isinstance(authors, list) and authors and all(isinstance(a, dict) for a in authors)):
        raise ValueError(f"CITATION.cff: {work.get('title', 'the package')!r} needs a list of authors")
    return authors


def _entry(kind: str, key: str, fields: dict[str, Any]) -> str:
    given = {k: v for k, v in fields.items() if v not in (None, "")}
    width = max(map(len, given))
    return "\n".join([f"@{kind}{{{key},", ",\n".join(f"  {k:<{width}} = {{{v}}}" for k, v in given.items()), "}"])


def _year(cff: dict[str, Any]) -> str:
    date = cff.get("date-released")
    if not (isinstance(date, str) and re.fullmatch(r"\d{4}-\d{2}-\d{2}", date)):
        raise ValueError(f"CITATION.cff: date-released must be a date YYYY-MM-DD, got {date!r}")
    return date[:4]


def _package(cff: dict[str, Any]) -> str:
    """The package's entry: title, authors, year of release, licence, address (``url``, else ``repository-code``)
    and DOI from CITATION.cff; the version of the running package."""
    for name in ("title", "license"):
        if not isinstance(cff.get(name), str):
            raise ValueError(f"CITATION.cff: {name} must be given as text, got {cff.get(name)!r}")
    return _entry("software", "rocknroller", {
        "author": " and ".join(map(_person, _authors(cff))), "title": _title(cff["title"]), "year": _year(cff),
        "version": __version__, "url": cff.get("url") or cff.get("repository-code"), "doi": cff.get("doi"),
        "license": _latex(cff["license"])})


def _reference_key(ref: dict[str, Any]) -> str:
    """The citation key of a reference: its authors' family names (the first and "EtAl" past two) and its year."""
    families = [a.get("family-names") or a.get("name", "") for a in _authors(ref)]
    names = families if len(families) <= 2 else [families[0], "EtAl"]
    return re.sub(r"[^A-Za-z0-9]", "", "".join(names)) + str(ref.get("year", ""))


def _article(ref: dict[str, Any]) -> tuple[str, str]:
    """(key, entry) of an article among CITATION.cff's references."""
    pages = "--".join(str(ref[k]) for k in ("start", "end") if ref.get(k) is not None)
    key = _reference_key(ref)
    return key, _entry("article", key, {
        "author": " and ".join(map(_person, _authors(ref))), "title": _title(ref["title"]),
        "journal": _latex(ref.get("journal", "")), "volume": ref.get("volume"), "number": ref.get("issue"),
        "pages": pages, "year": ref.get("year"), "doi": ref.get("doi")})


def _references(cff: dict[str, Any]) -> dict[str, str]:
    """The articles CITATION.cff lists under ``references``, by citation key."""
    refs = cff.get("references") or []
    return dict(_article(r) for r in refs if isinstance(r, dict) and r.get("type") == "article")


#: The BibTeX keys, among CITATION.cff's references, of the paper and of the codes it lists.
PAPER_KEY, HEYOKA_KEY = "LynchBustamante2009", "BiscaniIzzo2021"

# The codes CITATION.cff does not list.
_SCIPY = """@article{SciPy2020,
  author  = {Virtanen, Pauli and others},
  title   = {{SciPy} 1.0: Fundamental Algorithms for Scientific Computing in {Python}},
  journal = {Nature Methods},
  volume  = {17},
  pages   = {261--272},
  year    = {2020},
  doi     = {10.1038/s41592-019-0686-2}
}"""

_MPMATH = """@misc{mpmath,
  author       = {{The mpmath development team}},
  title        = {mpmath: a {Python} library for arbitrary-precision floating-point arithmetic},
  howpublished = {\\url{https://mpmath.org/}}
}"""


# The methods: MEGNO (the chaos indicator of the slow map and of the direct ODE's variational equations), Greene's
# residue (the stability of the periodic orbits), Chirikov's standard map (the slow map near pure rocking, K = eps kappa).
_MEGNO = """@article{CincottaSimo2000,
  author  = {Cincotta, Pablo M. and Sim{\\'o}, Carles},
  title   = {Simple tools to study global dynamics in non-axisymmetric galactic potentials -- {I}},
  journal = {Astronomy and Astrophysics Supplement Series},
  volume  = {147},
  pages   = {205--228},
  year    = {2000},
  doi     = {10.1051/aas:2000108}
}"""

_GREENE = """@article{Greene1979,
  author  = {Greene, John M.},
  title   = {A method for determining a stochastic transition},
  journal = {Journal of Mathematical Physics},
  volume  = {20},
  pages   = {1183--1201},
  year    = {1979},
  doi     = {10.1063/1.524170}
}"""

_CHIRIKOV = """@article{Chirikov1979,
  author  = {Chirikov, Boris V.},
  title   = {A universal instability of many-dimensional oscillator systems},
  journal = {Physics Reports},
  volume  = {52},
  pages   = {263--379},
  year    = {1979},
  doi     = {10.1016/0370-1573(79)90023-1}
}"""

_CHAPLYGIN = """@article{Chaplygin1903,
  author  = {Chaplygin, Sergey A.},
  title   = {On a ball's rolling on a horizontal plane},
  journal = {Regular and Chaotic Dynamics},
  volume  = {7},
  number  = {2},
  pages   = {131--148},
  year    = {2002},
  note    = {English translation of Mat. Sbornik 24 (1903), 139--168}
}"""

_BORISOV_MAMAEV = """@article{BorisovMamaev2002,
  author  = {Borisov, Alexey V. and Mamaev, Ivan S.},
  title   = {The rolling motion of a rigid body on a plane and a sphere. Hierarchy of dynamics},
  journal = {Regular and Chaotic Dynamics},
  volume  = {7},
  number  = {2},
  pages   = {177--200},
  year    = {2002},
  doi     = {10.1070/RD2002v007n02ABEH000204}
}"""

_BORISOV_KAZAKOV_SATAEV = """@article{BorisovKazakovSataev2014,
  author  = {Borisov, Alexey V. and Kazakov, Alexey O. and Sataev, Igor R.},
  title   = {The reversal and chaotic attractor in the nonholonomic model of {Chaplygin's} top},
  journal = {Regular and Chaotic Dynamics},
  volume  = {19},
  number  = {6},
  pages   = {718--733},
  year    = {2014}
}"""


#: The codes and methods each subcommand uses besides the package and the paper (which every run cites):
#: heyoka for the direct ODE and the averaging tables' variational orbits, scipy for the DOP853 check and the
#: quadrature nodes, mpmath for the high-precision references; MEGNO where a command reports order or chaos, the
#: standard map where it reads the slow map as one (K = eps kappa, its period doubling at K = 4, its (Theta, p)
#: plane), Greene's residue where it gives the stability of periodic orbits; Chaplygin, Borisov and Mamaev, and
#: Borisov, Kazakov and Sataev where a command works with the family of loaded spheres (its integrals, measures and
#: Chaplygin's top).  Every command of ``rocknroller`` has
#: an entry (``cite`` itself excepted), which the tests check against the dispatcher's list.
USES: dict[str, tuple[str, ...]] = {
    "reproduce": ("heyoka", "scipy", "mpmath"),
    "simulate": ("heyoka", "scipy", "megno", "hierarchy", "chaplygin_top"),
    "animate": ("heyoka",),
    "table": ("scipy", "mpmath"),
    "diagram": ("heyoka",),
    "slow": ("heyoka", "megno", "standard_map", "residue"),  # its periodic orbits carry Greene's residue
    "atlas": ("heyoka", "megno"),
    "bifurcation": ("heyoka", "scipy", "standard_map", "residue"),
    "portrait": ("heyoka", "megno", "standard_map"),
    "verify": ("heyoka", "scipy", "mpmath"),
    "warm": ("heyoka",),
    "hierarchy": ("heyoka", "chaplygin", "hierarchy"),
}


def bibtex_entries(command: str | None = None) -> list[str]:
    """BibTeX entries for ``command`` (a key of :data:`USES`; ``None``: everything the package can use): the
    package and the paper from ``CITATION.cff``, then the codes the command uses."""
    if command is not None and command not in USES:
        raise ValueError(f"command must be one of {', '.join(USES)} or None, got command={command!r}")
    cff = read_cff(citation_file())
    refs = _references(cff)
    missing = [k for k in (PAPER_KEY, HEYOKA_KEY) if k not in refs]
    if missing:
        raise ValueError(f"CITATION.cff: the references lack {', '.join(missing)} (found {', '.join(refs) or 'none'})")
    entries = {"heyoka": refs[HEYOKA_KEY], "scipy": _SCIPY, "mpmath": _MPMATH, "megno": _MEGNO, "residue": _GREENE,
               "standard_map": _CHIRIKOV, "chaplygin": _CHAPLYGIN, "hierarchy": _BORISOV_MAMAEV,
               "chaplygin_top": _BORISOV_KAZAKOV_SATAEV}
    # heyoka (the integrator of every command) first, then the methods and the literature in name order
    codes = sorted({c for uses in USES.values() for c in uses}, key=lambda c: (c != "heyoka", c)) if command is None \
        else USES[command]
    return [_package(cff), refs[PAPER_KEY], *(entries[c] for c in codes)]


def cite(command: str | None = None) -> str:
    """The BibTeX to cite for a run of ``command`` (see :func:`bibtex_entries`), as one string.

    Examples
    --------
    >>> import rocknroller as rr
    >>> bibtex = rr.cite()
    >>> print(bibtex.splitlines()[0])
    @software{rocknroller,
    >>> print("Lynch" in bibtex)
    True
    """
    return "\n\n".join(bibtex_entries(command)) + "\n"
