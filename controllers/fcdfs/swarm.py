"""A run's FCDFS robots as one :class:`FCDFSSwarm`: their state in arrays, a chunk decided in
compiled calls (chunk.py), the floor probes they ask answered at once between calls.

The same runs as the per-robot :class:`~controllers.fcdfs.robot.FCDFSRobot`, to the bit
(tests/controllers/baselines/test_fcdfs_swarm.py).
"""

from __future__ import annotations

from collections import Counter
from collections.abc import Sequence
from typing import Any

import numpy as np

from controllers.common.chunkio import probe_many_of, sensed_columns
from controllers.common.formation import CMD_NONE
from controllers.common.gradient import INF_GRADIENT
from swarmsim.controller import ChunkActions, DecideBatch, RobotSetup

from .chunk import Out, Params, Probes, Rows, Sensed, decide_chunk
from .params import NO_DOOR, STATUSES, TRAVEL, FCDFSParams

PROBES_PER_TICK = 48
"""The most floor probes one robot asks in a tick (FCDFSRobot.decide asks at most ~8)."""


class FCDFSSwarm:
    """The run's FCDFS robots (row i: robot i), the state an FCDFSRobot keeps (chunk.Rows)."""

    def __init__(self, setups: Sequence[RobotSetup], params: FCDFSParams):
        n = len(setups)
        leader = np.array([s.leader for s in setups], dtype=np.bool_)
        self.group = np.array([s.group for s in setups], dtype=np.int16)
        self.rows = Rows(
            robot_id=np.array([s.robot_id for s in setups], dtype=np.int64), leader=leader,
            status=np.full(n, TRAVEL, dtype=np.int64),
            grad=np.where(leader, 0, INF_GRADIENT).astype(np.int64),
            cmd=np.full(n, CMD_NONE, dtype=np.int64), travel=np.zeros((n, 2)),
            door=np.full(n, NO_DOOR, dtype=np.int64), pdir=np.ones(n, dtype=np.int64),
            touch=np.zeros(n, dtype=np.bool_), hops=np.full(n, INF_GRADIENT, dtype=np.int64),
            cell=np.zeros((n, 2), dtype=np.int64), goal=np.zeros((n, 2), dtype=np.int64),
            has_goal=np.zeros(n, dtype=np.bool_), hist_n=np.zeros(n, dtype=np.int64),
            hist=np.zeros((n, 2, 2), dtype=np.int64), pos=np.zeros((n, 2)),
            waited=np.zeros(n, dtype=np.int64), stepping=np.zeros(n, dtype=np.bool_),
            stepped=np.zeros(n))
        self.kernel_params = Params(
            d_safe=float(params.d_safe), d_min=float(params.d_min), v=float(params.v),
            turn=int(params.turn), queue_gap=float(params.queue_gap),
            door_depth=float(params.door_depth), door_radius=float(params.door_radius),
            clearance=float(params.clearance), arrive_tolerance=float(params.arrive_tolerance),
            avoid_range=float(params.avoid_range), patience=int(params.patience),
            init_timeout=int(params.init_timeout), spacing=float(params.spacing))

    def warm_up(self) -> None:
        """Compile (the first time) or load the chunk kernel for this run's types now."""
        warm_up()

    def decide(self, robots: np.ndarray, batch: DecideBatch) -> ChunkActions:
        """The chunk's actions (``robots``: their rows, in the batch's order), dense: the
        kernel decides every robot, then again those that read a probe not yet asked, with
        their questions answered, until none does."""
        sensed = _sensed(robots, batch)
        n = len(sensed.rows)
        q = Probes(offsets=np.zeros((n, PROBES_PER_TICK, 2)),
                   answers=np.zeros((n, PROBES_PER_TICK), dtype=np.int8),
                   count=np.zeros(n, dtype=np.int64), missed=np.zeros(n, dtype=np.bool_))
        out = _out(n)
        todo = np.arange(n, dtype=np.int64)
        probe_many = None
        while len(todo):
            decide_chunk(self.rows, sensed, self.kernel_params, q, todo, out)
            todo = np.flatnonzero(q.missed).astype(np.int64)
            if len(todo):
                probe_many = probe_many or probe_many_of(batch)
                ks, js = np.nonzero(q.answers < 0)
                q.answers[ks, js] = probe_many(ks, q.offsets[ks, js])
        broadcast = np.zeros(n, dtype=batch.neighbours.messages.dtype)
        r, rows = self.rows, sensed.rows
        broadcast["id"] = r.robot_id[rows]
        broadcast["status"] = r.status[rows]
        broadcast["moving"] = out.moving
        broadcast["gradient"] = out.gradient
        broadcast["group"] = self.group[rows]
        broadcast["leader"] = r.leader[rows]
        broadcast["cmd"] = r.cmd[rows]
        broadcast["vx"] = r.travel[rows, 0]
        broadcast["vy"] = r.travel[rows, 1]
        broadcast["door"] = r.door[rows]
        broadcast["pdir"] = r.pdir[rows]
        broadcast["touch"] = r.touch[rows]
        broadcast["hops"] = r.hops[rows]
        broadcast["ci"] = out.ci
        broadcast["cj"] = out.cj
        return ChunkActions.columns(
            velocities=out.velocity, listen=out.listen, broadcast=broadcast, sleep=out.sleep,
            wake_range=out.wake_range, wake_on_motion=np.ones(n, dtype=np.bool_),
            wake_tick=out.wake_tick)

    def summarize(self, failed: np.ndarray) -> dict[str, Any]:
        """How many robots end in each status (FormationTravel.summarize), failed robots
        counted as "Failed" (swarmsim.engine.swarm.RobotSwarm.summarize)."""
        counts = Counter(STATUSES[s] for s in self.rows.status[~failed].tolist())
        if failed.any():
            counts["Failed"] = int(failed.sum())
        return {"status_counts": dict(sorted(counts.items()))}


