"""The awake part (a demo): the most robots that decided in one tick."""

from __future__ import annotations

from collections.abc import Mapping

from swarmsim.metrics.part import MetricPart, Observation, Reporter


class AwakePart(MetricPart):
    """The largest number of robots that decided in one tick (summary ``peak_awake``)."""

    name = "awake"

    def __init__(self) -> None:
        self.peak = 0

    def observe(self, now: Observation) -> None:
        self.peak = max(self.peak, now.awake)

    def summary_fields(self) -> Mapping[str, Reporter]:
        return {"peak_awake": lambda: self.peak}


__all__ = ["AwakePart"]
