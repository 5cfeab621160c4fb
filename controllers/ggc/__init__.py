"""GGC: gradient-and-grouping self-organising coverage (the paper's controller).

``--controller ggc``. The class here only declares: its parameters (params.py), statuses
(statuses.py), broadcast fields (state.py). The run's robots are one :class:`GGCSwarm`
(swarm.py): their state rows (state.py) and the compiled driver (decide.py) that decides each
robot by the rules in rules/, one module per rule family:

=============================  =============================================================
rule                           where
=============================  =============================================================
travel (Initial)               rules/travel.py
gradient (Algorithm 1, 2:8)    rules/gradient.py
detection (Algorithm 7)        rules/detection.py
coverage (Algorithm 2)         rules/coverage.py (edge following, boundary fill, giving way)
arrival (Algorithm 2's stops)  rules/arrival.py
inter-group (Section 4.3)      rules/intergroup.py (the rule sets, GGCParams.ruleset)
deadlock (Algorithms 5-6)      rules/deadlock.py
surplus                        rules/surplus.py
aggregation (Algorithms 3-4)   rules/aggregation.py (the scattered start)
=============================  =============================================================
"""

from __future__ import annotations

import math
from collections.abc import Sequence

import numpy as np

from swarmsim.controller import (
    BASE_MESSAGE_FIELDS,
    Action,
    ChunkActions,
    DecideBatch,
    NeighbourBatch,
    Perception,
    RobotSetup,
    make_action,
    register,
)

from .params import GGCParams
from .state import MAX_GROUPS, message_fields
from .statuses import SETTLED, STATUSES
from .swarm import GGCSwarm

_BASE = tuple(f[0] for f in BASE_MESSAGE_FIELDS)


class _Actions(ChunkActions):
    __slots__ = ()

    def action(self, k: int) -> Action:
        """Row k as an Action (the per-robot path)."""
        sleeper = self.sleepers.get(k)
        return make_action((float(self.velocities[k, 0]), float(self.velocities[k, 1])),
                           self.messages.get(k), sleeper is not None,
                           None if sleeper is None else sleeper.wake_range,
                           float(self.listen[k]),
                           True if sleeper is None else sleeper.wake_on_motion,
                           None if sleeper is None else sleeper.wake_tick)


class RobotRow:
    """A robot as the engine holds it: its swarm and its row there."""

    __slots__ = ("row", "swarm")

    def __init__(self, swarm: GGCSwarm, row: int):
        self.swarm, self.row = swarm, row

    def step(self, p: Perception) -> Action:
        """One robot's tick on its own (the engine's per-robot path: decide_order
        "shuffled", batch_decide false): a chunk of one."""
        beacon = None if p.beacon is None else np.asarray(p.beacon, dtype=float)[None]
        batch = DecideBatch(p.tick, NeighbourBatch(p.messages, p.distances,
                                                   np.array([0, len(p.distances)])),
                            p.offsets, [p.on_target], np.asarray(p.moved, float)[None],
                            beacon, lambda k: p.probe, None)
        return GGC._actions(self.swarm, np.array([self.row]), batch).action(0)


