"""The state a run's GGC robots keep for edge following and Stop, one row per robot, in
arrays.

Each robot reads and writes its own row through properties of
:class:`~controllers.ggc.robot.GGCRobot` (``heading``, ``odometer``, ``sense``,
``circling_id``, ``circled``, ``last_bearing``, ``progress_tick``, ``pass_until``,
``stop_since``, ``resume_tick``), as it did its attributes. A chunk's Coverage movers
(movers.py) and robots waiting in Stop (fastpath.py) read their rows with one gather per
field and write them back with one scatter, instead of ~200 attribute reads and writes per
field and tick. Nothing here is global knowledge: a row is one robot's own memory.
"""

from __future__ import annotations

import math
from collections.abc import Callable
from typing import Any

import numpy as np

from swarmsim.controller import NO_SENDER


class EdgeBook:
    """Rows of the robots' edge-following and Stop state (row = the robot's place in the
    run).

    Attributes:
        heading: (N, 2) unit heading of the last move along an edge (0, 0 before any).
        odometer: (N, 2) displacement since the last progress sample, units.
        sense: (N,) orbit sense, +1 or -1.
        circling_id: (N,) id of the robot being circled (NO_SENDER: none).
        circled: (N,) how far round it, radians.
        last_bearing: (N,) bearing to it at the last tick, radians (NaN: none yet).
        progress_tick: (N,) tick of the last progress sample.
        pass_until: (N,) until this tick the robot does not Stop for other groups.
        stop_since: (N,) the tick its current Stop began.
        resume_tick: (N,) after a deadlock, it waits in Stop until this tick.
    """

    __slots__ = (
        "circled",
        "circling_id",
        "heading",
        "last_bearing",
        "odometer",
        "pass_until",
        "progress_tick",
        "resume_tick",
        "sense",
        "stop_since",
    )

    def __init__(self, robots: int, orbit: float):
        self.heading = np.zeros((robots, 2))
        self.odometer = np.zeros((robots, 2))
        self.sense = np.full(robots, float(orbit))
        self.circling_id = np.full(robots, NO_SENDER, dtype=np.int64)
        self.circled = np.zeros(robots)
        self.last_bearing = np.full(robots, math.nan)
        self.progress_tick = np.zeros(robots, dtype=np.int64)
        self.pass_until = np.zeros(robots, dtype=np.int64)
        self.stop_since = np.zeros(robots, dtype=np.int64)
        self.resume_tick = np.zeros(robots, dtype=np.int64)


def _row_field(name: str, read: Callable[[Any], Any], write: Callable[[Any], Any],
               doc: str) -> property:
    """A property over the robot's row of the book's array ``name``: ``read`` converts the
    stored value to what the robot sees, ``write`` what it sets to what is stored."""

    def get(self: BookRow) -> Any:
        return read(getattr(self.book, name)[self.row])

    def set_(self: BookRow, value: Any) -> None:
        getattr(self.book, name)[self.row] = write(value)

    return property(get, set_, doc=doc)


def _same(value: Any) -> Any:
    return value


def _bearing_or_none(stored: np.float64) -> float | None:
    bearing = float(stored)
    return None if math.isnan(bearing) else bearing


def _nan_for_none(value: float | None) -> float:
    return math.nan if value is None else value


class BookRow:
    """Mixin of :class:`~controllers.ggc.robot.GGCRobot`: its edge-following and Stop state
    as properties over its row ``self.row`` of ``self.book``, with the types plain
    attributes had (``heading`` and ``odometer`` are the row's live 2-vectors)."""

    book: EdgeBook
    row: int

    heading = _row_field("heading", _same, _same, "unit heading of the last move (2,)")
    odometer = _row_field("odometer", _same, _same, "displacement since the last sample (2,)")
    sense = _row_field("sense", float, _same, "orbit sense, +1 or -1")
    circling_id = _row_field("circling_id", int, _same, "the robot being circled")
    circled = _row_field("circled", float, _same, "how far round it, radians")
    last_bearing = _row_field("last_bearing", _bearing_or_none, _nan_for_none,
                              "bearing to it last tick, radians (None: none yet)")
    progress_tick = _row_field("progress_tick", int, _same, "tick of the last sample")
    pass_until = _row_field("pass_until", int, _same, "no Stop for other groups before")
    stop_since = _row_field("stop_since", int, _same, "the tick the current Stop began")
    resume_tick = _row_field("resume_tick", int, _same, "waits in Stop until this tick")
