"""A run's mean-shift robots as arrays: :class:`MeanShiftSwarm` moves and probes a chunk's
local maps (controllers.common.mapbatch, the floor probes of the whole chunk asked in one
query) and decides the chunk in chunk.py's compiled kernel.

It makes the very runs of the per-robot
:class:`~controllers.meanshift.controller.MeanShiftRobot` (tests/controllers/baselines/
test_meanshift_swarm.py compares them), at a fraction of the cost: no Perception or
Action objects, no Python per robot.
"""

from __future__ import annotations

from collections.abc import Callable, Sequence
from typing import Any

import numpy as np

from controllers.common.mapbatch import MapRows
from controllers.common.mapbatch import warm_up as _warm_up_maps
from swarmsim.controller import NO_SENDER, ChunkActions, DecideBatch, RobotSetup

from .chunk import RESTING, Gains, Lattice, decide_chunk


class MeanShiftSwarm:
    """The run's robots (row i: robot i): their local maps ``maps`` (odometry, windows of
    floor answers: controllers.common.mapbatch.MapRows), filtered velocity ``velocity``
    (N, 2), units per tick, and ``status`` (N,) int8 (controller.STATUSES).

    Args:
        setups: the robots' setups (their ids are their rows).
        params: a MeanShiftParams.
    """

    def __init__(self, setups: Sequence[RobotSetup], params: Any):
        n = len(setups)
        self.params = params
        self.maps = MapRows(n, params.r_sense, params.map_cell)
        self.lattice = Lattice(self.maps.cell, self.maps.reach, self.maps.radius2)
        self.gains = Gains(*(float(getattr(params, name)) for name in Gains._fields))
        self.velocity = np.zeros((n, 2))
        self.status = np.zeros(n, dtype=np.int8)  # SEEKING

    def decide(self, robots: np.ndarray, batch: DecideBatch) -> ChunkActions:
        """The chunk's actions (robot k: row ``robots[k]``): its map moved and probed, then
        its command, as MeanShiftRobot.step gives it."""
        rows = np.ascontiguousarray(robots, dtype=np.int64)
        r = len(rows)
        moved = np.ascontiguousarray(batch.moved, dtype=np.float64).reshape(r, 2)
        maps = self.maps
        maps.sense(rows, moved, batch.probe_many or _probe_one_by_one(batch))
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
        decide_chunk(rows, maps.odo, maps.grid, maps.origin, self.velocity, self.status,
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

    def summarize(self, failed: np.ndarray) -> dict[str, Any]:
        """No figures of its own (as the per-robot controller)."""
        return {}


def _probe_one_by_one(batch: DecideBatch) -> Callable[[np.ndarray, np.ndarray], np.ndarray]:
    """``probe_many`` for a batch without one (made by hand): each robot's probe, one
    offset (units) at a time."""
    def probe_many(ks: np.ndarray, offsets: np.ndarray) -> np.ndarray:
        return np.array([bool(batch.probe(int(k))(o)) for k, o in zip(ks, offsets, strict=True)],
                        dtype=np.bool_)

    return probe_many


def warm_up() -> None:
    """Compile (first time on a machine) or load (from the cache) the kernels now, for the
    argument types :meth:`MeanShiftSwarm.decide` passes them."""
    from .controller import MeanShiftParams

    _warm_up_maps()
    swarm = MeanShiftSwarm([RobotSetup(0)], MeanShiftParams())
    rows = np.zeros(1, dtype=np.int64)
    heard = (np.array([0, 1], dtype=np.int64), np.array([[3.0, 0.0]]), np.array([3.0]),
             np.zeros(1, dtype=np.int32), np.zeros(1, dtype=np.float32),
             np.zeros(1, dtype=np.float32))
    maps = swarm.maps
    decide_chunk(rows, maps.odo, maps.grid, maps.origin, swarm.velocity, swarm.status,
                 np.ones(1, dtype=np.bool_), True, np.zeros((1, 2)), heard, swarm.gains,
                 swarm.lattice, NO_SENDER, np.empty((1, 2)), np.empty(1, dtype=np.bool_))


__all__ = ["MeanShiftSwarm", "warm_up"]
