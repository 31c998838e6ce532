"""Shared fixtures: the paper's bodies and the figure-5 initial state."""

from __future__ import annotations

import pytest

from rocknroller.analysis.model.body import Body
from rocknroller.analysis.model.equations import EulerState, fig5_start


@pytest.fixture(scope="session")
def paper_body() -> Body:
    return Body.paper()


@pytest.fixture(scope="session")
def fig5_initial() -> EulerState:
    """Paper §7.1: θ0 = 0.95π, φ0 = ψ0 = 0, ω = (0, 0.001, −0.001)."""
    return fig5_start()
