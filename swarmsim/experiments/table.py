"""Tidy tables and mean curves: one row per run; time series on a common tick grid.

Pure data handling (csv + numpy); figures are drawn elsewhere from what these return.
"""

from __future__ import annotations

import csv
import io
import json
import math
from collections.abc import Iterable, Mapping, Sequence
from dataclasses import dataclass
from pathlib import Path
from typing import Any

import numpy as np

from swarmsim.results.output import atomic_write_text

ERROR_COLUMN = "error"


def flatten(summary: Mapping[str, Any], prefix: str = "") -> dict[str, Any]:
    """Nested dicts become ``outer.inner`` columns; lists become JSON text."""
    out: dict[str, Any] = {}
    for key, value in summary.items():
        name = f"{prefix}{key}"
        if isinstance(value, Mapping):
            out.update(flatten(value, f"{name}."))
        elif isinstance(value, (list, tuple)):
            out[name] = json.dumps(value)
        else:
            out[name] = value
    return out


def run_row(run, summary: Mapping[str, Any] | None = None, error: str | None = None,
            extra: Mapping[str, Any] | None = None) -> dict[str, Any]:
    """One table row: run id, parameters, seed, every summary field, error.

    Parameters keep the values the run was given (a world path stays a path, d_cover = 6 stays
    6); summary fields that repeat a parameter are not repeated.
    """
    row: dict[str, Any] = {"run_id": run.run_id, **dict(extra or {}), **run.params(),
                           "seed": run.seed}
    for key, value in flatten(summary or {}).items():
        row.setdefault(key, value)
    row[ERROR_COLUMN] = error or ""
    return row


def table_text(rows: Sequence[Mapping[str, Any]], lead: Sequence[str] = ()) -> str:
    """CSV text with columns in first-appearance order and the error column last.

    ``lead`` names columns that come first and are written even with no rows (a sweep's
    run id, parameters and seed), so that a table of no finished run still has its header.
    """
    columns: list[str] = [k for k in lead if k != ERROR_COLUMN]
    for row in rows:
        columns.extend(k for k in row if k not in columns and k != ERROR_COLUMN)
    columns.append(ERROR_COLUMN)
    buf = io.StringIO()
    writer = csv.DictWriter(buf, fieldnames=columns, lineterminator="\n", restval="")
    writer.writeheader()
    for row in rows:
        writer.writerow({k: _cell(v) for k, v in row.items()})
    return buf.getvalue()


def _cell(value: Any) -> Any:
    return "" if value is None else value


def write_table(path: str | Path, rows: Sequence[Mapping[str, Any]],
                lead: Sequence[str] = ()) -> None:
    """Write the tidy table atomically (``lead``: see :func:`table_text`)."""
    atomic_write_text(path, table_text(rows, lead))


def read_table(path: str | Path) -> list[dict[str, str]]:
    """A table written by :func:`write_table` (values as text)."""
    with open(path, newline="") as fh:
        return list(csv.DictReader(fh))


# ------------------------------------------------------------------------------------ curves
@dataclass(frozen=True)
class Band:
    """Mean curve of several runs on a common tick grid, with its spread.

    Attributes:
        ticks: the common grid.
        mean, sd, lo, hi: mean, standard deviation, minimum and maximum over runs.
        n: number of runs.
    """

    ticks: np.ndarray
    mean: np.ndarray
    sd: np.ndarray
    lo: np.ndarray
    hi: np.ndarray
    n: int

    def at(self, tick: float) -> float:
        return float(np.interp(tick, self.ticks, self.mean))


def series(rows: Iterable[Mapping[str, Any]], column: str) -> tuple[np.ndarray, np.ndarray]:
    """(ticks, values) of one time-series column, sorted by tick; blanks dropped."""
    pairs = [(float(r["tick"]), _num(r.get(column))) for r in rows]
    pairs = sorted((t, v) for t, v in pairs if not math.isnan(v))
    if not pairs:
        return np.zeros(0), np.zeros(0)
    t, v = np.array(pairs).T
    return t, v


def _num(value: Any) -> float:
    if value is None or value == "":
        return math.nan
    return float(value)


def mean_band(curves: Sequence[tuple[np.ndarray, np.ndarray]], points: int = 400,
              end: float | None = None) -> Band | None:
    """Interpolate curves to a common grid 0..end (default: the longest run) and aggregate.

    A run that stopped early holds its last value to the end of the grid (it is done).
    """
    curves = [(t, v) for t, v in curves if len(t)]
    if not curves:
        return None
    end = max(float(t[-1]) for t, _ in curves) if end is None else end
    grid = np.linspace(0.0, max(end, 1.0), points)
    stack = np.vstack([np.interp(grid, t, v) for t, v in curves])
    return Band(grid, stack.mean(axis=0), stack.std(axis=0), stack.min(axis=0),
                stack.max(axis=0), len(curves))


def settle_tick(ticks: np.ndarray, values: np.ndarray, fraction: float = 0.99) -> float | None:
    """First tick at which ``values`` reaches ``fraction`` of its final value (the time the
    curve becomes flat), or None for an empty or all-zero curve."""
    if not len(values) or values[-1] <= 0:
        return None
    hit = np.flatnonzero(values >= fraction * values[-1])
    return float(ticks[hit[0]])


def stats(values: Iterable[float | None]) -> tuple[float | None, float | None, int]:
    """(mean, sd, n) of the values that are not None."""
    vals = [float(v) for v in values if v is not None and not math.isnan(float(v))]
    if not vals:
        return None, None, 0
    arr = np.array(vals)
    return float(arr.mean()), float(arr.std()), len(vals)
