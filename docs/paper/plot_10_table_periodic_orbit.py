"""
Paper §7.2: the periodic orbit near ψ0 = 2.965π/8 (ε = 1e-3, released at rest from θ0 = 0.95π)
==============================================================================================

Runs :mod:`rocknroller.papers.lynch_bustamante.table_periodic_orbit` (``rocknroller reproduce --only table_periodic_orbit``).
"""

# %%
import tempfile
from pathlib import Path

from rocknroller.papers.lynch_bustamante import table_periodic_orbit as module

result = module.run(Path(tempfile.mkdtemp(prefix="rocknroller-gallery-")))
print(result.caption)

# %%
# The numbers measured
# --------------------
for quantity, value in result.numbers.items():
    print(f"{quantity}: {value}")
