"""rocknroller: Routh's sphere and the rock'n'roller.

Public API re-exported from ``analysis`` and ``numerics`` (no physics lives here).
"""

from analysis.body import Body

__all__ = ["Body"]
__version__ = "0.1.0"
