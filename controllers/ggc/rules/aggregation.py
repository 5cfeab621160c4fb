"""The scattered start (paper Sections 4.1-4.2): leaders, groups, aggregation, departure.

Every robot has a clock, so the phases follow from the tick (T = T_settle):

* Ticks [0, (h_max + 1) T): leader selection (Algorithm 3, Equation 2). Each leader is the
  source of a distance field: every robot keeps, per group, the shortest known path length
  to that group's leader (Bellman-Ford over the neighbours it hears, newest epoch first; the
  leader bumps its epoch every T ticks). Every T ticks a leader with hop budget h > 0 hands
  over to the neighbour within handover_reach whose summed field distance to the other
  leaders is largest, if larger than its own, with budget h - 1.
* Then grouping (Algorithm 4): a robot without a group joins its nearest grouped neighbour's.
* Aggregation (Figure 7): Approach down my group's field toward the leader; Pend while a
  robot of my group nearer the leader is close ahead; Join: circle the formation at d_min
  until two formed robots are at d_min, then Formed.
* Departure: formed robots relay a quiet count; once the leader's reaches T_quiet it leads
  the formation to the target (Initial) and the formed robots follow as the wave reaches
  them. A robot not formed aggregation_timeout ticks after leader selection covers alone.
"""

from __future__ import annotations

import math

import numpy as np
from numba import njit

from ..schema import FAR
from ..statuses import APPROACH, DETECTION, FORMED, INITIAL, JOIN, PEND
from .common import NO, clip1, move, rest, scaled, set_status, still, within
from .detection import detection
from .travel import initial

QUIET_CAP = 10_000


@njit(cache=True)
def gathering(status):  # pragma: no cover - compiled
    return status == APPROACH or status == PEND or status == JOIN


@njit(cache=True)
def update_fields(view, me, mine, sense, P):  # pragma: no cover - compiled
    """One Bellman-Ford step of every leader's distance field (newest epoch wins)."""
    source = me.leader and me.handover == NO  # handing over: no longer a source
    own_group = me.group - 1
    if source:
        if sense.tick % P.T_settle == 0:
            mine.lepoch[own_group] += 1  # refresh: the field follows the leader's moves
        mine.ldist[own_group] = 0.0
    heard = False
    for r in range(len(view.dist)):
        heard |= view.id[r] != NO
    if not heard:
        return
    # per group: the newest epoch heard, and the shortest path through a neighbour that
    # broadcast it; neighbour by neighbour (each one's entries lie side by side in its row)
    newest = np.full(P.groups, -1, dtype=np.int64)
    best = np.full(P.groups, FAR)
    for r in range(len(view.dist)):
        if view.id[r] == NO:
            continue
        for g in range(P.groups):
            epoch = view.lepoch[r, g]
            if epoch > newest[g]:
                newest[g], best[g] = epoch, FAR
            if epoch == newest[g]:
                best[g] = min(best[g], float(view.ldist[r, g]) + view.dist[r])
    for g in range(P.groups):
        newer = newest[g] > mine.lepoch[g]
        fresh = best[g] if newer else min(mine.ldist[g], best[g])
        if source and g == own_group:
            fresh, newer = 0.0, False
        mine.ldist[g] = min(fresh, FAR)
        if newer:
            mine.lepoch[g] = newest[g]


@njit(cache=True)
def take_over(view, me, mine):  # pragma: no cover - compiled
    """A leader handed over to me: I lead its group (and seed its formation)."""
    for r in range(len(view.dist)):
        if view.handover[r] == me.id and view.id[r] != NO:
            me.leader, me.group, me.h = True, view.group[r], view.h[r]
            set_status(me, FORMED)
            k = me.group - 1
            mine.lepoch[k] = view.lepoch[r, k] + 1
            mine.ldist[k] = 0.0
            return


@njit(cache=True)
def settle_handover(view, me, sense):  # pragma: no cover - compiled
    """Two ticks after handing over, step down if my successor leads my group now (else two
    leaders picked the same robot and it took the other group: I stay)."""
    if sense.tick < me.handover_tick + 2:
        return
    for r in range(len(view.dist)):
        if view.id[r] == me.handover and view.leader[r] and view.group[r] == me.group:
            me.leader, me.group, me.handover = False, 0, NO
            set_status(me, APPROACH)
            return
    me.handover = NO


@njit(cache=True)
def hand_over(view, me, mine, sense, P):  # pragma: no cover - compiled
    """Equation 2: hand over to the neighbour farther from the other leaders, if any."""
    mine_group = me.group - 1
    spread = 0.0
    for g in range(P.groups):
        if g != mine_group:
            spread += mine.ldist[g]
    me.h -= 1
    if P.groups == 1 or spread >= FAR:
        return
    best, best_score = -1, -1.0
    for r in range(len(view.dist)):
        if (view.id[r] == NO or view.leader[r] or view.handover[r] != NO
                or view.dist[r] > P.handover_reach):
            continue
        score = 0.0
        for g in range(P.groups):
            if g != mine_group:
                score += float(view.ldist[r, g])
        if score > best_score:
            best, best_score = r, score
    if best >= 0 and spread < best_score < FAR:
        me.handover = view.id[best]
        me.handover_tick = sense.tick


