"""One GGC robot: the paper's Section 3 state machine (Algorithms 1, 2 and 7's Detection).

Statuses (Figure 3): Initial -> Detection -> Coverage -> Arrive.

* Initial: the group stands as a hexagonal formation around its leader. The leader heads for
  the beacon and broadcasts a travel command with its velocity; every robot copies the command
  of its gradient parent one tick later, so a robot g hops from the leader starts g ticks late
  and stops g ticks late: the formation moves rigidly. When the leader's floor sensor reaches
  the target it halts, and the halt spreads the same way (Figure 4a).
* Detection: gradient = 1 + min gradient of stationary neighbours within 1.5 d_min
  (Algorithm 1); a robot starts when no neighbour within d_cover has a larger (gradient, id)
  and no moving robot is within d_cover + d_safe (Algorithm 7).
* Coverage: follow the edge of the stationary robots at d_cover from the nearest one (move
  away if closer, approach if farther, rotate around it; Algorithm 2), orbiting in one fixed
  sense; gradient = 1 + min gradient of stationary neighbours within gradient_reach * d_cover.
  Stop (Arrive) on the target when the probe ahead leaves it, or beside an arrived robot whose
  gradient is >= ours, at d_cover from it. A robot outside the target never stops.
* Robust edges: a robot that circles one robot all the way round, or moves less than theta in
  T_r ticks, arrives if it is on the target and otherwise carries on (toward the beacon when it
  is circling a lone robot outside).
"""

from __future__ import annotations

import math
from itertools import pairwise

import numpy as np

from controllers.edges import CirclingWatch, ProgressWatch, turn_between
from controllers.views import any_of, within
from swarmsim.controller import (
    INF_GRADIENT,
    NO_SENDER,
    Action,
    Perception,
    RobotSetup,
    make_action,
)

from .aggregation import AGGREGATION_FIELDS, MAX_GROUPS, Aggregation, aggregation_fields
from .batch import BLOCKED_BY_MOVER, BLOCKED_BY_WAITING, NOT_BLOCKED, Precomputed, WaitingAnswers
from .params import GGCParams
from .statuses import (  # noqa: F401 (re-exported)
    APPROACH,
    ARRIVE,
    CMD_HALT,
    CMD_NONE,
    CMD_TRAVEL,
    COVERAGE,
    DETECTION,
    FORMED,
    GATHERING,
    INITIAL,
    JOIN,
    MOVING_STATUSES,
    PEND,
    STATUSES,
    STOP,
    SURPLUS,
)

MESSAGE_FIELDS = [("cmd", "i1"), ("vx", "f4"), ("vy", "f4"), ("touch", "?"), ("stepped", "?"),
                  ("enclosed", "?"), *AGGREGATION_FIELDS]
"""GGC's broadcast fields for up to MAX_GROUPS groups (a run uses :func:`message_fields`)."""


def message_fields(groups: int) -> list[tuple]:
    """GGC's broadcast fields for a run with this many groups: the per-group fields of the
    scattered start have one entry per group (a smaller row is cheaper to gather and copy)."""
    return [*MESSAGE_FIELDS[:-len(AGGREGATION_FIELDS)], *aggregation_fields(groups)]


SMALL_VIEW = 16
"""Up to this many neighbours a query loops over Python values instead of numpy masks
(same answers: integer and boolean tests only)."""
ENCLOSED_GAP = math.radians(100)
"""A robot whose neighbours within 1.5 d_min leave no angular gap wider than this is enclosed."""


def unit(v: np.ndarray) -> np.ndarray:
    """``v`` scaled to length 1 (zero stays zero). In Python floats: the same quotients as
    numpy's, several times faster on a 2-vector."""
    x, y = float(v[0]), float(v[1])
    n = math.hypot(x, y)
    return np.array([x / n, y / n]) if n > 1e-12 else np.zeros(2)


