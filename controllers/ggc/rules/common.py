"""What every rule shares: the view, sensor and probe types, actions, small geometry.

An action is a tuple ``(vx, vy, sleep, wake_range, wake_on_motion, wake_tick)``: a velocity
in units per tick, and with ``sleep`` the promise of swarmsim.controller.Action
(``wake_range`` NaN: the full sensing range; ``wake_tick`` -1: none).
"""

from __future__ import annotations

import math
from collections import namedtuple

import numpy as np
from numba import njit, types
from numba.experimental import structref

from controllers.common.gradient import INF_GRADIENT
from swarmsim.controller import NO_SENDER

from ..schema import VIEW_FIELDS
from ..statuses import ARRIVE, DETECTION, INITIAL, SURPLUS


# Each struct type subclasses types.StructRef itself. A shared base class with the one
# preprocess_fields was tried: in a fresh clone, processes that loaded the rules from numba's
# on-disk cache then crashed (SIGSEGV).
@structref.register
class ViewType(types.StructRef):
    """numba's type of a View: a reference to one struct of arrays."""

    def preprocess_fields(self, fields):
        return tuple((name, types.unliteral(t)) for name, t in fields)


class View(structref.StructRefProxy):
    """One robot's neighbours, nearest first: offsets ``off`` (k, 2) relative to it and
    distances ``dist`` (k,), units, then the columns of their last broadcasts (k,) ((k,
    groups) for the per-group fields), each named as its datum (schema.VIEW_FIELDS).

    Passed by reference (one pointer), not as a tuple of arrays: a compiled call with a
    tuple of arrays copies and counts each one, and a decision makes dozens of rule calls."""

    def __new__(cls, *columns):
        return structref.StructRefProxy.__new__(cls, *columns)


structref.define_proxy(View, ViewType, list(VIEW_FIELDS))

Sense = namedtuple("Sense", ["tick", "on_target", "moved_x", "moved_y", "has_beacon",
                             "beacon_x", "beacon_y"])
"""One robot's own sensors: the tick, its floor sensor, its displacement over the last tick
(units) and the unit bearing to the beacon (when the world has one)."""


@structref.register
class ProbeType(types.StructRef):
    """numba's type of a Probe: a reference to one struct of arrays."""

    def preprocess_fields(self, fields):
        return tuple((name, types.unliteral(t)) for name, t in fields)


class Probe(structref.StructRefProxy):
    """One robot's floor probe for this decision (see :func:`probe`): its requests (4, 2), their
    answers (4,) (-1 unknown, 0, 1), and one-element counters: calls made, an answer missing.
    Passed by reference, as View is."""

    def __new__(cls, req, ans, calls, pending):
        return structref.StructRefProxy.__new__(cls, req, ans, calls, pending)


structref.define_proxy(Probe, ProbeType, ["req", "ans", "calls", "pending"])

INF = INF_GRADIENT
NO = NO_SENDER
MAX_PROBES = 4
"""Floor probes one decision may ask (two at most today)."""
_S11, _S12, _S25, _S27 = (np.uint64(s) for s in (11, 12, 25, 27))
_MUL = np.uint64(2685821657736338717)
ENCLOSED_GAP = math.radians(100)
"""A robot whose waiting neighbours within 1.5 d_min leave no angular gap wider than this is
enclosed."""


@njit(cache=True)
def move(vx, vy):  # pragma: no cover - compiled
    """Drive at (vx, vy), units per tick; stay awake."""
    return float(vx), float(vy), False, math.nan, True, -1


@njit(cache=True)
def still():  # pragma: no cover - compiled
    """Stand still this tick; stay awake."""
    return 0.0, 0.0, False, math.nan, True, -1


@njit(cache=True)
def rest(wake_range, wake_on_motion, wake_tick):  # pragma: no cover - compiled
    """Stand still and sleep until a change within ``wake_range`` (units, NaN: full range),
    moving neighbours too with ``wake_on_motion``, or ``wake_tick`` (-1: none)."""
    return 0.0, 0.0, True, float(wake_range), wake_on_motion, int(wake_tick)


