"""A reproduction's outputs: per-figure tables, plots and reports, and DIR/REPORT.md."""

from __future__ import annotations

import json
import os
import secrets
from collections import Counter
from collections.abc import Callable, Mapping, Sequence
from pathlib import Path
from typing import Any

from swarmsim.experiments.figures import (
    CondStats,
    Context,
    Figure,
    Panel,
    PaperSetup,
    num_text,
    panel_runs,
)
from swarmsim.experiments.spec import unique_runs
from swarmsim.experiments.table import write_table
from swarmsim.experiments.verdicts import _pct, _tick
from swarmsim.output import atomic_write_text, write_csv


# ----------------------------------------------------------------------------- outputs
def plot_figure(fig: Figure, panels: Sequence[Panel], stats_by_panel: Sequence[list[CondStats]],
                out_png: Path) -> Path:
    """Mean curves with a min-max band per condition, one axes per panel (PNG, atomic)."""
    return plot_bands(fig.title, panels, stats_by_panel, out_png)


def plot_bands(title: str, panels: Sequence[Panel], stats_by_panel: Sequence[list[CondStats]],
               out_png: Path) -> Path:
    """Mean curves with a min-max band per condition (their ``bands``), one axes per panel,
    under ``title`` (PNG, atomic)."""
    from matplotlib.backends.backend_agg import FigureCanvasAgg
    from matplotlib.figure import Figure as MplFigure

    mfig = MplFigure(figsize=(7 * len(panels), 5), dpi=100, layout="constrained")
    FigureCanvasAgg(mfig)
    axes = mfig.subplots(1, len(panels), squeeze=False)[0]
    for ax, panel, st in zip(axes, panels, stats_by_panel, strict=True):
        scale = 100.0 if panel.metric == "coverage" else 1.0
        for i, s in enumerate(st):
            band = s.bands.get(panel.metric)
            if band is None:
                continue
            color = f"C{i % 10}"
            ax.plot(band.ticks, scale * band.mean, color=color, lw=1.6,
                    label=f"{s.cond.label} (n={band.n})")
            ax.fill_between(band.ticks, scale * band.lo, scale * band.hi, color=color,
                            alpha=0.18, lw=0)
        ax.set_title(panel.title)
        ax.set_xlabel("tick")
        ax.set_ylabel("coverage (%)" if panel.metric == "coverage"
                      else "total distance moved (units)")
        if panel.metric == "coverage":
            ax.set_ylim(0, 102)
        ax.grid(True, alpha=0.3)
        if ax.get_legend_handles_labels()[0]:
            ax.legend(fontsize=8, loc="lower right" if panel.metric == "coverage" else "best")
    mfig.suptitle(f"{title}\n(mean, band = min-max over runs)")  # one panel: too wide for a line
    out_png.parent.mkdir(parents=True, exist_ok=True)
    tmp = out_png.with_name(f".{out_png.name}.{os.getpid()}.{secrets.token_hex(4)}.tmp.png")
    try:
        mfig.savefig(tmp, format="png")
        os.replace(tmp, out_png)
    except BaseException:
        tmp.unlink(missing_ok=True)
        raise
    return out_png


def _cond_row(panel: Panel, s: CondStats) -> dict[str, Any]:
    def r(x: float | None, nd: int = 4) -> Any:
        return None if x is None else round(x, nd)

    return {"panel": panel.title, panel.vary: s.cond.value, "condition": s.cond.label, "runs": s.runs, "done": s.done,
            "failed": s.failed, "coverage_mean": r(s.coverage[0]), "coverage_sd": r(s.coverage[1]),
            "completed": s.completion[2], "completion_tick_mean": r(s.completion[0], 1),
            "completion_tick_sd": r(s.completion[1], 1),
            "stop_reasons": s.stop_text(), "settle_tick_mean": r(s.settle_cov[0], 1), "settle_tick_sd": r(s.settle_cov[1], 1),
            "total_distance_mean": r(s.distance[0], 1), "total_distance_sd": r(s.distance[1], 1),
            "distance_settle_tick_mean": r(s.settle_dist[0], 1)}


def _md_table(rows: list[list[str]], head: list[str]) -> str:
    lines = ["| " + " | ".join(head) + " |", "|" + "|".join("---" for _ in head) + "|"]
    lines += ["| " + " | ".join(c.replace("|", "/") for c in row) + " |" for row in rows]
    return "\n".join(lines)


def _mean_sd(x: tuple[float | None, float | None, int], fmt: Callable) -> str:
    return "n/a" if x[0] is None else f"{fmt(x[0])} ± {fmt(x[1])}"


def figure_section(fig: Figure, ctx: Context, panels: Sequence[Panel],
                   stats_by_panel: Sequence[list[CondStats]], image: str) -> str:
    """The markdown section of one figure: setup, measurements, claims and verdicts."""
    n_runs = sum(s.runs for st in stats_by_panel for s in st)
    n_done = sum(s.done for st in stats_by_panel for s in st)
    n_failed = sum(s.failed for st in stats_by_panel for s in st)
    parts = [f"## {fig.title}", "", f"![{fig.key}]({image})", "",
             f"Runs: {n_done} of {n_runs} done, {n_failed} failed "
             f"(seeds 0..{ctx.reps - 1}" + (f", max_ticks {ctx.max_ticks}" if ctx.max_ticks else "")
             + f"). {setup_line(ctx.setup)} {versions_line(figure_versions(fig, ctx))}"]
    for panel, st in zip(panels, stats_by_panel, strict=True):
        rows = [[s.cond.label, f"{s.done}/{s.runs}", s.stop_text(), _mean_sd(s.coverage, _pct),
                 f"{_tick(s.completion[0])} ({s.completion[2]}/{s.done})",
                 _mean_sd(s.settle_cov, _tick), _mean_sd(s.distance, _tick)] for s in st]
        parts += ["", f"**{panel.title}**", "", _md_table(
            rows, ["condition", "runs", "stopped by", "final coverage", "completion tick (completed)",
                   "tick at 99% of final coverage", "total distance"])]
        parts += [f"\n_Note: {n}_" for n in panel.notes]
        errors = sorted({e for s in st for e in s.errors})
        parts += [f"\n_Failed runs: {e}_" for e in errors[:3]]
    claims = fig.claims(ctx)
    parts += ["", "| paper's claim | measured | verdict |", "|---|---|---|"]
    parts += [f"| {c.text} | {c.measured.replace('|', '/')} | **{c.verdict}** |" for c in claims]
    return "\n".join(parts) + "\n"


