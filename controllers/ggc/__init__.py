"""GGC: gradient-and-grouping self-organising coverage (the paper's controller).

``--controller ggc``. robot.py holds the state machine and the Initial status (travel);
detection.py, coverage.py, surplus.py and collisions.py the other statuses' rules (mixins of
GGCRobot); aggregation.py the scattered start; batch.py the chunk-wide neighbourhood queries;
params.py every parameter.
"""

from __future__ import annotations

from collections import Counter
from collections.abc import Sequence

import numpy as np

from controllers.gradient import COLOURINGS, SILENT
from swarmsim.controller import (
    ChunkActions,
    DecideBatch,
    NeighbourBatch,
    RobotSetup,
    message_dtype,
    register,
)

from .aggregation import MAX_GROUPS
from .batch import prepare_chunk
from .book import EdgeBook
from .enclosure import warm_up as warm_up_enclosure
from .fastpath import decide_chunk
from .moverkernel import warm_up as warm_up_movers
from .moverrows import warm_up as warm_up_mover_rows
from .params import GGCParams
from .robot import MESSAGE_FIELDS, STATUSES, GGCRobot, message_fields
from .statuses import SETTLED
from .waitrows import warm_up as warm_up_waiting


@register
class GGC(GGCRobot):
    """Gradient-and-grouping coverage (paper Sections 3-4)."""

    name = "ggc"
    Params = GGCParams
    STATUSES = STATUSES
    SETTLED_STATUSES = SETTLED
    MESSAGE_FIELDS = MESSAGE_FIELDS
    SILENT = SILENT
    COLOURINGS = COLOURINGS
    LEADER_FIELD = "leader"
    GROUP_FIELD = "group"
    INITIAL_STATUSES = ("Initial",)
    COVERING_STATUSES = ("Coverage",)
    default_start = "formation"
    max_groups = MAX_GROUPS
    requires_beacon = True
    probe_params = ("probe_distance", "boundary_probe")
    """Parameters that are floor-probe lengths (checked against the probe range)."""

    @classmethod
    def message_fields_for(cls, groups: int) -> list[tuple]:
        """The broadcast fields of a run with ``groups`` groups (see robot.message_fields)."""
        return message_fields(groups)

    @classmethod
    def create_robots(cls, setups: Sequence[RobotSetup], params: GGCParams,
                      rngs: Sequence[np.random.Generator]) -> list[GGC]:
        """The run's robots, sharing one :class:`~controllers.ggc.book.EdgeBook` (each its
        own row: movers.py reads and writes a chunk's rows at once)."""
        book = EdgeBook(len(setups), params.orbit)
        return [cls(setup, params, rng, book, row)
                for row, (setup, rng) in enumerate(zip(setups, rngs, strict=True))]

    @classmethod
    def prepare(cls, robots: list[GGCRobot], batch: NeighbourBatch) -> None:
        """Movers' and waiting robots' neighbourhood queries for a whole chunk at once
        (see batch.py)."""
        prepare_chunk(robots, batch)

    @classmethod
    def decide_batch(cls, robots: list[GGCRobot], batch: DecideBatch) -> ChunkActions:
        """The chunk's actions: movers' common case from the arrays, the rest by ``step``
        (see fastpath.py)."""
        return decide_chunk(robots, batch)

    @classmethod
    def warm_up(cls) -> None:
        """Compile (first time on a machine, a few seconds) or load the compiled kernels."""
        warm_up_movers()
        warm_up_enclosure()
        messages = np.zeros(1, dtype=message_dtype(MESSAGE_FIELDS))
        warm_up_mover_rows(messages)
        warm_up_waiting(messages)

    @classmethod
    def sensing_range(cls, params: GGCParams) -> float:
        """Robots hear broadcasts within R_c (and at least far enough to edge-follow)."""
        return max(params.R_c, params.gradient_reach * params.d_cover, params.d_cover + 2)

    @classmethod
    def summarize(cls, robots: Sequence[GGCRobot]) -> dict:
        """Per-run GGC figures for the summary: final statuses and deadlocks.

        ``deadlocks_detected`` counts every detection (Equation 3, once per T_r); a robot's
        consecutive detections make one episode (``deadlock_episodes``), released when it
        moves on or settles (``deadlocks_released``) or still open when the run ends
        (``deadlocks_open``): episodes = released + open.
        """
        counts = Counter(STATUSES[r.status] for r in robots)
        return {"status_counts": dict(sorted(counts.items())),
                "deadlocks_detected": sum(r.deadlocks for r in robots),
                "deadlock_episodes": sum(r.deadlock_episodes for r in robots),
                "deadlocks_released": sum(r.deadlocks_released for r in robots),
                "deadlocks_open": sum(r.in_deadlock for r in robots),
                "collision_stops": sum(r.collision_stops for r in robots),
                "surplus_stops": sum(r.surplus for r in robots)}


__all__ = ["GGC", "GGCParams"]
