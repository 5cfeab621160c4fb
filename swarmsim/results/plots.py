"""Time-series plots of a run: coverage % and total distance moved versus tick (PNG).

Uses matplotlib's Agg canvas directly (no pyplot, no global backend switch, no window).
"""

from __future__ import annotations

import csv
import math
import os
import secrets
from collections.abc import Iterable, Mapping
from pathlib import Path
from typing import Any

import numpy as np

REQUIRED_COLUMNS = ("tick", "coverage", "total_distance")


def _float(value: Any) -> float:
    if value is None or (isinstance(value, str) and not value.strip()):
        return math.nan
    return float(value)


def load_timeseries(source: str | os.PathLike[str] | Iterable[Mapping[str, Any]]
                    ) -> dict[str, np.ndarray]:
    """Time series columns ``tick``, ``coverage``, ``total_distance`` as float arrays.

    ``source`` is a CSV path (with a header row) or an iterable of dict rows. Extra columns are
    ignored; a missing required column raises ValueError naming it.
    """
    where = "rows"
    if isinstance(source, (str, os.PathLike)):
        where = str(source)
        with open(source, newline="") as fh:
            rows: list[Mapping[str, Any]] = list(csv.DictReader(fh))
    else:
        rows = list(source)
    if not rows:
        raise ValueError(f"{where}: no time-series rows")
    out: dict[str, np.ndarray] = {}
    for col in REQUIRED_COLUMNS:
        missing = [i for i, r in enumerate(rows) if col not in r]
        if missing:
            raise ValueError(f"{where}: row {missing[0]} has no column {col!r}; "
                             f"required columns: {', '.join(REQUIRED_COLUMNS)}")
        try:
            out[col] = np.array([_float(r[col]) for r in rows], dtype=float)
        except (TypeError, ValueError) as exc:
            raise ValueError(f"{where}: column {col!r} is not numeric ({exc})") from None
    return out


def plot_timeseries(source: str | os.PathLike[str] | Iterable[Mapping[str, Any]],
                    out_png: str | os.PathLike[str], title: str = "",
                    completion_tick: int | None = None, dpi: int = 100) -> Path:
    """Write a two-panel PNG: coverage % vs tick (top) and total distance moved vs tick (bottom).

    Args:
        source: CSV path or dict rows with at least ``tick, coverage, total_distance``.
            ``coverage`` is a fraction in [0, 1] (values above 1 are taken as percent already).
        out_png: output PNG path (written atomically).
        title: figure title.
        completion_tick: completion tick t_dpl to mark with a vertical line, if any.
        dpi: resolution.

    Returns:
        the output path.
    """
    from matplotlib.backends.backend_agg import FigureCanvasAgg
    from matplotlib.figure import Figure

    data = load_timeseries(source)
    tick, cov, dist = data["tick"], data["coverage"], data["total_distance"]
    order = np.argsort(tick, kind="stable")
    tick, cov, dist = tick[order], cov[order], dist[order]
    finite = cov[np.isfinite(cov)]
    pct = cov if finite.size and finite.max() > 1.0 + 1e-9 else 100.0 * cov

    fig = Figure(figsize=(8, 6), dpi=dpi, layout="constrained")
    FigureCanvasAgg(fig)
    ax1, ax2 = fig.subplots(2, 1, sharex=True)
    ax1.plot(tick, pct, color="tab:blue", lw=1.5)
    ax1.set_ylabel("coverage (%)")
    ax1.set_ylim(0, 102)
    ax1.grid(True, alpha=0.3)
    ax2.plot(tick, dist, color="tab:orange", lw=1.5)
    ax2.set_ylabel("total distance moved (units)")
    ax2.set_xlabel("tick")
    ax2.grid(True, alpha=0.3)
    if completion_tick is not None:
        for ax in (ax1, ax2):
            ax.axvline(completion_tick, color="tab:red", ls="--", lw=1)
        ax1.annotate(f"complete at tick {completion_tick}", xy=(completion_tick, 4),
                     xytext=(4, 0), textcoords="offset points", color="tab:red",
                     ha="left", va="bottom", fontsize=9)
    if title:
        fig.suptitle(title)

    out = Path(out_png)
    tmp = out.with_name(f".{out.name}.{os.getpid()}.{secrets.token_hex(4)}.tmp.png")
    try:
        fig.savefig(tmp, format="png")
        os.replace(tmp, out)
    except BaseException:
        try:
            tmp.unlink()
        except FileNotFoundError:
            pass
        raise
    return out
