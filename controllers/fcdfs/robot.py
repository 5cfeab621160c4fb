"""One FCDFS robot at a time (a per-robot controller, :class:`FCDFSRobot`): the reference
implementation of :class:`controllers.fcdfs.FCDFS`, whose swarm (swarm.py, chunk.py) makes the
very same runs (tests/controllers/baselines/test_fcdfs_swarm.py). The rules:
controllers/fcdfs/controller.py.
"""

from __future__ import annotations

import numpy as np

from controllers.common.formation import CMD_HALT, CMD_NONE, CMD_TRAVEL, FormationTravel, unit
from controllers.common.gradient import INF_GRADIENT
from swarmsim.controller import Action, Perception, RobotSetup, make_action

from .params import (
    AXES,
    DOOR,
    MAX_HOPS,
    MIN_PROBE_RANGE,
    MOVING,
    NO_DOOR,
    QUEUE,
    SETTLED,
    TRAVEL,
    FCDFSDeclarations,
    FCDFSParams,
    add,
    neg,
    rotate,
)


class FCDFSRobot(FCDFSDeclarations, FormationTravel):
    """One FCDFS robot: enter through a door in a line, settle in lattice corners (the
    reference of :class:`~controllers.fcdfs.FCDFS`)."""

    def __init__(self, setup: RobotSetup, params: FCDFSParams, rng: np.random.Generator):
        self.id = setup.robot_id
        self.group = setup.group
        self.leader = setup.leader
        self.params = params
        self.status = TRAVEL
        self.grad = 0 if self.leader else INF_GRADIENT
        self.cmd = CMD_NONE
        self.travel = np.zeros(2)
        self.door = NO_DOOR
        self.pdir = 1
        self.touch = False
        self.hops = INF_GRADIENT
        self.cell = (0, 0)          # current lattice cell (moving/settled), door at (0, 0)
        self.goal: tuple[int, int] | None = None
        self.history: list[tuple[int, int]] = []
        self.pos = np.zeros(2)      # position relative to the door (dead reckoning), units
        self.waited = 0
        self.stepping = False       # the door robot is still stepping in
        self.stepped = 0.0

    # ------------------------------------------------------------------ messages
    def act(self, velocity=(0.0, 0.0), sleep: bool = False,
            wake_range: float | None = None, wake_tick: int | None = None) -> Action:
        c = self.goal if (self.status == MOVING and self.goal is not None) else self.cell
        # the gradient field keeps the formation gradient (travel parents are chosen by it);
        # robots on the lattice show their lattice distance from the door instead
        grad = self.grad if self.status in (TRAVEL, QUEUE, DOOR) else abs(c[0]) + abs(c[1])
        moving = self.status == MOVING or (self.status in (QUEUE, DOOR) and bool(np.any(velocity)))
        msg = (self.id, self.status, moving, grad, self.group, self.leader, self.cmd,
               float(self.travel[0]), float(self.travel[1]), self.door, self.pdir, self.touch,
               self.hops, c[0], c[1])
        return make_action((float(velocity[0]), float(velocity[1])), msg, sleep, wake_range,
                           self.listen_range(), wake_tick=wake_tick)

    def listen_range(self) -> float | None:
        """How far this robot needs to hear next tick (less is cheaper)."""
        if self.status == TRAVEL and not self.leader:
            return 1.5 * self.params.d_min
        if self.status in (SETTLED, DOOR):
            return self.params.d_safe
        return None

    def step(self, perception: Perception) -> Action:
        self.pos = self.pos + perception.moved
        if self.status == TRAVEL:
            self.touch = perception.on_target
            return self.lead(perception) if self.leader else self.follow(perception)
        if self.status == QUEUE:
            return self.queue(perception)
        if self.status == MOVING:
            return self.moving(perception)
        if self.status == DOOR and self.stepping:
            return self.door_step(perception)
        return self.act(sleep=True, wake_range=0.0)

    # ------------------------------------------------------------------ travel (formation)
    def formation_gradient(self, perception: Perception) -> int | None:
        """1 + the smallest formation gradient of halted or travelling neighbours nearby."""
        m = perception.messages
        ok = (perception.distances <= 1.5 * self.params.d_min) & self.heard(perception)
        ok &= (m["status"] == TRAVEL) | (m["status"] == QUEUE) | (m["status"] == DOOR)
        ok &= m["gradient"] < INF_GRADIENT
        if not ok.any():
            return None
        return int(m["gradient"][ok].min()) + 1

    def lead(self, perception: Perception) -> Action:
        """Head for the beacon; halt when a robot (or the leader) reports target floor."""
        m = perception.messages
        touching = np.flatnonzero(m["touch"] & self.heard(perception) & (m["status"] == TRAVEL))
        if perception.on_target or len(touching) or perception.beacon is None:
            self.cmd, self.travel = CMD_HALT, np.zeros(2)
            self.door = self.id if (perception.on_target or not len(touching)) else int(
                m["id"][touching[0]])
            if perception.beacon is not None:
                self.pdir = int(np.argmax([perception.beacon @ np.array(a) for a in AXES]))
            return self.halt(perception)
        self.cmd, self.travel = CMD_TRAVEL, perception.beacon * self.params.v
        return self.act(self.travel)

    def follow(self, perception: Perception) -> Action:
        cmd = self.follow_travel(perception)
        if cmd is None:
            if perception.tick >= self.params.init_timeout:
                self.cmd = CMD_HALT
                return self.halt(perception)
            return self.act(sleep=True, wake_range=1.5 * self.params.d_min,
                            wake_tick=self.params.init_timeout)  # then the timeout above
        if cmd == CMD_HALT:
            parent = self.travel_parent(perception)
            self.door, self.pdir = int(parent["door"]), int(parent["pdir"])
            return self.halt(perception)
        return self.act(self.travel)

    def halt(self, perception: Perception) -> Action:
        if self.door == self.id:
            self.status, self.hops, self.cell = DOOR, 0, (0, 0)
            self.stepping = True
            return self.door_step(perception)
        self.status = QUEUE
        return self.act()

    def door_step(self, perception: Perception) -> Action:
        """The door robot moves along P until door_depth of target floor lies behind it."""
        P = np.array(AXES[self.pdir], dtype=float)
        if (self.stepping and not perception.probe(-P * self.params.door_depth)
                and perception.probe(P * self.params.door_depth)
                and self.stepped < 4 * self.params.door_depth):
            self.stepped += self.params.v
            return self.act(P * self.params.v)
        self.stepping = False
        return self.act(sleep=True, wake_range=0.0)

    # ------------------------------------------------------------------ queue (the line)
    def queue(self, perception: Perception) -> Action:
        m = perception.messages
        heard = self.heard(perception)
        if self.door == NO_DOOR:
            known = np.flatnonzero(heard & (m["door"] != NO_DOOR))
            if len(known):
                self.door, self.pdir = int(m["door"][known[0]]), int(m["pdir"][known[0]])
        link = ((perception.distances <= 2.0 * self.params.d_min) & heard
                & (m["hops"] < INF_GRADIENT))
        link &= ((m["status"] == QUEUE) | (m["status"] == DOOR)) & (m["door"] == self.door)
        sees_door = bool((heard & (m["id"] == self.door)).any())
        hops = 1 if sees_door else (int(m["hops"][link].min()) + 1 if link.any() else INF_GRADIENT)
        self.hops = hops if hops <= MAX_HOPS else INF_GRADIENT  # no counting to infinity
        movers = ((m["status"] == MOVING) & heard
                  & (perception.distances <= self.params.avoid_range + 0.5))
        if movers.any():  # make way for a robot entering the lattice
            k = int(np.flatnonzero(movers)[0])
            away = -perception.offsets[k] / max(float(perception.distances[k]), 1e-9)
            share = 1.0 if self.clear_ahead(perception, away) else 0.5
            return self.act(away * self.params.v * share)
        at = np.flatnonzero((m["id"] == self.door) & heard)
        if len(at):
            door = perception.offsets[int(at[0])]
            if m["moving"][int(at[0])]:  # the door robot is still stepping in: wait
                return self.queue_sleep(float(np.hypot(*door)) + 0.5)
            candidate = float(np.hypot(*door)) <= self.params.door_radius
            if candidate:
                entered = self.try_enter(perception, door)
                if entered is not None:
                    return entered
            # queue behind the door (on the side away from the lattice), so that the way from
            # the door into the lattice stays clear
            goal = door - np.array(AXES[self.pdir], dtype=float) * 0.6 * self.params.door_radius
            wake = self.params.clearance + self.params.door_radius + 0.5 if candidate else None
            if float(np.hypot(*goal)) <= self.params.queue_gap:
                return self.queue_sleep(wake or self.params.queue_gap + 0.5)
        else:
            wake = None
            parents = np.flatnonzero(link & (m["hops"] < self.hops))
            if not len(parents):
                return self.queue_sleep(2.0 * self.params.d_min)
            goal = perception.offsets[int(parents[0])]
        heading = unit(goal)
        if not self.clear_ahead(perception, heading):
            return self.queue_sleep(wake or self.params.queue_gap + 0.5)
        return self.act(heading * self.params.v)

    def queue_sleep(self, wake_range: float) -> Action:
        """Sleep in the queue until a robot within ``wake_range`` moves, or within the range at
        which a queued robot makes way for an entering one (avoid_range + 0.5): a shorter
        wake range slept through it."""
        return self.act(sleep=True, wake_range=max(wake_range, self.params.avoid_range + 0.5))

    def clear_ahead(self, perception: Perception, heading: np.ndarray) -> bool:
        """No robot within queue_gap in a 60-degree cone around ``heading``."""
        ahead = ((perception.distances <= self.params.queue_gap)
                 & (perception.offsets @ heading > 0.5 * perception.distances))
        return not ahead.any()

    def try_enter(self, perception: Perception, door: np.ndarray) -> Action | None:
        """Step onto the entry cell if it is my turn and the entry cell is free."""
        m = perception.messages
        heard = self.heard(perception)
        from_door = np.hypot(*(perception.offsets - door).T)
        heard &= m["door"] == self.door
        if ((m["status"] == MOVING) & heard & (from_door <= self.params.clearance)).any():
            return None
        mine = float(np.hypot(*door))
        rivals = heard & (m["status"] == QUEUE) & (from_door <= self.params.door_radius)
        tie = np.abs(from_door - mine) <= 1e-6
        rivals &= ((from_door < mine) & ~tie) | (tie & (m["id"] < self.id))
        if rivals.any():
            return None
        self.pos = -door
        entry = self.entry_cell(perception)
        if entry is None or self.settled_at(perception, entry) or self.active_at(perception, entry):
            return None
        self.status = MOVING
        self.cell, self.history, self.goal, self.waited = (0, 0), [], entry, 0
        return self.moving(perception)

    def entry_cell(self, perception: Perception) -> tuple[int, int] | None:
        """The door's first neighbouring cell (P, S, -S, -P order) on the target floor."""
        P = AXES[self.pdir]
        S = rotate(P, self.params.turn)
        for d in (P, S, neg(S), neg(P)):
            if not self.wall(perception, d):
                return d
        return None

    # ------------------------------------------------------------------ moving (FCDFS)
    def centre(self, c: tuple[int, int]) -> np.ndarray:
        return np.array(c, dtype=float) * self.params.spacing

    def wall(self, perception: Perception, c: tuple[int, int]) -> bool:
        """The floor at the centre of cell c is not target (out of probe reach counts as wall)."""
        offset = self.centre(c) - self.pos
        if float(offset @ offset) > MIN_PROBE_RANGE ** 2:
            return True
        return not perception.probe(offset)

    def settled_at(self, perception: Perception, c: tuple[int, int]) -> bool:
        """A settled robot holds cell c: one of this door's lattice, or any settled robot
        standing within half a cell of its centre (another group's lattice)."""
        m = perception.messages
        done = ((m["status"] == SETTLED) | (m["status"] == DOOR)) & self.heard(perception)
        mine = done & (m["door"] == self.door)
        if (mine & (m["ci"] == c[0]) & (m["cj"] == c[1])).any():
            return True
        other = done & ~mine
        if not other.any():
            return False
        there = self.pos + perception.offsets[other] - self.centre(c)
        return bool((np.hypot(*there.T) < 0.5 * self.params.spacing).any())

    def blocked(self, perception: Perception, c: tuple[int, int]) -> bool:
        """A wall or a settled robot (the door robot holds cell (0, 0))."""
        return c == (0, 0) or self.settled_at(perception, c) or self.wall(perception, c)

    def active_at(self, perception: Perception, c: tuple[int, int]) -> bool:
        """Another moving robot is heading to cell c or standing in it."""
        m = perception.messages
        moving = (m["status"] == MOVING) & self.heard(perception)
        if (moving & (m["door"] == self.door) & (m["ci"] == c[0]) & (m["cj"] == c[1])).any():
            return True
        there = self.pos + perception.offsets[moving] - self.centre(c)
        return bool((np.hypot(*there.T) < 0.5 * self.params.spacing).any()) if len(there) else False

    def decide(self, perception: Perception) -> tuple[int, int] | str | None:
        """FCDFS rules at the current cell: the next cell, "settle", or None (wait)."""
        c = self.cell
        P = AXES[self.pdir]
        S = rotate(P, self.params.turn)
        for d in (P, S):
            nxt = add(c, d)
            if not self.blocked(perception, nxt):
                return None if self.active_at(perception, nxt) else nxt
        came = (self.history[-1][0] - c[0], self.history[-1][1] - c[1]) if self.history \
            else neg(P)
        free = [a for a in AXES if not self.blocked(perception, add(c, a))]
        if len(free) <= 1:
            # a dead end, if the robot came in through its one free side; at the entry cell
            # (entered from the door robot's cell) the free side leads on: turn there
            if not free or free[0] == came:
                return "settle"
            return self.turn_to(perception, free[0])
        diag = add(c, neg(add(P, S)))
        if ((len(self.history) >= 2 and self.history[-2] == diag)
                or not self.blocked(perception, diag)):
            return "settle"
        return self.turn_to(perception, neg(S) if neg(P) == came else neg(P))

    def turn_to(self, perception: Perception, d: tuple[int, int]) -> tuple[int, int] | None:
        """Make ``d`` the primary direction and head one cell that way (None: wait)."""
        self.pdir = AXES.index(d)
        nxt = add(self.cell, d)
        return None if self.active_at(perception, nxt) else nxt

    def moving(self, perception: Perception) -> Action:
        if self.goal is not None and self.settled_at(perception, self.goal):
            self.goal = None  # someone settled there first: choose again from this cell
        if self.goal is None:  # (goal dropped on the way) back to the current cell first
            to_cell = self.centre(self.cell) - self.pos
            if float(np.hypot(*to_cell)) > self.params.arrive_tolerance:
                return self.go(perception, to_cell)
        else:
            to_goal = self.centre(self.goal) - self.pos
            if float(np.hypot(*to_goal)) > self.params.arrive_tolerance:
                return self.go(perception, to_goal)
            if self.cell != (0, 0):  # the door robot's cell is a wall, not a visited cell
                self.history.append(self.cell)
            self.cell, self.goal = self.goal, None
        if self.cell == (0, 0):  # lost the entry cell on the way in: back to the line
            self.status = QUEUE
            return self.act()
        choice = self.decide(perception)
        if choice == "settle":
            return self.settle()
        if choice is None:
            self.waited += 1
            if self.waited >= self.params.patience:
                return self.settle()
            return self.act()
        self.waited = 0
        self.goal = choice
        return self.go(perception, self.centre(choice) - self.pos)

    def settle(self) -> Action:
        self.status = SETTLED
        self.goal = None
        return self.act(sleep=True, wake_range=0.0)

    def go(self, perception: Perception, to_goal: np.ndarray) -> Action:
        """Head for the goal at speed v, side-stepping robots close ahead."""
        dist = float(np.hypot(*to_goal))
        v = unit(to_goal) * min(self.params.v, dist)
        close = (perception.distances <= self.params.avoid_range) & (perception.distances > 1e-9)
        for k in np.flatnonzero(close):
            u = perception.offsets[k] / perception.distances[k]
            toward = float(v @ u)
            if toward > 0:
                v = v - toward * u + rotate_vec(u, self.params.turn) * toward
        v = unit(v) * min(self.params.v, dist)
        return self.act(v)


def rotate_vec(u: np.ndarray, turn: int) -> np.ndarray:
    """A unit vector turned 90 degrees (side-step direction)."""
    return np.array([-u[1], u[0]]) if turn > 0 else np.array([u[1], -u[0]])


__all__ = ["FCDFSRobot", "rotate_vec"]