class GGCRobot(Aggregation, CirclingWatch, ProgressWatch):
    """One robot's GGC controller: travel and coverage here, the scattered start's leader
    selection, grouping and aggregation in aggregation.py."""

    def __init__(self, setup: RobotSetup, params: GGCParams, rng: np.random.Generator):
        if setup.groups > MAX_GROUPS:
            raise ValueError(f"GGC supports at most {MAX_GROUPS} groups, got {setup.groups}")
        self.id = setup.robot_id
        self.p = params
        self.rng = rng
        self.leader = setup.leader
        self.group = setup.group
        self.status = INITIAL
        self.history = [INITIAL]
        self.grad = 0 if self.leader else INF_GRADIENT
        self.cmd = CMD_NONE
        self.travel = np.zeros(2)
        self.touch = False
        self.odometer = np.zeros(2)
        self.progress_tick = 0
        self.heading = np.zeros(2)
        self.circling_id = NO_SENDER
        self.circled = 0.0
        self.last_bearing: float | None = None
        self.deadlocks = 0
        self.deadlock_episodes = 0
        self.in_deadlock = False
        self.restart_lap()
        self.surplus = 0
        self.surplus_rule = (params.surplus_stop and params.d_cover > params.yield_release
                             and setup.groups == 1)
        self.boundary_fill = (params.boundary_fill == "always"
                              or (params.boundary_fill == "one-group" and setup.groups == 1))
        self.sense = params.orbit
        self.route: tuple[float, float] | None = None  # the travel my formation followed
        self.orbit_chosen = False
        self.collision_stops = 0
        self.no_way_in: set[int] = set()
        self.stepping_in = False
        self.stepped_in = False
        self.groups = setup.groups
        self.resume_tick = 0
        self.stop_since = 0  # the tick my current Stop began
        self.pass_until = 0  # until this tick I do not Stop for other groups (stop_patience)
        self.scattered = setup.scattered
        self.enclosed = False
        self.turned_at = NO_SENDER
        self.yield_count = 0
        self.initial_since = 0
        self.init_aggregation()
        self.pre: Precomputed | None = None  # this tick's answers from GGC.prepare, if any
        self.pre_wait: WaitingAnswers | None = None
        self.handlers = {INITIAL: self.initial, DETECTION: self.detection,
                         COVERAGE: self.coverage, ARRIVE: self.arrive, STOP: self.stopped,
                         SURPLUS: self.arrive}  # by status; the others gather (aggregation.py)
        if self.scattered:
            self.status = FORMED if self.leader else APPROACH
            self.history = [self.status]

    # ------------------------------------------------------------------ messages and status
    def message(self) -> tuple:
        return (self.id, self.status, self.grad, self.group, self.leader,
                self.status in MOVING_STATUSES, self.cmd, float(self.travel[0]),
                float(self.travel[1]), self.touch, self.stepped_in, self.enclosed,
                *self.aggregation_message())

    def set_status(self, status: int) -> None:
        if status != self.status:
            self.status = status
            self.history.append(status)
            if status in (ARRIVE, SURPLUS):
                self.in_deadlock = False  # settled: an open deadlock episode is over

    def act(self, velocity: np.ndarray | tuple = (0.0, 0.0), sleep: bool = False,
            wake_range: float | None = None, wake_on_motion: bool = True) -> Action:
        return make_action((float(velocity[0]), float(velocity[1])), self.message(), sleep,
                           wake_range, self.listen_range(), wake_on_motion)

    def listen_range(self) -> float | None:
        """How far this robot needs to hear next tick (less is cheaper; R_c at most)."""
        if self.status == COVERAGE:  # the most frequent: first
            return min(2 * self.p.d_cover, self.p.R_c)
        if self.status in GATHERING or self.status == FORMED:
            return self.p.R_c
        if self.status == INITIAL:
            return 1.5 * self.p.d_min
        if self.status == DETECTION:
            return max(self.p.d_cover, 1.5 * self.p.d_min)
        if self.status in (ARRIVE, SURPLUS):
            return self.p.d_safe
        return min(2 * self.p.d_cover, self.p.R_c)

    def step(self, p: Perception) -> Action:
        self.odometer += p.moved
        if self.scattered and p.tick < self.selection_ticks:
            action = self.select_leaders(p)
        else:
            action = self.handlers.get(self.status, self.gather)(p)
        self.pre = self.pre_wait = None  # they answered this perception only
        return action

    # ------------------------------------------------------------------ neighbour views
    def own_group(self, p: Perception) -> np.ndarray:
        return p.messages["group"] == self.group

    @staticmethod
    def stationary(p: Perception) -> np.ndarray:
        """Neighbours that are not moving on purpose (formation, arrived, failed robots)."""
        return ~p.messages["moving"]

    def foreign(self, p: Perception) -> np.ndarray | None:
        """Which neighbours belong to another group (None with one group: none do)."""
        return None if self.groups == 1 else p.messages["group"] != self.group

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

    def gradient_from(self, p: Perception, reach: float) -> int | None:
        """1 + the smallest known gradient of own-group stationary neighbours within reach."""
        return self.gradient_in(p.messages[:within(p.distances, reach)])  # distances sorted

    def gradient_in(self, m: np.ndarray) -> int | None:
        """1 + the smallest known gradient of own-group stationary robots among messages m.

        A formation neighbourhood (within 1.5 d_min) has a handful of rows: for those a loop
        over Python ints is ~4x faster than numpy's masks, with the same answer.
        """
        if len(m) <= SMALL_VIEW:
            best = INF_GRADIENT
            for moving, group, sender, grad, status in zip(
                    m["moving"].tolist(), m["group"].tolist(), m["id"].tolist(),
                    m["gradient"].tolist(), m["status"].tolist()):
                if (grad < best and group == self.group and not moving and sender != NO_SENDER
                        and status != COVERAGE):
                    best = grad
            return None if best == INF_GRADIENT else best + 1
        ok = ~m["moving"] & (m["group"] == self.group)
        ok &= (m["id"] != NO_SENDER) & (m["gradient"] < INF_GRADIENT)
        ok &= m["status"] != COVERAGE
        if not any_of(ok):
            return None
        return int(m["gradient"][ok].min()) + 1

    # ------------------------------------------------------------------ Initial: travel
    def initial(self, p: Perception) -> Action:
        if self.leader:
            return self.lead(p)
        # Every travelling robot decides each tick: one slice of the formation neighbours
        # (within 1.5 d_min) serves gradient, touch and parent.
        m = p.messages[:within(p.distances, 1.5 * self.p.d_min)]  # distances are sorted
        grad = self.gradient_in(m)
        if grad is None:
            if p.tick - self.initial_since >= self.p.init_timeout:
                self.set_status(DETECTION)
            return self.act(sleep=True, wake_range=1.5 * self.p.d_min)
        self.grad = grad
        own = m["group"] == self.group
        self.touch = self.touching_in(p, m, own)
        parent = self.parent_in(m, own)
        self.cmd = int(parent["cmd"])
        self.travel = np.array([parent["vx"], parent["vy"]], dtype=float)
        self.remember_route()
        if self.cmd == CMD_HALT:
            self.travel[:] = 0.0
            self.set_status(DETECTION)
            return self.act()
        return self.act(self.travel if self.cmd == CMD_TRAVEL else (0.0, 0.0))

    def parent_in(self, m: np.ndarray, own: np.ndarray) -> np.void:
        """The nearest own-group (``own``) stationary robot among the formation neighbours
        ``m`` (within 1.5 d_min, nearest first) holding the gradient below mine."""
        ok = own & (m["id"] != NO_SENDER) & (m["gradient"] == self.grad - 1) & ~m["moving"]
        return m[ok.nonzero()[0][0]]

    def touching(self, p: Perception) -> bool:
        """Has the formation's front touched the target? (own floor sensor or a neighbour's)"""
        m = p.messages[:within(p.distances, 1.5 * self.p.d_min)]
        return self.touching_in(p, m, m["group"] == self.group)

    def touching_in(self, p: Perception, m: np.ndarray, own: np.ndarray) -> bool:
        """``touching`` with the formation neighbours ``m`` (within 1.5 d_min) already sliced
        and ``own`` marking those of my group."""
        return True if p.on_target else any_of(own & m["touch"])

    def lead(self, p: Perception) -> Action:
        """The leader heads for the beacon until the formation's front touches the target.

        The touch travels hop by hop to the leader, which then halts; the halt travels back
        through gradient parents, so every robot stops as many ticks late as it started.
        """
        if self.touching(p) or p.beacon is None:
            self.cmd = CMD_HALT
            self.travel = np.zeros(2)
            self.set_status(ARRIVE)
            return self.act()
        self.cmd = CMD_TRAVEL
        self.travel = p.beacon * self.p.v
        self.remember_route()
        return self.act(self.travel)

    def remember_route(self) -> None:
        """Keep the formation's travel vector for group_orbit (see GGCParams)."""
        if self.cmd == CMD_TRAVEL and (self.travel[0] or self.travel[1]):
            self.route = (float(self.travel[0]), float(self.travel[1]))

    def choose_orbit(self) -> None:
        """With groups, pick my group's orbit sense once, as I first leave (see
        GGCParams.group_orbit)."""
        if self.orbit_chosen or self.groups == 1:
            return
        self.orbit_chosen = True
        rule, orbit = self.p.group_orbit, self.p.orbit
        if rule == "alternate":
            self.sense = orbit if self.group % 2 else -orbit
        elif rule == "away" and self.route is not None:
            self.sense = -orbit if self.route[0] * self.route[1] > 0 else orbit

    # ------------------------------------------------------------------ Detection
    def detection(self, p: Perception) -> Action:
        pre = self.pre_wait  # the same answers, found for the whole chunk at once
        if self.surplus_rule and (pre.surplus if pre is not None else self.hears_surplus(p)):
            self.set_status(SURPLUS)  # my group's structure is full: stay where I am
            return self.act(sleep=True, wake_range=0.0)
        grad = pre.grad if pre is not None else self.gradient_from(p, 1.5 * self.p.d_min)
        if grad is not None:
            self.grad = grad
        blocker = pre.blocker if pre is not None else self.blocked(p)
        if self.yield_count and len(self.waiting_near(p)) < self.yield_count:
            self.yield_count = 0  # a robot around me has left: try again
        elif (self.yield_count and self.p.d_cover <= self.p.yield_release
              and self.nobody_to_yield_to(p)):
            self.yield_count = 0  # the robots around me all yield too: take turns again
            self.enclosed = self.is_enclosed(p)
            return self.act()  # broadcast it first, so that the (gradient, id) order decides
        self.enclosed = bool(self.yield_count) or self.is_enclosed(p)
        if not blocker and self.enclosed:  # my turn, but no way out: let the others go
            return self.act(sleep=True, wake_range=1.5 * self.p.d_min)
        if blocker:
            # Blocked by a waiting robot: only a changed broadcast can lift that.
            return self.act(sleep=True, wake_range=self.p.d_cover,
                            wake_on_motion=blocker == BLOCKED_BY_MOVER)
        self.start_coverage(p)
        return self.coverage(p)

    def blocked(self, p: Perception) -> int:
        """Algorithm 7: wait while a neighbour within d_cover has a larger (gradient, id).

        Moving robots count too: their gradient is their nearest neighbour's plus one.
        Returns NOT_BLOCKED, BLOCKED_BY_WAITING (a non-moving robot outranks me) or
        BLOCKED_BY_MOVER (only moving robots do).
        """
        m = p.messages[:within(p.distances, self.p.d_cover)]  # distances are sorted
        if self.waiting_outranks(m[:SMALL_VIEW]):
            return BLOCKED_BY_WAITING  # in a formation usually found among the nearest few
        status = m["status"]
        near = (m["group"] == self.group) & (m["id"] != NO_SENDER)
        near &= (status != ARRIVE) & (status != SURPLUS)
        if self.groups > 1:  # a mover in Stop has left already (Section 4.3): not my turn's
            near &= status != STOP
        outranks = near & ~m["enclosed"] & ((m["gradient"] > self.grad)
                                            | ((m["gradient"] == self.grad) & (m["id"] > self.id)))
        if not any_of(outranks):
            return NOT_BLOCKED
        return BLOCKED_BY_MOVER if m["moving"][outranks].all() else BLOCKED_BY_WAITING

    def waiting_outranks(self, m: np.ndarray) -> bool:
        """Does a waiting robot among the messages ``m`` block me (:meth:`blocked`'s test for
        a robot that is not moving), looped over Python values (for a few rows)?"""
        done = (ARRIVE, SURPLUS, STOP) if self.groups > 1 else (ARRIVE, SURPLUS)
        for sender, status, grad, group, moving, enclosed in zip(
                m["id"].tolist(), m["status"].tolist(), m["gradient"].tolist(),
                m["group"].tolist(), m["moving"].tolist(), m["enclosed"].tolist()):
            if (group == self.group and not moving and not enclosed and sender != NO_SENDER
                    and status not in done
                    and (grad > self.grad or (grad == self.grad and sender > self.id))):
                return True
        return False

    def is_enclosed(self, p: Perception) -> bool:
        """Waiting neighbours within 1.5 d_min all round (no gap wider than ENCLOSED_GAP): a
        robot inside a formation, which cannot leave before the robots around it have. (Formations
        gathered from a scattered start are not perfect lattices: their highest gradients
        are not always on the rim.)"""
        waiting = self.waiting_near(p)
        if len(waiting) < 3:
            return False
        return widest_gap(p.offsets[waiting]) < ENCLOSED_GAP

    def nobody_to_yield_to(self, p: Perception) -> bool:
        """A wedged robot waits (``yield_count``) for a robot around it to leave first. That
        wait never ends when every waiting robot around it is itself yielding or enclosed: the
        enclosed wait for the robots outside them, and the yielding for each other. At small
        d_cover a jam beside the formation wedges the whole rim this way, and the rest of the
        swarm stays in the formation for good (K, d_cover 2: 287 robots).

        True when all waiting neighbours within 1.5 d_min broadcast ``enclosed`` and I am on
        the outside: the stationary robots around me (waiting or arrived: the formation's
        leader counts) leave a gap wider than ENCLOSED_GAP. A robot inside the formation
        (around the leader's place) keeps yielding.
        """
        waiting = self.waiting_near(p)
        if len(waiting) == 0 or not p.messages["enclosed"][waiting].all():
            return False
        k = within(p.distances, 1.5 * self.p.d_min)
        still = self.stationary(p)[:k].nonzero()[0]
        if len(still) < 3:
            return True
        return widest_gap(p.offsets[still]) >= ENCLOSED_GAP

    def waiting_near(self, p: Perception) -> np.ndarray | list[int]:
        """Indices of neighbours within 1.5 d_min that wait to move (Initial, Detection)."""
        k = within(p.distances, 1.5 * self.p.d_min)
        status = p.messages["status"][:k]
        if k <= SMALL_VIEW:  # the same indices, over Python values
            return [j for j, s in enumerate(status.tolist()) if s == INITIAL or s == DETECTION]
        return ((status == INITIAL) | (status == DETECTION)).nonzero()[0]

    def hears_surplus(self, p: Perception) -> bool:
        """A Surplus robot of my group within d_cover + arrive_tolerance."""
        k = within(p.distances, self.p.d_cover + self.p.arrive_tolerance)
        return self.group_surplus_in(p.messages[:k])

    def start_coverage(self, p: Perception) -> None:
        self.choose_orbit()
        self.restart_lap()
        self.set_status(COVERAGE)
        self.odometer[:] = 0.0
        self.progress_tick = p.tick

    # ------------------------------------------------------------------ Coverage
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
        da, db = float(p.distances[a]), float(p.distances[b])
        (oax, oay), (obx, oby) = p.offsets[a].tolist(), p.offsets[b].tolist()
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

    def edge_follow(self, offset: np.ndarray, dist: float) -> np.ndarray:
        """Rotate around the neighbour at ``offset`` keeping d_cover from it (Algorithm 2)."""
        scale = max(dist, 1e-9)  # in scalars: the same arithmetic as arrays, faster
        rx, ry = offset[0] / scale, offset[1] / scale
        error = max(-1.0, min(1.0, (dist - self.p.d_cover) * self.p.radial_gain))
        vx, vy = ry * self.sense + error * rx, -rx * self.sense + error * ry
        norm = math.hypot(float(vx), float(vy))
        if norm <= 1e-12:
            return np.zeros(2)
        return np.array([vx / norm * self.p.v, vy / norm * self.p.v])

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
        k = within(p.distances, self.p.d_cover + self.p.arrive_tolerance)
        return int((p.messages["status"][:k] == ARRIVE).sum()) >= 2

    def stuck(self, p: Perception) -> bool:
        """Equation 3: displacement <= theta over T_r ticks. Also keeps the books on deadlock
        episodes: one opens at a detection and is released when a later sample shows
        progress or the robot settles (see ``set_status``)."""
        moved = self.sample_progress(p)
        if moved is None:
            return False
        if moved <= self.p.theta:
            self.deadlocks += 1
            self.deadlock_episodes += not self.in_deadlock
            self.in_deadlock = True
            return True
        self.in_deadlock = False  # progress: an open deadlock episode is over
        return False

    @property
    def deadlocks_released(self) -> int:
        """Deadlock episodes that have ended: all but the one still open, if any."""
        return self.deadlock_episodes - self.in_deadlock

    def may_arrive_when_stuck(self, p: Perception, nearest: int) -> bool:
        """May a deadlocked mover on the target stop here? Always in a single group; with
        groups (Algorithm 5, line 5) when a robot in Stop is within hearing, or with
        ``spaced_deadlock_arrive`` only at d_cover - arrive_tolerance from the nearest
        stationary robot."""
        if self.groups == 1:
            return True
        if self.p.spaced_deadlock_arrive:
            return bool(p.distances[nearest] >= self.p.d_cover - self.p.arrive_tolerance)
        return any_of(p.messages["status"] == STOP)

    def wedged(self, p: Perception) -> bool:
        """Pressed against waiting robots of my group (bodies touching: closer than 0.9 d_safe).

        A robot can start from inside a formation that aggregation packed unevenly; pushing
        gets it nowhere, so it waits its turn again and the robots outside it go first.

        While d_cover <= yield_release, a stuck robot outside the target rejoins its formation
        when a waiting robot of its group is within 1.5 d_min (a formation neighbour), touching
        or not. At small d_cover movers get pinned just outside the target between the
        formation's top and arrived robots; still moving, they outrank the formation's rim
        (their gradient comes from the arrived robots) and every waiting robot's turn chains
        up to them (K, d_cover 2: 190 robots never left). Back in Detection they wait their
        turn with the others (and yield_release lets them go again).

        With groups too, at any d_cover: other groups' movers and robots in Stop crowd round a
        formation, and a mover of its group stuck one unit from it blocked its rim for good
        (house, 3 groups, seed 1: 116 robots never left; see docs/ggc-findings.md, house).
        """
        reach = 0.9 * self.p.d_safe
        if self.p.d_cover <= self.p.yield_release or self.groups > 1:
            reach = 1.5 * self.p.d_min
        k = within(p.distances, reach)
        m = p.messages[:k]
        return any_of((m["status"] == DETECTION) & (m["group"] == self.group))

    def deadlock_stop(self, p: Perception) -> Action:
        self.set_status(STOP)
        self.stop_since = p.tick
        self.resume_tick = p.tick + self.p.T_s
        return self.act()

    def other_group_mover(self, p: Perception) -> bool:
        """A robot of another group in Coverage within d_cover, with priority (larger id)."""
        if self.groups == 1:
            return False
        found = self.pre.movers if self.pre is not None else self.other_group_movers(p)
        if len(found) == 0:
            return False
        if self.p.stop_ahead_only and any_of(self.heading):
            k = within(p.distances, self.p.d_cover)
            return any_of((p.offsets[:k] @ self.heading > 0)[found])
        return True

    def other_group_movers(self, p: Perception) -> list[int] | np.ndarray:
        """Indices of the robots of another group in Coverage within d_cover with a larger id."""
        k = within(p.distances, self.p.d_cover)
        m = p.messages[:k]  # distances are sorted: the first k are within d_cover
        if k <= SMALL_VIEW:  # the same indices, over Python values
            return [j for j, (group, sender, status) in enumerate(zip(
                m["group"].tolist(), m["id"].tolist(), m["status"].tolist()))
                if group != self.group and sender > self.id and status == COVERAGE]
        return ((m["group"] != self.group) & (m["id"] > self.id)
                & (m["status"] == COVERAGE)).nonzero()[0]

    def stopped(self, p: Perception) -> Action:
        """Stop (Section 4.3): wait until no other group's mover is within d_cover (and, after
        a deadlock, T_s ticks: Algorithm 6). Waiting does not count as making no progress.

        With ``stop_patience`` > 0, a robot off the target that has waited that many ticks
        goes on while the mover is still there, and does not Stop for other groups for the
        next T_s ticks. On the target it waits as long as the paper says.
        """
        self.progress_tick = p.tick
        self.odometer[:] = 0.0
        if p.tick < self.resume_tick:
            return self.act()
        if self.other_group_mover(p):
            patience = self.p.stop_patience
            if not patience or p.on_target or p.tick - self.stop_since < patience:
                return self.act()
            self.pass_until = p.tick + self.p.T_s  # waited long enough: go, and pass
        self.set_status(COVERAGE)
        return self.coverage(p)

    def give_way(self, p: Perception, velocity: np.ndarray) -> np.ndarray | None:
        """Give way to a moving robot with a larger id close ahead (ids break symmetry).

        If it is coming toward us, back away from it so that it can pass; if it goes our
        way, wait. Returns the velocity to use instead, or None to carry on.
        """
        ahead = self.pre.ahead if self.pre is not None else self.movers_outranking(p)
        if len(ahead) == 0:
            return None
        ahead = np.asarray(ahead, dtype=np.intp)
        ahead = ahead[p.offsets[ahead] @ velocity > 0]
        if len(ahead) == 0:
            return None
        other = ahead[0]
        if p.distances[other] < self.p.yield_distance * 0.75:
            return -unit(p.offsets[other]) * self.p.v * 0.5
        return np.zeros(2)

    def movers_outranking(self, p: Perception) -> list[int] | np.ndarray:
        """Indices of the moving robots with a larger id within yield_distance."""
        k = within(p.distances, self.p.yield_distance)
        m = p.messages[:k]  # distances are sorted: the first k are within yield_distance
        if k <= SMALL_VIEW:  # the same indices, over Python values
            return [j for j, (moving, sender) in enumerate(zip(
                m["moving"].tolist(), m["id"].tolist())) if moving and sender > self.id]
        return (m["moving"] & (m["id"] > self.id)).nonzero()[0]

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

    # ------------------------------------------------------------------ Arrive
    def arrive(self, p: Perception) -> Action:
        return self.act(sleep=True, wake_range=0.0)


def widest_gap(offsets: np.ndarray) -> float:
    """Widest angle (radians) between the bearings of two or more neighbours (k, 2)."""
    if len(offsets) <= SMALL_VIEW:  # the same angles and differences, in Python floats
        angles = sorted(math.atan2(y, x) for x, y in offsets.tolist())
        return max(max(b - a for a, b in pairwise(angles)),
                   angles[0] + 2 * math.pi - angles[-1])
    angles = np.sort(np.arctan2(offsets[:, 1], offsets[:, 0]))
    return max(float((angles[1:] - angles[:-1]).max()),
               float(angles[0]) + 2 * math.pi - float(angles[-1]))
