"""A reproduction's outputs: per-figure tables, plots and reports, and DIR/REPORT.md."""

from __future__ import annotations

import json
import os
import secrets
from collections import Counter
from collections.abc import Callable, Mapping, Sequence
from dataclasses import dataclass
from pathlib import Path
from typing import Any

from swarmsim.experiments.figures import (
    Claim,
    CondStats,
    Context,
    Figure,
    FigureTable,
    Panel,
    PaperSetup,
    num_text,
    panel_runs,
)
from swarmsim.experiments.runner import run_cost
from swarmsim.experiments.spec import unique_runs
from swarmsim.experiments.table import read_table, write_table
from swarmsim.experiments.verdicts import NOTE, _pct, _tick, counted
from swarmsim.results.output import atomic_write_text, write_csv


# ----------------------------------------------------------------------------- outputs
@dataclass(frozen=True)
class Column:
    """One rule set's share of a figure: its context, panels and their measurements."""

    ctx: Context
    panels: tuple[Panel, ...]
    stats: tuple[list[CondStats], ...]

    @property
    def name(self) -> str:
        """The column's name: its rule set, '(ghost)' for point robots ('' for a controller
        without rule sets in rigid mode)."""
        return self.ctx.setup.column_name

    @classmethod
    def of(cls, fig: Figure, ctx: Context) -> Column:
        panels = ctx.panels(fig.key)
        return cls(ctx, panels, tuple(ctx.stats(fig.key, i) for i in range(len(panels))))


def plot_figure(fig: Figure, columns: Sequence[Column], out_png: Path) -> Path:
    """Mean curves with a min-max band per condition: one row of axes per rule set, one axes
    per panel (PNG, atomic)."""
    rows = [(f"{c.name}: " if c.name else "", c.panels, c.stats) for c in columns]
    return plot_band_rows(fig.title, rows, out_png)


def plot_bands(title: str, panels: Sequence[Panel], stats_by_panel: Sequence[list[CondStats]],
               out_png: Path) -> Path:
    """Mean curves with a min-max band per condition (their ``bands``), one axes per panel,
    under ``title`` (PNG, atomic)."""
    return plot_band_rows(title, [("", panels, stats_by_panel)], out_png)


def plot_band_rows(title: str,
                   rows: Sequence[tuple[str, Sequence[Panel], Sequence[list[CondStats]]]],
                   out_png: Path) -> Path:
    """:func:`plot_bands` for several rows of panels, each row's titles prefixed by its
    first element."""
    from matplotlib.backends.backend_agg import FigureCanvasAgg
    from matplotlib.figure import Figure as MplFigure

    width = max(len(panels) for _, panels, _ in rows)
    mfig = MplFigure(figsize=(7 * width, 5 * len(rows)), dpi=100, layout="constrained")
    FigureCanvasAgg(mfig)
    axes = mfig.subplots(len(rows), width, squeeze=False)
    for row_axes, (prefix, panels, stats_by_panel) in zip(axes, rows, strict=True):
        for ax, panel, st in zip(row_axes, panels, stats_by_panel, strict=False):
            _plot_panel(ax, prefix + panel.title, panel, st)
        for ax in row_axes[len(panels):]:
            ax.set_visible(False)
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


def _plot_panel(ax: Any, title: str, panel: Panel, st: list[CondStats]) -> None:
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
    ax.set_title(title)
    ax.set_xlabel("tick")
    ax.set_ylabel("coverage (%)" if panel.metric == "coverage"
                  else "total distance moved (units)")
    if panel.metric == "coverage":
        ax.set_ylim(0, 102)
    ax.grid(True, alpha=0.3)
    if ax.get_legend_handles_labels()[0]:
        ax.legend(fontsize=8, loc="lower right" if panel.metric == "coverage" else "best")


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


