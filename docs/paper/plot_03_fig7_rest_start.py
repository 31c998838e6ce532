"""
Paper fig. 7: released from rest (φ̇0 = ψ̇0 = 0, so Q_R = Q_J = 0), ε = 1e-3, ψ0 = π/4, 200 time units
======================================================================================================

Runs :mod:`rocknroller.papers.lynch_bustamante.fig7_rest_start` (``rocknroller reproduce --only fig7``).
"""

# %%
import tempfile
from pathlib import Path

from rocknroller.papers.lynch_bustamante import fig7_rest_start as module

result = module.run(Path(tempfile.mkdtemp(prefix="rocknroller-gallery-")))
print(result.caption)

# %%
# The numbers measured
# --------------------
for quantity, value in result.numbers.items():
    print(f"{quantity}: {value}")
