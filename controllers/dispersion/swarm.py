"""A run's dispersion robots as one :class:`DispersionSwarm`: a chunk's commands in one
compiled pass (chunk.py), the floor probes of the robots that would step asked in one query,
the rest in a few numpy operations over the chunk.

The same runs as the per-robot :class:`~controllers.dispersion.robot.DispersionRobot`, to the
bit (tests/controllers/baselines/test_dispersion_swarm.py).
"""

from __future__ import annotations

from collections.abc import Sequence
from typing import Any

import numpy as np

from controllers.common.chunkio import probe_many_of
from swarmsim.controller import ChunkActions, DecideBatch, RobotSetup

from .chunk import Gains, wished
from .params import IDLE, SEEKING, SPREADING, DispersionParams


class DispersionSwarm:
    """The run's robots (row i: robot i). Dispersion keeps no state between ticks: a robot's
    action is its perception's."""

    def __init__(self, setups: Sequence[RobotSetup], params: DispersionParams):
        self.params = params
        self.gains = Gains(*(float(getattr(params, name)) for name in Gains._fields))

    def warm_up(self) -> None:
        """Compile (the first time) or load the chunk kernel for a run's argument types now."""
        wished(np.zeros(2, dtype=np.int64), np.zeros((1, 2)), np.ones(1),
               np.ones(1, dtype=np.bool_), True, np.zeros((1, 2)), self.gains,
               np.empty((1, 2)), np.empty(1), np.empty(1, dtype=np.bool_), np.empty((1, 2)))

    def decide(self, robots: np.ndarray, batch: DecideBatch) -> ChunkActions:
        """The chunk's actions (robot k: row ``robots[k]``), as DispersionRobot.step gives
        them: every robot broadcasts (id, status, moving) and sleeps while it rests."""
        r = len(robots)
        on_target = np.ascontiguousarray(batch.on_target, dtype=np.bool_)
        has_beacon = batch.beacons is not None
        beacons = (np.ascontiguousarray(batch.beacons, dtype=np.float64).reshape(r, 2)
                   if has_beacon else np.zeros((r, 2)))
        velocity, speed = np.empty((r, 2)), np.empty(r)
        ask, probe_at = np.empty(r, dtype=np.bool_), np.empty((r, 2))
        wished(np.ascontiguousarray(batch.neighbours.starts, dtype=np.int64),
               np.ascontiguousarray(batch.offsets, dtype=np.float64).reshape(-1, 2),
               np.ascontiguousarray(batch.neighbours.distances, dtype=np.float64),
               on_target, has_beacon, beacons, self.gains, velocity, speed, ask, probe_at)
        asked = np.flatnonzero(ask)
        if len(asked):
            stays = probe_many_of(batch)(asked, probe_at[asked])
            speed[asked[~np.asarray(stays, dtype=np.bool_)]] = 0.0
        moving = speed > self.gains.deadband
        velocity[~moving] = 0.0
        broadcast = np.zeros(r, dtype=batch.neighbours.messages.dtype)
        broadcast["id"] = robots
        broadcast["status"] = np.where(moving, SPREADING, np.where(on_target, IDLE, SEEKING))
        broadcast["moving"] = moving
        return ChunkActions.columns(
            velocities=velocity, listen=np.full(r, np.nan), broadcast=broadcast,
            sleep=~moving, wake_range=np.full(r, np.nan),
            wake_on_motion=np.ones(r, dtype=np.bool_), wake_tick=np.full(r, -1, dtype=np.int64))

    def summarize(self, failed: np.ndarray) -> dict[str, Any]:
        """No figures of its own (as the per-robot controller)."""
        return {}



__all__ = ["DispersionSwarm"]
