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


class BookRow:
    """Mixin of :class:`~controllers.ggc.robot.GGCRobot`: its edge-following state as
    properties over its row ``self.row`` of ``self.book`` (the same types as plain
    attributes would have: ``heading`` and ``odometer`` are the row's live 2-vectors)."""

    book: EdgeBook
    row: int

    @property
    def heading(self) -> np.ndarray:
        return self.book.heading[self.row]

    @heading.setter
    def heading(self, value) -> None:
        self.book.heading[self.row] = value

    @property
    def odometer(self) -> np.ndarray:
        return self.book.odometer[self.row]

    @odometer.setter
    def odometer(self, value) -> None:
        self.book.odometer[self.row] = value

    @property
    def sense(self) -> float:
        return float(self.book.sense[self.row])

    @sense.setter
    def sense(self, value: float) -> None:
        self.book.sense[self.row] = value

    @property
    def circling_id(self) -> int:
        return int(self.book.circling_id[self.row])

    @circling_id.setter
    def circling_id(self, value: int) -> None:
        self.book.circling_id[self.row] = value

    @property
    def circled(self) -> float:
        return float(self.book.circled[self.row])

    @circled.setter
    def circled(self, value: float) -> None:
        self.book.circled[self.row] = value

    @property
    def last_bearing(self) -> float | None:
        bearing = float(self.book.last_bearing[self.row])
        return None if math.isnan(bearing) else bearing

    @last_bearing.setter
    def last_bearing(self, value: float | None) -> None:
        self.book.last_bearing[self.row] = math.nan if value is None else value

    @property
    def progress_tick(self) -> int:
        return int(self.book.progress_tick[self.row])

    @progress_tick.setter
    def progress_tick(self, value: int) -> None:
        self.book.progress_tick[self.row] = value

    @property
    def pass_until(self) -> int:
        return int(self.book.pass_until[self.row])

    @pass_until.setter
    def pass_until(self, value: int) -> None:
        self.book.pass_until[self.row] = value

    @property
    def stop_since(self) -> int:
        return int(self.book.stop_since[self.row])

    @stop_since.setter
    def stop_since(self, value: int) -> None:
        self.book.stop_since[self.row] = value

    @property
    def resume_tick(self) -> int:
        return int(self.book.resume_tick[self.row])

    @resume_tick.setter
    def resume_tick(self, value: int) -> None:
        self.book.resume_tick[self.row] = value