def _out(n: int) -> Out:
    """Room for n robots' actions."""
    return Out(velocity=np.zeros((n, 2)), listen=np.zeros(n), sleep=np.zeros(n, dtype=np.bool_),
               wake_range=np.zeros(n), wake_tick=np.zeros(n, dtype=np.int64),
               moving=np.zeros(n, dtype=np.bool_), gradient=np.zeros(n, dtype=np.int64),
               ci=np.zeros(n, dtype=np.int64), cj=np.zeros(n, dtype=np.int64))



def _sensed(robots: np.ndarray, batch: Any) -> Sensed:
    """The batch's sensing as the kernel's columns."""
    return Sensed(**sensed_columns(robots, batch, _HEARD))


_HEARD = {"status": np.int64, "moving": np.bool_, "gradient": np.int64, "cmd": np.int64,
          "vx": np.float64, "vy": np.float64, "door": np.int64, "pdir": np.int64,
          "touch": np.bool_, "hops": np.int64, "ci": np.int64, "cj": np.int64}
"""The broadcast fields the kernel reads, with the dtypes it takes them in."""


def warm_up() -> None:
    """Compile (first time on a machine) or load (from the cache) the chunk kernel now, for
    the argument types :meth:`FCDFSSwarm.decide` passes it."""
    from swarmsim.controller import NeighbourBatch, message_dtype

    from .params import MESSAGE_FIELDS

    class _One:  # a chunk of one robot hearing one neighbour, with a run's batches' types
        tick = 0
        neighbours = NeighbourBatch(np.zeros(1, dtype=message_dtype(MESSAGE_FIELDS)),
                                    np.ones(1), np.array([0, 1], dtype=np.int64))
        offsets = np.array([[1.0, 0.0]])
        on_target = np.zeros(1, dtype=np.bool_)
        moved = np.zeros((1, 2))
        beacons: np.ndarray | None = np.array([[1.0, 0.0]])

    swarm = FCDFSSwarm([RobotSetup(0, leader=True), RobotSetup(1)], FCDFSParams())
    for beacons in (np.array([[1.0, 0.0]]), None):
        _One.beacons = beacons
        q = Probes(offsets=np.zeros((1, PROBES_PER_TICK, 2)),
                   answers=np.zeros((1, PROBES_PER_TICK), dtype=np.int8),
                   count=np.zeros(1, dtype=np.int64), missed=np.zeros(1, dtype=np.bool_))
        decide_chunk(swarm.rows, _sensed(np.array([1]), _One), swarm.kernel_params, q,
                     np.zeros(1, dtype=np.int64), _out(1))


__all__ = ["FCDFSSwarm", "warm_up"]
