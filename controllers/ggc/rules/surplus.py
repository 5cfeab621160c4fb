"""The surplus lap (our addition, GGCParams.surplus_stop; with groups, the SURPLUS flag).

A lap starts when a mover leaves hearing of its group's waiting robots and ends back beside
them; it counts if it went round the beacon (surplus_winding) and passed at most
surplus_frontier units of target floor with free target floor outward. Then there is no
place left that the mover can find: it stops for good (Surplus; Arrive on the target), and
so do its formation and the movers that hear it.

With groups a mover's formation may be gone, so a whole turn round the beacon without passing
free target floor counts as well (passing some starts the count again); a mover on the target
walled in by arrived robots (inside the structure's wide lattice) stops where it is; and a
mover off the target stops on hearing a Surplus robot of any group: the news that the target
is full spreads to every group.
"""

from __future__ import annotations

import math

from numba import njit

from ..statuses import ARRIVE, DETECTION, INITIAL, SURPLUS
from .common import (
    NO,
    group_status_heard,
    is_waiting,
    probe,
    set_status,
    status_heard,
    still,
    surrounded,
    turn_between,
)


@njit(cache=True)
def restart_lap(me, whole):  # pragma: no cover - compiled
    """Start a new lap; one begun by turning round is not whole (it comes home early)."""
    me.away = False
    me.frontier = 0.0
    me.lap_whole = whole
    me.winding = 0.0
    me.beacon_angle = math.nan


@njit(cache=True)
def track_winding(me, sense):  # pragma: no cover - compiled
    """Add up how far the bearing to the beacon has turned this lap (radians)."""
    if not sense.has_beacon:
        return
    angle = math.atan2(sense.beacon_y, sense.beacon_x)
    if not math.isnan(me.beacon_angle):
        me.winding += turn_between(me.beacon_angle, angle)
    me.beacon_angle = angle


@njit(cache=True)
def hears_surplus(view, me, P):  # pragma: no cover - compiled
    """A Surplus robot of my group within d_cover + arrive_tolerance."""
    return group_status_heard(view, me, SURPLUS, P.d_cover + P.arrive_tolerance)


@njit(cache=True)
def group_waiting_heard(view, me):  # pragma: no cover - compiled
    for r in range(len(view.dist)):
        if view.group[r] == me.group and is_waiting(view.status[r]):
            return True
    return False


@njit(cache=True)
def walled_in(view, P):  # pragma: no cover - compiled
    """Arrived robots within 1.2 d_cover on every side (three or more, no gap of half a turn):
    I am inside the structure, not on its edge."""
    return surrounded(view, 1.2 * P.d_cover, False, math.pi)


@njit(cache=True)
def is_surplus(view, me, nearest, sense, pb, P):  # pragma: no cover - compiled
    """Back beside my group's waiting robots after a lap that passed no free target floor, or
    at a Surplus robot of my group (see the module docstring)."""
    if not me.away:
        me.away = not group_waiting_heard(view, me)
    if sense.on_target and me.frontier <= P.surplus_frontier:
        d = max(view.dist[nearest], 1e-9)
        outward_x = -view.off[nearest, 0] / d * P.boundary_probe
        outward_y = -view.off[nearest, 1] / d * P.boundary_probe
        if probe(pb, outward_x, outward_y):
            me.frontier += math.hypot(sense.moved_x, sense.moved_y)
    if P.groups > 1:  # no formation to come home to: a whole turn without free floor
        if sense.on_target and walled_in(view, P):
            return True  # inside the full structure's lattice: no place is left here
        if me.frontier > P.surplus_frontier:
            restart_lap(me, True)
        elif me.lap_whole and abs(me.winding) >= 2.0 * math.pi:
            return True
    if P.surplus_spread and not sense.on_target and (
            status_heard(view, SURPLUS, math.inf) if P.groups > 1
            else group_status_heard(view, me, SURPLUS, math.inf)):
        return True
    if view.id[nearest] == NO or view.group[nearest] != me.group:
        return False
    status = view.status[nearest]
    if status == SURPLUS:
        return True
    if not (me.away and (status == INITIAL or status == DETECTION)):
        return False
    if view.dist[nearest] > P.d_cover + P.arrive_tolerance:
        return False
    went_round = (math.isnan(me.beacon_angle) or abs(me.winding) >= P.surplus_turn)
    if me.lap_whole and me.frontier <= P.surplus_frontier and went_round:
        return True
    restart_lap(me, True)  # free floor passed, or I turned round: go round again
    return False


@njit(cache=True)
def give_up(me, sense):  # pragma: no cover - compiled
    """No place left: stop for good (Arrive on the target, covering it; else Surplus)."""
    me.surplus += 1
    set_status(me, ARRIVE if sense.on_target else SURPLUS)
    return still()
