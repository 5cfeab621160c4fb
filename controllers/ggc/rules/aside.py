"""Formations that turn aside (flag ASIDE): a formation whose front meets another group's
robots slides along them instead of pushing its way through.

A robot in Initial that hears another group's robot ahead of its travel (within 60 degrees,
within 1.5 d_min: all a robot in Initial hears) says which side to turn to: away from that
robot. The word runs inward, from each robot to its gradient parent (one hop a tick), to the
leader, which heads at right angles to the beacon's bearing on that side for as long as some
robot of its formation says so, then toward the beacon again.

A formation that slides along another can shed a robot or two at its rim. Shed followers
that still hear each other take their gradients from each other, counting up for ever, and
copy each other's travel command: so a follower whose gradient has risen LOST_HOPS above the
lowest it held in Initial has lost its formation, and starts alone, as one that never heard
a gradient does after init_timeout. (A formation that only deforms raises a robot's
gradient by fewer hops: docs/reports/ggc-findings-journal.md, "Formations that turn aside".)
"""

from __future__ import annotations

from numba import njit

from ..statuses import INITIAL
from .common import NO, within
from .rulesets import ASIDE

LOST_HOPS = 64
"""Hops a follower's gradient may rise above its lowest before it counts as lost."""


@njit(cache=True)
def side_ahead(view, me, P):  # pragma: no cover - compiled
    """+1 (turn left) or -1 (turn right): the nearest robot of another group ahead of my
    travel lies on my other side; 0: none ahead, or I am not travelling."""
    tx, ty = me.travel_x, me.travel_y
    if tx == 0.0 and ty == 0.0:
        return 0
    for r in range(within(view.dist, 1.5 * P.d_min)):
        if view.group[r] == me.group or view.id[r] == NO:
            continue
        ox, oy = view.off[r, 0], view.off[r, 1]
        # ahead: the offset within 60 degrees of my travel
        if ox * tx + oy * ty >= 0.5 * view.dist[r] * (tx * tx + ty * ty) ** 0.5:
            return -1 if tx * oy - ty * ox > 0.0 else 1
    return 0


@njit(cache=True)
def heard_side(view, me, P):  # pragma: no cover - compiled
    """The side a robot of my group in Initial one hop farther from the leader says; 0:
    none says one."""
    for r in range(within(view.dist, 1.5 * P.d_min)):
        if (view.group[r] == me.group and view.gradient[r] == me.gradient + 1
                and view.status[r] == INITIAL and view.blocked[r] != 0):
            return view.blocked[r]
    return 0


@njit(cache=True)
def blocked_side(view, me, P):  # pragma: no cover - compiled
    """The side my formation should turn to now (0: none), mine or heard from farther out."""
    if not P.flags & ASIDE or P.groups == 1:
        return 0
    side = side_ahead(view, me, P)
    if side == 0:
        side = heard_side(view, me, P)
    return side


@njit(cache=True)
def turned(bx, by, side):  # pragma: no cover - compiled
    """The unit bearing (bx, by) turned a right angle: left for side +1, right for -1."""
    if side > 0:
        return -by, bx
    return by, -bx


@njit(cache=True)
def lost(me, grad, P):  # pragma: no cover - compiled
    """Has my formation gradient, now ``grad``, risen LOST_HOPS above the lowest I held?"""
    if not P.flags & ASIDE:
        return False
    me.gradient_low = min(me.gradient_low, grad)
    return grad > me.gradient_low + LOST_HOPS