def figure_section(fig: Figure, columns: Sequence[Column],
                   claims: Sequence[Sequence[Claim]], image: str,
                   tables: Sequence[FigureTable] | None = None) -> str:
    """The markdown section of one figure: per rule set its setup and measurements (its
    ``tables[i]`` for a figure that is a table), then the paper's claims with each rule
    set's measurement and verdict side by side."""
    parts = [f"## {fig.title}"] + ([] if tables else ["", f"![{fig.key}]({image})"])
    for i, col in enumerate(columns):
        if col.name:
            parts += ["", f"### Column `{col.name}`"]
        parts += ["", _runs_line(fig, col)]
        if tables:
            parts += ["", tables[i].markdown]
            continue
        for panel, st in zip(col.panels, col.stats, strict=True):
            parts += ["", f"**{panel.title}**", "", _conditions_table(st)]
            parts += [f"\n_Note: {n}_" for n in panel.notes]
            errors = sorted({e for s in st for e in s.errors})
            parts += [f"\n_Failed runs: {e}_" for e in errors[:3]]
    parts += ["", claims_table([c.name for c in columns], claims)]
    return "\n".join(parts) + "\n"


def _runs_line(fig: Figure, col: Column) -> str:
    ctx = col.ctx
    n_runs = sum(s.runs for st in col.stats for s in st)
    n_done = sum(s.done for st in col.stats for s in st)
    n_failed = sum(s.failed for st in col.stats for s in st)
    return (f"Runs: {n_done} of {n_runs} done, {n_failed} failed "
            f"(seeds 0..{ctx.reps - 1}" + (f", max_ticks {ctx.max_ticks}" if ctx.max_ticks else "")
            + f"). {setup_line(ctx.setup)} {versions_line(figure_versions(fig, ctx))}")


def _conditions_table(st: list[CondStats]) -> str:
    rows = [[s.cond.label, f"{s.done}/{s.runs}", s.stop_text(), _mean_sd(s.coverage, _pct),
             f"{_tick(s.completion[0])} ({s.completion[2]}/{s.done})",
             _mean_sd(s.settle_cov, _tick), _mean_sd(s.distance, _tick)] for s in st]
    return _md_table(rows, ["condition", "runs", "stopped by", "final coverage",
                            "completion tick (completed)", "tick at 99% of final coverage",
                            "total distance"])


def claims_table(names: Sequence[str], claims: Sequence[Sequence[Claim]]) -> str:
    """The paper's claims, one row each: the claim (with the paper's words where it adapts
    them), how and where it is tested, then each rule set's measurement and verdict side by
    side (``names[i]`` made ``claims[i]``; '' for a controller without rule sets)."""
    by_text: dict[str, list[Claim | None]] = {}
    for i, column in enumerate(claims):
        for c in column:
            by_text.setdefault(c.text, [None] * len(claims))[i] = c
    head = ["paper's claim", "test (where)"]
    for name in names:
        head += [f"{name}: measured" if name else "measured", "verdict"]
    rows = []
    for text, found in by_text.items():
        first = next(c for c in found if c is not None)
        cells = [text + (f" (paper: \"{first.paper}\")" if first.paper else ""),
                 (first.test or "-") + (f" ({first.where})" if first.where else "")]
        for c in found:
            cells += ["n/a", "-"] if c is None else [c.measured, verdict_text(c)]
        rows.append(cells)
    return _md_table(rows, head)


def verdict_text(claim: Claim) -> str:
    """A claim's verdict for a report: bold, marked when it is not counted as evidence."""
    if claim.verdict == NOTE:
        return "note"
    if not claim.evidence:
        return f"**{claim.verdict}** (decided by construction: not counted)"
    return f"**{claim.verdict}**"


def claim_row(claim: Claim) -> dict[str, Any]:
    """A claim as a claims.csv row (without its figure and rule set)."""
    return {"claim": claim.text, "measured": claim.measured, "verdict": claim.verdict,
            "counted": counted(claim), "test": claim.test, "where": claim.where,
            "paper": claim.paper}


