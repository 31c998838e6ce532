"""
Package figure: the azimuth span Φ(ψ0) — direct ODE, averaged map, pendulum closed form, and π − 2ψ0
====================================================================================================

Runs :mod:`rocknroller.papers.lynch_bustamante.fig_azimuth_span` (``rocknroller reproduce --only fig_azimuth_span``).
"""

# %%
import tempfile
from pathlib import Path

from rocknroller.papers.lynch_bustamante import fig_azimuth_span as module

result = module.run(Path(tempfile.mkdtemp(prefix="rocknroller-gallery-")))
print(result.caption)

# %%
# The numbers measured
# --------------------
for quantity, value in result.numbers.items():
    print(f"{quantity}: {value}")
