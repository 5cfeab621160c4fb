"""Which robots of a chunk are enclosed by waiting robots, compiled (numba): the answer of
:meth:`~controllers.ggc.detection.DetectionRules.is_enclosed` for every robot at once.

A robot is enclosed when its waiting neighbours (Initial or Detection) within 1.5 d_min are
at least three and leave no angular gap wider than ``ENCLOSED_GAP``. The bearings are the C
library's ``atan2``, as Python's ``math.atan2`` (geometry.widest_gap) is, and the gaps are
the same differences of the same sorted values, so the answers are the same to the bit.
Why compiled: Detection robots are ~20 % of the awake in a formation's first minutes, and
the Python version cost ~10 us a robot in list building and sorting.
"""

from __future__ import annotations

import math

import numpy as np
from numba import njit


@njit(cache=True)
def _within(distances, start, end, reach):  # pragma: no cover - compiled
    """The end of rows ``start:end`` within ``reach``: numpy's ``searchsorted(reach,
    side="right")`` on them, the same bisection (so the same answer, even were a view's
    distances out of order in the last bit)."""
    low, high = start, end
    while low < high:
        mid = low + ((high - low) >> 1)
        if distances[mid] <= reach:
            low = mid + 1
        else:
            high = mid
    return low


@njit(cache=True)
def enclosed_robots(offsets, distances, status, starts, reach, waiting_a, waiting_b,
                    gap):  # pragma: no cover - compiled
    """(R,) bool: robot k (rows ``starts[k]:starts[k+1]``, nearest first) hears at least
    three robots with status ``waiting_a`` or ``waiting_b`` within ``reach`` units, and the
    widest angle between their bearings is below ``gap`` radians."""
    robots = len(starts) - 1
    out = np.zeros(robots, dtype=np.bool_)
    angles = np.empty(max(1, len(distances)))
    for k in range(robots):
        count = 0
        for row in range(starts[k], _within(distances, starts[k], starts[k + 1], reach)):
            if status[row] == waiting_a or status[row] == waiting_b:
                angles[count] = math.atan2(offsets[row, 1], offsets[row, 0])
                count += 1
        if count < 3:
            continue
        sorted_angles = np.sort(angles[:count])
        widest = sorted_angles[0] + 2 * math.pi - sorted_angles[count - 1]
        for j in range(1, count):
            widest = max(widest, sorted_angles[j] - sorted_angles[j - 1])
        out[k] = widest < gap
    return out


def warm_up() -> None:
    """Compile (first time on a machine) or load (from the cache) the kernel now."""
    enclosed_robots(np.ones((1, 2)), np.ones(1), np.zeros(1, dtype=np.int64),
                    np.array([0, 1], dtype=np.int64), 1.0, 0, 1, 1.0)