def write_figure(fig: Figure, contexts: Sequence[Context], out: Path) -> Path:
    """Write DIR/<fig>/results.csv, conditions.csv, claims.csv, <fig>.png (table.csv instead
    for a figure that is a table) and REPORT.md, with one column (rule set) per context."""
    columns = [Column.of(fig, ctx) for ctx in contexts]
    fig_dir = out / fig.key
    rows, cond_rows, claim_rows, claims = [], [], [], []
    for col in columns:
        tag = {"ruleset": col.name} if col.name else {}
        runs = [panel_runs(p, col.ctx.setup, col.ctx.reps, col.ctx.max_ticks)
                for p in col.panels]
        for panel, runs_by_cond in zip(col.panels, runs, strict=True):
            for cond, cond_runs in zip(panel.conditions, runs_by_cond, strict=True):
                rows += [{**tag, "panel": panel.title, "condition": cond.label, **row}
                         for row in map(col.ctx.sweep.row, cond_runs) if row is not None]
        cond_rows += [{**tag, **_cond_row(p, s)}
                      for p, st in zip(col.panels, col.stats, strict=True) for s in st]
        claims.append(fig.claims(col.ctx))
        claim_rows += [{"figure": fig.key, **tag, **claim_row(c)} for c in claims[-1]]
    write_table(fig_dir / "results.csv", rows)
    write_csv(fig_dir / "conditions.csv", cond_rows)
    write_csv(fig_dir / "claims.csv", claim_rows)
    tables = None if fig.table is None else [fig.table(col.ctx) for col in columns]
    if tables is None:
        plot_figure(fig, columns, fig_dir / f"{fig.key}.png")
    else:
        write_csv(fig_dir / "table.csv", [{**({"ruleset": col.name} if col.name else {}), **row}
                                          for col, t in zip(columns, tables, strict=True)
                                          for row in t.rows])
    atomic_write_text(fig_dir / "REPORT.md",
                      figure_section(fig, columns, claims, f"{fig.key}.png", tables))
    atomic_write_text(fig_dir / "section.md",
                      figure_section(fig, columns, claims, f"{fig.key}/{fig.key}.png", tables))
    return fig_dir


def setup_line(setup: PaperSetup) -> str:
    """The setup a figure (or this reproduction) was made with, in one sentence."""
    return (f"World {setup.world!r}, controller {setup.controller!r}, robots "
            f"{setup.robots or 'world default'}, d_cover {num_text(setup.d_cover)} and "
            f"{setup.groups} groups where not varied"
            + (f", rule set {setup.ruleset!r}" if setup.ruleset else "")
            + (f", physics mode {setup.mode!r}" if setup.mode else "")
            + (f", extra settings {dict(setup.extra)}" if setup.extra else "") + ".")


def figure_versions(fig: Figure, ctx: Context) -> Counter[str]:
    """How many of a figure's finished runs each code version made."""
    runs = [run for panel in ctx.panels(fig.key)
            for rs in panel_runs(panel, ctx.setup, ctx.reps, ctx.max_ticks) for run in rs]
    rows = (ctx.sweep.row(run) for run in unique_runs(runs))
    return Counter(str(r.get("code_version") or "unrecorded") for r in rows
                   if r is not None and not r.get("error"))


