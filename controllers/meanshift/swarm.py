"""A run's mean-shift robots as arrays: :class:`MeanShiftSwarm` decides a chunk of robots in
the compiled kernels of chunk.py, the floor probes of the whole chunk asked in one query.

It makes the very runs of the per-robot
:class:`~controllers.meanshift.controller.MeanShiftRobot` (tests/controllers/baselines/
test_meanshift_swarm.py compares them), at a fraction of the cost: no Perception or
Action objects, no Python per robot.
"""

from __future__ import annotations

import math
from collections.abc import Sequence
from typing import Any

import numpy as np

from controllers.common.localmap import LocalMap
from swarmsim.controller import NO_SENDER, ChunkActions, DecideBatch, RobotSetup

from .chunk import RESTING, Gains, Lattice, decide_chunk, prepare_chunk, put_answers


class MeanShiftSwarm:
    """The run's robots (row i: robot i): odometry ``odo`` (N, 2), units; filtered velocity
    ``velocity`` (N, 2), units per tick; ``status`` (N,) int8 (controller.STATUSES); each
    robot's local map window ``grid`` (N, size, size) int8 (1 target, 0 not, -1 not yet
    probed) and the lattice index of its first row and column ``origin`` (N, 2), as
    controllers.common.localmap.LocalMap keeps them.

    Args:
        setups: the robots' setups (their ids are their rows).
        params: a MeanShiftParams.
    """

    def __init__(self, setups: Sequence[RobotSetup], params: Any):
        n = len(setups)
        self.params = params
        reach = math.ceil(float(params.r_sense) / float(params.map_cell)) + 1
        self.lattice = Lattice(float(params.map_cell), reach, LocalMap.MARGIN,
                               float(params.r_sense) * float(params.r_sense))
        self.gains = Gains(*(float(getattr(params, name)) for name in Gains._fields))
        size = 2 * (reach + LocalMap.MARGIN) + 1
        self.odo = np.zeros((n, 2))
        self.velocity = np.zeros((n, 2))
        self.status = np.zeros(n, dtype=np.int8)  # SEEKING
        self.grid = np.full((n, size, size), -1, dtype=np.int8)
        self.origin = np.full((n, 2), -(reach + LocalMap.MARGIN), dtype=np.int64)

    def decide(self, robots: np.ndarray, batch: DecideBatch) -> ChunkActions:
        """The chunk's actions (robot k: row ``robots[k]``): its map moved and probed, then
        its command, as MeanShiftRobot.step gives it."""
        rows = np.ascontiguousarray(robots, dtype=np.int64)
        r = len(rows)
        moved = np.ascontiguousarray(batch.moved, dtype=np.float64).reshape(r, 2)
        ks, offsets, where = prepare_chunk(rows, moved, self.odo, self.grid, self.origin,
                                           self.lattice)
        if len(ks):
            put_answers(self.grid, where, self._probe(batch, ks, offsets))
        m = batch.neighbours.messages
        heard = (np.ascontiguousarray(batch.neighbours.starts, dtype=np.int64),
                 np.ascontiguousarray(batch.offsets, dtype=np.float64).reshape(-1, 2),
                 np.ascontiguousarray(batch.neighbours.distances, dtype=np.float64),
                 np.ascontiguousarray(m["id"], dtype=np.int32),
                 np.ascontiguousarray(m["vx"], dtype=np.float32),
                 np.ascontiguousarray(m["vy"], dtype=np.float32))
        has_beacon = batch.beacons is not None
        beacons = (np.ascontiguousarray(batch.beacons, dtype=np.float64).reshape(r, 2)
                   if has_beacon else np.zeros((r, 2)))
        velocities = np.empty((r, 2))
        sleep = np.empty(r, dtype=np.bool_)
        decide_chunk(rows, self.odo, self.grid, self.origin, self.velocity, self.status,
                     np.ascontiguousarray(batch.on_target, dtype=np.bool_), has_beacon,
                     beacons, heard, self.gains, self.lattice, NO_SENDER, velocities, sleep)
        return ChunkActions.columns(velocities, np.full(r, np.nan), self._broadcast(rows, m.dtype),
                                    sleep, np.full(r, np.nan), np.ones(r, dtype=np.bool_),
                                    np.full(r, -1, dtype=np.int64))

    def _broadcast(self, rows: np.ndarray, dtype: np.dtype) -> np.ndarray:
        """The robots' broadcasts (id, status, moving, vx, vy), MeanShiftRobot.message's."""
        out = np.zeros(len(rows), dtype=dtype)
        status = self.status[rows]
        out["id"] = rows
        out["status"] = status
        out["moving"] = status != RESTING
        out["vx"] = self.velocity[rows, 0]
        out["vy"] = self.velocity[rows, 1]
        return out

    @staticmethod
    def _probe(batch: DecideBatch, ks: np.ndarray, offsets: np.ndarray) -> np.ndarray:
        """(M,) bool: robot ``ks[j]``'s floor probe at ``offsets[j]`` (units), in one query
        where the batch offers one (a run's always does)."""
        if batch.probe_many is not None:
            return np.asarray(batch.probe_many(ks, offsets), dtype=np.bool_)
        return np.array([bool(batch.probe(int(k))(o)) for k, o in zip(ks, offsets, strict=True)],
                        dtype=np.bool_)

    def summarize(self, failed: np.ndarray) -> dict[str, Any]:
        """No figures of its own (as the per-robot controller)."""
        return {}


def warm_up() -> None:
    """Compile (first time on a machine) or load (from the cache) the chunk kernels now, for
    the argument types :meth:`MeanShiftSwarm.decide` passes them."""
    from .controller import MeanShiftParams

    swarm = MeanShiftSwarm([RobotSetup(0)], MeanShiftParams())
    rows = np.zeros(1, dtype=np.int64)
    ks, _offsets, where = prepare_chunk(rows, np.zeros((1, 2)), swarm.odo, swarm.grid,
                                       swarm.origin, swarm.lattice)
    put_answers(swarm.grid, where, np.ones(len(ks), dtype=np.bool_))
    heard = (np.array([0, 1], dtype=np.int64), np.array([[3.0, 0.0]]), np.array([3.0]),
             np.zeros(1, dtype=np.int32), np.zeros(1, dtype=np.float32),
             np.zeros(1, dtype=np.float32))
    decide_chunk(rows, swarm.odo, swarm.grid, swarm.origin, swarm.velocity, swarm.status,
                 np.ones(1, dtype=np.bool_), True, np.zeros((1, 2)), heard, swarm.gains,
                 swarm.lattice, NO_SENDER, np.empty((1, 2)), np.empty(1, dtype=np.bool_))


__all__ = ["MeanShiftSwarm", "warm_up"]
