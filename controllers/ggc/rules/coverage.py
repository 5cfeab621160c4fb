"""Coverage: follow the structure's edge and stop on a place (Algorithm 2).

A mover follows the edge of the stationary robots at d_cover from the nearest one (or the
valley between the nearest two), orbiting in its sense, takes its nearest stationary
neighbour's gradient plus one, and arrives by arrival.py's rules. Off the target it never
stops, except: boundary fill (step in across a strip the structure leaves uncovered: with
one group, or, with the rule set's HOLES flag, a mover that has walked HOLE_PATH), the surplus
lap, the inter-group rule (Stop) and giving way to a moving robot
with a larger id close ahead. With groups, other groups' waiting formations are not edges.
With the rule set's HOLES flag, a mover that has walked a while without finding a place goes
for a hole that arrived robots report instead (rules/holes.py). At small d_cover a mover
that went round an island off the target leaves it for the beacon (rules/island.py), and
under the SURPLUS flag a mover that stays within a small reach for long gives up
(rules/confined.py).
"""

from __future__ import annotations

import math

from numba import njit

from ..schema import NO_WAY_SLOTS
from ..statuses import ARRIVE, COVERAGE, DETECTION, STOP, SURPLUS
from .arrival import should_arrive
from .common import (
    NO,
    clip1,
    move,
    next_random,
    probe,
    scaled,
    set_status,
    still,
    waiting_near,
    within,
)
from .confined import confined
from .cross import cross
from .deadlock import circling, deadlock_stop, may_arrive_when_stuck, stuck, wedged
from .flow import FLOW_ARRIVE, FLOW_DRIVE, flow
from .gradient import follow_gradient
from .holes import HOLE_PATH, HOLE_REST, hole_heard, to_hole
from .intergroup import keeps_waiting, stops
from .island import leave_island, on_island_watch, restart_turn
from .rulesets import HOLES, THROUGH
from .surplus import give_up, is_surplus, restart_lap, track_winding


@njit(cache=True)
def edge_rows(view, me, P):  # pragma: no cover - compiled
    """My nearest two edge robots (rows, -1: none): stationary robots; with groups of my
    group, arrived, surplus or silent (not other groups' waiting formations)."""
    a, b = -1, -1
    for r in range(len(view.dist)):
        if view.moving[r]:
            continue
        s = view.status[r]
        if not (P.groups == 1 or view.group[r] == me.group or s == ARRIVE or s == SURPLUS
                or view.id[r] == NO):
            continue
        if a < 0:
            a = r
        else:
            b = r
            break
    return a, b


@njit(cache=True)
def edge_follow(ox, oy, d, sense, P):  # pragma: no cover - compiled
    """Rotate around the neighbour at (ox, oy), d away, keeping d_cover from it."""
    scale = max(d, 1e-9)
    rx, ry = ox / scale, oy / scale
    error = clip1((d - P.d_cover) * P.radial_gain)
    return scaled(ry * sense + error * rx, -rx * sense + error * ry, P.v)


@njit(cache=True)
def valley(view, me, a, b, P):  # pragma: no cover - compiled
    """Between two robots on opposite sides, both closer than d_cover: go along the valley,
    the way I was heading, centred between them. (ok, vx, vy); not ok: not a valley."""
    da, db = max(view.dist[a], 1e-9), max(view.dist[b], 1e-9)
    ax, ay = view.off[a, 0] / da, view.off[a, 1] / da
    bx, by = view.off[b, 0] / db, view.off[b, 1] / db
    if ax * bx + ay * by >= 0:
        return False, 0.0, 0.0
    ux, uy = scaled(ax - bx, ay - by, 1.0)
    along_x, along_y = uy, -ux
    hx, hy = me.head_x, me.head_y
    if hx == 0.0 and hy == 0.0:
        hx, hy = ay * me.sense, -ax * me.sense
    if along_x * hx + along_y * hy < 0:
        along_x, along_y = -along_x, -along_y
    half = 0.5 * clip1((da - db) * P.radial_gain)
    vx, vy = scaled(along_x + half * ux, along_y + half * uy, P.v)
    return True, vx, vy


@njit(cache=True)
def edge_velocity(view, me, a, b, P):  # pragma: no cover - compiled
    if b >= 0 and view.dist[b] < P.d_cover:
        ok, vx, vy = valley(view, me, a, b, P)
        if ok:
            return vx, vy
    return edge_follow(view.off[a, 0], view.off[a, 1], view.dist[a], me.sense, P)


