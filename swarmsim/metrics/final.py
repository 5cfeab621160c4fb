"""What robots.csv reads from the end of a run (its leading columns: position, status and
the controller's fields)."""

from __future__ import annotations

from collections.abc import Mapping
from dataclasses import dataclass, field
from typing import Any

import numpy as np


@dataclass(frozen=True)
class FinalState:
    """What robots.csv reads from the end of a run.

    Attributes:
        positions: (N, 2) final positions, units.
        messages: (N,) the final broadcasts (structured array; any controller's dtype).
        statuses: the controller's status names, indexed by the ``status`` field.
        failed: (N,) bool, robots that failed during the run.
        fields: the broadcast fields copied into robots.csv (a controller's colourings and
            leader field: GGC's group, gradient, leader), each only if the messages have it.
        unknown: field values that mean "none" (the controller's SILENT values, e.g. an
            unknown gradient): written as an empty cell.
    """

    positions: np.ndarray
    messages: np.ndarray
    statuses: tuple[str, ...]
    failed: np.ndarray
    fields: tuple[str, ...] = ()
    unknown: Mapping[str, Any] = field(default_factory=dict)

    def columns(self) -> list[dict]:
        """Per robot: x, y, and status, group, gradient, leader as far as the broadcasts
        carry them. A failed robot's status reads "Failed"; a status code the controller
        does not name reads as an empty cell."""
        n = len(self.positions)
        xy = np.round(self.positions, 4).tolist()
        cols: dict[str, list] = {}
        names = self.messages.dtype.names or ()
        if "status" in names:
            codes = self.messages["status"].tolist()
            failed = self.failed.tolist()
            cols["status"] = ["Failed" if failed[i] else
                              self.statuses[code] if 0 <= code < len(self.statuses) else ""
                              for i, code in enumerate(codes)]
        for name in self.fields:
            if name not in names:
                continue
            values = self.messages[name]
            if values.ndim != 1:  # a field holding an array per robot: not a column
                continue
            out = values.tolist()
            if name in self.unknown:
                none = self.unknown[name]
                out = ["" if v == none else v for v in out]
            elif values.dtype == bool:
                out = [int(v) for v in out]
            cols[name] = out
        return [{"x": xy[i][0], "y": xy[i][1], **{k: v[i] for k, v in cols.items()}}
                for i in range(n)]


__all__ = ["FinalState"]
