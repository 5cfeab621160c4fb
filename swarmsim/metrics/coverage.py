"""The coverage part: coverage P each tick and the completion tick t_dpl (paper Section 6)."""

from __future__ import annotations

from collections.abc import Mapping

from swarmsim.metrics.grid import CoverageGrid, IncrementalCoverage
from swarmsim.metrics.part import MetricPart, Observation, Reporter

COMPLETE_SLACK = 1e-12
"""Rounding slack of the completion test 1 - P <= eps0 (a fraction of the target)."""


class CoveragePart(MetricPart):
    """Coverage P (swarmsim.metrics.grid.CoverageGrid) and the completion tick.

    Attributes:
        coverage: P at the end of the last observed tick, in [0, 1].
        completion_tick: the first tick with 1 - P <= eps0 (None until then).

    Args:
        grid: the coverage raster.
        eps0: the completion threshold (fraction of the target left uncovered).
    """

    name = "coverage"

    def __init__(self, grid: CoverageGrid, eps0: float):
        self.grid = grid
        self.eps0 = eps0
        self.coverage = 0.0
        self.completion_tick: int | None = None
        self._incremental: IncrementalCoverage | None = None

    def observe(self, now: Observation) -> None:
        if self._incremental is None:
            self._incremental = IncrementalCoverage(self.grid, now.positions)
        self.coverage = self._incremental.update(now.positions)
        if self.completion_tick is None and 1.0 - self.coverage <= self.eps0 + COMPLETE_SLACK:
            self.completion_tick = now.tick

    def columns(self) -> Mapping[str, Reporter]:
        return {"coverage": lambda: round(self.coverage, 6)}

    def summary_fields(self) -> Mapping[str, Reporter]:
        return {"coverage": lambda: round(self.coverage, 6),
                "completion_tick": lambda: self.completion_tick}


__all__ = ["CoveragePart"]