@njit(cache=True)
def wander(view, me, sense, pb, P):  # pragma: no cover - compiled
    """No edge in range: head for the beacon (or keep going, or a random way); on the target,
    arrive where the probe ahead leaves it."""
    if sense.has_beacon and not sense.on_target:
        me.head_x, me.head_y = sense.beacon_x, sense.beacon_y
    if me.head_x == 0.0 and me.head_y == 0.0:
        angle = 2 * math.pi * next_random(me)
        me.head_x, me.head_y = math.cos(angle), math.sin(angle)
    if sense.on_target and not probe(pb, me.head_x * P.probe_distance,
                                     me.head_y * P.probe_distance):
        set_status(me, ARRIVE)
        return still()
    return move(me.head_x * P.v, me.head_y * P.v)


@njit(cache=True)
def no_way_in(me, sender):  # pragma: no cover - compiled
    for slot in range(NO_WAY_SLOTS):
        if me.no_way[slot] == sender:
            return True
    return False


@njit(cache=True)
def fills_boundary(me, P):  # pragma: no cover - compiled
    """Boundary fill applies: with one group, or with HOLES once I have walked HOLE_PATH (with
    groups an early step-in seals off a part of the target the structure has not reached;
    late, the structure has reached it)."""
    return P.boundary_fill or (P.flags & HOLES and me.path >= HOLE_PATH)


@njit(cache=True)
def target_inward(view, me, a, sense, pb, P):  # pragma: no cover - compiled
    """Boundary fill: off the target beside an arrived robot (that did not step in itself),
    with target floor toward it: the strip between structure and boundary is uncovered."""
    if sense.on_target or view.status[a] != ARRIVE or no_way_in(me, view.id[a]):
        return False
    if view.stepped[a] or view.dist[a] < P.d_cover - P.arrive_tolerance:
        return False
    d = max(view.dist[a], 1e-9)
    return probe(pb, view.off[a, 0] / d * P.boundary_probe,
                 view.off[a, 1] / d * P.boundary_probe)


@njit(cache=True)
def step_in(view, me, a, P):  # pragma: no cover - compiled
    """Move straight toward that robot until the floor sensor finds the target (arrival's
    rules stop me); give up on it within 2 d_safe."""
    if view.dist[a] <= 2 * P.d_safe:
        me.no_way[me.no_way_next % NO_WAY_SLOTS] = view.id[a]
        me.no_way_next += 1
        me.stepping = False
        return still()
    me.stepping = True
    d = max(view.dist[a], 1e-9)
    return move(view.off[a, 0] / d * P.v, view.off[a, 1] / d * P.v)


@njit(cache=True)
def give_way(view, me, vx, vy, P):  # pragma: no cover - compiled
    """Give way to the nearest moving robot with a larger id close ahead: back away from it
    when it is very close, else wait. Otherwise drive at (vx, vy)."""
    for r in range(within(view.dist, P.yield_distance)):
        if not (view.moving[r] and view.id[r] > me.id):
            continue
        ox, oy = view.off[r, 0], view.off[r, 1]
        if ox * vx + oy * vy > 0:
            if view.dist[r] < P.yield_distance * 0.75:
                ux, uy = scaled(ox, oy, 1.0)
                return move(-ux * P.v * 0.5, -uy * P.v * 0.5)
            return still()
    return move(vx, vy)


