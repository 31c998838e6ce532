"""
Paper App. A.1: parameters of the bowling-ball rock'n'roller (polar cap with d = cos Θ removed)
===============================================================================================

Runs :mod:`rocknroller.papers.lynch_bustamante.table_polar_cap` (``rocknroller reproduce --only table_polar_cap``).
"""

# %%
import tempfile
from pathlib import Path

from rocknroller.papers.lynch_bustamante import table_polar_cap as module

result = module.run(Path(tempfile.mkdtemp(prefix="rocknroller-gallery-")))
print(result.caption)

# %%
# The numbers measured
# --------------------
for quantity, value in result.numbers.items():
    print(f"{quantity}: {value}")
