"""
Paper fig. 5: contact track and φ at the θ-maxima, symmetric body against ε = 1e-3, 1500 time units
===================================================================================================

Runs :mod:`rocknroller.papers.lynch_bustamante.fig5_symmetry_breaking` (``rocknroller reproduce --only fig5``).
"""

# %%
import tempfile
from pathlib import Path

from rocknroller.papers.lynch_bustamante import fig5_symmetry_breaking as module

result = module.run(Path(tempfile.mkdtemp(prefix="rocknroller-gallery-")))
print(result.caption)

# %%
# The numbers measured
# --------------------
for quantity, value in result.numbers.items():
    print(f"{quantity}: {value}")
