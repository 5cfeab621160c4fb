"""Trains (flag TRAINS): a formation releases its robots as trains, not one per d_cover.

Algorithm 7 lets a waiting robot leave only when no robot of its group within d_cover that
outranks it by (gradient, id) is waiting or moving, so the robots of one exit leave about
d_cover apart. Under TRAINS a waiting robot reads its neighbours of its group within d_cover
along its way out: the tangent of its formation's edge in its orbit sense (its outward
normal, away from its waiting neighbours within 1.5 d_min, turned a quarter turn in that
sense), the way its edge following will take it (Rubenstein et al.'s self-assembly queue: a
robot follows the one in front).

* A mover ahead of me along my way out (its offset along the tangent more than half the
  train gap) blocks me only while it is within the train gap (:data:`TRAIN_GAP` d_safe, at
  most d_cover): I leave as soon as the robot I will follow is that far ahead. A mover behind
  me or beside me (one that may walk into my way out) blocks me within d_cover, as in
  Algorithm 7. Every mover of my group counts, not only those that outrank me.
* A waiting robot that outranks me blocks me within d_cover (Algorithm 7), unless it is
  ahead of me along my way out by more than the train gap: then we may leave together, one
  behind the other, walking the same way. So a formation releases from more than one place
  at once only where the robots leave in line.

Enclosed robots, robots in Stop (with groups) and settled robots are not counted, as in
Algorithm 7; an enclosed robot still waits (rules/detection.py). A robot that has no
waiting neighbour within 1.5 d_min has no way out to read: every mover and every outranking
waiting robot within d_cover blocks it.
"""

from __future__ import annotations

import math

from numba import njit

from ..statuses import ARRIVE, STOP, SURPLUS
from .common import NO, is_waiting, within

TRAIN_GAP = 3.0
"""Gap (multiples of d_safe, at most d_cover) a robot of a train keeps behind the mover in
front when it leaves its formation."""


@njit(cache=True)
def train_gap(P):  # pragma: no cover - compiled
    """The train gap in units: TRAIN_GAP d_safe, at most d_cover."""
    return min(TRAIN_GAP * P.d_safe, P.d_cover)


@njit(cache=True)
def way_out(view, me, P):  # pragma: no cover - compiled
    """My way out of my formation, a unit vector (tx, ty): the edge's tangent in my orbit
    sense. (0, 0) when no waiting robot of my group is within 1.5 d_min (no edge to read)."""
    nx, ny = 0.0, 0.0
    for r in range(within(view.dist, 1.5 * P.d_min)):
        if view.group[r] == me.group and is_waiting(view.status[r]):
            nx -= view.off[r, 0]
            ny -= view.off[r, 1]
    norm = math.hypot(nx, ny)
    if norm <= 1e-9:
        return 0.0, 0.0
    nx, ny = nx / norm, ny / norm
    return -ny * me.sense, nx * me.sense


@njit(cache=True)
def counts(view, me, r, P):  # pragma: no cover - compiled
    """Does neighbour ``r`` count for my release: of my group, heard, neither settled nor
    enclosed, nor (with groups) in Stop (Algorithm 7's robots)?"""
    s = view.status[r]
    return not (view.group[r] != me.group or view.id[r] == NO or s == ARRIVE or s == SURPLUS
                or view.enclosed[r] or (P.groups > 1 and s == STOP))


@njit(cache=True)
def train_blockers(view, me, P):  # pragma: no cover - compiled
    """(by_waiting, by_mover): is my release held by a waiting robot, by a mover (see the
    module docstring)? Without a way out to read, Algorithm 7's answer."""
    tx, ty = way_out(view, me, P)
    known = tx != 0.0 or ty != 0.0
    gap = train_gap(P)
    by_mover = False
    for r in range(within(view.dist, P.d_cover)):
        if not counts(view, me, r, P):
            continue
        ahead = view.off[r, 0] * tx + view.off[r, 1] * ty
        if view.moving[r]:
            if not known or ahead <= 0.5 * gap or view.dist[r] < gap:
                by_mover = True
            continue
        g = view.gradient[r]
        outranks = g > me.gradient or (g == me.gradient and view.id[r] > me.id)
        if outranks and (not known or ahead <= gap):
            return True, by_mover
    return False, by_mover
