"""What deciding costs a run's robots: broadcasts heard and controller time per robot-tick.

The paper's Table 3 rates methods by their communication and computing cost. The engine knows
no controller, so it measures both where every controller's perception and actions pass
through it (swarmsim.engine.sim.Simulation._decide): once per decided chunk of robots (a
tick's awake robots, up to DECIDE_CHUNK of them), never per robot in Python.

- A *decision* is one robot deciding in one tick (a robot-tick in which its controller was
  called: not asleep, not failed).
- A *heard broadcast* is a neighbour's row in a deciding robot's perception whose sender was
  heard (``id`` is not NO_SENDER): a neighbour that never broadcast, has failed or whose
  message was lost reads as silent and is not counted. A robot hears only within how far it
  listens (Action.listen), so a controller that listens less hears less.
- Controller time is the process's CPU time (time.process_time) inside the controller's
  ``decide`` call: for a batch controller (GGC) its whole chunk's decision, for a per-robot
  controller every robot's ``step`` plus the engine's making of each robot's Perception
  object (swarmsim.engine.swarm.RobotSwarm: a few microseconds a robot). Sensing (the
  neighbour search, the heard rows) and checking and writing the actions are not included.
  It varies from run to run and machine to machine: a figure, never part of what decides a
  run or of a determinism check (swarmsim.engine.sim.TIMING_FIELDS).
"""

from __future__ import annotations

from dataclasses import dataclass
from typing import Any

import numpy as np

TIMING_FIELDS = ("controller_ms_per_robot_tick",)
"""The cost fields that time the run (they differ between two runs of the same seed)."""
WORK_FIELDS = ("decisions", "messages_heard_per_robot_tick")
"""The cost fields that count the work done: the same for two runs of one seed and setting,
but fewer when robots sleep (``allow_sleep``: a sleeping robot neither decides nor
listens), so a check that sleeping changes nothing else leaves them out."""


@dataclass
class CostCounter:
    """Running totals of a run's decisions (mutable: the engine adds to it every chunk; a
    checkpoint saves it with the run).

    Attributes:
        message_bytes: bytes per broadcast: the run's message dtype's itemsize.
        message_fields: fields per broadcast (``id``, ``status``, ``moving`` and the
            controller's own).
        decisions: robot-ticks in which a robot's controller was called.
        heard: broadcasts heard by those robots, summed over them.
        controller_seconds: CPU seconds inside the controller's decide calls.
    """

    message_bytes: int
    message_fields: int
    decisions: int = 0
    heard: int = 0
    controller_seconds: float = 0.0

    @classmethod
    def for_dtype(cls, dtype: np.dtype) -> CostCounter:
        """A counter at zero for a run whose broadcasts have ``dtype``."""
        return cls(int(dtype.itemsize), len(dtype.names or ()))

    def add(self, robots: int, heard: int, seconds: float) -> None:
        """Count one decided chunk: ``robots`` deciding robots, the broadcasts they ``heard``
        (:func:`heard_count`), ``seconds`` of CPU time in the controller."""
        self.decisions += robots
        self.heard += heard
        self.controller_seconds += seconds

    def fields(self) -> dict[str, Any]:
        """summary.json's cost fields (docs/outputs.md): per robot-tick figures are None
        before any robot decided."""
        n = self.decisions
        return {
            "decisions": n,
            "messages_heard_per_robot_tick": round(self.heard / n, 4) if n else None,
            "message_bytes": self.message_bytes,
            "message_fields": self.message_fields,
            "controller_ms_per_robot_tick": (round(1e3 * self.controller_seconds / n, 5)
                                             if n else None),
        }


def heard_count(senders: np.ndarray, quiet: np.ndarray, lost: np.ndarray | None) -> int:
    """How many of a chunk's heard rows arrive with a sender: rows from ``senders`` (P,)
    robot indices, less those from a ``quiet`` robot ((N,) bool: its broadcast is silent, it
    never broadcast or has failed) and those ``lost`` ((P,) bool, or None: none).

    Reads the senders' indices, never the rows themselves (a row is a cache line or more: on
    K, reading every heard row's id cost more than the rest of the count); when no robot is
    quiet and none is lost (most ticks), reads nothing of size P."""
    if not quiet.any():
        return len(senders) - (0 if lost is None else int(np.count_nonzero(lost)))
    silent = quiet[senders]
    if lost is not None:
        silent |= lost
    return len(senders) - int(np.count_nonzero(silent))


__all__ = ["TIMING_FIELDS", "WORK_FIELDS", "CostCounter", "heard_count"]
