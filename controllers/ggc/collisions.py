"""GGC's collision rules between movers (Sections 4.3 and 4.4, Algorithms 5 and 6).

* Stop (Section 4.3): a mover that senses a mover of another group in Coverage within
  d_cover, with a larger id, stops until that robot has gone.
* Deadlock (Equation 3): a mover whose displacement over T_r ticks is at most theta is stuck.
  On the target it arrives where it is (with groups: when a robot in Stop is near,
  Algorithm 5) or stops for T_s ticks (Algorithm 6); off the target it turns round, and a
  mover wedged against its own formation waits in Detection again.
* Giving way: a mover yields to a moving robot with a larger id close ahead.
"""

from __future__ import annotations

import numpy as np

from controllers.views import any_of, within
from swarmsim.controller import Action, Perception

from .geometry import SMALL_VIEW, unit
from .statuses import COVERAGE, DETECTION, STOP


class CollisionRules:
    """Mixin of :class:`~controllers.ggc.robot.GGCRobot`: Stop, deadlocks and giving way."""

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
        vx, vy = float(velocity[0]), float(velocity[1])
        ahead = [r for r, (x, y) in zip(ahead, p.offsets[ahead].tolist(), strict=True)
                 if x * vx + y * vy > 0]  # IEEE products and sum, as the compiled kernel
        if not ahead:
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
