"""The local map's queries, compiled (numba): which remembered lattice points lie within the
sensing radius and what is known of them (:func:`window_within`), and what is known at
arbitrary offsets (:func:`lattice_values`), each in one pass where numpy made ten calls (most
of a mean-shift or CVT robot's tick). Elementwise arithmetic only, so the same offsets and
lattice indices, to the bit, as the numpy formulas.
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


@njit(cache=True)
def lattice_values(odo, offsets, cell, origin, grid, radius2):  # pragma: no cover - compiled
    """What the map knows of the floor at arbitrary offsets: the nearest lattice point's value.

    Args:
        odo: (2,) the robot's position in its odometry frame, units.
        offsets: (n, 2) offsets from the robot, units.
        cell: the lattice spacing, units.
        origin: (2,) int, the lattice index of the window's first row and column.
        grid: (size, size) int8 window of values: 1 target, 0 not, -1 not yet probed.
        radius2: the squared sensing radius, units^2.

    Returns:
        values: (n,) int8 (0 outside the window); local: (n, 2) each point's window row and
        column; unknown: (u,) the offsets whose lattice point is not yet probed and lies
        within the sensing radius (to probe now); points: (u, 2) those lattice points'
        offsets from the robot, units.
    """
    n, size = offsets.shape[0], grid.shape[0]
    values = np.zeros(n, dtype=np.int8)
    local = np.empty((n, 2), dtype=np.int64)
    unknown = np.empty(n, dtype=np.int64)
    points = np.empty((n, 2))
    u = 0
    for k in range(n):
        ix = np.int64(np.floor((odo[0] + offsets[k, 0]) / cell + 0.5))
        iy = np.int64(np.floor((odo[1] + offsets[k, 1]) / cell + 0.5))
        row, col = ix - origin[0], iy - origin[1]
        local[k, 0], local[k, 1] = row, col
        if not (0 <= row < size and 0 <= col < size):
            continue
        values[k] = grid[row, col]
        if values[k] < 0:
            px = ix * cell - odo[0]
            py = iy * cell - odo[1]
            if px * px + py * py <= radius2:
                unknown[u] = k
                points[u, 0], points[u, 1] = px, py
                u += 1
    return values, local, unknown[:u], points[:u]


def warm_up() -> None:
    """Compile (first time on a machine) or load (from the cache) the kernel now."""
    window_within(np.zeros((1, 2)), np.zeros(2), 1.0, np.zeros(1, dtype=np.int8))
    lattice_values(np.zeros(2), np.zeros((1, 2)), 1.0, np.zeros(2, dtype=np.int64),
                   np.zeros((1, 1), dtype=np.int8), 1.0)
