"""A run's Kilobot robots as one :class:`KilobotSwarm`: their state in arrays, a chunk decided
in two compiled calls (chunk.py: the probes it asks, then the decision), its floor probes
asked at once in between.

The same runs as the per-robot :class:`~controllers.kilobot.robot.KilobotRobot`, to the bit
(tests/controllers/baselines/test_kilobot_swarm.py).
"""

from __future__ import annotations

from collections import Counter
from collections.abc import Sequence
from typing import Any

import numpy as np

from controllers.common.chunkio import probe_many_of, sensed_columns
from controllers.common.formation import CMD_NONE
from controllers.common.gradient import INF_GRADIENT
from swarmsim.controller import NO_SENDER, ChunkActions, DecideBatch, RobotSetup

from .chunk import Out, Params, Rows, Sensed, decide_chunk, probe_questions
from .params import INSIDE, OUTSIDE, STATUSES, TRAVEL, KilobotParams


class KilobotSwarm:
    """The run's Kilobot robots (row i: robot i), the state a KilobotRobot keeps
    (chunk.Rows)."""

    def __init__(self, setups: Sequence[RobotSetup], params: KilobotParams):
        n = len(setups)
        leader = np.array([s.leader for s in setups], dtype=np.bool_)
        self.group = np.array([s.group for s in setups], dtype=np.int16)
        self.rows = Rows(
            robot_id=np.array([s.robot_id for s in setups], dtype=np.int64), leader=leader,
            status=np.full(n, TRAVEL, dtype=np.int64),
            grad=np.where(leader, 0, INF_GRADIENT).astype(np.int64),
            cmd=np.full(n, CMD_NONE, dtype=np.int64), travel=np.zeros((n, 2)),
            heading=np.zeros((n, 2)), circling_id=np.full(n, NO_SENDER, dtype=np.int64),
            circled=np.zeros(n), last_bearing=np.zeros(n), has_bearing=np.zeros(n, np.bool_),
            odometer=np.zeros((n, 2)), progress_tick=np.zeros(n, dtype=np.int64),
            escape_until=np.full(n, -1, dtype=np.int64), traps=np.zeros(n, dtype=np.int64))
        self.kernel_params = Params(
            d_safe=float(params.d_safe), d_cover=float(params.d_cover),
            d_min=float(params.d_min), v=float(params.v),
            gradient_reach=float(params.gradient_reach), start_range=float(params.start_range),
            quiet_range=float(params.quiet_range), yield_distance=float(params.yield_distance),
            radial_gain=float(params.radial_gain),
            arrive_tolerance=float(params.arrive_tolerance),
            probe_distance=float(params.probe_distance), orbit=float(params.orbit),
            init_timeout=int(params.init_timeout), T_r=int(params.T_r),
            theta=float(params.theta))

    def warm_up(self) -> None:
        """Compile (the first time) or load the chunk kernels for this run's types now."""
        warm_up()

    def decide(self, robots: np.ndarray, batch: DecideBatch) -> ChunkActions:
        """The chunk's actions (``robots``: their rows, in the batch's order), dense."""
        sensed = _sensed(robots, batch)
        n = len(sensed.rows)
        ask, offsets = np.zeros(n, dtype=np.bool_), np.zeros((n, 2))
        probe_questions(self.rows, sensed, self.kernel_params, ask, offsets)
        answers = np.zeros(n, dtype=np.bool_)
        asked = np.flatnonzero(ask)
        if len(asked):
            answers[asked] = probe_many_of(batch)(asked, offsets[asked])
        out = Out(velocity=np.zeros((n, 2)), listen=np.zeros(n),
                  sleep=np.zeros(n, dtype=np.bool_), wake_range=np.zeros(n),
                  wake_tick=np.zeros(n, dtype=np.int64))
        decide_chunk(self.rows, sensed, self.kernel_params, answers, out)
        return ChunkActions.columns(
            velocities=out.velocity, listen=out.listen,
            broadcast=self._broadcast(sensed.rows, batch.neighbours.messages.dtype),
            sleep=out.sleep, wake_range=out.wake_range,
            wake_on_motion=np.ones(n, dtype=np.bool_), wake_tick=out.wake_tick)

    def _broadcast(self, rows: np.ndarray, dtype: np.dtype) -> np.ndarray:
        """The robots' broadcasts (KilobotRobot.act's message) after deciding."""
        r = self.rows
        status = r.status[rows]
        out = np.zeros(len(rows), dtype=dtype)
        out["id"] = r.robot_id[rows]
        out["status"] = status
        out["moving"] = (status == OUTSIDE) | (status == INSIDE)
        out["gradient"] = r.grad[rows]
        out["group"] = self.group[rows]
        out["leader"] = r.leader[rows]
        out["cmd"] = r.cmd[rows]
        out["vx"] = r.travel[rows, 0]
        out["vy"] = r.travel[rows, 1]
        return out

    def summarize(self, failed: np.ndarray) -> dict[str, Any]:
        """How many robots end in each status (FormationTravel.summarize), failed robots
        counted as "Failed" (swarmsim.engine.swarm.RobotSwarm.summarize)."""
        counts = Counter(STATUSES[s] for s in self.rows.status[~failed].tolist())
        if failed.any():
            counts["Failed"] = int(failed.sum())
        return {"status_counts": dict(sorted(counts.items()))}



def _sensed(robots: np.ndarray, batch: DecideBatch) -> Sensed:
    """The batch's sensing as the kernels' columns."""
    return Sensed(**sensed_columns(robots, batch, _HEARD))


_HEARD = {"status": np.int64, "moving": np.bool_, "gradient": np.int64, "cmd": np.int64,
          "vx": np.float64, "vy": np.float64}
"""The broadcast fields the kernels read, with the dtypes they take them in."""


def warm_up() -> None:
    """Compile (first time on a machine) or load (from the cache) the chunk kernels now, for
    the argument types :meth:`KilobotSwarm.decide` passes them."""
    from swarmsim.controller import message_dtype

    from .params import MESSAGE_FIELDS

    swarm = KilobotSwarm([RobotSetup(0, leader=True), RobotSetup(1)], KilobotParams())
    messages = np.zeros(1, dtype=message_dtype(MESSAGE_FIELDS))
    for has_beacon in (True, False):
        sensed = _sensed(np.array([1]), _OneBatch(messages, has_beacon))  # type: ignore[arg-type]
        ask, offsets = np.zeros(1, dtype=np.bool_), np.zeros((1, 2))
        probe_questions(swarm.rows, sensed, swarm.kernel_params, ask, offsets)
        out = Out(velocity=np.zeros((1, 2)), listen=np.zeros(1),
                  sleep=np.zeros(1, dtype=np.bool_), wake_range=np.zeros(1),
                  wake_tick=np.zeros(1, dtype=np.int64))
        decide_chunk(swarm.rows, sensed, swarm.kernel_params, ask, out)


class _OneBatch:
    """A chunk of one robot that hears one neighbour, with a run's batches' types."""

    def __init__(self, messages: np.ndarray, has_beacon: bool):
        from swarmsim.controller import NeighbourBatch

        self.tick = 0
        self.neighbours = NeighbourBatch(messages, np.ones(1), np.array([0, 1], dtype=np.int64))
        self.offsets = np.array([[1.0, 0.0]])
        self.on_target = np.zeros(1, dtype=np.bool_)
        self.moved = np.zeros((1, 2))
        self.beacons = np.array([[1.0, 0.0]]) if has_beacon else None


__all__ = ["KilobotSwarm", "warm_up"]
