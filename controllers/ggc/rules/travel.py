"""Initial: the formation travels to the target (paper Section 3, Figure 4a).

The leader heads for the beacon and broadcasts a travel command with its velocity; every
robot copies its gradient parent's command one tick later, so the formation moves rigidly.
When the formation's front touches the target the leader halts (Arrive) and the halt runs
back the same way; each robot then waits in Detection. Beyond the paper, with groups: the
flag ASIDE turns a formation aside along another group's robots it meets (rules/aside.py),
and BESIDE halts it there when they belong to a formation that reached the target.
"""

from __future__ import annotations

from numba import njit

from ..statuses import ARRIVE, CMD_HALT, CMD_NONE, CMD_TRAVEL, DETECTION
from .aside import blocked_side, lost, turned
from .common import INF, move, rest, set_status, still, within
from .gradient import formation_gradient, parent_row
from .rulesets import BESIDE, SOW
from .sow import passed_beacon, settle_sown, sow_touching, sows


@njit(cache=True)
def touching(view, me, sense, P):  # pragma: no cover - compiled
    """Has the formation's front touched the target (my floor sensor, or a formation
    neighbour of my group that says so; with BESIDE, or a halted robot, in Detection, of
    another group's formation that says so)?"""
    if sense.on_target:
        return True
    for r in range(within(view.dist, 1.5 * P.d_min)):
        if view.touch[r] and (view.group[r] == me.group or (
                P.flags & BESIDE and view.status[r] == DETECTION)):
            return True
    return False


@njit(cache=True)
def remember_route(me):  # pragma: no cover - compiled
    """Keep my formation's travel vector (it decides my group's orbit sense later)."""
    if me.cmd == CMD_TRAVEL and (me.travel_x != 0.0 or me.travel_y != 0.0):
        me.route_x, me.route_y, me.has_route = me.travel_x, me.travel_y, True


@njit(cache=True)
def halts(view, me, sense, pb, P):  # pragma: no cover - compiled
    """The leader's halt: the front touched the target (under SOW: rules/sow.py's signal, or
    the beacon passed), or there is no beacon."""
    if not sense.has_beacon:
        return True
    if P.flags & SOW:
        return sow_touching(view, me, sense, pb, P) or passed_beacon(me, sense)
    return touching(view, me, sense, P)


@njit(cache=True)
def lead(view, me, sense, pb, P):  # pragma: no cover - compiled
    """The leader: toward the beacon until the front touches the target, then halt."""
    if halts(view, me, sense, pb, P):
        me.cmd = CMD_HALT
        me.travel_x, me.travel_y = 0.0, 0.0
        me.blocked = 0
        set_status(me, ARRIVE)
        return still()
    me.cmd = CMD_TRAVEL
    bx, by = sense.beacon_x, sense.beacon_y
    me.travel_x, me.travel_y = bx * P.v, by * P.v  # "ahead" is toward the beacon
    me.blocked = blocked_side(view, me, P)
    if me.blocked != 0:
        bx, by = turned(bx, by, me.blocked)
        me.travel_x, me.travel_y = bx * P.v, by * P.v
    remember_route(me)
    return move(me.travel_x, me.travel_y)


@njit(cache=True)
def initial(view, me, sense, pb, P):  # pragma: no cover - compiled
    """Travel with the formation: copy my gradient parent's command (under SOW, settle on
    the target where the formation leaves me behind: rules/sow.py)."""
    if me.leader:
        return lead(view, me, sense, pb, P)
    if P.flags & SOW and sows(view, me, sense, P):
        settle_sown(me)
        set_status(me, ARRIVE)
        return still()
    reach = 1.5 * P.d_min
    grad = formation_gradient(view, me, reach)
    if grad < 0:  # nobody to follow (yet): wait, and after init_timeout start alone
        if sense.tick - me.initial_since >= P.init_timeout:
            set_status(me, DETECTION)
        return rest(reach, True, me.initial_since + P.init_timeout)
    if lost(me, grad, P):  # start alone, as one that heard no gradient does
        set_status(me, DETECTION)
        me.gradient, me.cmd, me.travel_x, me.travel_y, me.blocked = INF, CMD_NONE, 0.0, 0.0, 0
        return still()
    me.gradient = grad
    if P.flags & SOW:
        me.touch = sow_touching(view, me, sense, pb, P)
    else:
        me.touch = touching(view, me, sense, P)
    parent = parent_row(view, me, reach)
    me.cmd = view.cmd[parent]
    me.travel_x, me.travel_y = float(view.travel_x[parent]), float(view.travel_y[parent])
    remember_route(me)
    me.blocked = blocked_side(view, me, P) if me.cmd == CMD_TRAVEL else 0
    if me.cmd == CMD_HALT:
        me.travel_x, me.travel_y = 0.0, 0.0
        set_status(me, DETECTION)
        return still()
    if me.cmd == CMD_TRAVEL:
        return move(me.travel_x, me.travel_y)
    return still()
