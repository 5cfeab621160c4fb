"""Robot failures injected at a phase of the run (paper Sections 5 and 6.6, Figure 23).

How a robot fails is the plan's mode (:meth:`swarmsim.engine.sim.Simulation.fail`):

* ``"dead"`` (the default, every controller's): it stops moving and communicating but stays a
  physical body that others must go around.
* a mode its controller declares (``FAILURE_MODES``: name -> meaning; the engine knows no
  controller's modes): the engine tells the failing robots' controllers, which simulate it
  (``fail(mode)``; see swarmsim.controller.ControllerClass); the robots keep working. GGC's
  ``"no_gradient"`` is the paper's gradient-phase failure: the robot's gradient is lost and
  it sets off to cover first.

A :class:`FaultPlan` says how many robots fail, how and when:

* ``"gradient"``: during gradient formation: at the end of the first tick on which some robot
  has left the controller's ``INITIAL_STATUSES`` (GGC: the formation has reached the target
  and the gradient is being (re)built). Controllers that declare none fail robots at tick 1.
* ``"coverage"``: at the end of the first tick on which some robot broadcasts ``moving = True``
  or one of the controller's ``COVERING_STATUSES`` (the first robot sets off to cover).
* ``"tick"``: at the end of the given tick.

Which robots fail (the rule): ``count`` robots drawn uniformly at random, without replacement,
from the robots that are still working, are not a (group) leader (the controller's
``LEADER_FIELD``) and have not already settled (its ``SETTLED_STATUSES``): those are the robots whose failure the paper studies (a robot
that cannot get its gradient, or that stops on its way). Failing a leader would remove its whole
group, and failing an arrived robot only silences a robot that is done. If fewer eligible robots
are left than ``count``, the rest are drawn from the arrived robots, and leaders only last.

The draw uses its own numpy Generator derived from the run seed (:func:`fault_rng`), so the run
stays reproducible and its other random streams are unchanged by failures.

Run settings ``failures``, ``failure_phase``, ``failure_tick`` and ``failure_mode`` (see
:class:`swarmsim.engine.config.SimConfig`) build the plan, e.g.
``swarmsim run K --set failures=10 --set failure_phase=gradient --set failure_mode=no_gradient``.
"""

from __future__ import annotations

from dataclasses import dataclass
from typing import Any, Protocol

import numpy as np

from swarmsim.engine.config import DEAD
from swarmsim.engine.controller_info import ControllerInfo
from swarmsim.engine.hooks import Hook
from swarmsim.errors import ConfigError

PHASES = ("gradient", "coverage", "tick")
FAULT_STREAM = 0xFA17
"""Spawn key of the fault Generator's SeedSequence (distinct from the run's other streams)."""


@dataclass(frozen=True)
class FaultPlan:
    """How many robots fail, how and when.

    Attributes:
        count: number of robots that fail (0 = none).
        phase: "gradient", "coverage" or "tick" (see the module docstring).
        tick: the tick at which they fail, for phase "tick" (>= 1).
        mode: how they fail: "dead" or a mode the run's controller declares (the run checks
            that it does: Simulation).
    """

    count: int = 0
    phase: str = "coverage"
    tick: int | None = None
    mode: str = DEAD

    def __post_init__(self) -> None:
        if isinstance(self.count, bool) or not isinstance(self.count, int) or self.count < 0:
            raise ConfigError(f"must be an integer >= 0, got {self.count!r}", key="failures")
        if self.phase not in PHASES:
            raise ConfigError(f"must be one of {', '.join(PHASES)}, got {self.phase!r}",
                              key="failure_phase")
        if self.phase == "tick" and self.count and (self.tick is None or self.tick < 1):
            raise ConfigError(f"failure_phase 'tick' needs failure_tick >= 1, got {self.tick!r}",
                              key="failure_tick")

    @classmethod
    def from_config(cls, config: Any) -> FaultPlan:
        """The plan of a SimConfig's ``failures``, ``failure_phase``, ``failure_tick`` and
        ``failure_mode``."""
        tick = int(getattr(config, "failure_tick", 0)) or None
        return cls(int(getattr(config, "failures", 0)),
                   str(getattr(config, "failure_phase", "coverage")), tick,
                   str(getattr(config, "failure_mode", DEAD)))


