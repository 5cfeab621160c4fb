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


def as_words(rows: np.ndarray) -> np.ndarray:
    """A view of a structured array's rows (N,) as (N, W) unsigned words, the widest (8, 4,
    2 or 1 bytes) that divide a row's size: the same bytes, for compiled code to compare a
    row a word at a time (numba takes no opaque records). A copy first if ``rows`` is not
    C-contiguous."""
    rows = np.ascontiguousarray(rows)
    size = rows.dtype.itemsize
    word = next(w for w in (8, 4, 2, 1) if size % w == 0)
    return rows.view(_WORDS[word]).reshape(len(rows), size // word)


_WORDS = {8: np.uint64, 4: np.uint32, 2: np.uint16, 1: np.uint8}
"""The unsigned integer type of each word size, bytes (as_words)."""


@functools.cache
def _record(size: int) -> np.dtype:
    """The opaque record dtype of ``size`` bytes (made once per size, not per call)."""
    return np.dtype((np.void, size))
