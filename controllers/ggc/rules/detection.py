"""Detection: a waiting robot's gradient and its turn to leave (Algorithms 1 and 7).

A robot of a formation that has reached the target takes 1 + the smallest gradient of its
group's stationary neighbours within 1.5 d_min and starts to cover when no neighbour of its
group within d_cover outranks it by (gradient, id) (Algorithm 7). A robot inside its
formation (enclosed) or pressed against it (``yield_count``) lets the others go first. With a
drive that must turn and cannot back up (P.face_to_leave), the robot next in line, waiting
only for movers to clear, turns toward its way out meanwhile (:func:`face_way_out`), so that
it sets off when its turn comes instead of turning round first. Under the rule set's TRAINS
flag a robot goes once the mover ahead on its way out is a train gap away (rules/trains.py).
"""

from __future__ import annotations

import math

import numpy as np
from numba import njit

from ..statuses import ARRIVE, COVERAGE, STOP, SURPLUS
from .common import (
    ENCLOSED_GAP,
    NO,
    is_waiting,
    move,
    rest,
    set_status,
    still,
    surrounded,
    waiting_near,
    widest_gap,
    within,
)
from .coverage import coverage, edge_rows, edge_velocity
from .gradient import formation_gradient
from .island import restart_turn
from .rulesets import TRAINS
from .surplus import hears_surplus, restart_lap
from .trains import train_blockers

NOT_BLOCKED, BY_WAITING, BY_MOVER = 0, 1, 2


@njit(cache=True)
def blocked(view, me, P):  # pragma: no cover - compiled
    """Algorithm 7: does a robot of my group within d_cover, neither settled nor enclosed
    (nor, with groups, in Stop), outrank me by (gradient, id)? BY_WAITING if a waiting one
    does, BY_MOVER if only moving ones do, else NOT_BLOCKED. Under TRAINS, rules/trains.py
    decides (the robot in front a train gap ahead is enough)."""
    if P.flags & TRAINS:
        choose_orbit(me, P)  # my way out follows my orbit sense
        by_waiting, by_mover = train_blockers(view, me, P)
        if by_waiting:
            return BY_WAITING
        return BY_MOVER if by_mover else NOT_BLOCKED
    by_mover = False
    for r in range(within(view.dist, P.d_cover)):
        s = view.status[r]
        if (view.group[r] != me.group or view.id[r] == NO or s == ARRIVE or s == SURPLUS
                or view.enclosed[r] or (P.groups > 1 and s == STOP)):
            continue
        g = view.gradient[r]
        if g > me.gradient or (g == me.gradient and view.id[r] > me.id):
            if not view.moving[r]:
                return BY_WAITING
            by_mover = True
    return BY_MOVER if by_mover else NOT_BLOCKED


@njit(cache=True)
def is_enclosed(view, P):  # pragma: no cover - compiled
    """Three or more waiting neighbours within 1.5 d_min that leave no gap wider than
    ENCLOSED_GAP: I am inside a formation and cannot leave before the robots around me."""
    return surrounded(view, 1.5 * P.d_min, True, ENCLOSED_GAP)


@njit(cache=True)
def nobody_to_yield_to(view, P):  # pragma: no cover - compiled
    """Every waiting neighbour within 1.5 d_min is enclosed (yielding itself) and I am on the
    formation's outside (the stationary robots around me leave a gap wider than
    ENCLOSED_GAP): then yielding would never end."""
    k = within(view.dist, 1.5 * P.d_min)
    waiting = 0
    for r in range(k):
        if is_waiting(view.status[r]):
            waiting += 1
            if not view.enclosed[r]:
                return False
    if waiting == 0:
        return False
    angles = np.empty(max(k, 1))
    n = 0
    for r in range(k):
        if not view.moving[r]:
            angles[n] = math.atan2(view.off[r, 1], view.off[r, 0])
            n += 1
    return n < 3 or widest_gap(angles, n) >= ENCLOSED_GAP


@njit(cache=True)
def choose_orbit(me, P):  # pragma: no cover - compiled
    """With groups, my group's orbit sense, once, as I first leave: a formation that
    travelled (dx, dy) with dx * dy > 0 orbits -orbit, the others orbit."""
    if me.orbit_chosen or P.groups == 1:
        return
    me.orbit_chosen = True
    if me.has_route:
        me.sense = -P.orbit if me.route_x * me.route_y > 0 else P.orbit


FACE_CRAWL = 1e-3
"""While it faces its way out a waiting robot wishes this share of that way's velocity: the
drive turns it and it barely moves (a zero wish would stop the drive)."""


@njit(cache=True)
def face_way_out(view, me, P):  # pragma: no cover - compiled
    """Next to leave, with a drive that must turn round: wish, barely, the way I will take first
    when my turn comes (following my nearest edge robots, in my orbit sense), so that the
    drive turns me toward it now. No edge robot in range: rest as a holonomic robot does."""
    choose_orbit(me, P)
    a, b = edge_rows(view, me, P)
    if a < 0:
        return rest(P.d_cover, True, -1)
    vx, vy = edge_velocity(view, me, a, b, P)
    return move(vx * FACE_CRAWL, vy * FACE_CRAWL)


@njit(cache=True)
def start_coverage(me, sense, P):  # pragma: no cover - compiled
    choose_orbit(me, P)
    restart_lap(me, True)
    restart_turn(me)
    set_status(me, COVERAGE)
    me.no_gradient = False  # I take my gradient from the structure I follow from now on
    me.odo_x, me.odo_y = 0.0, 0.0
    me.path = 0.0
    me.flow_rest, me.ban_next = 0.0, 0
    me.progress_tick = sense.tick


@njit(cache=True)
def detection(view, me, sense, pb, P):  # pragma: no cover - compiled
    """One tick of Detection (see the module docstring)."""
    if P.surplus_rule and hears_surplus(view, me, P):
        set_status(me, SURPLUS)  # my group's structure is full: stay where I am
        return rest(0.0, True, -1)
    grad = formation_gradient(view, me, 1.5 * P.d_min)
    if grad >= 0 and not me.no_gradient:  # a lost gradient stays lost (gradient.py)
        me.gradient = grad
    blocker = blocked(view, me, P)
    if me.yield_count and waiting_near(view, P) < me.yield_count:
        me.yield_count = 0  # a robot around me has left: try again
    elif me.yield_count and P.d_cover <= P.yield_release and nobody_to_yield_to(view, P):
        me.yield_count = 0  # everyone around me yields too: take turns again
        me.enclosed = is_enclosed(view, P)
        return still()  # broadcast it first, so that the (gradient, id) order decides
    me.enclosed = me.yield_count != 0 or is_enclosed(view, P)
    if blocker == NOT_BLOCKED and me.enclosed:  # my turn, but no way out
        return rest(1.5 * P.d_min, True, -1)
    if blocker == BY_MOVER and P.face_to_leave:  # next to leave: face the way out meanwhile
        return face_way_out(view, me, P)
    if blocker != NOT_BLOCKED:  # only a changed broadcast (or a mover) can lift it
        return rest(P.d_cover, blocker == BY_MOVER, -1)
    start_coverage(me, sense, P)
    return coverage(view, me, sense, pb, P)
