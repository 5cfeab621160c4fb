"""Arrays as compiled kernels take them: C-contiguous, of one dtype (one compiled signature).

:func:`c_array` does what ``np.require(a, dtype, "C")`` (or ``("C", "W")``) does, at a
fraction of its cost when ``a`` already qualifies, which on the per-tick path it nearly always
does.
"""

from __future__ import annotations

import functools

import numpy as np


def c_array(a: np.ndarray, dtype: type | np.dtype, writeable: bool = False) -> np.ndarray:
    """``a`` itself if it is a C-contiguous ndarray of ``dtype`` (and writeable, if asked),
    else a copy that is."""
    out = np.ascontiguousarray(a, dtype=dtype)
    return out if out.flags.writeable or not writeable else out.copy()


def as_records(rows: np.ndarray) -> np.ndarray:
    """A view of a structured array's rows as opaque records (numpy void of the same size), so
    that copying, taking and assigning rows move bytes (memcpy) instead of walking the
    fields one by one (see docs/reports/performance-log.md). ``.view(rows.dtype)`` turns
    the result back."""
    return rows.view(_record(rows.dtype.itemsize))


@functools.cache
def _record(size: int) -> np.dtype:
    """The opaque record dtype of ``size`` bytes (made once per size, not per call)."""
    return np.dtype((np.void, size))