def store_totals(runs_dir: Path) -> tuple[Counter[str], float]:
    """Code versions (with run counts) and summed run seconds of every finished run in a
    store (each run's ``cpu_seconds``; its ``wall_seconds`` if it predates them): the figures
    of one folder may come from several invocations."""
    versions: Counter[str] = Counter()
    seconds = 0.0
    for summary in sorted(runs_dir.glob("*/summary.json")):
        try:
            data = json.loads(summary.read_text())
        except (OSError, ValueError):
            continue
        versions[str(data.get("code_version") or "unrecorded")] += 1
        seconds += run_cost(data)
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
    """DIR/REPORT.md and DIR/claims.csv: every figure of ``keys`` (the registry's, in the
    paper's order) reproduced so far in DIR."""
    sections = [(out / k / "section.md").read_text() for k in keys
                if (out / k / "section.md").is_file()]
    judged = [c.column_name for c in setup.columns() if c.column_name]
    head = ["# Reproduction of the paper's Section 6 experiments", "",
            (f"This run of the command: {setup_line(setup)}"
             + (f" Rule sets judged side by side: {', '.join(judged)}." if judged else "")
             + " Each figure's section names the setup and code it was made with."),
            ("Curves are means over seeds on a common tick grid (a run that stopped holds its "
             "last value); bands span min-max. A comparison holds only where it is "
             "significant at 95% over seeds (Welch's interval, or ranks where a run never "
             "completed: it is slower than any that does, the paper's Definition 4; 'not "
             "resolved at N runs' otherwise); claims about d_cover are judged only where the robots "
             "fill the lattice; 'tick at 99% of final coverage' is when a curve becomes flat."),
            ""]
    if versions is not None:
        head[-1:-1] = [versions_line(versions), ""]
    if run_seconds is not None and versions:
        head[-1:-1] = [run_time_line(run_seconds, sum(versions.values())), ""]
    summary = claims_summary(out, keys)
    write_csv(out / "claims.csv", [row for k in keys if (out / k / "claims.csv").is_file()
                                   for row in read_table(out / k / "claims.csv")])
    path = out / "REPORT.md"
    atomic_write_text(path, "\n".join(head) + "\n" + summary + "\n".join(sections))
    return path


TALLY = ("consistent", "partly consistent", "not consistent", "not resolved", "not measured")
"""The verdicts a tally counts ("not resolved at N runs" counts as "not resolved")."""


def tally(rows: Sequence[Mapping[str, Any]]) -> dict[str, Counter[str]]:
    """Per rule set, how many counted claims (claims.csv rows with ``counted`` true: no
    notes, no checks decided by construction) got each verdict of :data:`TALLY`."""
    out: dict[str, Counter[str]] = {}
    for row in rows:
        name = str(row.get("ruleset") or "")
        found = out.setdefault(name, Counter())
        if str(row.get("counted")).lower() not in ("true", "1"):
            continue
        verdict = str(row["verdict"])
        found["not resolved" if verdict.startswith("not resolved") else verdict] += 1
    return out


def claims_summary(out: Path, keys: Sequence[str]) -> str:
    """'## Claims' of DIR/REPORT.md from every figure's DIR/<fig>/claims.csv ('' before any
    figure is written): see :func:`claims_summary_text`."""
    rows = [row for key in keys if (out / key / "claims.csv").is_file()
            for row in read_table(out / key / "claims.csv")]
    return claims_summary_text(rows)


def claims_summary_text(rows: Sequence[Mapping[str, Any]]) -> str:
    """'## Claims': the tally of verdicts per rule set, then every claim (claims.csv rows)
    with one verdict column per rule set ('' for no rows)."""
    verdicts: dict[tuple[str, str], dict[str, str]] = {}
    names: dict[str, None] = {}
    for row in rows:
        name = row.get("ruleset") or ""
        names[name] = None
        mark = "" if str(row.get("counted")).lower() in ("true", "1") else " (not counted)"
        verdicts.setdefault((row["figure"], row["claim"]), {})[name] = row["verdict"] + mark
    if not verdicts:
        return ""
    counts = tally(rows)
    tally_rows = [[n or "-"] + [str(counts.get(n, Counter())[v]) for v in TALLY] for n in names]
    head = ["figure", "paper's claim"] + [f"{n}: verdict" if n else "verdict" for n in names]
    table = [[key, text] + [found.get(n, "-") for n in names]
             for (key, text), found in verdicts.items()]
    return ("## Claims\n\nCounted claims (notes and checks decided by construction left out):"
            "\n\n" + _md_table(tally_rows, ["rule set", *TALLY]) + "\n\n"
            + _md_table(table, head) + "\n\n")
