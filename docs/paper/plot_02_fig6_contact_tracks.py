"""
Paper fig. 6: contact tracks for six initial spin phases ψ0, ε = 1e-3, 1000 time units, from rest at 0.95π
==========================================================================================================

Runs :mod:`rocknroller.papers.lynch_bustamante.fig6_contact_tracks` (``rocknroller reproduce --only fig6``).
"""

# %%
import tempfile
from pathlib import Path

from rocknroller.papers.lynch_bustamante import fig6_contact_tracks as module

result = module.run(Path(tempfile.mkdtemp(prefix="rocknroller-gallery-")))
print(result.caption)

# %%
# The numbers measured
# --------------------
for quantity, value in result.numbers.items():
    print(f"{quantity}: {value}")
