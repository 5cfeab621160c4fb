"""Dead ends and deadlocks (Section 4.4: Equation 3, Algorithms 5-6; our circling watch).

A mover whose displacement over T_r ticks is at most theta is stuck; one that has gone all
the way round the same robot is circling. Either way, on the target it arrives where it is
(with groups only when a robot in Stop is heard, Algorithm 5) or waits T_s ticks in Stop
(Algorithm 6); off the target it turns round, and one wedged against its own waiting
formation (with YIELD, or against another group's beside its own) waits in Detection again.
"""

from __future__ import annotations

import math

from numba import njit

from ..statuses import DETECTION, STOP
from .common import NO, group_status_heard, set_status, status_heard, still, turn_between
from .rulesets import YIELD


@njit(cache=True)
def stuck(me, sense, P):  # pragma: no cover - compiled
    """Equation 3: displacement <= theta over T_r ticks (sampled every T_r ticks). Keeps the
    books on deadlock episodes (one opens at a detection; progress or settling closes it)."""
    if sense.tick - me.progress_tick < P.T_r:
        return False
    moved = math.hypot(me.odo_x, me.odo_y)
    me.odo_x, me.odo_y = 0.0, 0.0
    me.progress_tick = sense.tick
    if moved <= P.theta:
        me.deadlocks += 1
        if not me.in_deadlock:
            me.episodes += 1
        me.in_deadlock = True
        return True
    me.in_deadlock = False
    return False


@njit(cache=True)
def circling(view, me, nearest):  # pragma: no cover - compiled
    """True once I have gone all the way round the same neighbour (row ``nearest``)."""
    sender = view.id[nearest]
    bearing = math.atan2(-view.off[nearest, 1], -view.off[nearest, 0])
    if sender != me.circ_id or sender == NO or math.isnan(me.last_bearing):
        me.circ_id, me.circled, me.last_bearing = sender, 0.0, bearing
        return False
    me.circled += turn_between(me.last_bearing, bearing)
    me.last_bearing = bearing
    return abs(me.circled) > 2 * math.pi


@njit(cache=True)
def may_arrive_when_stuck(view, P):  # pragma: no cover - compiled
    """May a stuck mover on the target stop here? Always with one group; with groups when a
    robot in Stop is heard (Algorithm 5, line 5)."""
    if P.groups == 1:
        return True
    for r in range(len(view.dist)):
        if view.status[r] == STOP:
            return True
    return False


@njit(cache=True)
def wedged(view, me, P):  # pragma: no cover - compiled
    """Pressed against waiting robots of my group: a Detection robot of my group closer than
    0.9 d_safe (bodies touching), or within 1.5 d_min with groups or while d_cover <=
    yield_release (see docs/reports/ggc-findings-journal.md). With YIELD, also pressed (within
    1.5 d_min) against another group's waiting robots while a waiting robot of my group is
    within d_cover: jammed there, I hold my own formation back (its robots wait for me)."""
    reach = 0.9 * P.d_safe
    if P.d_cover <= P.yield_release or P.groups > 1:
        reach = 1.5 * P.d_min
    if group_status_heard(view, me, DETECTION, reach):
        return True
    return (P.groups > 1 and P.flags & YIELD and status_heard(view, DETECTION, reach)
            and group_status_heard(view, me, DETECTION, P.d_cover))


@njit(cache=True)
def deadlock_stop(me, sense, P):  # pragma: no cover - compiled
    """Algorithm 6: wait T_s ticks in Stop, then resume."""
    set_status(me, STOP)
    me.resume_tick = sense.tick + P.T_s
    return still()
