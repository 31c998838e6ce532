"""What to cite for a run: BibTeX for the package, the paper it builds on and the codes a command used
(after REBOUND's ``sim.cite()``).  No physics here.

>>> import rocknroller as rr
>>> print(rr.cite("simulate"))  # doctest: +SKIP
"""

from __future__ import annotations

from rocknroller.numerics.provenance import __version__

__all__ = ["USES", "cite", "bibtex_entries"]

_PAPER = """@article{LynchBustamante2009,
  author  = {Lynch, Peter and Bustamante, Miguel D.},
  title   = {Precession and recession of the rock'n'roller},
  journal = {Journal of Physics A: Mathematical and Theoretical},
  volume  = {42},
  number  = {42},
  pages   = {425203},
  year    = {2009},
  doi     = {10.1088/1751-8113/42/42/425203}
}"""

_HEYOKA = """@article{BiscaniIzzo2021,
  author  = {Biscani, Francesco and Izzo, Dario},
  title   = {Revisiting high-order {Taylor} methods for astrodynamics and celestial mechanics},
  journal = {Monthly Notices of the Royal Astronomical Society},
  volume  = {504},
  number  = {2},
  pages   = {2614--2628},
  year    = {2021},
  doi     = {10.1093/mnras/stab1032}
}"""

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


def _package() -> str:
    return ("@software{rocknroller,\n"
            "  author  = {{The rocknroller developers}},\n"
            "  title   = {rocknroller: asymptotic and perturbation analysis of Routh's sphere and the rock'n'roller},\n"
            f"  version = {{{__version__}}},\n"
            "  license = {MIT}\n"
            "}")


#: The codes each subcommand uses besides the package and the paper (which every run cites):
#: heyoka for the direct ODE and the averaging tables' variational orbits, scipy for the DOP853 check and the
#: quadrature nodes, mpmath for the high-precision references.
USES: dict[str, tuple[str, ...]] = {
    "simulate": ("heyoka", "scipy"),
    "diagram": ("heyoka",),
    "table": ("scipy", "mpmath"),
    "slow": ("heyoka",),
    "verify": ("heyoka", "scipy", "mpmath"),
    "reproduce": ("heyoka", "scipy", "mpmath"),
}
_ENTRIES = {"heyoka": _HEYOKA, "scipy": _SCIPY, "mpmath": _MPMATH}


def bibtex_entries(command: str | None = None) -> list[str]:
    """BibTeX entries for ``command`` (a key of :data:`USES`; ``None``: everything the package can use)."""
    if command is not None and command not in USES:
        raise ValueError(f"command must be one of {', '.join(USES)} or None, got command={command!r}")
    codes = sorted({c for uses in USES.values() for c in uses}) if command is None else USES[command]
    return [_package(), _PAPER, *(_ENTRIES[c] for c in codes)]


def cite(command: str | None = None) -> str:
    """The BibTeX to cite for a run of ``command`` (see :func:`bibtex_entries`), as one string."""
    return "\n\n".join(bibtex_entries(command)) + "\n"
