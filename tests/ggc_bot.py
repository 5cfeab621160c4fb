"""One GGC robot decided on hand-made neighbourhoods (no simulation), through the same
driver as a run: its state row is ``bot.me``, what it did ``bot.step(...)``'s ChunkActions."""

from __future__ import annotations

import numpy as np

from controllers.ggc import GGC, GGCParams, GGCSwarm
from controllers.ggc.rules.common import View
from controllers.ggc.schema import BROADCAST_NAMES
from controllers.ggc.statuses import COVERAGE
from swarmsim.controller import (
    ChunkActions,
    DecideBatch,
    NeighbourBatch,
    RobotSetup,
    message_dtype,
    run_message_fields,
)


def messages(rows, groups: int = 3, scattered: bool = False, **fields
             ) -> tuple[np.ndarray, np.ndarray]:
    """rows: (offset, id, group, status), nearest first -> (offsets (k, 2), messages) of a
    run with ``groups`` groups, started ``scattered`` or not; a robot in Coverage broadcasts
    moving; ``fields``: columns to set (a value or a list)."""
    m = np.zeros(len(rows), dtype=message_dtype(run_message_fields(GGC, groups, scattered)))
    offsets = np.array([r[0] for r in rows], dtype=float).reshape(-1, 2)
    for k, (_, rid, group, status) in enumerate(rows):
        m[k]["id"], m[k]["group"], m[k]["status"] = rid, group, status
        m[k]["moving"] = status == COVERAGE
    for name, value in fields.items():
        m[name] = value
    return offsets, m


class Bot:
    """Robot ``robot_id`` of group ``group`` in a run with ``groups`` groups, whose drive
    turns it at most ``turn_rate`` rad/tick (``inf``: holonomic) and can ``reverse``."""

    def __init__(self, groups: int = 3, robot_id: int = 5, group: int = 1,
                 status: int = COVERAGE, leader: bool = False, scattered: bool = False,
                 turn_rate: float = float("inf"), reverse: bool = True, **params):
        setup = RobotSetup(robot_id, leader=leader, group=group, groups=groups,
                           scattered=scattered, turn_rate=turn_rate, reverse=reverse)
        self.groups = groups
        self.scattered = scattered
        self.swarm = GGCSwarm([setup], GGCParams(**params), [np.random.default_rng(0)])
        self.me["status"] = status
        self.tick = 10

    @property
    def me(self) -> np.void:
        """My state row (writeable)."""
        return self.swarm.state[0]

    def step(self, rows, on_target: bool = False, probe=lambda offset: False,
             moved=(0.1, 0.0), beacon_deg: float | None = None, tick: int | None = None,
             **fields) -> ChunkActions:
        """Decide one tick with these neighbours (see :func:`messages`)."""
        offsets, m = messages(rows, self.groups, self.scattered, **fields)
        distances = np.hypot(offsets[:, 0], offsets[:, 1])
        beacon = None if beacon_deg is None else np.array(
            [[np.cos(np.radians(beacon_deg)), np.sin(np.radians(beacon_deg))]])
        tick = self.tick if tick is None else tick
        self.tick = tick + 1
        batch = DecideBatch(tick, NeighbourBatch(m, distances, np.array([0, len(rows)])),
                            offsets, [on_target], np.array([moved], dtype=float), beacon,
                            lambda k: probe, None)
        return self.swarm.decide(np.array([0]), batch)


def view(rows, groups: int = 3, scattered: bool = False, **fields) -> View:
    """A rule's view of these neighbours (see :func:`messages`), for calling a rule alone."""
    offsets, m = messages(rows, groups, scattered, **fields)
    m.flags.writeable = False  # as the driver passes them: read-only strided columns
    return View(offsets, np.hypot(offsets[:, 0], offsets[:, 1]),
                *(m[name] for name in BROADCAST_NAMES))


def ggc_state(sim) -> np.ndarray:
    """A GGC run's state rows (row i: robot i)."""
    return sim.swarm.state
