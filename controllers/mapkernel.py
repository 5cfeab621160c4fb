"""The local map's window query, compiled (numba): which remembered lattice points lie within
the sensing radius, their offsets and what is known of them, in one pass where numpy made ten
calls (most of a mean-shift or CVT robot's tick). Elementwise arithmetic only, so the same
offsets, to the bit, as ``points - odo``.
"""

from __future__ import annotations

import numpy as np
from numba import njit


@njit(cache=True)
def window_within(points, odo, radius2, values):  # pragma: no cover - compiled
    """The window's lattice points within the sensing radius of the robot.

    Args:
        points: (n, 2) the window's lattice points in the robot's odometry frame, units.
        odo: (2,) the robot's position in that frame, units.
        radius2: the squared sensing radius, units^2.
        values: (n,) int8, what is known of each point: 1 target, 0 not, -1 not yet probed.

    Returns:
        offsets: (k, 2) the points within the radius, from the robot, in window order;
        known: (k,) int8 their values; unknown: (u,) window indices of those not yet probed;
        unknown_at: (u,) their places among the k.
    """
    n = points.shape[0]
    offsets = np.empty((n, 2))
    known = np.empty(n, dtype=np.int8)
    unknown = np.empty(n, dtype=np.int64)
    unknown_at = np.empty(n, dtype=np.int64)
    k = u = 0
    for i in range(n):
        dx = points[i, 0] - odo[0]
        dy = points[i, 1] - odo[1]
        if dx * dx + dy * dy <= radius2:
            offsets[k, 0] = dx
            offsets[k, 1] = dy
            known[k] = values[i]
            if values[i] < 0:
                unknown[u] = i
                unknown_at[u] = k
                u += 1
            k += 1
    return offsets[:k], known[:k], unknown[:u], unknown_at[:u]


def warm_up() -> None:
    """Compile (first time on a machine) or load (from the cache) the kernel now."""
    window_within(np.zeros((1, 2)), np.zeros(2), 1.0, np.zeros(1, dtype=np.int8))
