"""GGC from a scattered start (paper Sections 4.1-4.2): leaders, groups, aggregation.

Every robot has a clock, so the phases follow from the tick (T = ``T_settle``):

* Ticks [0, (h_max + 1) T): **leader selection** (Algorithm 3, Equation 2). Each leader is the
  source of a distance field: every robot keeps, per group, the shortest known path length to
  that group's leader (1 + min over neighbours of their estimate plus the distance to them;
  Bellman-Ford over the communication graph, within R_c). Fields carry an epoch that the
  leader bumps every T ticks, so estimates follow leaders that move or change. Every T ticks
  a leader with hop budget h > 0 hands leadership to the neighbour whose summed field distance
  to the other leaders is largest, if larger than its own (Equation 2, with path length for
  distance: robots know no positions), with budget h - 1; with no such neighbour h drops by
  one. Leaders with h = 0 are final.
* From then on, **grouping** (Algorithm 4): a robot without a group joins the group of its
  nearest neighbour that has one (a breadth-first wave out of the leaders, one hop a tick).
* **Aggregation** (Figure 7): Approach: walk down the own group's field toward the leader;
  Pend: wait while an own-group robot that is closer to the leader is moving within 1.5 d_min
  ahead; Join: next to the formation, circle it at d_min until two formed robots (the leader
  alone, at first) are at d_min: then Formed (the paper's aggregation Arrive). The leader is
  Formed from the start.
* **Departure**: formed robots relay a "quiet" count (0 when they hear an own-group robot that
  is not formed yet, else 1 + the smallest of their formed neighbours'); once the leader's count
  reaches ``T_quiet`` it switches to Initial and leads the formation to the target; formed
  robots switch to Initial as the wave reaches them, and the one-group controller takes over.
  A robot still not formed ``aggregation_timeout`` ticks into the aggregation gives up and
  covers on its own (Detection with an infinite gradient).
"""

from __future__ import annotations

import numpy as np

from controllers.views import any_of, within
from swarmsim.controller import NO_SENDER, Action, Perception

from .geometry import unit
from .statuses import APPROACH, FORMED

MAX_GROUPS = 16
"""Largest number of groups a run may have (the size of the per-group field in messages)."""
FAR = 1e9
"""Field distance of a leader not heard of yet (units)."""
QUIET_CAP = 10_000


def aggregation_fields(groups: int = MAX_GROUPS) -> list[tuple]:
    """The scattered start's broadcast fields: one leader distance and epoch per group."""
    return [("h", "i1"), ("handover", "i4"), ("ldist", "f4", (groups,)),
            ("lepoch", "i4", (groups,)), ("quiet", "i4")]


AGGREGATION_FIELDS = aggregation_fields()


def status_in(status: np.ndarray, statuses: tuple[int, ...]) -> np.ndarray:
    """``np.isin(status, statuses)`` for a few statuses, without isin's overhead."""
    out = status == statuses[0]
    for s in statuses[1:]:
        out |= status == s
    return out


