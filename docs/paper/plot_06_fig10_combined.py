"""
Paper fig. 10: the (Q_R, Q_J) orbits of figs. 7, 8 and 9 together, with the critical lines
==========================================================================================

Runs :mod:`rocknroller.papers.lynch_bustamante.fig10_combined` (``rocknroller reproduce --only fig10``).
"""

# %%
import tempfile
from pathlib import Path

from rocknroller.papers.lynch_bustamante import fig10_combined as module

result = module.run(Path(tempfile.mkdtemp(prefix="rocknroller-gallery-")))
print(result.caption)

# %%
# The numbers measured
# --------------------
for quantity, value in result.numbers.items():
    print(f"{quantity}: {value}")
