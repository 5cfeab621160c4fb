"""The spacing part: how evenly the robots on the target are spaced at the end."""

from __future__ import annotations

from collections.abc import Mapping

import numpy as np
from scipy.spatial import cKDTree

from swarmsim.metrics.part import MetricPart, Reporter, RunEnd


class SpacingPart(MetricPart):
    """Nearest-neighbour spacing of the robots on the target (summary only)."""

    name = "spacing"

    def __init__(self) -> None:
        self._spacing: tuple[float | None, ...] = (None, None, None)

    def conclude(self, end: RunEnd) -> None:
        self._spacing = nearest_neighbour_spacing(end.positions[end.on_target])

    def summary_fields(self) -> Mapping[str, Reporter]:
        return {"spacing_mean": lambda: self._spacing[0], "spacing_std": lambda: self._spacing[1],
                "spacing_cv": lambda: self._spacing[2]}


def nearest_neighbour_spacing(positions: np.ndarray) -> tuple[float | None, ...]:
    """Mean, standard deviation and coefficient of variation of nearest-neighbour distances.

    The spacing-uniformity measure of robots on the target (None when fewer than 2 robots).
    """
    if len(positions) < 2:
        return (None, None, None)
    d, _ = cKDTree(positions).query(positions, k=2)
    nn = d[:, 1]
    mean, std = float(nn.mean()), float(nn.std())
    return (round(mean, 4), round(std, 4), round(std / mean, 4) if mean > 0 else None)


__all__ = ["SpacingPart", "nearest_neighbour_spacing"]
