"""Which sleeping robots wake this tick, compiled (numba): the robots that drifted since they
were last looked at, and the sleepers within wake range of a robot that changed.

The same answers as the numpy code they replaced in sim.py, to the bit: the offsets are the
same differences, the distances the C library's ``hypot`` (which numpy's ``hypot`` calls too),
the comparisons the same. Why compiled: a tick on K did ~20 numpy calls here over 600 robots
and ~2,000 pairs, ~0.15 ms; one pass is a tenth of that.
"""

from __future__ import annotations

import math

import numpy as np
from numba import njit


@njit(cache=True)
def drifted(positions, ref, velocities, eps):  # pragma: no cover - compiled
    """(N,) drift: robots farther than ``eps`` units from ``ref`` (their position when last
    looked at), whose ``ref`` is then moved to where they are (in place); (N,) pushed: those
    of them that were not told to move (velocity zero)."""
    n = positions.shape[0]
    drift, pushed = np.zeros(n, dtype=np.bool_), np.zeros(n, dtype=np.bool_)
    for i in range(n):
        if math.hypot(positions[i, 0] - ref[i, 0], positions[i, 1] - ref[i, 1]) > eps:
            drift[i] = True
            pushed[i] = velocities[i, 0] == 0 and velocities[i, 1] == 0
            ref[i, 0], ref[i, 1] = positions[i, 0], positions[i, 1]
    return drift, pushed


@njit(cache=True)
def wake_pairs(positions, asleep, wake_range, wake_on_motion, wakes_all, sources, pair_source,
               near, margin):  # pragma: no cover - compiled
    """Wake (in ``asleep``, in place) each sleeper ``near[p]`` within its wake range plus
    ``margin`` units of the changed robot ``sources[pair_source[p]]``, if it wakes on motion
    or that robot ``wakes_all`` (its broadcast changed, or it was pushed)."""
    for p in range(len(near)):
        j, s = near[p], sources[pair_source[p]]
        if not asleep[j] or not (wake_on_motion[j] or wakes_all[s]):
            continue
        d = math.hypot(positions[j, 0] - positions[s, 0], positions[j, 1] - positions[s, 1])
        if d <= wake_range[j] + margin:
            asleep[j] = False


def warm_up() -> None:
    """Compile (first time on a machine) or load (from the cache) the kernels now."""
    one, flag = np.zeros((1, 2)), np.zeros(1, dtype=np.bool_)
    drifted(one, one.copy(), one, 1.0)
    ints = np.zeros(1, dtype=np.intp)
    wake_pairs(one, flag, np.ones(1), flag, flag, ints, ints, ints, 1.0)
