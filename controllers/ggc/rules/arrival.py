"""Arrival: Algorithm 2's stop rules for a mover on the target, at covering distance from its
nearest stationary robot.

(a) The probe ahead leaves the target. (b) The nearest stationary robot has arrived with a
gradient >= mine; with one group (lattice_stop) only where a second arrived robot is within
d_cover + arrive_tolerance, so that robots stop on lattice sites; beside another group's
arrived robot (gradients are per group) only there too. A mover that stepped in across the
boundary stops as soon as it is on the target.
"""

from __future__ import annotations

from numba import njit

from ..statuses import ARRIVE
from .common import NO, probe, within


@njit(cache=True)
def two_arrived(view, reach):  # pragma: no cover - compiled
    """Are two of my neighbours within ``reach`` arrived?"""
    n = 0
    for r in range(within(view.dist, reach)):
        if view.status[r] == ARRIVE:
            n += 1
    return n >= 2


@njit(cache=True)
def should_arrive(view, me, nearest, sense, pb, P):  # pragma: no cover - compiled
    """Stop here (see the module docstring)? ``me.gradient`` is the gradient before this tick's
    update."""
    if not sense.on_target:
        return False
    if me.stepping:
        me.stepped = True
        return True
    if view.dist[nearest] < P.d_cover - P.arrive_tolerance:
        return False
    if (me.head_x != 0.0 or me.head_y != 0.0) and not probe(
            pb, me.head_x * P.probe_distance, me.head_y * P.probe_distance):
        return True
    if view.id[nearest] == NO or view.status[nearest] != ARRIVE:
        return False
    reach = P.d_cover + P.arrive_tolerance
    if P.lattice_stop and reach <= P.lattice_reach and P.groups == 1 and not two_arrived(
            view, reach):
        return False
    if view.group[nearest] != me.group:  # where the groups meet: close triangles only
        return two_arrived(view, reach)
    return view.gradient[nearest] >= me.gradient
