"""The inter-group rule: what a mover does about other groups' movers.

:func:`stops` (does a mover in Coverage Stop now?) and :func:`keeps_waiting` (does a robot in
Stop wait on?), by the run's rule set (rules/rulesets.py):

* the paper's (Section 4.3): a mover that hears another group's mover in Coverage within
  d_cover with a larger id stops until no such mover is left;
* with the YIELD flag: no Stop between groups; movers of every group give way to each other
  as movers of one group do (coverage.give_way).
"""

from __future__ import annotations

from numba import njit

from ..statuses import COVERAGE
from .common import within
from .rulesets import YIELD


@njit(cache=True)
def other_group_mover(view, me, P):  # pragma: no cover - compiled
    """Another group's robot in Coverage within d_cover with a larger id."""
    if P.groups == 1:
        return False
    for r in range(within(view.dist, P.d_cover)):
        if view.group[r] != me.group and view.id[r] > me.id and view.status[r] == COVERAGE:
            return True
    return False


@njit(cache=True)
def stops(view, me, sense, P):  # pragma: no cover - compiled
    """Does a mover in Coverage Stop now, for another group's movers?"""
    if P.flags & YIELD:
        return False
    return other_group_mover(view, me, P)


@njit(cache=True)
def keeps_waiting(view, me, sense, P):  # pragma: no cover - compiled
    """Does a robot in Stop (not waiting out a deadlock) wait on?"""
    if P.flags & YIELD:
        return False
    return other_group_mover(view, me, P)

