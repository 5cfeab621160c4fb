"""A run's DASH robots as one :class:`DashSwarm`: their spacing state in arrays, a chunk's
spacing adjustment and commands in one compiled pass (chunk.py), the floor probes of the
robots that would step asked in one query, the rest in a few numpy operations over the chunk.

The same runs as the per-robot :class:`~controllers.dash.robot.DashRobot`, to the bit
(tests/controllers/baselines/test_dash_swarm.py).
"""

from __future__ import annotations

import math
from collections.abc import Sequence
from typing import Any

import numpy as np

from controllers.common.chunkio import probe_many_of
from swarmsim.controller import NO_SENDER, ChunkActions, DecideBatch, RobotSetup

from .chunk import Gains, Heard, wished
from .params import RESTING, SEEKING, DashParams


class DashSwarm:
    """The run's robots (row i: robot i): ``level`` (N,) int64, each robot's spacing in
    adapt_rate steps above s_start; ``s`` (N,) its spacing, units; ``status`` (N,) int8
    (params.STATUSES)."""

    def __init__(self, setups: Sequence[RobotSetup], params: DashParams):
        n = len(setups)
        self.params = params
        self.gains = Gains(*(float(getattr(params, name)) for name in Gains._fields))
        self.max_level = math.floor((params.d_cover - params.s_start) / params.adapt_rate)
        self.level = np.zeros(n, dtype=np.int64)
        self.s = np.full(n, float(params.s_start))
        self.status = np.full(n, SEEKING, dtype=np.int8)

    def decide(self, robots: np.ndarray, batch: DecideBatch) -> ChunkActions:
        """The chunk's actions (robot k: row ``robots[k]``), as DashRobot.step gives them:
        every robot broadcasts (id, status, moving, spacing), listens as far as its next
        decision needs and sleeps once it rests with its spacing settled."""
        rows = np.ascontiguousarray(robots, dtype=np.int64)
        r = len(rows)
        m = batch.neighbours.messages
        heard = Heard(np.ascontiguousarray(batch.neighbours.starts, dtype=np.int64),
                      np.ascontiguousarray(batch.offsets, dtype=np.float64).reshape(-1, 2),
                      np.ascontiguousarray(batch.neighbours.distances, dtype=np.float64),
                      np.ascontiguousarray(m["id"], dtype=np.int32),
                      np.ascontiguousarray(m["status"], dtype=np.int8),
                      np.ascontiguousarray(m["spacing"], dtype=np.float32))
        on_target = np.ascontiguousarray(batch.on_target, dtype=np.bool_)
        has_beacon = batch.beacons is not None
        beacons = (np.ascontiguousarray(batch.beacons, dtype=np.float64).reshape(r, 2)
                   if has_beacon else np.zeros((r, 2)))
        velocity, speed = np.empty((r, 2)), np.empty(r)
        settled, ask = np.empty(r, dtype=np.bool_), np.empty(r, dtype=np.bool_)
        probe_at = np.empty((r, 2))
        wished(rows, heard, on_target, has_beacon, beacons, self.gains, self.max_level,
               NO_SENDER, self.level, self.s, self.status, velocity, speed, settled, ask,
               probe_at)
        asked = np.flatnonzero(ask)
        if len(asked):
            stays = probe_many_of(batch)(asked, probe_at[asked])
            speed[asked[~np.asarray(stays, dtype=np.bool_)]] = 0.0
        moving = speed > self.gains.deadband
        velocity[~moving] = 0.0
        rest = ~moving & on_target & settled
        self.status[rows[rest]] = RESTING
        status = self.status[rows]
        p = self.params
        listen = np.where(status != SEEKING, 1.5 * p.d_cover, 1.5 * p.d_safe)
        broadcast = np.zeros(r, dtype=m.dtype)
        broadcast["id"] = rows
        broadcast["status"] = status
        broadcast["moving"] = moving
        broadcast["spacing"] = self.s[rows]
        return ChunkActions.columns(
            velocities=velocity, listen=listen, broadcast=broadcast, sleep=rest,
            wake_range=np.full(r, np.nan), wake_on_motion=np.ones(r, dtype=np.bool_),
            wake_tick=np.full(r, -1, dtype=np.int64))

    def summarize(self, failed: np.ndarray) -> dict[str, Any]:
        """No figures of its own (as the per-robot controller)."""
        return {}



__all__ = ["DashSwarm"]
