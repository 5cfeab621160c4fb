"""Which sleeping robots wake this tick, compiled (numba): the robots that drifted since they
were last looked at, and the sleepers within wake range of a robot that changed (found in a
grid of the sleepers, not in the whole swarm's neighbour search).

The same answers as the numpy code they replaced in sim.py, to the bit: the offsets are the
same differences, the distances the C library's ``hypot`` (which numpy's ``hypot`` calls too),
the comparisons the same. Why compiled: a tick on K did ~20 numpy calls here over 600 robots
and ~2,000 pairs, ~0.15 ms; one pass is a tenth of that.
"""

from __future__ import annotations

import math

import numpy as np
from numba import njit

from swarmsim.kernels.warmup import kernel_warm_up
from swarmsim.sensing.cellsearch import MAX_CELLS_PER_ROBOT, grid, grid_frame


@njit(cache=True, inline="always")
def hypot_at_most(dx, dy, limit):  # pragma: no cover - compiled
    """``math.hypot(dx, dy) <= limit``, to the bit, mostly without calling ``hypot``: the
    squared length decides wherever it is more than a relative 1e-9 from ``limit`` squared
    (its rounding error is ~1e-16), and ``hypot`` decides the rest (NaN, a negative or
    subnormal ``limit`` squared included)."""
    d2 = dx * dx + dy * dy
    square = limit * limit
    if limit >= 0 and square > 1e-300:  # a normal number: its rounding is relative
        if d2 < square * (1 - 1e-9):
            return True
        if d2 > square * (1 + 1e-9):
            return False
    return math.hypot(dx, dy) <= limit


@njit(cache=True)
def drifted(positions, ref, velocities, eps):  # pragma: no cover - compiled
    """(N,) drift: robots farther than ``eps`` units from ``ref`` (their position when last
    looked at), whose ``ref`` is then moved to where they are (in place); (N,) pushed: those
    of them that were not told to move (velocity zero)."""
    n = positions.shape[0]
    drift, pushed = np.zeros(n, dtype=np.bool_), np.zeros(n, dtype=np.bool_)
    for i in range(n):
        if not hypot_at_most(positions[i, 0] - ref[i, 0], positions[i, 1] - ref[i, 1], eps):
            drift[i] = True
            pushed[i] = velocities[i, 0] == 0 and velocities[i, 1] == 0
            ref[i, 0], ref[i, 1] = positions[i, 0], positions[i, 1]
    return drift, pushed


@njit(cache=True)
def wake_near(positions, asleep, wake_range, wake_on_motion, wakes_all, sources,
              margin):  # pragma: no cover - compiled
    """Wake (in ``asleep``, in place) each sleeper within its wake range plus ``margin`` units
    of a changed robot in ``sources`` (a source itself included), if it wakes on motion or
    that robot ``wakes_all`` (its broadcast changed, or it was pushed).

    The sleepers are sorted into a grid (cellsearch.grid) of cells no smaller than the widest
    wake range plus the margin, so each source looks at the 3 x 3 cells round it; the
    distance is the C library's ``hypot`` against ``wake_range[j] + margin``, as a pair list
    would compare it.
    """
    sleepers = np.flatnonzero(asleep)
    if len(sleepers) == 0 or len(sources) == 0:
        return
    at = positions[sleepers]
    reach = wake_range[sleepers].max() + margin
    x0, y0, cell, nx, ny = grid_frame(at, reach, MAX_CELLS_PER_ROBOT)
    members, _, _, starts, _, _, _ = grid(at, x0, y0, cell, nx, ny)
    for s in sources:
        fx, fy = (positions[s, 0] - x0) / cell, (positions[s, 1] - y0) / cell
        if fx < -1.0 or fy < -1.0 or fx >= nx + 1.0 or fy >= ny + 1.0:
            continue  # more than a cell beyond every sleeper
        cx, cy = math.floor(fx), math.floor(fy)  # an int in numba
        for gy in range(max(cy - 1, 0), min(cy + 1, ny - 1) + 1):
            for gx in range(max(cx - 1, 0), min(cx + 1, nx - 1) + 1):
                c = gy * nx + gx
                for m in range(starts[c], starts[c + 1]):
                    j = sleepers[members[m]]
                    if not asleep[j] or not (wake_on_motion[j] or wakes_all[s]):
                        continue
                    if hypot_at_most(positions[j, 0] - positions[s, 0],
                                     positions[j, 1] - positions[s, 1], wake_range[j] + margin):
                        asleep[j] = False


@njit(cache=True)
def awake_robots(asleep, failed, wake_tick, tick, positions, ref, velocities, eps,
                 changed_msg, wake_range, wake_on_motion, margin):  # pragma: no cover - compiled
    """Indices of the robots to decide this tick: the awake ones, plus the sleepers that
    wake now (``asleep`` is updated in place; failed robots are never listed).

    A sleeper wakes at its own ``wake_tick``; when it drifted more than ``eps`` units since it
    was last looked at (``ref``, moved on in place, see :func:`drifted`); and when it lies
    within its wake range plus ``margin`` of a robot that drifted or whose broadcast changed
    (``changed_msg``), see :func:`wake_near`. A robot that drifted without being told to move
    was pushed, which wakes even the sleepers that asked not to be woken by motion. With no
    sleeper, every ``ref`` is set to where its robot is.
    """
    n = positions.shape[0]
    any_sleeping = False
    for i in range(n):
        if asleep[i] and not failed[i]:
            any_sleeping = True
            if wake_tick[i] <= tick:
                asleep[i] = False
    if any_sleeping:
        drift, pushed = drifted(positions, ref, velocities, eps)
        sources = np.flatnonzero(drift | changed_msg)
        if len(sources):
            wake_near(positions, asleep, wake_range, wake_on_motion, changed_msg | pushed,
                      sources, margin)
            for i in range(n):
                if drift[i]:
                    asleep[i] = False
    else:  # ref[:, :] = positions, as a loop: numba's slice copy compiles a shape-error
        for i in range(n):  # message (its string code, ~5 s of the first run's build)
            ref[i, 0], ref[i, 1] = positions[i, 0], positions[i, 1]
    return np.flatnonzero(~asleep & ~failed)


@kernel_warm_up("wakes")
def warm_up() -> None:
    """Compile (first time on a machine) or load (from the cache) the kernels now."""
    one, flag = np.zeros((1, 2)), np.zeros(1, dtype=np.bool_)
    drifted(one, one.copy(), one, 1.0)
    wake_near(one, flag, np.ones(1), flag, flag, np.zeros(1, dtype=np.intp), 1.0)
    awake_robots(flag, flag, np.zeros(1, dtype=np.int64), 0, one, one.copy(), one, 1.0, flag,
                 np.ones(1), flag, 1.0)