def fault_rng(seed: int) -> np.random.Generator:
    """The Generator that picks failing robots, derived from the run seed."""
    return np.random.default_rng(np.random.SeedSequence(seed, spawn_key=(FAULT_STREAM,)))


class FaultTarget(Protocol):
    """What a fault hook sees of a run (a Simulation is one)."""

    n: int
    tick: int
    info: ControllerInfo
    messages: np.ndarray
    failed: np.ndarray

    def fail(self, robots: np.ndarray, mode: str = DEAD) -> None: ...


class FaultInjector(Hook):
    """A loop hook (swarmsim.engine.hooks) that fails the plan's robots once, at the end of the
    tick on which its phase starts (after the physics step, before the tick's metrics).

    After firing, ``fired_tick`` is the tick and ``robots`` the indices of the failed robots.
    """

    def __init__(self, plan: FaultPlan, rng: np.random.Generator):
        self.plan = plan
        self.rng = rng
        self.fired_tick: int | None = None
        self.robots: np.ndarray = np.zeros(0, dtype=np.intp)

    def post_step(self, sim: FaultTarget) -> None:
        if self.fired_tick is None and self.plan.count > 0 and self.due(sim):
            self.robots = self.choose(sim)
            sim.fail(self.robots, self.plan.mode)
            self.fired_tick = sim.tick

    def due(self, sim: FaultTarget) -> bool:
        """Has the plan's phase begun (at the end of the current tick)?"""
        if self.plan.phase == "tick":
            return sim.tick >= (self.plan.tick or 1)
        info = sim.info
        msgs = sim.messages[~sim.failed]
        heard = msgs["status"] >= 0  # silent rows (nothing broadcast yet) have status -1
        if self.plan.phase == "gradient":
            initial = info.codes(info.initial)
            if not initial:
                return True
            return bool((heard & ~np.isin(msgs["status"], initial)).any())
        moving = msgs["moving"] & heard
        return bool(moving.any()
                    or np.isin(msgs["status"][heard], info.codes(info.covering)).any())

    def choose(self, sim: FaultTarget) -> np.ndarray:
        """Indices of the robots that fail (the rule of the module docstring), sorted."""
        info = sim.info
        msgs = sim.messages
        working = ~sim.failed
        leader = (msgs[info.leader_field].astype(bool) if info.leader_field
                  else np.zeros(len(msgs), dtype=bool))
        arrived = np.isin(msgs["status"], info.codes(info.settled))
        tiers = (working & ~leader & ~arrived, working & ~leader & arrived, working & leader)
        chosen: list[np.ndarray] = []
        need = self.plan.count
        for tier in tiers:
            pool = np.flatnonzero(tier)
            take = min(need, len(pool))
            if take:
                chosen.append(self.rng.choice(pool, size=take, replace=False))
                need -= take
            if need == 0:
                break
        if not chosen:
            return np.zeros(0, dtype=np.intp)
        return np.sort(np.concatenate(chosen)).astype(np.intp)


def fault_injector(plan: FaultPlan, robots: int, rng: np.random.Generator
                   ) -> FaultInjector | None:
    """The hook that makes ``plan.count`` of a run's ``robots`` fail when the plan's phase
    begins, or None when the plan fails no robot (ConfigError if it fails more robots than
    the run has). The run puts it before its metrics in ``Simulation.hooks``."""
    if plan.count <= 0:
        return None
    if plan.count > robots:
        raise ConfigError(f"{plan.count} failures need at least as many robots "
                          f"(robots = {robots})", key="failures")
    return FaultInjector(plan, rng)


__all__ = ["PHASES", "FaultInjector", "FaultPlan", "fault_injector", "fault_rng"]