@njit(cache=True)
def probe(pb, ox, oy):  # pragma: no cover - compiled
    """Is the floor at my position + (ox, oy) target? The answer comes from the engine between
    two passes of the decision (decide.py): a question not answered yet reads False and marks
    the decision pending, and the driver decides the robot again with the answer."""
    c = pb.calls[0]
    pb.calls[0] = c + 1
    if c >= MAX_PROBES:
        pb.pending[0] = True
        return False
    if pb.ans[c] >= 0 and pb.req[c, 0] == ox and pb.req[c, 1] == oy:
        return pb.ans[c] == 1
    pb.req[c, 0], pb.req[c, 1] = ox, oy
    for later in range(c, MAX_PROBES):
        pb.ans[later] = -1
    pb.pending[0] = True
    return False


@njit(cache=True)
def set_status(me, status):  # pragma: no cover - compiled
    """Change my status; settling ends an open deadlock episode."""
    if status != me.status:
        me.status = status
        me.visited |= 1 << status
        if status == ARRIVE or status == SURPLUS:
            me.in_deadlock = False


@njit(cache=True)
def within(dist, reach):  # pragma: no cover - compiled
    """How many of the ascending ``dist`` are at most ``reach`` (the first ones)."""
    low, high = 0, len(dist)
    while low < high:
        mid = (low + high) >> 1
        if dist[mid] <= reach:
            low = mid + 1
        else:
            high = mid
    return low


@njit(cache=True)
def scaled(x, y, length):  # pragma: no cover - compiled
    """(x, y) scaled to ``length`` (zero stays zero)."""
    norm = math.hypot(x, y)
    if norm <= 1e-12:
        return 0.0, 0.0
    return x / norm * length, y / norm * length


@njit(cache=True)
def clip1(x):  # pragma: no cover - compiled
    return max(-1.0, min(1.0, x))


@njit(cache=True)
def turn_between(before, after):  # pragma: no cover - compiled
    """Signed turn (radians, in [-pi, pi)) from bearing ``before`` to ``after``."""
    return (after - before + math.pi) % (2 * math.pi) - math.pi


@njit(cache=True)
def widest_gap(angles, count):  # pragma: no cover - compiled
    """Widest angle (radians) between the first ``count`` (>= 2) bearings of ``angles``
    (sorted in place)."""
    a = angles[:count]
    a.sort()
    widest = a[0] + 2 * math.pi - a[count - 1]
    for j in range(1, count):
        widest = max(widest, a[j] - a[j - 1])
    return widest


@njit(cache=True)
def is_waiting(status):  # pragma: no cover - compiled
    return status == INITIAL or status == DETECTION


@njit(cache=True)
def surrounded(view, reach, waiting, max_gap):  # pragma: no cover - compiled
    """Three or more neighbours within ``reach`` (waiting ones if ``waiting``, else arrived
    ones) that leave no angular gap of ``max_gap`` (radians) or more round me."""
    k = within(view.dist, reach)
    angles = np.empty(max(k, 1))
    n = 0
    for r in range(k):
        if is_waiting(view.status[r]) if waiting else view.status[r] == ARRIVE:
            angles[n] = math.atan2(view.off[r, 1], view.off[r, 0])
            n += 1
    return n >= 3 and widest_gap(angles, n) < max_gap


@njit(cache=True)
def group_status_heard(view, me, status, reach):  # pragma: no cover - compiled
    """Is a robot of my group with ``status`` within ``reach``?"""
    for r in range(within(view.dist, reach)):
        if view.status[r] == status and view.group[r] == me.group:
            return True
    return False


@njit(cache=True)
def status_heard(view, status, reach):  # pragma: no cover - compiled
    """Is a robot of any group with ``status`` within ``reach``?"""
    for r in range(within(view.dist, reach)):
        if view.status[r] == status:
            return True
    return False


@njit(cache=True)
def waiting_near(view, P):  # pragma: no cover - compiled
    """How many neighbours within 1.5 d_min wait to move (Initial, Detection)."""
    n = 0
    for r in range(within(view.dist, 1.5 * P.d_min)):
        if is_waiting(view.status[r]):
            n += 1
    return n


@njit(cache=True)
def next_random(me):  # pragma: no cover - compiled
    """A uniform draw in [0, 1) from my own generator (xorshift64*, state in my row)."""
    x = me.rng
    x ^= x >> _S12
    x ^= x << _S25
    x ^= x >> _S27
    me.rng = x
    return float((x * _MUL) >> _S11) / 9007199254740992.0