def write_figure(fig: Figure, ctx: Context, out: Path) -> Path:
    """Write DIR/<fig>/results.csv, conditions.csv, <fig>.png and REPORT.md."""
    panels = ctx.panels(fig.key)
    stats_by_panel = [ctx.stats(fig.key, i) for i in range(len(panels))]
    fig_dir = out / fig.key
    rows = []
    for panel, runs_by_cond in zip(panels, [panel_runs(p, ctx.setup, ctx.reps, ctx.max_ticks)
                                            for p in panels], strict=True):
        for cond, runs in zip(panel.conditions, runs_by_cond, strict=True):
            for run in runs:
                row = ctx.sweep.row(run)
                if row is not None:
                    rows.append({"panel": panel.title, "condition": cond.label, **row})
    write_table(fig_dir / "results.csv", rows)
    write_csv(fig_dir / "conditions.csv",
              [_cond_row(p, s) for p, st in zip(panels, stats_by_panel, strict=True) for s in st])
    plot_figure(fig, panels, stats_by_panel, fig_dir / f"{fig.key}.png")
    atomic_write_text(fig_dir / "REPORT.md",
                      figure_section(fig, ctx, panels, stats_by_panel, f"{fig.key}.png"))
    atomic_write_text(fig_dir / "section.md",
                      figure_section(fig, ctx, panels, stats_by_panel,
                                     f"{fig.key}/{fig.key}.png"))
    return fig_dir


def setup_line(setup: PaperSetup) -> str:
    """The setup a figure (or this reproduction) was made with, in one sentence."""
    return (f"World {setup.world!r}, controller {setup.controller!r}, robots "
            f"{setup.robots or 'world default'}, d_cover {num_text(setup.d_cover)} and "
            f"{setup.groups} groups where not varied"
            + (f", extra settings {dict(setup.extra)}" if setup.extra else "") + ".")


def figure_versions(fig: Figure, ctx: Context) -> Counter[str]:
    """How many of a figure's finished runs each code version made."""
    runs = [run for panel in ctx.panels(fig.key)
            for rs in panel_runs(panel, ctx.setup, ctx.reps, ctx.max_ticks) for run in rs]
    rows = (ctx.sweep.row(run) for run in unique_runs(runs))
    return Counter(str(r.get("code_version") or "unrecorded") for r in rows
                   if r is not None and not r.get("error"))


def store_totals(runs_dir: Path) -> tuple[Counter[str], float]:
    """Code versions (with run counts) and summed wall seconds of every finished run in a
    store: the figures of one folder may come from several invocations."""
    versions: Counter[str] = Counter()
    seconds = 0.0
    for summary in sorted(runs_dir.glob("*/summary.json")):
        try:
            data = json.loads(summary.read_text())
        except (OSError, ValueError):
            continue
        versions[str(data.get("code_version") or "unrecorded")] += 1
        seconds += float(data.get("wall_seconds") or 0.0)
    return versions, seconds


def versions_line(versions: Mapping[str, int]) -> str:
    """The report's line on which code made the runs; a warning when it is more than one."""
    listed = ", ".join(f"{v} ({n} runs)" for v, n in sorted(versions.items()))
    if len(versions) <= 1:
        return f"Code: {listed or 'no runs yet'}."
    return (f"**Warning: these runs were made by {len(versions)} code versions: {listed}.** "
            "Results are averaged over all of them; to redo every run with one version, "
            "reproduce into a fresh --out.")


def run_time_line(seconds: float, runs: int) -> str:
    """The report's line on what the finished runs cost (simulation time, summed)."""
    return (f"Run time: {runs} finished runs simulated for {seconds / 3600:.2f} CPU-hours "
            f"in total ({seconds / max(runs, 1):.0f} s a run on average).")


def write_report(out: Path, keys: Sequence[str], setup: PaperSetup,
                 versions: Mapping[str, int] | None = None,
                 run_seconds: float | None = None) -> Path:
    """DIR/REPORT.md: every figure of ``keys`` (the registry's, in the paper's order)
    reproduced so far in DIR."""
    sections = [(out / k / "section.md").read_text() for k in keys
                if (out / k / "section.md").is_file()]
    head = ["# Reproduction of the paper's Section 6 experiments", "",
            (f"This run of the command: {setup_line(setup)} Each figure's section names the "
             "setup and code it was made with."),
            ("Curves are means over seeds on a common tick grid (a run that stopped holds its "
             "last value); bands span min-max. Verdicts compare the measured means with the "
             "paper's statements; 'tick at 99% of final coverage' is when a curve becomes flat."),
            ""]
    if versions is not None:
        head[-1:-1] = [versions_line(versions), ""]
    if run_seconds is not None and versions:
        head[-1:-1] = [run_time_line(run_seconds, sum(versions.values())), ""]
    path = out / "REPORT.md"
    atomic_write_text(path, "\n".join(head) + "\n" + "\n".join(sections))
    return path
