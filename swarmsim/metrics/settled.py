"""The settled part: robots pushed out of place after they settled (GGC: Arrive)."""

from __future__ import annotations

from collections.abc import Mapping

import numpy as np

from swarmsim.metrics.part import MetricPart, Observation, Reporter, RobotReporter
from swarmsim.metrics.tallies import watch_settled


class SettledWatch:
    """Robots pushed out of place after they settled (GGC: Arrive), from their broadcasts.

    A robot is settled while it broadcasts one of the controller's settled statuses and is not
    moving on purpose; its anchor is where it settled. It counts as displaced once it is more
    than ``threshold`` units from its anchor: with rigid bodies only a push moves it.

    Args:
        n: number of robots.
        codes: status codes that mean "settled" (index into the controller's STATUSES).
        threshold: displacement that counts as "pushed out of place", units.
    """

    def __init__(self, n: int, codes: tuple[int, ...], threshold: float):
        self._is_settled = np.zeros(257, dtype=bool)  # status code + 128 -> settled?
        self._is_settled[np.asarray(codes, dtype=np.int64) + 128] = True
        self.threshold = threshold
        self.settled = np.zeros(n, dtype=bool)
        self.anchor = np.zeros((n, 2))
        self.max_shift = np.zeros(n)  # largest displacement of each robot while settled, units
        self._displaced_now = 0

    def observe(self, positions: np.ndarray, messages: np.ndarray) -> None:
        """Account for the state at the end of a tick (``messages``: the broadcasts)."""
        self._displaced_now = watch_settled(positions, messages["status"], messages["moving"],
                                            self._is_settled, self.settled, self.anchor,
                                            self.max_shift, self.threshold)

    @property
    def displaced_now(self) -> int:
        """Settled robots currently more than ``threshold`` from where they settled."""
        return self._displaced_now

    @property
    def ever_displaced(self) -> np.ndarray:
        """(N,) bool: robots that were once pushed more than ``threshold`` while settled."""
        return self.max_shift > self.threshold


class SettledPart(MetricPart):
    """Settled robots displaced now (time series), ever, and by how much (summary, robots.csv).

    Args:
        n: number of robots.
        codes: status codes that mean "settled".
        threshold: displacement that counts as "pushed out of place", units.
    """

    name = "settled"

    def __init__(self, n: int, codes: tuple[int, ...], threshold: float):
        self.watch = SettledWatch(n, codes, threshold)

    def observe(self, now: Observation) -> None:
        self.watch.observe(now.positions, now.messages)

    def columns(self) -> Mapping[str, Reporter]:
        return {"settled_displaced": lambda: self.watch.displaced_now}

    def robot_columns(self) -> Mapping[str, RobotReporter]:
        return {"settled_max_displacement": lambda: np.round(self.watch.max_shift, 4).tolist()}

    def summary_fields(self) -> Mapping[str, Reporter]:
        return {"settled_displaced": lambda: int(self.watch.ever_displaced.sum()),
                "settled_max_displacement": self._max_displacement}

    def _max_displacement(self) -> float:
        """The largest displacement of any robot while settled, units (0.0 for no robots)."""
        shift = self.watch.max_shift
        return round(float(shift.max()), 4) if shift.size else 0.0


__all__ = ["SettledPart", "SettledWatch"]
