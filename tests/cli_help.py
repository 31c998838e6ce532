"""Every ``--help`` text of the command line, for the tests that read them as a user would (shared helper)."""

from __future__ import annotations

import contextlib
import io

import pytest

from rocknroller.cli import COMMANDS, main


def help_texts() -> dict[str | None, str]:
    """``rocknroller --help`` (key None) and ``rocknroller COMMAND --help`` for every command, whitespace folded."""
    texts = {}
    for command in [None, *COMMANDS]:
        out = io.StringIO()
        with contextlib.redirect_stdout(out), pytest.raises(SystemExit):
            main(([command] if command else []) + ["--help"])
        texts[command] = " ".join(out.getvalue().split())
    return texts
