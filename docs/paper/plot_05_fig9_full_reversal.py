"""
Paper fig. 9: a start on the critical line Q_J = Q_J,0^crit (full-angle reversals), ψ̇0 = 0.378
===============================================================================================

Runs :mod:`rocknroller.papers.lynch_bustamante.fig9_full_reversal` (``rocknroller reproduce --only fig9``).
"""

# %%
import tempfile
from pathlib import Path

from rocknroller.papers.lynch_bustamante import fig9_full_reversal as module

result = module.run(Path(tempfile.mkdtemp(prefix="rocknroller-gallery-")))
print(result.caption)

# %%
# The numbers measured
# --------------------
for quantity, value in result.numbers.items():
    print(f"{quantity}: {value}")
