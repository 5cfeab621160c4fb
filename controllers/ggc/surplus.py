"""GGC's surplus lap (our addition, GGCParams.surplus_stop): a mover that went round its
group's structure past no free target floor stops for good, and so does its formation.

One group only (with groups every formation empties before a lap closes). A lap starts when
the mover leaves hearing of its group's waiting robots and ends back beside them; it counts
only if it went round the beacon (``surplus_winding``) and passed at most
``surplus_frontier`` units of target floor with free target floor outward.
"""

from __future__ import annotations

import math

import numpy as np

from controllers.edges import turn_between
from controllers.views import any_of, within
from swarmsim.controller import NO_SENDER, Action, Perception

from .geometry import SMALL_VIEW
from .statuses import ARRIVE, DETECTION, INITIAL, SURPLUS


class SurplusLap:
    """Mixin of :class:`~controllers.ggc.robot.GGCRobot`: the surplus lap's books."""

    def is_surplus(self, p: Perception, nearest: int) -> bool:
        """Back beside my group's waiting robots after a lap round the structure that passed
        no free target floor, or at a Surplus robot of my group (my nearest stationary
        robot): see GGCParams.surplus_stop."""
        m = p.messages
        if not self.away:
            self.away = not self.group_waiting_in(m)
        if p.on_target and self.frontier <= self.p.surplus_frontier:
            outward = -p.offsets[nearest] / max(float(p.distances[nearest]), 1e-9)
            if p.probe(outward * self.p.boundary_probe):
                self.frontier += math.hypot(float(p.moved[0]), float(p.moved[1]))
        if self.p.surplus_spread and not p.on_target and self.hears_group_surplus(p):
            return True
        if m["id"][nearest] == NO_SENDER or m["group"][nearest] != self.group:
            return False
        status = m["status"][nearest]
        if status == SURPLUS:
            return True
        if not (self.away and status in (INITIAL, DETECTION)):
            return False
        if p.distances[nearest] > self.p.d_cover + self.p.arrive_tolerance:
            return False
        if self.lap_whole and self.frontier <= self.p.surplus_frontier and self.went_round():
            return True
        self.restart_lap()  # the lap passed free floor, or I turned round: go round again
        return False

    def group_waiting_in(self, m: np.ndarray) -> bool:
        """Is a waiting robot (Initial, Detection) of my group among these messages? Near my
        formation one usually is among the nearest few, found by a loop over Python values."""
        head = m[:SMALL_VIEW]
        for status, group in zip(head["status"].tolist(), head["group"].tolist()):
            if group == self.group and (status == INITIAL or status == DETECTION):
                return True
        if len(m) <= SMALL_VIEW:
            return False
        status = m["status"]
        return any_of(((status == INITIAL) | (status == DETECTION)) & (m["group"] == self.group))

    def restart_lap(self, whole: bool = True) -> None:
        """Start a new lap (see GGCParams.surplus_stop). A robot that turns round starts one
        that is not whole (``whole=False``): retracing its way it comes back home early."""
        self.away = False
        self.frontier = 0.0
        self.lap_whole = whole
        self.winding = 0.0
        self.beacon_angle: float | None = None

    def track_winding(self, p: Perception) -> None:
        """Add up how far the bearing to the beacon has turned this lap (radians)."""
        if p.beacon is None:
            return
        angle = math.atan2(float(p.beacon[1]), float(p.beacon[0]))
        if self.beacon_angle is not None:
            self.winding += turn_between(self.beacon_angle, angle)
        self.beacon_angle = angle

    def went_round(self) -> bool:
        """Did this lap go round the beacon (see GGCParams.surplus_winding)? True without a
        beacon."""
        if self.beacon_angle is None:
            return True
        return abs(self.winding) >= math.radians(self.p.surplus_winding)

    def hears_surplus(self, p: Perception) -> bool:
        """A Surplus robot of my group within d_cover + arrive_tolerance."""
        k = within(p.distances, self.p.d_cover + self.p.arrive_tolerance)
        return self.group_surplus_in(p.messages[:k])

    def hears_group_surplus(self, p: Perception) -> bool:
        """A Surplus robot of my group within hearing."""
        return self.group_surplus_in(p.messages)

    def group_surplus_in(self, m: np.ndarray) -> bool:
        """Is a Surplus robot of my group among these messages?"""
        surplus = m["status"] == SURPLUS
        return any_of(surplus) and any_of(surplus & (m["group"] == self.group))

    def give_up(self, p: Perception) -> Action:
        """No place left: stop for good, as Arrive on the target (covering what is here),
        else as Surplus."""
        self.surplus += 1
        self.set_status(ARRIVE if p.on_target else SURPLUS)
        return self.act()
