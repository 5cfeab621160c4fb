"""Contacts as rows, merged and tallied in compiled code (numba).

A tick's contacts are rows: ``robots`` (M, 2) the robot index of each side (-1: a wall),
``depth`` (M,) penetration (units, >= 0), ``impulse`` (M,) the last substep's impulse. Robots
asleep in pymunk have no live arbiters, so Physics keeps their last rows: :func:`carry_over`
merges the two. :func:`tally` gives the per-tick figures. Why compiled: ~40 numpy calls a tick
over a few hundred rows, ~0.1 ms on K and ~1 ms in a crowd of movers.
"""

from __future__ import annotations

import math

import numpy as np
from numba import njit

from swarmsim.kernels.warmup import kernel_warm_up
from swarmsim.physics.bodysleep import IdTable, lookup_ids


@njit(cache=True)
def from_batch(ids, floats, table, used, codes, shift, mask, probes):  # pragma: no cover
    """pymunk.batch's arbiter rows as contact rows: ``ids`` (2M,) uint64 the bodies of each
    arbiter, ``floats`` (3M,) its TOTAL_IMPULSE (x, y) and DISTANCE_1, then an IdTable's
    :attr:`arrays` (body id -> robot). Returns robots (M, 2) (-1: not a robot), depth (M,)
    (the penetration, -DISTANCE_1, at least 0) and impulse (M,) (its length, libm's hypot)."""
    m = len(ids) // 2
    robots = lookup_ids(ids, table, used, codes, shift, mask, probes).reshape(m, 2)
    depth, impulse = np.empty(m), np.empty(m)
    for row in range(m):
        d = -floats[3 * row + 2]
        depth[row] = d if (d > 0.0 or math.isnan(d)) else 0.0  # np.maximum(0, d)
        impulse[row] = math.hypot(floats[3 * row], floats[3 * row + 1])
    return robots, depth, impulse


@njit(cache=True)
def _flags(row, robots, asleep):  # pragma: no cover - compiled
    """(any real side asleep, every real side asleep and at least one real side)."""
    some, every, real = False, True, False
    for side in range(2):
        r = robots[row, side]
        if r >= 0:
            real = True
            if asleep[r]:
                some = True
            else:
                every = False
    return some, every and real


@njit(cache=True)
def carry_over(live_robots, live_depth, live_impulse, old_robots, old_depth, old_impulse,
               asleep):  # pragma: no cover - compiled
    """The live rows that touch no sleeping robot (a sleeper's live arbiters are stale), then
    the old rows whose robots all sleep (their contacts as they fell asleep)."""
    m = len(live_depth) + len(old_depth)
    robots = np.empty((m, 2), dtype=live_robots.dtype)
    depth, impulse = np.empty(m), np.empty(m)
    k = 0
    for row in range(len(live_depth)):
        if not _flags(row, live_robots, asleep)[0]:
            robots[k, 0], robots[k, 1] = live_robots[row, 0], live_robots[row, 1]
            depth[k], impulse[k] = live_depth[row], live_impulse[row]
            k += 1
    for row in range(len(old_depth)):
        if _flags(row, old_robots, asleep)[1]:
            robots[k, 0], robots[k, 1] = old_robots[row, 0], old_robots[row, 1]
            depth[k], impulse[k] = old_depth[row], old_impulse[row]
            k += 1
    return robots[:k].copy(), depth[:k].copy(), impulse[:k].copy()


@njit(cache=True)
def tally(robots, depth, n):  # pragma: no cover - compiled
    """(N,) bool robots touching anything, (N,) bool robots touching a wall (a row whose other
    side is not a robot: a wall or an obstacle), (M,) bool robot-robot rows with a
    penetration, and the deepest penetration of any row (units, 0.0 for none)."""
    in_contact = np.zeros(n, dtype=np.bool_)
    on_wall = np.zeros(n, dtype=np.bool_)
    pair = np.zeros(len(depth), dtype=np.bool_)
    deepest = 0.0
    for row in range(len(depth)):
        a, b = robots[row, 0], robots[row, 1]
        if a >= 0:
            in_contact[a] = True
            if b < 0:
                on_wall[a] = True
        if b >= 0:
            in_contact[b] = True
            if a < 0:
                on_wall[b] = True
        pair[row] = a >= 0 and b >= 0 and depth[row] > 0
        deepest = max(deepest, depth[row])
    return in_contact, on_wall, pair, deepest


@kernel_warm_up("contacts")
def warm_up() -> None:
    """Compile (first time on a machine) or load (from the cache) the kernels now."""
    robots, one, flag = np.zeros((1, 2), dtype=np.intp), np.zeros(1), np.zeros(1, np.bool_)
    carry_over(robots, one, one, robots, one, one, flag)
    tally(robots, one, 1)
    from_batch(np.full(2, 16, dtype=np.uint64), np.zeros(3), *IdTable([16], [0]).arrays)
