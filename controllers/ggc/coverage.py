"""GGC's Coverage: follow the structure's edge and stop on a place (Algorithm 2).

A mover follows the edge of the stationary robots at d_cover from the nearest one (or the
valley between two), orbiting in one sense, and takes its nearest stationary neighbour's
gradient plus one. It arrives on the target when its probe ahead leaves the target (rule a)
or beside an arrived robot whose gradient is not below its own (rule b); off the target it
never stops. Our additions (see GGCParams): boundary fill (step in across a strip the
structure leaves uncovered), lattice sites, the junction rule between groups and turning at
another group's structure. The surplus lap is in surplus.py, Stop and deadlocks in
collisions.py.
"""

from __future__ import annotations

import math
from collections.abc import Sequence

import numpy as np

from controllers.gradient import INF_GRADIENT
from controllers.views import any_of, within
from swarmsim.controller import NO_SENDER, Action, Perception

from .geometry import unit
from .statuses import ARRIVE, DETECTION, STOP, SURPLUS


def two_arrived(distances: np.ndarray, statuses: np.ndarray, reach: float) -> bool:
    """Are two of these neighbours (nearest first) within ``reach`` (units) arrived?"""
    k = within(distances, reach)
    return int((statuses[:k] == ARRIVE).sum()) >= 2


