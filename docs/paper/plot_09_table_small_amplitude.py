"""
Paper §2.2 and §4.1: small-amplitude rocking frequencies about the two principal axes, and their ratio
======================================================================================================

Runs :mod:`rocknroller.papers.lynch_bustamante.table_small_amplitude` (``rocknroller reproduce --only table_small_amplitude``).
"""

# %%
import tempfile
from pathlib import Path

from rocknroller.papers.lynch_bustamante import table_small_amplitude as module

result = module.run(Path(tempfile.mkdtemp(prefix="rocknroller-gallery-")))
print(result.caption)

# %%
# The numbers measured
# --------------------
for quantity, value in result.numbers.items():
    print(f"{quantity}: {value}")
