"""A run's metrics: named parts gathered into the time series, robots.csv and the summary.

Each part (swarmsim.metrics.part.MetricPart) declares its own outputs; :class:`RunMetrics`
observes the parts in order, writes a time-series row every ``record_every`` ticks and
collects the parts' robots.csv columns and summary fields, refusing a name that two parts
both report in one output. A new metric is one new part in :func:`standard_parts`.
"""

from __future__ import annotations

from collections.abc import Iterable, Sequence
from typing import Any, Protocol, TypeVar

import numpy as np

from swarmsim.metrics.contacts import ContactsPart
from swarmsim.metrics.coverage import CoveragePart
from swarmsim.metrics.final import FinalState
from swarmsim.metrics.grid import CoverageGrid
from swarmsim.metrics.part import MetricPart, Observation, Reporter, RobotReporter, RunEnd
from swarmsim.metrics.progress import ProgressPart
from swarmsim.metrics.settled import SettledPart
from swarmsim.metrics.spacing import SpacingPart
from swarmsim.metrics.stuck import StuckPart

TICK_COLUMN = "tick"
"""The time series' first column, written by the collector."""
ROBOT_COLUMN = "robot"
"""robots.csv's first column, written by the collector."""

P = TypeVar("P", bound=MetricPart)


class ObservedRun(Protocol):
    """What the metrics read of a run at the end of a tick (a Simulation is one)."""

    tick: int
    positions: np.ndarray
    on_target: np.ndarray
    messages: np.ndarray
    awake_count: int
    velocities: np.ndarray
    failed: np.ndarray


def standard_parts(grid: CoverageGrid, config: Any, physics: Any,
                   settled_codes: tuple[int, ...], broadcasts: np.dtype) -> list[MetricPart]:
    """The parts of every run, in the order their outputs are written: coverage, progress,
    contacts, settled robots, spacing, stuck robots.

    Args:
        grid: the coverage raster.
        config: the run's SimConfig (eps0, record_every, plateau_delta, v_max,
            displaced_threshold).
        physics: the Physics whose contact counters and arbiters are read.
        settled_codes: the controller's status codes that mean "settled".
        broadcasts: the dtype of the run's broadcasts.
    """
    coverage = CoveragePart(grid, config.eps0)
    settled = SettledPart(physics.n, settled_codes, config.displaced_threshold)
    progress = ProgressPart(physics.n, coverage, settled, settled_codes, config,
                            counts_broadcast_moving="moving" in (broadcasts.names or ()))
    contacts = ContactsPart(physics)
    return [coverage, progress, contacts, settled, SpacingPart(),
            StuckPart(physics.n, contacts, config.v_max)]


