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
  sense; gradient = 1 + the gradient of the nearest stationary neighbour (with groups: of its
  own group, within 1.5 d_cover).
  Stop (Arrive) on the target when the probe ahead leaves it, or beside an arrived robot whose
  gradient is >= ours, at d_cover from it. A robot outside the target never stops.
* Robust edges: a robot that circles one robot all the way round, or moves less than theta in
  T_r ticks, arrives if it is on the target and otherwise carries on (toward the beacon when it
  is circling a lone robot outside).
"""

from __future__ import annotations

import numpy as np

from controllers.edges import CirclingWatch, ProgressWatch
from controllers.gradient import INF_GRADIENT
from controllers.views import any_of, within
from swarmsim.controller import (
    NO_SENDER,
    Action,
    Perception,
    RobotSetup,
    make_action,
)

from .aggregation import AGGREGATION_FIELDS, MAX_GROUPS, Aggregation, aggregation_fields
from .batch import Precomputed, WaitingAnswers
from .book import BookRow, EdgeBook
from .collisions import CollisionRules
from .coverage import CoverageRules
from .detection import DetectionRules
from .fastpath import BatchDecisions
from .geometry import SMALL_VIEW
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
from .surplus import SurplusLap

MESSAGE_FIELDS = [("gradient", "i4"), ("group", "i2"), ("leader", "?"), ("cmd", "i1"),
                  ("vx", "f4"), ("vy", "f4"), ("touch", "?"), ("stepped", "?"),
                  ("enclosed", "?"), *AGGREGATION_FIELDS]
"""GGC's broadcast fields for up to MAX_GROUPS groups (a run uses :func:`message_fields`)."""


def message_fields(groups: int) -> list[tuple]:
    """GGC's broadcast fields for a run with this many groups: the per-group fields of the
    scattered start have one entry per group (a smaller row is cheaper to gather and copy)."""
    return [*MESSAGE_FIELDS[:-len(AGGREGATION_FIELDS)], *aggregation_fields(groups)]


class GGCRobot(BookRow, DetectionRules, CoverageRules, BatchDecisions, CollisionRules,
               SurplusLap, Aggregation, CirclingWatch, ProgressWatch):
    """One robot's GGC controller: its state, broadcasts and the Initial status (travel)
    here; Detection in detection.py, Coverage in coverage.py, the surplus lap in surplus.py,
    Stop and deadlocks in collisions.py; the common cases a chunk at a time in fastpath.py
    (the Coverage movers' geometry as arrays in movers.py); the scattered start's leader
    selection, grouping
    and aggregation in aggregation.py. Its edge-following state lives in its row of a
    run-wide :class:`~controllers.ggc.book.EdgeBook` (``create_robots`` makes one for the
    run; a robot made on its own gets a book of one row)."""

    def __init__(self, setup: RobotSetup, params: GGCParams, rng: np.random.Generator,
                 book: EdgeBook | None = None, row: int = 0):
        if setup.groups > MAX_GROUPS:
            raise ValueError(f"GGC supports at most {MAX_GROUPS} groups, got {setup.groups}")
        self.book = EdgeBook(1, params.orbit) if book is None else book
        self.row = 0 if book is None else row
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
        self.batch_coverage = not (params.own_edges or params.stop_ahead_only)  # fastpath.py
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
        return (self.id, self.status, self.status in MOVING_STATUSES, self.grad, self.group,
                self.leader, self.cmd, float(self.travel[0]),
                float(self.travel[1]), self.touch, self.stepped_in, self.enclosed,
                *self.aggregation_message())

    def set_status(self, status: int) -> None:
        if status != self.status:
            self.status = status
            self.history.append(status)
            if status in (ARRIVE, SURPLUS):
                self.in_deadlock = False  # settled: an open deadlock episode is over

    def act(self, velocity: np.ndarray | tuple = (0.0, 0.0), sleep: bool = False,
            wake_range: float | None = None, wake_on_motion: bool = True,
            wake_tick: int | None = None, repeat: bool = False) -> Action:
        """This tick's action with my broadcast (``repeat``: the caller knows it is the same
        as last tick's, so the engine repeats that row and no tuple is built)."""
        return make_action((float(velocity[0]), float(velocity[1])),
                           None if repeat else self.message(), sleep, wake_range,
                           self.listen_range(), wake_on_motion, wake_tick)

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
            return self.act(sleep=True, wake_range=1.5 * self.p.d_min,
                            wake_tick=self.initial_since + self.p.init_timeout)
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
