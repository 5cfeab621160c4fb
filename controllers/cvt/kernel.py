"""CVT's cell ownership, compiled (numba): which sample points are no nearer to any
neighbour than to the robot (:func:`owned`). One pass with an early exit, where numpy built the
whole point-by-neighbour table of squared distances (most of a CVT robot's tick). The same
products and sums as the numpy formula, so the same answer to the bit.
"""

from __future__ import annotations

import numpy as np
from numba import njit


@njit(cache=True)
def owned(points, others):  # pragma: no cover - compiled
    """(k,) bool: whether each of ``points`` (k, 2, from the robot, units) is at least as near
    the robot as every one of ``others`` (m, 2, the neighbours' offsets, units; m may be 0).

    A point on the bisector (equally near) belongs to the robot, as in
    ``(q * q).sum(1) <= ((q[:, None] - others) ** 2).sum(2).min(1)``.
    """
    k = points.shape[0]
    m = others.shape[0]
    mine = np.ones(k, dtype=np.bool_)
    for i in range(k):
        x = points[i, 0]
        y = points[i, 1]
        own = x * x + y * y
        for j in range(m):
            dx = x - others[j, 0]
            dy = y - others[j, 1]
            if own > dx * dx + dy * dy:
                mine[i] = False
                break
    return mine


def warm_up() -> None:
    """Compile (first time on a machine) or load (from the cache) the kernel now."""
    owned(np.zeros((1, 2)), np.ones((1, 2)))
