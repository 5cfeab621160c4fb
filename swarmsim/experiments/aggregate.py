"""A sweep's aggregates: per condition (grid point), its runs over seeds summed up.

Written into ``DIR/aggregate/`` after every ``swarmsim sweep`` (rewritten from all finished
runs each time, so a resumed sweep brings them up to date)::

    conditions.csv   one row per condition: runs, finished, failed, final coverage,
                     completion tick, total distance, distance at settle (mean and sd)
    curves.csv       per condition, coverage and total distance over ticks on a common tick
                     grid: mean, sd, min and max over the condition's finished runs
    coverage.png     mean coverage over ticks per condition, the band spanning min-max

A condition is every run setting but the seed. Curves are interpolated onto one grid of at
most ``CURVE_POINTS`` whole ticks from 0 to the end of the longest run; a run that stopped
early holds its last value (it is done). sd is the population standard deviation (ddof 0) over the
finished runs; ``completion_tick`` statistics are over the runs that completed (their number
is ``completed``). docs/outputs.md lists every column.
"""

from __future__ import annotations

import json
import math
from collections.abc import Mapping, Sequence
from pathlib import Path
from typing import Any

from swarmsim.experiments.figures import Condition, CondStats, Panel, condition_stats, num_text
from swarmsim.experiments.runner import RunStore
from swarmsim.experiments.spec import RunSpec
from swarmsim.experiments.table import mean_band
from swarmsim.results.output import atomic_write_text, csv_text

AGGREGATE_DIR = "aggregate"
CURVE_POINTS = 201
"""Most ticks in the common grid of curves.csv (and the plot): whole ticks, evenly spaced,
from 0 to the longest run's end (or just past it)."""
METRICS = ("coverage", "total_distance")
DIGITS = {"coverage": 6, "total_distance": 3}


def conditions(runs: Sequence[RunSpec]) -> list[tuple[Condition, list[RunSpec]]]:
    """The runs grouped by condition (all settings but the seed), in first-run order, each
    run id once per condition; each condition labelled by its grid values
    (``d_cover=4, robots=30``). A run id that several conditions share (the same run by
    construction, see spec.run_id) is in each."""
    groups: dict[str, tuple[Condition, list[RunSpec]]] = {}
    for run in runs:
        key = json.dumps(run.params(), sort_keys=True, default=str)
        if key not in groups:
            labels = dict(run.labels)
            text = ", ".join(f"{k}={num_text(v)}" for k, v in labels.items()) or "all runs"
            groups[key] = (Condition(text, labels, run.controller, dict(run.settings)), [])
        if all(r.run_id != run.run_id for r in groups[key][1]):
            groups[key][1].append(run)
    return list(groups.values())


def aggregate(store: RunStore, runs: Sequence[RunSpec]) -> list[CondStats]:
    """Each condition's statistics and curves (bands on one common tick grid)."""
    out = [condition_stats(store, cond, rs) for cond, rs in conditions(runs)]
    ends = [float(t[-1]) for s in out for cs in s.curves.values() for t, _ in cs if len(t)]
    points, end = tick_grid(max(ends) if ends else 0.0)
    for s in out:
        s.bands = {m: mean_band(c, points=points, end=end) for m, c in s.curves.items()}
    return out


def tick_grid(last: float, most: int = CURVE_POINTS) -> tuple[int, float]:
    """(points, end) of a grid of whole ticks 0, step, ..., end >= ``last`` with at most
    ``most`` points (``mean_band``'s arguments)."""
    step = max(1, math.ceil(last / (most - 1)))
    intervals = max(1, math.ceil(last / step))
    return intervals + 1, float(step * intervals)


def write_aggregate(store: RunStore, runs: Sequence[RunSpec], out_dir: str | Path,
                    title: str | None = None) -> Path:
    """Write conditions.csv, curves.csv and coverage.png (if any run finished) into
    ``out_dir`` (atomically, each file); returns ``out_dir``. ``title`` heads the plot
    (default: the runs' worlds and controllers and how many runs finished)."""
    out = Path(out_dir)
    out.mkdir(parents=True, exist_ok=True)
    st = aggregate(store, runs)
    if title is None:
        worlds = ", ".join(dict.fromkeys(r.world for r in runs))
        controllers = ", ".join(dict.fromkeys(r.controller for r in runs))
        title = (f"{worlds} / {controllers}: {sum(s.done for s in st)} of {len(runs)} runs "
                 "finished")
    keys = grid_keys(runs)
    _write_csv(out / "conditions.csv", [condition_row(s, keys) for s in st],
               ["condition", *keys, "runs"])
    _write_csv(out / "curves.csv", [row for s in st for row in curve_rows(s, keys)],
               ["condition", *keys, "tick", "runs"])
    if any(s.bands.get("coverage") is not None for s in st):
        from swarmsim.experiments.report import plot_bands

        panel = Panel("coverage over time per condition", "condition", "coverage",
                      tuple(s.cond for s in st))
        plot_bands(title, [panel], [st], out / "coverage.png")
    return out


def _write_csv(path: Path, rows: list[dict[str, Any]], head: Sequence[str]) -> None:
    """The rows as CSV (None as an empty cell); with no rows, just the ``head`` columns."""
    text = csv_text([{k: "" if v is None else v for k, v in r.items()} for r in rows])
    atomic_write_text(path, text if rows else ",".join(head) + "\n")


def grid_keys(runs: Sequence[RunSpec]) -> list[str]:
    """The grid keys of the runs' labels, in first-appearance order."""
    keys: list[str] = []
    for run in runs:
        keys.extend(k for k in run.labels if k not in keys)
    return keys


def _r(x: float | None, digits: int) -> Any:
    return None if x is None else round(x, digits)


def condition_row(s: CondStats, keys: Sequence[str]) -> dict[str, Any]:
    """conditions.csv's row of one condition."""
    labels: Mapping[str, Any] = s.cond.value
    return {"condition": s.cond.label, **{k: labels.get(k) for k in keys},
            "runs": s.runs, "done": s.done, "failed": s.failed,
            "coverage_mean": _r(s.coverage[0], 6), "coverage_sd": _r(s.coverage[1], 6),
            "completed": s.completion[2],
            "completion_tick_mean": _r(s.completion[0], 1),
            "completion_tick_sd": _r(s.completion[1], 1),
            "total_distance_mean": _r(s.distance[0], 3),
            "total_distance_sd": _r(s.distance[1], 3),
            "distance_at_settle_mean": _r(s.distance_at_settle[0], 3),
            "distance_at_settle_sd": _r(s.distance_at_settle[1], 3),
            "stop_reasons": s.stop_text()}


def curve_rows(s: CondStats, keys: Sequence[str]) -> list[dict[str, Any]]:
    """curves.csv's rows of one condition: one per tick of the common grid."""
    bands = {m: s.bands.get(m) for m in METRICS}
    first = next((b for b in bands.values() if b is not None), None)
    if first is None:
        return []
    labels: Mapping[str, Any] = s.cond.value
    lead = {"condition": s.cond.label, **{k: labels.get(k) for k in keys}}
    rows = []
    for i, tick in enumerate(first.ticks.tolist()):
        row: dict[str, Any] = {**lead, "tick": round(tick), "runs": first.n}
        for metric, band in bands.items():
            digits = DIGITS[metric]
            for stat in ("mean", "sd", "lo", "hi"):
                name = {"lo": "min", "hi": "max"}.get(stat, stat)
                row[f"{metric}_{name}"] = (None if band is None
                                           else round(float(getattr(band, stat)[i]), digits))
        rows.append(row)
    return rows
