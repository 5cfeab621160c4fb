"""The inter-group rule: what a mover does about other groups' movers (rule sets).

A rule set is one integer code (``GGCParams.ruleset`` by name, see RULESETS) and the
functions it selects here: :func:`stops` (does a mover in Coverage Stop now?) and
:func:`keeps_waiting` (does a robot in Stop wait on?). Adding a rule set is an entry in
RULESETS and a branch in each of these two functions.

* "paper" (Section 4.3): a mover that hears another group's mover in Coverage within
  d_cover with a larger id stops until no such mover is left.
* "yield": no Stop between groups: movers of every group give way to each other as movers
  of one group do (coverage.give_way: a larger-id mover close ahead), so no robot is parked
  as structure for another group.
"""

from __future__ import annotations

from numba import njit

from ..statuses import COVERAGE
from .common import within

PAPER, YIELD, FILL = 0, 1, 2
RULESETS = {"paper": PAPER, "yield": YIELD, "fill": PAPER | FILL, "yield-fill": YIELD | FILL}
"""Rule set names and their codes: bit YIELD, no Stop between groups; bit FILL, movers fill
the holes arrived robots report (rules/holes.py)."""


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
    if P.ruleset & YIELD:
        return False
    return other_group_mover(view, me, P)


@njit(cache=True)
def keeps_waiting(view, me, sense, P):  # pragma: no cover - compiled
    """Does a robot in Stop (not waiting out a deadlock) wait on?"""
    if P.ruleset & YIELD:
        return False
    return other_group_mover(view, me, P)

