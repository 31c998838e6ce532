"""
Paper fig. 11: visible-angle reversal at high Q_R = 0.1, started slightly above Q_J,π^crit
==========================================================================================

Runs :mod:`rocknroller.papers.lynch_bustamante.fig11_high_QR` (``rocknroller reproduce --only fig11``).
"""

# %%
import tempfile
from pathlib import Path

from rocknroller.papers.lynch_bustamante import fig11_high_QR as module

result = module.run(Path(tempfile.mkdtemp(prefix="rocknroller-gallery-")))
print(result.caption)

# %%
# The numbers measured
# --------------------
for quantity, value in result.numbers.items():
    print(f"{quantity}: {value}")
