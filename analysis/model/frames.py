"""Results as pandas DataFrames.  pandas is optional: it is imported only when a ``to_dataframe()`` is called.

Quantities that do not exist at some points (masked arrays, :func:`rocknroller.analysis.routh.reduction.where_defined`)
become pandas' missing values (nullable ``Float64``), never NaN.
"""

from __future__ import annotations

from typing import TYPE_CHECKING, Any, Mapping

import numpy as np

if TYPE_CHECKING:
    import pandas

__all__ = ["COLUMN_NAMES", "dataframe"]

#: Column names for people, the same in every DataFrame and CSV file the package writes: Routh's and Jellett's
#: quantities as the paper writes them (attributes keep the Python names ``QR``, ``QJ``).
COLUMN_NAMES = {"QR": "Q_R", "QJ": "Q_J"}


def _column(values: Any) -> Any:
    import pandas as pd

    if np.ma.isMaskedArray(values):
        data = np.ma.getdata(values).reshape(-1)
        if data.dtype.kind == "f":
            return pd.arrays.FloatingArray(data.astype(np.float64), np.ma.getmaskarray(values).reshape(-1).copy())
        return pd.array(np.ma.filled(values, None).reshape(-1) if np.ma.getmaskarray(values).any() else data)
    return np.asarray(values).reshape(-1)


def dataframe(columns: Mapping[str, Any]) -> "pandas.DataFrame":
    """A :class:`pandas.DataFrame` of equal-length columns (scalars and 0-d arrays become one row), named as in
    ``COLUMN_NAMES`` (``QR`` is the column ``Q_R``).

    Raises
    ------
    ImportError
        If pandas is not installed (rocknroller does not require it).
    """
    try:
        import pandas as pd
    except ImportError as exc:  # pragma: no cover - depends on the environment
        raise ImportError("to_dataframe() needs pandas, which rocknroller does not require: pip install pandas") \
            from exc
    return pd.DataFrame({COLUMN_NAMES.get(name, name): _column(values) for name, values in columns.items()})
