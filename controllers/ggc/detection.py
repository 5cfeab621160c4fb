"""GGC's Detection: a waiting robot's gradient and its turn to leave (Algorithms 1 and 7).

A robot of a formation that has reached the target takes 1 + the smallest gradient of its
group's stationary neighbours within 1.5 d_min (Algorithm 1) and starts to cover when no
neighbour within d_cover outranks it by (gradient, id) (Algorithm 7). A robot inside its
formation (enclosed) or pressed against it (``yield_count``) lets the others go first.
"""

from __future__ import annotations

import numpy as np

from controllers.views import any_of, within
from swarmsim.controller import NO_SENDER, Action, Perception

from .batch import BLOCKED_BY_MOVER, BLOCKED_BY_WAITING, NOT_BLOCKED
from .geometry import ENCLOSED_GAP, SMALL_VIEW, widest_gap
from .statuses import ARRIVE, COVERAGE, DETECTION, INITIAL, STOP, SURPLUS


class DetectionRules:
    """Mixin of :class:`~controllers.ggc.robot.GGCRobot`: the Detection status."""

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

    def start_coverage(self, p: Perception) -> None:
        self.choose_orbit()
        self.restart_lap()
        self.set_status(COVERAGE)
        self.odometer[:] = 0.0
        self.progress_tick = p.tick
