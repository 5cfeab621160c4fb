"""Leaving an island (our addition; only while d_cover <= yield_release).

A formation halts where its front touches the target, so its leader, and at small d_cover
the rest of the formation, may wait off the target, apart from the structure the other robots
build. Movers follow the edge of every stationary robot, so the last movers circled such an
island off the target for ever, and the movers around a waiting formation kept its robots
from leaving (Algorithm 7: a mover of a higher gradient within d_cover blocks them): K, one
group, d_cover 2 and 4.

A mover off the target whose heading has turned a whole turn since it last had target floor
under it has gone round an island (going round the structure, it passes target floor). Once
the island lies behind it, away from the beacon, it leaves for the beacon, and follows edges
again when it reaches target floor, meets a stationary robot ahead (toward the beacon)
within d_cover, or is pinned on the way (Equation 3). Going all the way round one robot
there is such a turn too: the mover keeps going round (it does not turn back, as elsewhere)
until it can leave.
"""

from __future__ import annotations

import math

from numba import njit

from .common import turn_between


@njit(cache=True)
def restart_turn(me):  # pragma: no cover - compiled
    """Count my heading's turn afresh (I had target floor under me, or turned round)."""
    me.turned = 0.0
    me.leaving = False


@njit(cache=True)
def on_island_watch(sense, P):  # pragma: no cover - compiled
    """Does the island rule watch me now (small d_cover, off the target, a beacon heard)?"""
    return P.d_cover <= P.yield_release and sense.has_beacon and not sense.on_target


@njit(cache=True)
def ahead(view, a, sense):  # pragma: no cover - compiled
    """Does edge robot ``a`` lie toward the beacon from me?"""
    return view.off[a, 0] * sense.beacon_x + view.off[a, 1] * sense.beacon_y > 0.0


@njit(cache=True)
def leave_island(view, me, a, vx, vy, sense, P):  # pragma: no cover - compiled
    """(leaving, vx, vy): head for the beacon at (vx, vy) rather than follow edge robot ``a``
    at the velocity given (see the module docstring)."""
    if not on_island_watch(sense, P):
        if sense.on_target:
            restart_turn(me)
        return False, vx, vy
    if me.leaving:
        if ahead(view, a, sense) and view.dist[a] < P.d_cover:
            restart_turn(me)  # new ground: follow its edge
            return False, vx, vy
        return True, sense.beacon_x * P.v, sense.beacon_y * P.v
    if me.head_x != 0.0 or me.head_y != 0.0:
        me.turned += turn_between(math.atan2(me.head_y, me.head_x), math.atan2(vy, vx))
    if abs(me.turned) >= 2.0 * math.pi and not ahead(view, a, sense):
        me.leaving = True
        return True, sense.beacon_x * P.v, sense.beacon_y * P.v
    return False, vx, vy