class Aggregation:
    """Mixin for GGCRobot: the scattered-start phases. Needs the robot's p, id, group,
    groups, leader, status, set_status, act and the status constants of robot.py."""

    def init_aggregation(self) -> None:
        self.h = self.p.h_max if self.leader else 0
        self.ldist = np.full(self.groups, FAR)  # one entry per group of the run
        self.lepoch = np.zeros(self.groups, dtype=np.int64)
        if self.leader:
            self.ldist[self.group - 1] = 0.0
        self.handover = NO_SENDER
        self.handover_tick = -1
        self.quiet = 0

    def aggregation_message(self) -> tuple:
        return (self.h, self.handover, self.ldist, self.lepoch, self.quiet)  # ldist: f8 -> f4

    @property
    def selection_ticks(self) -> int:
        """Length of the leader-selection phase (ticks)."""
        return (self.p.h_max + 1) * self.p.T_settle

    # ------------------------------------------------------------------ fields
    def update_fields(self, p: Perception) -> None:
        """One Bellman-Ford step of every leader's distance field (newest epoch wins)."""
        m = p.messages
        ok = m["id"] != NO_SENDER
        source = self.leader and self.handover == NO_SENDER  # handing over: no longer one
        if source:
            k = self.group - 1
            if p.tick % self.p.T_settle == 0:
                self.lepoch[k] += 1  # refresh: the field follows the leader's moves
            self.ldist[k] = 0.0
        if not any_of(ok):
            return
        g = self.groups  # fields of groups that do not exist stay FAR at epoch 0
        epochs = m["lepoch"][ok, :g]
        through = m["ldist"][ok, :g] + p.distances[ok][:, None]
        newest = epochs.max(axis=0)
        best = np.where(epochs == newest, through, FAR).min(axis=0)
        newer = newest > self.lepoch[:g]
        fresh = np.where(newer, best, np.minimum(self.ldist[:g], best))
        if source:
            fresh[self.group - 1] = 0.0
            newer[self.group - 1] = False
        self.ldist[:g] = np.minimum(fresh, FAR)
        self.lepoch[:g] = np.where(newer, newest, self.lepoch[:g])

    # ------------------------------------------------------------------ Algorithm 3
    def select_leaders(self, p: Perception) -> Action:
        self.update_fields(p)
        m = p.messages
        if not self.leader:
            self.take_over(p)
        elif self.handover != NO_SENDER:
            self.settle_handover(p)
        elif self.h > 0 and p.tick % self.p.T_settle == self.p.T_settle - 1:
            self.hand_over(p, m)
        return self.act()

    def settle_handover(self, p: Perception) -> None:
        """Two ticks after handing over (its broadcast, then the successor's), step down if the
        successor now leads my group; otherwise (two leaders picked the same robot, and it
        took over the other group) stay leader."""
        if p.tick < self.handover_tick + 2:
            return
        m = p.messages
        successor = (m["id"] == self.handover) & m["leader"] & (m["group"] == self.group)
        if any_of(successor):
            self.leader, self.group, self.handover = False, 0, NO_SENDER
            self.status = self.history[-1] = APPROACH
        else:
            self.handover = NO_SENDER

    def take_over(self, p: Perception) -> None:
        m = p.messages
        mine = np.flatnonzero((m["handover"] == self.id) & (m["id"] != NO_SENDER))
        if len(mine):
            giver = m[mine[0]]
            self.leader, self.group, self.h = True, int(giver["group"]), int(giver["h"])
            self.status = self.history[-1] = FORMED  # the leader is the formation's seed
            k = self.group - 1
            self.lepoch[k] = int(giver["lepoch"][k]) + 1
            self.ldist[k] = 0.0

    def hand_over(self, p: Perception, m: np.ndarray) -> None:
        """Equation 2: hand over to the neighbour farther from the other leaders, if any."""
        others = [j for j in range(self.groups) if j != self.group - 1]
        mine = float(self.ldist[others].sum()) if others else 0.0
        ok = (m["id"] != NO_SENDER) & ~m["leader"] & (m["handover"] == NO_SENDER)
        ok &= p.distances <= self.p.handover_reach
        self.h -= 1
        if not others or not any_of(ok) or mine >= FAR:
            return
        scores = np.where(ok, m["ldist"][:, others].astype(float).sum(axis=1), -1.0)
        best = int(np.argmax(scores))
        if mine < scores[best] < FAR:
            self.handover = int(m["id"][best])
            self.handover_tick = p.tick

    # ------------------------------------------------------------------ Algorithm 4
    def join_group(self, p: Perception) -> None:
        """Join the group of the nearest neighbour that has one (neighbours come sorted)."""
        m = p.messages
        grouped = np.flatnonzero((m["group"] > 0) & (m["id"] != NO_SENDER))
        if len(grouped):
            self.group = int(m["group"][grouped[0]])

    # ------------------------------------------------------------------ aggregation
    def gather(self, p: Perception) -> Action:
        """Approach / Pend / Join / Formed, then departure (see the module docstring)."""
        from .statuses import FORMED, GATHERING

        self.update_fields(p)
        if p.tick >= self.gather_deadline and self.status in GATHERING:
            return self.cover_alone(p)  # also a robot that never heard of a group
        if self.group == 0:
            self.join_group(p)
            return self.act()
        if self.status == FORMED:
            return self.formed(p)
        return self.approach(p)

    @property
    def gather_deadline(self) -> int:
        """The tick from which a robot not yet formed covers on its own (aggregation_timeout
        ticks after leader selection)."""
        return self.selection_ticks + self.p.aggregation_timeout + 1

    def own(self, p: Perception, statuses: tuple[int, ...]) -> np.ndarray:
        m = p.messages
        return (m["group"] == self.group) & status_in(m["status"], statuses) & (m["id"] != NO_SENDER)

    def approach(self, p: Perception) -> Action:
        from .statuses import APPROACH, FORMED, INITIAL, JOIN, PEND

        formed = np.flatnonzero(self.own(p, (FORMED, INITIAL)))
        if len(formed) and p.distances[formed[0]] <= 1.5 * self.p.d_min:
            return self.join(p, formed)
        velocity = self.toward_leader(p)
        if velocity is None or self.must_pend(p, velocity):
            self.set_status(PEND)
            # no way down the field yet: what can change that is any neighbour's broadcast
            # (toward_leader reads them all), or the timeout
            return self.act(sleep=velocity is None, wake_tick=self.gather_deadline)
        self.set_status(APPROACH if not len(formed) or p.distances[formed[0]] > 3 * self.p.d_min
                        else JOIN)
        return self.act(velocity)

    def toward_leader(self, p: Perception) -> np.ndarray | None:
        """Down the own group's field: toward the neighbour with the shortest path to the
        leader (straight at the leader when it is heard)."""
        m = p.messages
        k = self.group - 1
        ok = (m["id"] != NO_SENDER)
        lead = np.flatnonzero(ok & m["leader"] & (m["group"] == self.group))
        if len(lead):
            return unit(p.offsets[lead[0]]) * self.p.v
        via = np.where(ok, m["ldist"][:, k].astype(float) + p.distances, np.inf)
        if not len(via) or not np.isfinite(via.min()) or via.min() >= FAR:
            return None
        return unit(p.offsets[int(np.argmin(via))]) * self.p.v

    def must_pend(self, p: Perception, velocity: np.ndarray) -> bool:
        """Wait (Pend) while a gathering robot of my group that is nearer the leader than I
        am (by the field: a strict order, so no two robots wait for each other) is close
        ahead."""
        from .statuses import GATHERING

        k = within(p.distances, 1.2 * self.p.d_min)
        m = p.messages[:k]
        ahead = (m["group"] == self.group) & status_in(m["status"], GATHERING)
        ahead &= m["ldist"][:, self.group - 1] < self.ldist[self.group - 1]
        ahead &= p.offsets[:k] @ velocity > 0.5 * self.p.v * p.distances[:k]
        return any_of(ahead)

    def join(self, p: Perception, formed: np.ndarray) -> Action:
        """Circle the formation at d_min until two formed robots are at d_min: Formed."""
        from .statuses import FORMED, JOIN

        close = p.distances[formed] <= self.p.d_min + self.p.join_tolerance
        if close.sum() >= min(2, len(formed)):
            self.set_status(FORMED)
            return self.act()
        self.set_status(JOIN)
        nearest = formed[0]
        dist = float(p.distances[nearest])
        radial = p.offsets[nearest] / max(dist, 1e-9)
        tangent = np.array([radial[1], -radial[0]]) * self.sense
        error = max(-1.0, min(1.0, (dist - self.p.d_min) * 4.0))
        velocity = unit(tangent + error * radial) * self.p.v
        if self.must_pend(p, velocity):
            return self.act()
        return self.act(velocity)

    def formed(self, p: Perception) -> Action:
        """In the formation: relay the quiet count; depart when the leader's count is full."""
        from .statuses import GATHERING, INITIAL

        m = p.messages
        if any_of(self.own(p, GATHERING)):
            self.quiet = 0
        else:
            peers = self.own(p, (self.status,))
            below = int(m["quiet"][peers].min()) if any_of(peers) else self.quiet
            self.quiet = min(QUIET_CAP, min(below, self.quiet) + 1)
        near = (p.distances <= 1.5 * self.p.d_min) & self.own(p, (INITIAL,))
        if (self.leader and self.quiet >= self.p.T_quiet) or any_of(near):
            self.depart(p)
            return self.initial(p)
        return self.act()

    def depart(self, p: Perception) -> None:
        from .statuses import INITIAL

        self.set_status(INITIAL)
        self.initial_since = p.tick
        self.grad = 0 if self.leader else self.grad

    def cover_alone(self, p: Perception) -> Action:
        """Not formed in time (cut off from the group): cover on my own from now on.

        (Named apart from SurplusLap.give_up, which stops a mover for good: until 2026-11-27
        that method shadowed this one, and such robots stopped as Surplus where they were.)"""
        from .statuses import DETECTION

        self.set_status(DETECTION)
        return self.detection(p)
