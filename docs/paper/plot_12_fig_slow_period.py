"""
Package figure: the slow period of the (Q_R, Q_J) oscillation against ψ0 and ε (ODE, map, closed form)
======================================================================================================

Runs :mod:`rocknroller.papers.lynch_bustamante.fig_slow_period` (``rocknroller reproduce --only fig_slow_period``).
"""

# %%
import tempfile
from pathlib import Path

from rocknroller.papers.lynch_bustamante import fig_slow_period as module

result = module.run(Path(tempfile.mkdtemp(prefix="rocknroller-gallery-")))
print(result.caption)

# %%
# The numbers measured
# --------------------
for quantity, value in result.numbers.items():
    print(f"{quantity}: {value}")