class RunMetrics:
    """Accumulates a run's metrics tick by tick from named parts and keeps the time series.

    A loop hook (swarmsim.engine.hooks): :meth:`start` and :meth:`post_step` observe the run, so a
    hook placed before it in ``Simulation.hooks`` changes what a tick's metrics see, and one
    placed after it reads them.

    Args:
        parts: the parts, in the order they are observed and their outputs written.
        record_every: a time-series row every this many ticks.

    Raises:
        ValueError: two parts share a name, or report the same column or field.
    """

    def __init__(self, parts: Sequence[MetricPart], record_every: int):
        self.parts = tuple(parts)
        self.record_every = record_every
        _unique("name", ((part.name, part) for part in self.parts))
        self._columns: list[tuple[str, Reporter]] = _declared(
            "time-series column", self.parts, "columns", reserved=TICK_COLUMN)
        self._robot_columns: list[tuple[str, RobotReporter]] = _declared(
            "robots.csv column", self.parts, "robot_columns", reserved=ROBOT_COLUMN)
        self._summary_fields: list[tuple[str, Reporter]] = _declared(
            "summary field", self.parts, "summary_fields")
        self.rows: list[dict] = []
        self._last_recorded = -1

    def part(self, kind: type[P]) -> P:
        """The run's part of class ``kind`` (KeyError if it has none)."""
        for part in self.parts:
            if isinstance(part, kind):
                return part
        raise KeyError(f"no {kind.__name__} among the run's metric parts")

    @property
    def coverage(self) -> float:
        """The coverage fraction P at the end of the last observed tick (the coverage
        part's)."""
        return self.part(CoveragePart).coverage

    # --------------------------------------------------------------- the loop hook
    def start(self, run: ObservedRun) -> None:
        """Observe the start (tick 0)."""
        self.post_step(run)

    def pre_step(self, run: ObservedRun) -> None:
        """Nothing before a tick."""

    def post_step(self, run: ObservedRun) -> None:
        """Observe the end of the tick that just ended."""
        self.observe(Observation(run.tick, run.positions, run.on_target, run.messages,
                                 run.awake_count, run.velocities, run.failed))

    def is_finished(self, run: ObservedRun) -> str | None:
        """The metrics never stop a run (the stop rules read them)."""
        return None

    # --------------------------------------------------------------- observing, writing
    def observe(self, now: Observation) -> None:
        """Account for the state at the end of ``now.tick`` (every part, in order)."""
        for part in self.parts:
            part.observe(now)
        self.record(now.tick)

    def record(self, tick: int, force: bool = False) -> None:
        """Append a time-series row every ``record_every`` ticks (or now, if forced)."""
        if tick == self._last_recorded or not (force or tick % self.record_every == 0):
            return
        self._last_recorded = tick
        row: dict[str, Any] = {TICK_COLUMN: tick}
        for name, reporter in self._columns:
            row[name] = reporter()
        self.rows.append(row)

    def summary(self, positions: np.ndarray, on_target: np.ndarray) -> dict[str, Any]:
        """The parts' summary.json fields, in order, for robots at ``positions``
        (``on_target``: their floor sensors); docs/outputs.md says what each means."""
        end = RunEnd(positions, on_target)
        for part in self.parts:
            part.conclude(end)
        return {name: reporter() for name, reporter in self._summary_fields}

    def robot_rows(self, final: FinalState | None = None) -> list[dict]:
        """One row per robot (robots.csv; docs/outputs.md lists the columns).

        Without ``final`` (the run's end state), only the columns the parts report.
        """
        columns = [(name, reporter()) for name, reporter in self._robot_columns]
        n = len(columns[0][1]) if columns else len(final.positions) if final is not None else 0
        lead = final.columns() if final is not None else [{} for _ in range(n)]
        return [{ROBOT_COLUMN: i, **lead[i], **{name: values[i] for name, values in columns}}
                for i in range(n)]


def _declared(output: str, parts: Iterable[MetricPart], declare: str,
              reserved: str | None = None) -> list[tuple[str, Any]]:
    """Every part's reporters of one output (``declare``: the MetricPart method that gives
    them), in order: (name, reporter) (ValueError naming
    both parts for a name two parts report, or a part reporting the collector's own
    ``reserved`` column)."""
    found = [(name, (part, reporter)) for part in parts
             for name, reporter in getattr(part, declare)().items()]
    _unique(output, ((name, part) for name, (part, _) in found), reserved)
    return [(name, reporter) for name, (_, reporter) in found]


def _unique(output: str, named: Iterable[tuple[str, MetricPart]],
            reserved: str | None = None) -> None:
    """ValueError naming the two parts that give one ``output`` the same name."""
    owner: dict[str, MetricPart] = {}
    for name, part in named:
        if name == reserved:
            raise ValueError(f"metric part {part.name!r}: {output} {name!r} is the "
                             "collector's own")
        if name in owner:
            raise ValueError(f"{output} {name!r} reported by both metric parts "
                             f"{owner[name].name!r} and {part.name!r}")
        owner[name] = part


__all__ = ["ObservedRun", "RunMetrics", "standard_parts"]
