"""Gradients: Algorithm 1 (a waiting robot's hop count from its formation) and Algorithm 2,
line 8 (a mover's, from the structure it follows)."""

from __future__ import annotations

from numba import njit

from ..statuses import COVERAGE
from .common import INF, NO, within


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
