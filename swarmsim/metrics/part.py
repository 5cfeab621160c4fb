"""What a metric part is: one named quantity of a run, observed tick by tick, with the
time-series columns, robots.csv columns and summary fields it reports.

A part declares each of its outputs once, as a reporter: a name and a function of no
arguments that reads the part's state when the output is written (as Mesa's DataCollector
takes named reporters). :class:`swarmsim.metrics.collector.RunMetrics` gathers the parts of a
run and refuses a name that two parts both report in the same output.
"""

from __future__ import annotations

from collections.abc import Callable, Mapping
from dataclasses import dataclass
from typing import Any

import numpy as np

Reporter = Callable[[], Any]
"""One output value (a column's cell, a summary field), read from a part's state when
called."""
RobotReporter = Callable[[], list]
"""One robots.csv column: a list with a value per robot, in robot order."""


@dataclass(frozen=True, slots=True)
class Observation:
    """The state at the end of a tick, as the metrics see it (read-only by contract: a part
    keeps a reference, never changes it).

    Attributes:
        tick: the tick that just ended (0: the start, before any tick).
        positions: (N, 2) robot positions, units.
        on_target: (N,) bool, floor sensors: robots on the target.
        messages: (N,) the broadcasts at the end of the tick (the controller's dtype).
        awake: robots that decided during the tick (all of them at the start).
        commanded: (N, 2) the velocities the robots' drives were told in the tick, units per
            tick (zeros at the start).
        failed: (N,) bool, robots that have failed.
    """

    tick: int
    positions: np.ndarray
    on_target: np.ndarray
    messages: np.ndarray
    awake: int
    commanded: np.ndarray
    failed: np.ndarray


@dataclass(frozen=True, slots=True)
class RunEnd:
    """The state a summary is made from (the end of the run, or now).

    Attributes:
        positions: (N, 2) robot positions, units.
        on_target: (N,) bool, robots on the target.
    """

    positions: np.ndarray
    on_target: np.ndarray


class MetricPart:
    """One named quantity of a run (subclass it; every method has a do-nothing default).

    Contract:
        - ``name``: the part's name, unique in a run.
        - :meth:`observe` is called once at the start (tick 0) and once at the end of every
          tick, after the physics step and the fault hooks, in the order of the run's parts
          (a part may read the parts before it). It must not change the Observation's arrays.
          Any pass over all robots belongs in a compiled kernel (swarmsim/metrics/tallies.py).
        - :meth:`conclude` is called before the summary fields are read (at the end of a
          run, or whenever a summary is asked for).
        - :meth:`columns`, :meth:`robot_columns` and :meth:`summary_fields` are called once,
          when the collector is made: each maps an output name to its reporter, in the
          order the outputs are written (time-series columns after ``tick``; robots.csv
          columns after ``robot`` and the end state's columns; summary.json fields).
    """

    name: str = ""

    def observe(self, now: Observation) -> None:
        """Account for the state at the end of ``now.tick``."""

    def conclude(self, end: RunEnd) -> None:
        """Work out what the summary fields need from ``end``."""

    def columns(self) -> Mapping[str, Reporter]:
        """Time-series columns (timeseries.csv): name -> the value now."""
        return {}

    def robot_columns(self) -> Mapping[str, RobotReporter]:
        """robots.csv columns: name -> one value per robot."""
        return {}

    def summary_fields(self) -> Mapping[str, Reporter]:
        """summary.json fields: name -> the value (after :meth:`conclude`)."""
        return {}


__all__ = ["MetricPart", "Observation", "Reporter", "RobotReporter", "RunEnd"]
