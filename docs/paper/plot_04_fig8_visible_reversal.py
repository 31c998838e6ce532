"""
Paper fig. 8: a start on the critical line Q_J = Q_J,π^crit (visible-angle reversals), ψ̇0 = 0.002
==================================================================================================

Runs :mod:`rocknroller.papers.lynch_bustamante.fig8_visible_reversal` (``rocknroller reproduce --only fig8``).
"""

# %%
import tempfile
from pathlib import Path

from rocknroller.papers.lynch_bustamante import fig8_visible_reversal as module

result = module.run(Path(tempfile.mkdtemp(prefix="rocknroller-gallery-")))
print(result.caption)

# %%
# The numbers measured
# --------------------
for quantity, value in result.numbers.items():
    print(f"{quantity}: {value}")
