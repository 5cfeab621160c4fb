"""DASH's spacing arithmetic, compiled (numba): the neighbours' mean spacing and the count of
those too close (:func:`spacing_view`), in one pass where numpy made ~10 calls on a robot's
neighbours. The same numbers as numpy's, to the bit (float32 spacings summed pairwise, in
float32, as numpy's ``mean`` does); tests compare both. Its push: controllers/common/push.py.
"""

from __future__ import annotations

import numpy as np
from numba import njit

from controllers.common.npsum import pairwise_sum


@njit(cache=True)
def spacing_view(distances, sender, status, spacing, reach, too_close, no_sender, seeking
                 ):  # pragma: no cover - compiled
    """The mean broadcast spacing (float32, as numpy's mean of float32; NaN: no peer) of the
    peers within ``reach`` (units) that speak and have left Seeking, and how many neighbours
    are closer than ``too_close`` (units)."""
    return spacing_view_into(np.empty(distances.shape[0], dtype=spacing.dtype), distances,
                             sender, status, spacing, reach, too_close, no_sender, seeking)


@njit(cache=True)
def spacing_view_into(peers, distances, sender, status, spacing, reach, too_close, no_sender,
                      seeking):  # pragma: no cover - compiled
    """:func:`spacing_view`, the peers' spacings gathered in ``peers`` (of spacing's dtype,
    at least as long as ``distances``): no array made per robot."""
    k = close = 0
    for j in range(distances.shape[0]):
        if (distances[j] <= reach and sender[j] != no_sender and status[j] != seeking
                and status[j] >= 0):
            peers[k] = spacing[j]
            k += 1
        if distances[j] < too_close:
            close += 1
    if k == 0:
        return np.nan, close
    mean = pairwise_sum(peers, 0, k) / spacing.dtype.type(k)
    return np.float64(mean), close


def warm_up() -> None:
    """Compile (first time on a machine) or load (from the cache) the kernel now."""
    rows = np.zeros(1, dtype=[("id", "i4"), ("status", "i1"), ("spacing", "f4")])
    spacing_view(np.ones(1), rows["id"], rows["status"], rows["spacing"], 1.0, 1.0, -1, 0)
