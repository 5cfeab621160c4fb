"""Crossing: a mover walled in beside its formation crosses the structure toward the beacon.

With the rule set's CROSS flag (our addition; rule set "yield-holes-cross", not the default).
Movers follow the structure's outer edge, so a mover whose formation halted in a pocket of the
target (the large K's notch between stem and leg) must walk round the whole structure to reach
its frontier: six formations of ten wait there while their movers circle them
(docs/reports/ggc-findings-journal.md, "The large K").

* **When.** A mover in Coverage, off the target, that has walked CROSS_PATH units since it
  left its formation (or since its last crossing) without finding a place, hears the beacon,
  and still hears a waiting robot of its own formation within 2 d_cover (it is walled in
  with it).
* **How.** Straight for the beacon, through the structure (its spacing, d_cover, leaves room
  to pass), sidestepping a robot close ahead as a mover going for a hole does.
* **Until.** On the target with no stationary robot within 1.5 d_cover ahead (within 60
  degrees of its heading): it has reached open floor (the frontier or a hole), and
  edge-follows and arrives there by the usual rules. A crossing that has gone CROSS_MAX
  units, or is stuck (Equation 3), ends where it is; the mover crosses again only after
  another CROSS_PATH units.
"""

from __future__ import annotations

import math

from numba import njit

from ..statuses import DETECTION
from .common import group_status_heard, within
from .deadlock import stuck
from .holes import sidestep
from .rulesets import CROSS

CROSS_PATH = 250.0
"""Units a mover walks off the target without finding a place before it crosses (and between
two crossings)."""
CROSS_MAX = 200.0
"""Longest crossing (units)."""
AHEAD_COS = 0.5
"""A crossing ends where no stationary robot lies within 1.5 d_cover ahead: inside this cosine
of the heading (60 degrees either side)."""


@njit(cache=True)
def open_ahead(view, hx, hy, P):  # pragma: no cover - compiled
    """No stationary robot within 1.5 d_cover ahead of heading (hx, hy) (unit), within
    AHEAD_COS of it: open floor ahead."""
    for r in range(within(view.dist, 1.5 * P.d_cover)):
        along = view.off[r, 0] * hx + view.off[r, 1] * hy
        if not view.moving[r] and along > AHEAD_COS * view.dist[r]:
            return False
    return True


@njit(cache=True)
def end_cross(me):  # pragma: no cover - compiled
    me.crossing = False
    me.cross_after = me.path + CROSS_PATH


@njit(cache=True)
def cross(view, me, sense, P):  # pragma: no cover - compiled
    """(crossing, vx, vy): this tick of my crossing, if I cross (see the module docstring)."""
    if not (P.flags & CROSS) or not sense.has_beacon:
        return False, 0.0, 0.0
    if not me.crossing:
        if sense.on_target or me.path < max(me.cross_after, CROSS_PATH):
            return False, 0.0, 0.0
        if not group_status_heard(view, me, DETECTION, 2 * P.d_cover):
            return False, 0.0, 0.0  # not walled in with my formation
        me.crossing, me.cross_from = True, me.path
    bx, by = sense.beacon_x, sense.beacon_y
    if sense.on_target and open_ahead(view, bx, by, P):
        end_cross(me)
        return False, 0.0, 0.0
    if stuck(me, sense, P) or me.path - me.cross_from > CROSS_MAX:
        end_cross(me)
        return False, 0.0, 0.0
    ux, uy = sidestep(view, bx, by, math.inf, P)
    me.head_x, me.head_y = ux, uy
    return True, ux * P.v, uy * P.v
