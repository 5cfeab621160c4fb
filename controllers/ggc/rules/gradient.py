"""Gradients: Algorithm 1 (a waiting robot's hop count from its formation) and Algorithm 2,
line 8 (a mover's, from the structure it follows); and the failure that loses one (paper
Section 5: a robot that cannot obtain its neighbours' gradient during gradient formation).
"""

from __future__ import annotations

from numba import njit

from ..statuses import CMD_NONE, COVERAGE, DETECTION, INITIAL
from .common import INF, NO, set_status, within


@njit(cache=True)
def formation_gradient(view, me, reach):  # pragma: no cover - compiled
    """1 + the smallest gradient of my group's stationary neighbours within ``reach`` that
    are heard and not in Coverage (Algorithm 1); -1 when there is none."""
    best = INF
    for r in range(within(view.dist, reach)):
        if (view.group[r] == me.group and not view.moving[r] and view.id[r] != NO
                and view.status[r] != COVERAGE and view.gradient[r] < best):
            best = view.gradient[r]
    return -1 if best == INF else best + 1


@njit(cache=True)
def parent_row(view, me, reach):  # pragma: no cover - compiled
    """The nearest of my group's stationary neighbours within ``reach`` holding the gradient
    below mine (my gradient parent), -1: none."""
    for r in range(within(view.dist, reach)):
        if (view.group[r] == me.group and view.id[r] != NO and view.gradient[r] == me.gradient - 1
                and not view.moving[r]):
            return r
    return -1


@njit(cache=True)
def follow_gradient(view, me, nearest, P):  # pragma: no cover - compiled
    """Algorithm 2, line 8: my gradient is my nearest stationary neighbour's plus one. With
    groups each group keeps its own: beside another group's robot, my group's nearest
    stationary robot within 1.5 d_cover gives it (none: I keep mine)."""
    source = nearest
    if view.group[nearest] != me.group:
        source = -1
        for r in range(within(view.dist, 1.5 * P.d_cover)):
            if not view.moving[r] and view.group[r] == me.group:
                source = r
                break
        if source < 0:
            return
    if view.id[source] != NO and view.gradient[source] < INF:
        me.gradient = view.gradient[source] + 1


@njit(cache=True)
def lose_gradient(me):  # pragma: no cover - compiled
    """Failure mode "no_gradient" (paper Section 5, Figure 10): I cannot obtain my
    neighbours' gradient, so mine is infinite. Travelling with my formation (Initial), I can
    follow no parent: I stop and wait in Detection, as a robot that heard no gradient does
    (rules/travel.py). Waiting in Detection I take no gradient from my formation
    (``no_gradient``), so that no neighbour of my group outranks me: I set off to cover
    first, unless robots round me leave no way out (then when they do), follow the
    structure's edge round my nearest robot and take its gradient plus one from then on
    (Algorithm 2, line 8), as any mover does. A mover just loses its gradient and takes one
    again from the structure. A leader's gradient is its own (0), obtained from nobody: it
    is not lost."""
    if me.leader:
        return
    me.gradient = INF
    if me.status == INITIAL:
        set_status(me, DETECTION)
        me.cmd, me.travel_x, me.travel_y, me.blocked = CMD_NONE, 0.0, 0.0, 0
    me.no_gradient = me.status == DETECTION
