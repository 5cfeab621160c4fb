"""Written by controllers/ggc/schema.py from its DATA: do not edit.

Regenerate: python controllers/ggc/schema.py
(tests/controllers/ggc/test_ggc_schema.py fails while this file is not current)."""

from __future__ import annotations

from numba import njit

from .borrow import borrowed
from .heard import Heard
from .rules.common import View
from .schema import PerGroup


@njit(inline="always")
def borrow_heard(heard):  # pragma: no cover - compiled
    """``heard`` (a Heard of the driver's arguments) with borrowed columns."""
    return Heard(
        borrowed(heard.starts),
        borrowed(heard.off),
        borrowed(heard.dist),
        borrowed(heard.id),
        borrowed(heard.status),
        borrowed(heard.moving),
        borrowed(heard.group),
        borrowed(heard.leader),
        borrowed(heard.gradient),
        borrowed(heard.cmd),
        borrowed(heard.travel_x),
        borrowed(heard.travel_y),
        borrowed(heard.touch),
        borrowed(heard.stepped),
        borrowed(heard.enclosed),
        borrowed(heard.blocked),
        borrowed(heard.h),
        borrowed(heard.handover),
        borrowed(heard.quiet),
        borrowed(heard.ldist),
        borrowed(heard.lepoch),
        borrowed(heard.hole),
        borrowed(heard.hole_x),
        borrowed(heard.hole_y),
    )


@njit(inline="always")
def empty_view(heard):  # pragma: no cover - compiled
    """A View of no neighbours, of the types of ``heard``'s columns."""
    return View(
        heard.off[:0],
        heard.dist[:0],
        heard.id[:0],
        heard.status[:0],
        heard.moving[:0],
        heard.group[:0],
        heard.leader[:0],
        heard.gradient[:0],
        heard.cmd[:0],
        heard.travel_x[:0],
        heard.travel_y[:0],
        heard.touch[:0],
        heard.stepped[:0],
        heard.enclosed[:0],
        heard.blocked[:0],
        heard.h[:0],
        heard.handover[:0],
        heard.quiet[:0],
        heard.ldist[:0],
        heard.lepoch[:0],
        heard.hole[:0],
        heard.hole_x[:0],
        heard.hole_y[:0],
    )


@njit(inline="always")
def point_view(view, heard, a, b):  # pragma: no cover - compiled
    """Point ``view`` at rows ``a:b`` of ``heard``'s columns."""
    view.off = heard.off[a:b]
    view.dist = heard.dist[a:b]
    view.id = heard.id[a:b]
    view.status = heard.status[a:b]
    view.moving = heard.moving[a:b]
    view.group = heard.group[a:b]
    view.leader = heard.leader[a:b]
    view.gradient = heard.gradient[a:b]
    view.cmd = heard.cmd[a:b]
    view.travel_x = heard.travel_x[a:b]
    view.travel_y = heard.travel_y[a:b]
    view.touch = heard.touch[a:b]
    view.stepped = heard.stepped[a:b]
    view.enclosed = heard.enclosed[a:b]
    view.blocked = heard.blocked[a:b]
    view.h = heard.h[a:b]
    view.handover = heard.handover[a:b]
    view.quiet = heard.quiet[a:b]
    view.ldist = heard.ldist[a:b]
    view.lepoch = heard.lepoch[a:b]
    view.hole = heard.hole[a:b]
    view.hole_x = heard.hole_x[a:b]
    view.hole_y = heard.hole_y[a:b]


@njit(inline="always")
def borrow_per_group(values):  # pragma: no cover - compiled
    """``values`` (a PerGroup of the driver's arguments) with borrowed arrays."""
    return PerGroup(
        borrowed(values.ldist),
        borrowed(values.lepoch),
    )


@njit(inline="always")
def group_rows(values, i):  # pragma: no cover - compiled
    """Robot ``i``'s rows of the PerGroup arrays ``values`` (views)."""
    return PerGroup(
        values.ldist[i],
        values.lepoch[i],
    )


@njit(inline="always")
def copy_group_rows(source, a, target, b):  # pragma: no cover - compiled
    """Copy row ``a`` of the PerGroup arrays ``source`` into row ``b`` of ``target``."""
    target.ldist[b, :] = source.ldist[a, :]
    target.lepoch[b, :] = source.lepoch[a, :]


@njit(inline="always")
def copy_broadcast(me, mine, msg):  # pragma: no cover - compiled
    """Copy the broadcast fields of state row ``me`` and per-group rows ``mine`` (a
    PerGroup) into broadcast ``msg`` (cast to the broadcast's types; moving: not here)."""
    msg.id = me.id
    msg.group = me.group
    msg.leader = me.leader
    msg.status = me.status
    msg.gradient = me.gradient
    msg.cmd = me.cmd
    msg.travel_x = me.travel_x
    msg.travel_y = me.travel_y
    msg.touch = me.touch
    msg.stepped = me.stepped
    msg.enclosed = me.enclosed
    msg.blocked = me.blocked
    msg.h = me.h
    msg.handover = me.handover
    msg.quiet = me.quiet
    for g in range(msg.ldist.shape[0]):
        msg.ldist[g] = mine.ldist[g]
    for g in range(msg.lepoch.shape[0]):
        msg.lepoch[g] = mine.lepoch[g]
    msg.hole = me.hole
    msg.hole_x = me.hole_x
    msg.hole_y = me.hole_y
