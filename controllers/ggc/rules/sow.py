"""Sowing (flag SOW): a formation walks into the target and leaves robots behind as it goes.

Without it a formation halts where its front first touches the target and releases its
robots one exit at a time (Algorithm 7), so every robot leaves by one lane round the
formation. Under SOW the formation keeps travelling toward the beacon across the target, and
its rear drops robots on the target at about d_cover apart, several across its width at
once, none of them enclosed or waiting for a turn:

* **Sowing.** A robot in Initial, travelling, on the target (its floor sensor), that is the
  rearmost robot of its formation within d_cover (no robot of its group in Initial within
  d_cover lies farther back along its travel vector by more than :data:`LEVEL` units; among
  those level with it, it has the largest id) and has no settled robot (any group) within
  d_cover - arrive_tolerance, settles where it is (Arrive, keeping its formation gradient).
  The order (how far back, id) is the same seen from either robot, so two robots within
  d_cover of each other never sow on the same tick.
* **Halting.** The formation halts (the leader's halt command runs back as in the paper)
  when a robot of it on the target finds the floor :attr:`probe_distance` ahead along its
  travel vector off the target (the front reached the target's far edge), when a robot of
  it is within 1.5 d_min of another group's settled or waiting robot (the front met another
  group's structure or formation), or when the leader has passed the beacon (its bearing
  turned more than a quarter turn from its route). It then releases the robots it still
  holds by Algorithm 7, as without SOW.

It uses the floor sensor and probe, neighbours' relative positions and broadcasts (status,
group, id), and the beacon bearing. A robot in Initial listens to d_cover under SOW
(decide.listen_range) to hear the settled robots near it.
"""

from __future__ import annotations

import math

from numba import njit

from ..statuses import ARRIVE, CMD_NONE, CMD_TRAVEL, DETECTION, INITIAL, SURPLUS
from .common import probe, within

LEVEL = 0.25
"""Two robots of a formation whose offsets along the travel vector differ by at most this
(units) are level: the larger id is the rearmost."""


@njit(cache=True)
def travel_unit(me):  # pragma: no cover - compiled
    """My travel vector as a unit vector, (0, 0) when I am not travelling."""
    norm = math.hypot(me.travel_x, me.travel_y)
    if norm <= 1e-12:
        return 0.0, 0.0
    return me.travel_x / norm, me.travel_y / norm


@njit(cache=True)
def rearmost(view, me, ux, uy, P):  # pragma: no cover - compiled
    """Am I the rearmost robot of my formation within d_cover, travelling along the unit
    vector (ux, uy) (see the module docstring)?"""
    for r in range(within(view.dist, P.d_cover)):
        if view.group[r] != me.group or view.status[r] != INITIAL:
            continue
        along = view.off[r, 0] * ux + view.off[r, 1] * uy
        if along < -LEVEL or (along <= LEVEL and view.id[r] > me.id):
            return False
    return True


@njit(cache=True)
def room(view, P):  # pragma: no cover - compiled
    """No settled robot (any group) within d_cover - arrive_tolerance."""
    for r in range(within(view.dist, P.d_cover - P.arrive_tolerance)):
        s = view.status[r]
        if s == ARRIVE or s == SURPLUS:
            return False
    return True


@njit(cache=True)
def sows(view, me, sense, P):  # pragma: no cover - compiled
    """Do I settle here, left behind by my travelling formation (see the module docstring)?
    The caller makes me Arrive."""
    if me.leader or me.cmd != CMD_TRAVEL or not sense.on_target:
        return False
    tx, ty = travel_unit(me)
    if tx == 0.0 and ty == 0.0:
        return False
    return rearmost(view, me, tx, ty, P) and room(view, P)


@njit(cache=True)
def settle_sown(me):  # pragma: no cover - compiled
    """Leave my formation where I stand: no command to pass on, no touch to report."""
    me.cmd = CMD_NONE
    me.travel_x, me.travel_y = 0.0, 0.0
    me.touch = False


@njit(cache=True)
def front_out(me, sense, pb, P):  # pragma: no cover - compiled
    """On the target, with the floor probe_distance ahead along my travel vector off it."""
    if not sense.on_target:
        return False
    tx, ty = travel_unit(me)
    if tx == 0.0 and ty == 0.0:
        return False
    return not probe(pb, tx * P.probe_distance, ty * P.probe_distance)


@njit(cache=True)
def sow_touching(view, me, sense, pb, P):  # pragma: no cover - compiled
    """SOW's halt signal (replaces travel.touching): my front reached the target's far edge,
    or met another group's settled or waiting robot, or a robot of my formation (in Initial
    or Detection) says so."""
    for r in range(within(view.dist, 1.5 * P.d_min)):
        s = view.status[r]
        if view.group[r] == me.group:
            if view.touch[r] and (s == INITIAL or s == DETECTION):
                return True
        elif s == ARRIVE or s == SURPLUS or s == DETECTION:
            return True
    return front_out(me, sense, pb, P)


@njit(cache=True)
def passed_beacon(me, sense):  # pragma: no cover - compiled
    """The leader has passed the beacon: its bearing is more than a quarter turn from the
    route it travelled."""
    return me.has_route and sense.beacon_x * me.route_x + sense.beacon_y * me.route_y < 0.0