@njit(cache=True)
def coverage(view, me, sense, pb, P):  # pragma: no cover - compiled
    """One tick of Coverage (see the module docstring)."""
    me.path += math.hypot(sense.moved_x, sense.moved_y)
    if confined(view, me, sense, P):
        return give_up(me, sense)
    if P.flags & HOLES:
        found, hx, hy = hole_heard(view, me, sense, P)
        if found:
            return fill_hole(view, me, sense, pb, hx, hy, P)
    if P.flags & THROUGH:
        mode, vx, vy = flow(view, me, sense, pb, stuck(me, sense, P), P)
        if mode == FLOW_ARRIVE:
            set_status(me, ARRIVE)
            return still()
        if mode == FLOW_DRIVE:
            return flow_drive(view, me, sense, vx, vy, P)
    crossing, vx, vy = cross(view, me, sense, P)
    if crossing:
        return drive(view, me, sense, vx, vy, P)
    a, b = edge_rows(view, me, P)
    if a < 0:
        return wander(view, me, sense, pb, P)
    vx, vy = edge_velocity(view, me, a, b, P)
    leaving, lx, ly = leave_island(view, me, a, vx, vy, sense, P)
    if leaving and not stuck(me, sense, P):
        me.head_x, me.head_y = scaled(lx, ly, 1.0)
        return drive(view, me, sense, lx, ly, P)
    if leaving:
        restart_turn(me)  # pinned on the way out: back to the edge and its dead-end rules
    me.head_x, me.head_y = scaled(vx, vy, 1.0)
    if P.surplus_rule:
        track_winding(me, sense)
    if should_arrive(view, me, a, sense, pb, P):
        set_status(me, ARRIVE)
        return still()
    if P.surplus_rule and is_surplus(view, me, a, sense, pb, P):
        return give_up(me, sense)
    follow_gradient(view, me, a, P)
    if fills_boundary(me, P) and target_inward(view, me, a, sense, pb, P):
        return step_in(view, me, a, P)
    me.stepping = False
    full_circle = circling(view, me, a)
    if full_circle and on_island_watch(sense, P):  # round a lone robot: an island
        me.circled = 0.0
        full_circle = False
    if stuck(me, sense, P) or full_circle:
        return dead_end(view, me, sense, vx, vy, P)
    return drive(view, me, sense, vx, vy, P)


@njit(cache=True)
def flow_drive(view, me, sense, vx, vy, P):  # pragma: no cover - compiled
    """Walk the way the flow chose (rules/flow.py), keeping my gradient from the structure."""
    a, _ = edge_rows(view, me, P)
    if a >= 0:
        follow_gradient(view, me, a, P)
    me.head_x, me.head_y = scaled(vx, vy, 1.0)
    return drive(view, me, sense, vx, vy, P)


@njit(cache=True)
def dead_end(view, me, sense, vx, vy, P):  # pragma: no cover - compiled
    """Stuck, or all the way round one robot: on the target arrive where I am (Algorithm 5)
    or wait in Stop (Algorithm 6); off it turn round, and if wedged against waiting robots
    wait in Detection until they have gone, then leave the other way."""
    if sense.on_target and may_arrive_when_stuck(view, P):
        set_status(me, ARRIVE)
        return still()
    me.sense = -me.sense
    me.circled = 0.0
    restart_lap(me, False)
    restart_turn(me)
    if sense.on_target:
        return deadlock_stop(me, sense, P)
    if wedged(view, me, P):
        set_status(me, DETECTION)
        me.head_x, me.head_y = -me.head_x, -me.head_y
        me.yield_count = waiting_near(view, P)
        return still()
    return drive(view, me, sense, vx, vy, P)


@njit(cache=True)
def drive(view, me, sense, vx, vy, P):  # pragma: no cover - compiled
    """Stop for the inter-group rule, or else drive at (vx, vy), giving way."""
    if stops(view, me, sense, P):
        set_status(me, STOP)
        me.collision_stops += 1
        return still()
    return give_way(view, me, vx, vy, P)


@njit(cache=True)
def fill_hole(view, me, sense, pb, hx, hy, P):  # pragma: no cover - compiled
    """Go for a hole arrived robots report (rules/holes.py); stuck, rest from holes."""
    if stuck(me, sense, P):
        me.hole_rest = sense.tick + HOLE_REST
        return still()
    arrived, vx, vy = to_hole(view, me, sense, pb, hx, hy, P)
    if arrived:
        a, _ = edge_rows(view, me, P)
        if a >= 0:
            follow_gradient(view, me, a, P)
        return still()
    return drive(view, me, sense, vx, vy, P)


@njit(cache=True)
def stopped(view, me, sense, pb, P):  # pragma: no cover - compiled
    """Stop: wait out a deadlock (T_s) or the inter-group rule, then cover again. Waiting is
    not a lack of progress."""
    me.progress_tick = sense.tick
    me.odo_x, me.odo_y = 0.0, 0.0
    if sense.tick < me.resume_tick:
        if confined(view, me, sense, P):
            return give_up(me, sense)
        return still()
    if keeps_waiting(view, me, sense, P):
        return still()
    set_status(me, COVERAGE)
    return coverage(view, me, sense, pb, P)