class CoverageRules:
    """Mixin of :class:`~controllers.ggc.robot.GGCRobot`: the Coverage status."""

    def coverage(self, p: Perception) -> Action:
        structure = self.nearest_edge_robots(p)
        if len(structure) == 0:
            return self.wander(p)
        nearest = structure[0]
        velocity = self.edge_velocity(p, structure)
        self.heading = unit(velocity)
        if self.surplus_rule:
            self.track_winding(p)
        if self.should_arrive(p, nearest):
            self.set_status(ARRIVE)
            return self.act()
        if self.surplus_rule and self.is_surplus(p, nearest):
            return self.give_up(p)
        self.follow_gradient(p, nearest)
        if self.p.own_edges:
            self.turn_at_junction(p, nearest)
        if self.boundary_fill and self.target_inward(p, nearest):
            return self.step_in(p, nearest)
        self.stepping_in = False
        if self.circling(p, nearest) | self.stuck(p):
            if p.on_target and self.may_arrive_when_stuck(p, nearest):
                self.set_status(ARRIVE)
                return self.act()
            self.sense = -self.sense  # a dead end: try the other way round
            self.circled = 0.0
            self.restart_lap(whole=False)
            if p.on_target:  # Algorithm 6: wait T_s, then resume
                return self.deadlock_stop(p)
            if self.wedged(p):
                self.set_status(DETECTION)  # wait until the robots around me have gone
                # and then leave the other way: a valley is followed by heading, not sense,
                # and it pushed into the same corner each time (K, 1 group, scattered, seed 4)
                self.heading = -self.heading
                self.yield_count = len(self.waiting_near(p))
                return self.act()
        if ((p.on_target or not self.p.stop_on_target_only)
                and p.tick >= self.pass_until and self.other_group_mover(p)):
            self.set_status(STOP)  # Section 4.3: avoid another group's moving robot
            self.stop_since = p.tick
            self.collision_stops += 1
            return self.act()
        give_way = self.give_way(p, velocity)
        if give_way is not None:
            return self.act(give_way)
        return self.act(velocity)

    def nearest_edge_robots(self, p: Perception) -> list[int]:
        """The indices of the nearest two of :meth:`edge_robots` (fewer if there are fewer):
        the same robots, found without masking every neighbour."""
        if self.pre is not None:
            return self.pre.edge
        m = p.messages
        still = (~m["moving"]).nonzero()[0]
        if self.p.follow_other_formations or self.groups == 1:
            return still[:2].tolist()
        group, status, sender = m["group"], m["status"], m["id"]
        found: list[int] = []
        for k in still.tolist():
            if (group[k] == self.group or status[k] == ARRIVE or status[k] == SURPLUS
                    or sender[k] == NO_SENDER):
                found.append(k)
                if len(found) == 2:
                    break
        return found

    def edge_robots(self, p: Perception) -> np.ndarray:
        """The stationary robots whose edge a mover follows: all of them, or without
        ``follow_other_formations`` not the waiting formations of other groups. (Movers ask
        only for the nearest two: :meth:`nearest_edge_robots`.)"""
        still = self.stationary(p)
        if self.p.follow_other_formations or self.groups == 1:
            return still
        foreign = self.foreign(p)
        if not any_of(still & foreign):
            return still  # the usual case, and the cheap one: no other group's robot stands here
        m = p.messages
        status = m["status"]
        return still & (~foreign | (status == ARRIVE) | (status == SURPLUS)
                        | (m["id"] == NO_SENDER))

    def edge_velocity(self, p: Perception, structure: list[int]) -> np.ndarray:
        """Follow the edge of the stationary robots (Algorithm 2), or a valley between two."""
        nearest = structure[0]
        if len(structure) > 1 and p.distances[structure[1]] < self.p.d_cover:
            valley = self.valley_follow(p, nearest, structure[1])
            if valley is not None:
                return valley
        return self.edge_follow(p.offsets[nearest], float(p.distances[nearest]))

    def valley_follow(self, p: Perception, a: int, b: int) -> np.ndarray | None:
        """Between two robots on opposite sides, both closer than d_cover: go along the valley.

        Orbiting whichever is nearest would flip direction each time the nearest changes
        side; instead keep going the way we were heading, centred between them. (In Python
        floats: the same arithmetic as on numpy 2-vectors, several times faster.)
        """
        return self.valley_between(float(p.distances[a]), float(p.distances[b]),
                                   p.offsets[a].tolist(), p.offsets[b].tolist())

    def valley_between(self, da: float, db: float, offset_a: Sequence[float],
                       offset_b: Sequence[float]) -> np.ndarray | None:
        """:meth:`valley_follow` from the two robots' distances (units) and offsets (x, y)."""
        (oax, oay), (obx, oby) = offset_a, offset_b
        ax, ay, bx, by = oax / da, oay / da, obx / db, oby / db
        if ax * bx + ay * by >= 0:
            return None
        ux, uy = ax - bx, ay - by  # the axis from b to a, made unit length
        n = math.hypot(ux, uy)
        ux, uy = (ux / n, uy / n) if n > 1e-12 else (0.0, 0.0)
        along_x, along_y = uy, -ux
        hx, hy = float(self.heading[0]), float(self.heading[1])
        if not (hx != 0.0 or hy != 0.0):
            hx, hy = ay * self.sense, -ax * self.sense
        if along_x * hx + along_y * hy < 0:
            along_x, along_y = -along_x, -along_y
        centring = max(-1.0, min(1.0, (da - db) * self.p.radial_gain))
        half = 0.5 * centring
        vx, vy = along_x + half * ux, along_y + half * uy
        n = math.hypot(vx, vy)
        if n <= 1e-12:
            return np.zeros(2)
        return np.array([vx / n * self.p.v, vy / n * self.p.v])

    def edge_follow(self, offset: np.ndarray | Sequence[float], dist: float) -> np.ndarray:
        """Rotate around the neighbour at ``offset`` (x, y) keeping d_cover from it
        (Algorithm 2)."""
        scale = max(dist, 1e-9)  # in scalars: the same arithmetic as arrays, faster
        rx, ry = offset[0] / scale, offset[1] / scale
        error = max(-1.0, min(1.0, (dist - self.p.d_cover) * self.p.radial_gain))
        vx, vy = ry * self.sense + error * rx, -rx * self.sense + error * ry
        norm = math.hypot(float(vx), float(vy))
        if norm <= 1e-12:
            return np.zeros(2)
        return np.array([vx / norm * self.p.v, vy / norm * self.p.v])

    def turn_at_junction(self, p: Perception, nearest: int) -> None:
        """With ``own_edges``: off the target, reaching another group's structure (my nearest
        stationary robot is another group's) turns me back, once per such robot."""
        m = p.messages[nearest]
        if m["group"] == self.group or m["id"] == NO_SENDER or p.on_target:
            return
        if int(m["id"]) != self.turned_at:
            self.turned_at = int(m["id"])
            self.sense = -self.sense
            self.circled = 0.0
            self.restart_lap(whole=False)

    def target_inward(self, p: Perception, nearest: int) -> bool:
        """Outside the target, beside an arrived robot, with target floor toward it.

        Then the strip between the structure and the boundary is wider than coverage reaches
        (our addition to Algorithm 2: the paper leaves it uncovered).
        """
        if p.on_target:
            return False
        m = p.messages[nearest]
        if m["status"] != ARRIVE or int(m["id"]) in self.no_way_in:
            return False
        if m["stepped"] or p.distances[nearest] < self.p.d_cover - self.p.arrive_tolerance:
            return False  # next to a robot that stepped in itself: the strip is covered
        toward = p.offsets[nearest] / max(float(p.distances[nearest]), 1e-9)
        return bool(p.probe(toward * self.p.boundary_probe))

    def step_in(self, p: Perception, nearest: int) -> Action:
        """Move straight toward the structure until the floor sensor finds the target.

        Arrival itself happens through the usual stop rules once on the target; if the robot
        gets within 2 d_safe of that robot without finding the target, it gives up on it.
        """
        if p.distances[nearest] <= 2 * self.p.d_safe:
            self.no_way_in.add(int(p.messages["id"][nearest]))
            self.stepping_in = False
            return self.act()
        self.stepping_in = True
        toward = p.offsets[nearest] / max(float(p.distances[nearest]), 1e-9)
        return self.act(toward * self.p.v)

    def follow_gradient(self, p: Perception, nearest: int) -> None:
        """Algorithm 2, line 8: my gradient is my nearest stationary neighbour's plus one.

        With groups, each group keeps its own gradient: only my group's robots count.
        """
        m = p.messages
        if m["group"][nearest] != self.group:
            mine = (self.stationary(p) & self.own_group(p)
                    & (p.distances <= 1.5 * self.p.d_cover)).nonzero()[0]
            if len(mine) == 0:
                return
            nearest = mine[0]
        g = int(m["gradient"][nearest])
        if m["id"][nearest] != NO_SENDER and g < INF_GRADIENT:
            self.grad = g + 1

    def should_arrive(self, p: Perception, nearest: int) -> bool:
        """Algorithm 2's stop rules, on the target and at covering distance from the nearest.

        (a) the probe ahead would leave the target; (b) the nearest stationary neighbour has
        arrived with a gradient >= mine (compared before this tick's gradient update). A robot
        still closer than d_cover - arrive_tolerance to its nearest keeps moving away first.
        """
        if not p.on_target:
            return False
        if self.stepping_in:
            self.stepped_in = True  # stepped in across the boundary: stop right there
            return True
        if p.distances[nearest] < self.p.d_cover - self.p.arrive_tolerance:
            return False
        if any_of(self.heading) and not p.probe(self.heading * self.p.probe_distance):
            return True
        m = p.messages[nearest]
        if m["id"] == NO_SENDER or m["status"] != ARRIVE:
            return False
        reach = self.p.d_cover + self.p.arrive_tolerance
        lattice = self.p.lattice_stop and reach <= self.p.lattice_reach
        lattice &= self.groups == 1  # with groups it slowed the corridor and K: see params.py
        if lattice and not self.at_lattice_site(p):
            return False
        if m["group"] != self.group:  # the groups meet here (gradients are per group)
            return self.junction_stop(p)
        return bool(m["gradient"] >= self.grad)

    def junction_stop(self, p: Perception) -> bool:
        """Rule (b) beside another group's arrived robot (see GGCParams.junction_stop)."""
        if self.p.junction_stop == "always":
            return True
        return self.p.junction_stop == "lattice" and self.at_lattice_site(p)

    def at_lattice_site(self, p: Perception) -> bool:
        """Two arrived robots within d_cover + arrive_tolerance: stopping here closes a
        triangle whose sides are at most that long, which discs of radius r cover when
        d_cover + arrive_tolerance <= r * sqrt(3)."""
        return two_arrived(p.distances, p.messages["status"],
                           self.p.d_cover + self.p.arrive_tolerance)

    def wander(self, p: Perception) -> Action:
        """No stationary robot in range: head for the beacon (or keep going)."""
        if p.beacon is not None and not p.on_target:
            self.heading = p.beacon
        if not any_of(self.heading):
            angle = self.rng.uniform(0, 2 * math.pi)
            self.heading = np.array([math.cos(angle), math.sin(angle)])
        if p.on_target and not p.probe(self.heading * self.p.probe_distance):
            self.set_status(ARRIVE)
            return self.act()
        return self.act(self.heading * self.p.v)

    def arrive(self, p: Perception) -> Action:
        return self.act(sleep=True, wake_range=0.0)