@register
class GGC:
    """Gradient-and-grouping coverage (paper Sections 3-4)."""

    name = "ggc"
    Params = GGCParams
    STATUSES = STATUSES
    SETTLED_STATUSES = SETTLED
    MESSAGE_FIELDS = message_fields(MAX_GROUPS, _BASE)
    default_start = "formation"
    max_groups = MAX_GROUPS
    requires_beacon = True
    probe_params = ("probe_distance", "boundary_probe")

    @classmethod
    def message_fields_for(cls, groups: int) -> list[tuple]:
        """GGC's broadcast fields for a run with ``groups`` groups."""
        return message_fields(groups, _BASE)

    @classmethod
    def sensing_range(cls, params: GGCParams) -> float:
        """Robots hear broadcasts within R_c (and at least far enough to edge-follow)."""
        return max(params.R_c, params.gradient_reach * params.d_cover, params.d_cover + 2)

    @classmethod
    def warm_up(cls) -> None:
        """Compile (first time on a machine, about a minute) or load the rules."""
        warm_up_rules(cls)

    @classmethod
    def create_swarm(cls, setups: Sequence[RobotSetup], params: GGCParams,
                     rngs: Sequence[np.random.Generator]) -> GGCSwarm:
        """The run's robots (row i: robot i)."""
        return GGCSwarm(setups, params, rngs)

    # The engine's create_robots / decide_batch protocol, until create_swarm replaces it.
    @classmethod
    def create_robots(cls, setups: Sequence[RobotSetup], params: GGCParams,
                      rngs: Sequence[np.random.Generator]) -> list[RobotRow]:
        swarm = GGCSwarm(setups, params, rngs)
        swarm.sent = None
        return [RobotRow(swarm, i) for i in range(len(setups))]

    @classmethod
    def decide_batch(cls, robots: list[RobotRow], batch: DecideBatch) -> ChunkActions:
        rows = np.fromiter((r.row for r in robots), dtype=np.intp, count=len(robots))
        return cls._actions(robots[0].swarm, rows, batch)

    @staticmethod
    def _actions(swarm: GGCSwarm, rows: np.ndarray, batch: DecideBatch) -> ChunkActions:
        d = swarm.decide(rows, batch)
        if swarm.sent is None:
            swarm.sent = np.zeros(len(swarm.state), dtype=d.broadcast.dtype)
            swarm.sent["id"] = -1
        old = swarm.sent[rows]
        changed = np.flatnonzero((old.view(np.uint8).reshape(len(rows), -1)
                                  != d.broadcast.view(np.uint8).reshape(len(rows), -1))
                                 .any(axis=1))
        swarm.sent[rows[changed]] = d.broadcast[changed]
        messages = dict(zip(changed.tolist(), d.broadcast[changed].tolist(), strict=True))
        sleepers = {}
        for k in np.flatnonzero(d.sleep).tolist():
            wake = float(d.wake_range[k])
            tick = int(d.wake_tick[k])
            sleepers[k] = make_action(sleep=True, wake_range=None if math.isnan(wake) else wake,
                                      wake_on_motion=bool(d.wake_on_motion[k]),
                                      wake_tick=None if tick < 0 else tick)
        return _Actions(d.velocities, d.listen, messages, sleepers)

    @classmethod
    def summarize(cls, robots: Sequence[RobotRow]) -> dict:
        if not robots:
            return {"status_counts": {}}
        swarm = robots[0].swarm
        keep = np.zeros(len(swarm.state), dtype=bool)
        keep[[r.row for r in robots]] = True
        return swarm.summarize(~keep)


def warm_up_rules(cls: type) -> None:
    """Compile (first time on a machine) or load the driver for the run's types: decide two
    robots of a made-up chunk."""
    from swarmsim.controller import NeighbourBatch, message_dtype, run_message_fields

    setups = [RobotSetup(0, leader=True, group=1), RobotSetup(1, group=1)]
    rngs = [np.random.default_rng(0), np.random.default_rng(1)]
    swarm = GGCSwarm(setups, cls.Params(), rngs)
    messages = np.zeros(2, dtype=message_dtype(run_message_fields(cls, 1)))
    messages["id"] = [1, 0]
    offsets = np.array([[1.0, 0.0], [-1.0, 0.0]])
    batch = DecideBatch(0, NeighbourBatch(messages, np.ones(2), np.array([0, 1, 2])),
                        offsets, [False, False], np.zeros((2, 2)), np.zeros((2, 2)),
                        lambda k: (lambda offset: False), None)
    swarm.decide(np.arange(2), batch)


__all__ = ["GGC", "GGCParams", "GGCSwarm"]
