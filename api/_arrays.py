"""Arrays handed to users as values: read-only, in scipy.spatial's dtypes."""

from __future__ import annotations

from typing import Any

import numpy as np
from numpy.typing import NDArray

__all__ = ["read_only"]


def read_only(a: NDArray[Any], dtype: type[np.generic] | None = None) -> NDArray[Any]:
    """``a`` (copied into ``dtype`` when it differs) as an array nobody can write to through it.

    The results of persistri are values: a hull's arrays are shared by every view
    of it and by the hulls derived from it, so writing to one would change them all. O(1), or O(size) to convert.
    """
    out = np.array(a, dtype=dtype) if dtype is not None and a.dtype != dtype else a.view()
    out.flags.writeable = False
    return out
