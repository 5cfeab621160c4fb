"""Movers confined without a place give up (our addition; the rule set's SURPLUS flag, only
while d_cover <= yield_release).

At small d_cover the target has room for every robot, so the surplus lap (rules/surplus.py,
d_cover > yield_release) does not apply; yet some movers find no place they can reach and
never stop: at d_cover 1 they wedge between two robots of a dense band outside the target,
are released (Algorithm 5) and wedge there again; at d_cover 2 and 4 a mover on the target
deadlocks and waits in Stop over and over, or wanders a pocket inside the structure's
lattice. The runs then end by the plateau rule with movers walking.

A mover counts the ticks it spends in Coverage (and in Stop) and the displacement its own
odometry has added up meanwhile (``sense.moved``). Once it gets farther than
confined_reach * d_cover from where the count started, it has reached new ground, and once
it hears more arrived robots than it has since the count started, the structure has grown
near it (early on, movers jam while it grows round them): either way it counts afresh.
After RuleParams.confined_span ticks within that reach (GGCParams.confined_ticks at d_cover
= d_safe, in proportion to d_safe + d_cover: the reach, and the time to walk round it, grow
with d_cover), it has found no place it can reach: it stops for good (surplus.give_up:
Arrive on the target, else Surplus). The count goes on while the mover waits in its
formation in between (a wedged mover rejoins it, rules/deadlock.py): leaving it again is no
progress. It pauses while the mover hears robots of its own group waiting to be sent
(Initial or Detection): beside a formation that still releases robots, a slow search is not
yet a hopeless one (at d_cover 2 with one group, movers there gave up and left floor
uncovered).

A walk along the structure changes how many arrived robots the mover hears, so the count
can start afresh for ever while the mover circles a stretch of it. So a mover that has walked
more than RuleParams.confined_path units in Coverage since it left its formation
(``me.path``) gives up too (docs/reports/ggc-findings-journal.md has the runs that needed it).
"""

from __future__ import annotations

import math

from numba import njit

from ..statuses import ARRIVE
from .rulesets import SURPLUS
from .surplus import group_waiting_heard


@njit(cache=True)
def watched(P):  # pragma: no cover - compiled
    """Does the rule apply in this run (the SURPLUS flag, d_cover <= yield_release)?"""
    return bool(P.flags & SURPLUS) and P.d_cover <= P.yield_release


@njit(cache=True)
def arrived_heard(view):  # pragma: no cover - compiled
    """How many arrived robots I hear."""
    k = 0
    for r in range(len(view.dist)):
        if view.status[r] == ARRIVE:
            k += 1
    return k


@njit(cache=True)
def confined(view, me, sense, P):  # pragma: no cover - compiled
    """Count one tick of my search, my displacement and the arrived robots I hear since the
    count started; True once I have spent P.confined_span ticks within P.confined_radius units
    of where it started, hearing no more arrived robots than I did then, or once I have
    walked more than P.confined_path units since I left my formation (see the module
    docstring)."""
    if not watched(P):
        return False
    me.roam_x += sense.moved_x
    me.roam_y += sense.moved_y
    heard = arrived_heard(view)
    if math.hypot(me.roam_x, me.roam_y) > P.confined_radius or heard > me.roam_seen:
        me.roam_x, me.roam_y, me.roam_ticks = 0.0, 0.0, 0
        me.roam_seen = heard
    if not group_waiting_heard(view, me):  # my formation still has robots to send: wait
        me.roam_ticks += 1
    return me.roam_ticks >= P.confined_span or me.path > P.confined_path