@njit(cache=True)
def select_leaders(view, me, mine, sense, P):  # pragma: no cover - compiled
    """Algorithm 3, one tick."""
    update_fields(view, me, mine, sense, P)
    if not me.leader:
        take_over(view, me, mine)
    elif me.handover != NO:
        settle_handover(view, me, sense)
    elif me.h > 0 and sense.tick % P.T_settle == P.T_settle - 1:
        hand_over(view, me, mine, sense, P)
    return still()


@njit(cache=True)
def own(view, me, r, status):  # pragma: no cover - compiled
    return view.group[r] == me.group and view.status[r] == status and view.id[r] != NO


@njit(cache=True)
def must_pend(view, me, mine, vx, vy, P):  # pragma: no cover - compiled
    """A gathering robot of my group nearer the leader (by the field: a strict order) close
    ahead of my way (vx, vy)."""
    k = me.group - 1
    for r in range(within(view.dist, 1.2 * P.d_min)):
        if (view.group[r] == me.group and gathering(view.status[r])
                and view.ldist[r, k] < mine.ldist[k]
                and view.off[r, 0] * vx + view.off[r, 1] * vy > 0.5 * P.v * view.dist[r]):
            return True
    return False


@njit(cache=True)
def toward_leader(view, me, mine, P):  # pragma: no cover - compiled
    """Down my group's field: straight at the leader when heard, else toward the neighbour
    with the shortest path to it. (ok, vx, vy)."""
    k = me.group - 1
    for r in range(len(view.dist)):
        if view.id[r] != NO and view.leader[r] and view.group[r] == me.group:
            vx, vy = scaled(view.off[r, 0], view.off[r, 1], P.v)
            return True, vx, vy
    best, via = -1, math.inf
    for r in range(len(view.dist)):
        if view.id[r] != NO:
            d = float(view.ldist[r, k]) + view.dist[r]
            if d < via:
                best, via = r, d
    if best < 0 or via >= FAR:
        return False, 0.0, 0.0
    vx, vy = scaled(view.off[best, 0], view.off[best, 1], P.v)
    return True, vx, vy


@njit(cache=True)
def join(view, me, mine, nearest, P):  # pragma: no cover - compiled
    """Circle the formation at d_min until two formed robots are at d_min: Formed."""
    formed = close = 0
    for r in range(len(view.dist)):
        if own(view, me, r, FORMED) or own(view, me, r, INITIAL):
            formed += 1
            if view.dist[r] <= P.d_min + P.join_tolerance:
                close += 1
    if close >= min(2, formed):
        set_status(me, FORMED)
        return still()
    set_status(me, JOIN)
    d = max(view.dist[nearest], 1e-9)
    rx, ry = view.off[nearest, 0] / d, view.off[nearest, 1] / d
    error = clip1((view.dist[nearest] - P.d_min) * 4.0)
    vx, vy = scaled(ry * me.sense + error * rx, -rx * me.sense + error * ry, P.v)
    if must_pend(view, me, mine, vx, vy, P):
        return still()
    return move(vx, vy)


@njit(cache=True)
def approach(view, me, mine, sense, P):  # pragma: no cover - compiled
    formed = -1
    for r in range(len(view.dist)):
        if own(view, me, r, FORMED) or own(view, me, r, INITIAL):
            formed = r
            break
    if formed >= 0 and view.dist[formed] <= 1.5 * P.d_min:
        return join(view, me, mine, formed, P)
    ok, vx, vy = toward_leader(view, me, mine, P)
    if not ok or must_pend(view, me, mine, vx, vy, P):
        set_status(me, PEND)
        if not ok:  # no way down the field yet: any neighbour's broadcast may give one
            return rest(math.nan, True, P.gather_deadline)
        return still()
    far = formed < 0 or view.dist[formed] > 3 * P.d_min
    set_status(me, APPROACH if far else JOIN)
    return move(vx, vy)


@njit(cache=True)
def formed(view, me, sense, pb, P):  # pragma: no cover - compiled
    """In the formation: relay the quiet count; depart when the leader's count is full."""
    still_gathering = False
    below = me.quiet
    near_initial = False
    for r in range(len(view.dist)):
        if view.group[r] != me.group or view.id[r] == NO:
            continue
        s = view.status[r]
        if gathering(s):
            still_gathering = True
        elif s == me.status:
            below = min(below, view.quiet[r])
        elif s == INITIAL and view.dist[r] <= 1.5 * P.d_min:
            near_initial = True
    me.quiet = 0 if still_gathering else min(QUIET_CAP, below + 1)
    if (me.leader and me.quiet >= P.T_quiet) or near_initial:
        set_status(me, INITIAL)
        me.initial_since = sense.tick
        if me.leader:
            me.gradient = 0
        return initial(view, me, sense, pb, P)
    return still()


@njit(cache=True)
def gather(view, me, mine, sense, pb, P):  # pragma: no cover - compiled
    """Approach / Pend / Join / Formed, then departure (see the module docstring)."""
    update_fields(view, me, mine, sense, P)
    if sense.tick >= P.gather_deadline and gathering(me.status):
        set_status(me, DETECTION)  # not formed in time: cover on my own
        return detection(view, me, sense, pb, P)
    if me.group == 0:  # Algorithm 4: join the nearest grouped neighbour's group
        for r in range(len(view.dist)):
            if view.group[r] > 0 and view.id[r] != NO:
                me.group = view.group[r]
                break
        return still()
    if me.status == FORMED:
        return formed(view, me, sense, pb, P)
    return approach(view, me, mine, sense, P)
