"""A run's CVT robots as one :class:`CVTSwarm`: their state in arrays, a chunk decided in two
compiled passes (the maps sense, controllers/common/mapbatch.py; then chunk.py decides).

The same runs as the per-robot :class:`~controllers.cvt.robot.CVTRobot`, to the bit
(tests/controllers/baselines/test_cvt_swarm.py).
"""

from __future__ import annotations

from collections.abc import Sequence
from typing import Any

import numpy as np

from controllers.common.chunkio import probe_many_of
from controllers.common.mapbatch import MapRows
from swarmsim.controller import ChunkActions, DecideBatch, RobotSetup

from .chunk import Out, Params, Rows, Sensed, decide_chunk
from .params import DISC, SEEKING, CVTParams


class CVTSwarm:
    """The run's CVT robots (row i: robot i): their local maps (:class:`MapRows`) and the
    state a CVTRobot keeps (chunk.Rows)."""

    def __init__(self, setups: Sequence[RobotSetup], params: CVTParams,
                 rngs: Sequence[np.random.Generator]):
        n = len(setups)
        self.params = params
        self.maps = MapRows(n, params.cell_radius, params.map_cell)
        self.rows = Rows(
            status=np.full(n, SEEKING, dtype=np.int8),
            extent=np.full(n, float(params.cell_radius)),
            heard=np.full(n, 2 * params.cell_radius, dtype=np.float64),
            reach=np.zeros(n), still=np.zeros(n, dtype=np.bool_),
            still_extent=np.zeros(n), still_heard=np.zeros(n),
            odo=self.maps.odo, origin=self.maps.origin, grid=self.maps.grid)
        self.kernel_params = Params(
            cell_radius=float(params.cell_radius), d_safe=float(params.d_safe),
            v=float(params.v), gain=float(params.gain),
            repulsion_gain=float(params.repulsion_gain), tolerance=float(params.tolerance),
            map_cell=self.maps.cell, map_radius2=self.maps.radius2, disc=DISC)

    def warm_up(self) -> None:
        """Compile (the first time) or load the chunk kernel for this run's types now: a
        chunk of no robots."""
        self.decide(np.zeros(0, dtype=np.intp), _empty_batch())

    def decide(self, robots: np.ndarray, batch: DecideBatch) -> ChunkActions:
        """The chunk's actions (``robots``: their rows, in the batch's order), dense."""
        rows = np.ascontiguousarray(robots, dtype=np.int64)
        moved = _c_array(batch.moved, np.float64).reshape(-1, 2)
        self.maps.sense(rows, moved, probe_many_of(batch))
        n = len(rows)
        has_beacon = batch.beacons is not None
        sensed = Sensed(
            rows=rows, starts=_c_array(batch.neighbours.starts, np.int64),
            offsets=_c_array(batch.offsets, np.float64).reshape(-1, 2),
            distances=_c_array(batch.neighbours.distances, np.float64),
            on_target=_c_array(batch.on_target, np.bool_),
            beacons=(_c_array(batch.beacons, np.float64).reshape(-1, 2) if has_beacon
                     else np.zeros((n, 2))),
            has_beacon=has_beacon)
        out = Out(velocity=np.zeros((n, 2)), listen=np.zeros(n),
                  status=np.zeros(n, dtype=np.int8), moving=np.zeros(n, dtype=np.bool_),
                  sleep=np.zeros(n, dtype=np.bool_))
        bad = decide_chunk(self.rows, sensed, self.kernel_params, out)
        if bad >= 0:
            raise RuntimeError(f"robot {int(rows[bad])}'s local map lacks a lattice point "
                               "within its radius after sensing")
        broadcast = np.zeros(n, dtype=batch.neighbours.messages.dtype)
        broadcast["status"] = out.status
        broadcast["moving"] = out.moving
        return ChunkActions.columns(
            velocities=out.velocity, listen=out.listen, broadcast=broadcast, sleep=out.sleep,
            wake_range=np.where(out.sleep, out.listen, np.nan),
            wake_on_motion=np.ones(n, dtype=np.bool_), wake_tick=np.full(n, -1, dtype=np.int64))

    def summarize(self, failed: np.ndarray) -> dict[str, Any]:
        """CVT reports no figures of its own (the engine counts statuses from broadcasts)."""
        return {}


def _c_array(a: Any, dtype: type) -> np.ndarray:
    """``a`` as a C-contiguous, writeable array of ``dtype`` (a copy only when it is not one
    already): the chunk kernel is compiled for one set of argument types."""
    return np.require(a, dtype=dtype, requirements=("C", "W"))



def _empty_batch() -> DecideBatch:
    """A chunk of no robots, with the types of a run's batches (for warm_up)."""
    from swarmsim.controller import NeighbourBatch, message_dtype

    messages = np.zeros(0, dtype=message_dtype())
    return DecideBatch(0, NeighbourBatch(messages, np.zeros(0), np.zeros(1, dtype=np.int64)),
                       np.zeros((0, 2)), np.zeros(0, dtype=bool), np.zeros((0, 2)),
                       np.zeros((0, 2)), _no_robot, _no_robot,
                       lambda ks, offsets: np.zeros(len(ks), dtype=bool), np.zeros(0))


def _no_robot(k: int) -> Any:
    """A chunk of no robots has no robot k to perceive or probe for."""
    raise IndexError(f"no robot {k} in a chunk of none")
