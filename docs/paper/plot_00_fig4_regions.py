"""
Paper fig. 4: the four critical regions of the (Q_R, Q_J) plane with V_φ(θ) in each (paper body, I1 = I2)
=========================================================================================================

Runs :mod:`rocknroller.papers.lynch_bustamante.fig4_regions` (``rocknroller reproduce --only fig4``).
"""

# %%
import tempfile
from pathlib import Path

from rocknroller.papers.lynch_bustamante import fig4_regions as module

result = module.run(Path(tempfile.mkdtemp(prefix="rocknroller-gallery-")))
print(result.caption)

# %%
# The numbers measured
# --------------------
for quantity, value in result.numbers.items():
    print(f"{quantity}: {value}")
