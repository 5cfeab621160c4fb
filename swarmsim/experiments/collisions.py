"""``swarmsim study collisions``: what real bodies change, compared with the paper's points.

The paper's robots are points that pass through each other (NetLogo). The same controller,
world, robots and seeds run in ``ghost`` mode (robots pass through each other; walls hold) and
in ``rigid`` mode (pymunk discs that push each other), optionally at several noise levels (a
level x sets speed_noise = heading_noise = distance_noise = bearing_noise = x, see
swarmsim/robots/imperfections.py). Runs are resumable (one run store, as in ``swarmsim sweep``).

Outputs in DIR: ``runs/<id>/`` (each run), ``results.csv`` (one row per run),
``conditions.csv`` (means and sds per condition), ``collisions.png`` (mean coverage, distance
and robots in contact over time, with min-max bands) and ``REPORT.md`` (the table and what
rigid bodies cost: ticks and distance to reach each coverage milestone, relative to ghost).
"""

from __future__ import annotations

import io
from collections.abc import Mapping, Sequence
from dataclasses import dataclass, field
from pathlib import Path
from typing import Any

import numpy as np

from swarmsim.errors import ConfigError
from swarmsim.experiments.runner import DONE, Sweep
from swarmsim.experiments.spec import RunSpec, drop_unused_groups
from swarmsim.experiments.table import Band, mean_band, series, stats
from swarmsim.limits import MAX_REPS, check_count
from swarmsim.results.output import atomic_write_bytes, atomic_write_text, write_csv

MILESTONES = (0.5, 0.6, 0.7, 0.8, 0.9)
"""Coverage fractions at which the study compares ticks and distance moved."""

NOISE_KEYS = ("speed_noise", "heading_noise", "distance_noise", "bearing_noise")
CONTACT_FIELDS = ("collisions_robot_robot", "collisions_robot_wall", "contact_robot_ticks",
                  "max_overlap", "mean_overlap", "peak_contact_impulse", "robots_touched",
                  "settled_displaced")


@dataclass(frozen=True)
class StudySetup:
    """What the study runs.

    Attributes:
        world: world name or path (default 'K', the paper's Figure 14).
        controller: controller under study.
        robots, groups, d_cover: None = the world's / controller's defaults (groups is left
            out for a controller that has no use for it: see drop_unused_groups).
        modes: physics modes compared ("ghost" = the paper's point robots).
        noise: noise levels (0 = ideal robots).
        max_ticks: tick limit of every run (None = the engine's default).
        extra: any other run setting, applied to every run.
    """

    world: str = "K"
    controller: str = "ggc"
    robots: int | None = None
    groups: int | None = 3
    d_cover: float | None = None
    modes: tuple[str, ...] = ("ghost", "rigid")
    noise: tuple[float, ...] = (0.0,)
    max_ticks: int | None = None
    extra: Mapping[str, Any] = field(default_factory=dict)

    def settings(self, mode: str, noise: float) -> dict[str, Any]:
        out: dict[str, Any] = {"mode": mode}
        for key in ("robots", "groups", "d_cover", "max_ticks"):
            if getattr(self, key) is not None:
                out[key] = getattr(self, key)
        if noise:
            out.update(dict.fromkeys(NOISE_KEYS, noise))
        out.update(self.extra)
        return drop_unused_groups(self.controller, out)  # groups 3 is ggc's default


@dataclass(frozen=True)
class StudyCondition:
    """One condition of a study: its name, the values that define it and its runs.

    Attributes:
        label: the condition's name in tables and plots (e.g. "rigid, noise 0.05").
        labels: what the condition sets, by axis (this study: ``mode``, ``noise``), in the
            order conditions.csv writes them.
        runs: the condition's runs, one per seed.
    """

    label: str
    labels: Mapping[str, Any]
    runs: tuple[RunSpec, ...]

    @property
    def mode(self) -> str:
        """The physics mode (``labels["mode"]``)."""
        return self.labels["mode"]

    @property
    def noise(self) -> float:
        """The noise level (``labels["noise"]``)."""
        return self.labels["noise"]


def conditions(setup: StudySetup, reps: int) -> list[StudyCondition]:
    """Every (noise level, mode) pair with its runs (seeds 0..reps-1)."""
    check_count("--reps", reps, MAX_REPS, "seeds per condition")
    out = []
    for noise in setup.noise:
        for mode in setup.modes:
            label = mode if not noise else f"{mode}, noise {noise:g}"
            settings = setup.settings(mode, noise)
            labels = {"mode": mode, "noise": noise}
            runs = tuple(RunSpec(setup.world, setup.controller, settings, seed, labels=labels)
                         for seed in range(reps))
            out.append(StudyCondition(label, labels, runs))
    return out


def check_setup(setup: StudySetup) -> None:
    """Fail early, naming the key, on a bad world, controller, mode, level or setting."""
    from swarmsim.controller import get_controller
    from swarmsim.engine.config import build_configs
    from swarmsim.world.world import load_world

    load_world(setup.world)
    cls = get_controller(setup.controller)
    if not setup.modes:
        raise ConfigError("give at least one mode", key="--modes")
    for key in ("mode", *NOISE_KEYS):
        if key in setup.extra:
            option = "--modes" if key == "mode" else "--noise"
            raise ConfigError(f"is what the study varies ({option}); give {option} instead of "
                              f"--set {key}={setup.extra[key]!r}", key=key)
    for noise in setup.noise:
        if not noise >= 0:
            raise ConfigError(f"must be >= 0, got {noise!r}", key="--noise")
    for mode in setup.modes:
        settings = setup.settings(mode, max(setup.noise))
        if setup.d_cover is not None and "d_cover" not in cls.Params.__dataclass_fields__:
            raise ConfigError(f"controller {setup.controller!r} has no d_cover parameter "
                              f"(value {setup.d_cover!r})", key="--d-cover")
        build_configs(settings, cls.Params)


# ----------------------------------------------------------------------------- analysis
@dataclass
class ConditionStats:
    """What one condition measured (means, sds and counts over its finished runs)."""

    cond: StudyCondition
    summaries: list[dict[str, Any]]
    curves: dict[str, list[tuple[np.ndarray, np.ndarray]]]
    milestones: dict[float, dict[int, tuple[float, float]]]
    """Per coverage level: seed -> (first tick at that coverage, total distance by then)."""
    bands: dict[str, Band | None] = field(default_factory=dict)

    def field_stats(self, key: str) -> tuple[float | None, float | None, int]:
        return stats(s.get(key) for s in self.summaries)

    def tick_to(self, level: float, seeds: Sequence[int] | None = None
                ) -> tuple[float | None, float | None, int]:
        reached = self.milestones[level]
        return stats(reached[k][0] for k in (reached if seeds is None else seeds))

    def distance_to(self, level: float, seeds: Sequence[int] | None = None
                    ) -> tuple[float | None, float | None, int]:
        reached = self.milestones[level]
        return stats(reached[k][1] for k in (reached if seeds is None else seeds))


def milestone(rows: list[dict[str, str]], level: float) -> tuple[float | None, float | None]:
    """First tick at which coverage reaches ``level``, and the total distance by then."""
    t, cov = series(rows, "coverage")
    _, dist = series(rows, "total_distance")
    hit = np.flatnonzero(cov >= level)
    if not len(hit):
        return None, None
    return float(t[hit[0]]), float(dist[hit[0]])


CURVES = ("coverage", "total_distance", "in_contact")
"""The time-series columns whose mean curves this study draws."""


def analyse(sweep: Sweep, conds: Sequence[StudyCondition], curves_of: Sequence[str] = CURVES
            ) -> list[ConditionStats]:
    """What each condition measured, from its finished runs (``curves_of``: the time-series
    columns to keep as curves and mean bands)."""
    out = []
    for cond in conds:
        summaries: list[dict[str, Any]] = []
        curves: dict[str, list[tuple[np.ndarray, np.ndarray]]] = {m: [] for m in curves_of}
        marks: dict[float, dict[int, tuple[float, float]]] = {m: {} for m in MILESTONES}
        for run in cond.runs:
            if sweep.store.status(run.run_id) != DONE:
                continue
            summaries.append(sweep.store.summary(run.run_id))
            rows = sweep.store.timeseries(run.run_id)
            for metric, found in curves.items():
                found.append(series(rows, metric))
            for level, reached in marks.items():
                tick, dist = milestone(rows, level)
                if tick is not None:
                    reached[run.seed] = (tick, dist)
        out.append(ConditionStats(cond, summaries, curves, marks))
    ends = [float(t[-1]) for s in out for t, _ in s.curves["coverage"] if len(t)]
    for s in out:
        s.bands = {m: mean_band(c, end=max(ends) if ends else None) for m, c in s.curves.items()}
    return out


# ----------------------------------------------------------------------------- outputs
def _fmt(x: float | None, digits: int = 0) -> str:
    return "n/a" if x is None else f"{x:,.{digits}f}"


def _mean_sd(x: tuple[float | None, float | None, int], digits: int = 0, scale: float = 1.0
             ) -> str:
    if x[0] is None:
        return "n/a"
    return f"{_fmt(scale * x[0], digits)} ± {_fmt(scale * x[1], digits)}"


ROW_FIELDS = ("coverage", "completion_tick", "total_distance", *CONTACT_FIELDS)
"""The summary fields whose means and sds conditions.csv gives."""


def condition_rows(st: Sequence[ConditionStats], fields: Sequence[str] = ROW_FIELDS
                   ) -> list[dict[str, Any]]:
    """conditions.csv: per condition its labels, runs, runs done, the mean and sd of each
    summary field in ``fields``, and the ticks and distance to each coverage milestone."""
    rows = []
    for s in st:
        row: dict[str, Any] = {"condition": s.cond.label, **s.cond.labels,
                               "runs": len(s.cond.runs), "done": len(s.summaries)}
        for key in fields:
            mean, sd, n = s.field_stats(key)
            row[f"{key}_mean"], row[f"{key}_sd"] = mean, sd
            if key == "completion_tick":
                row["completed"] = n
        for level in MILESTONES:
            pct = round(100 * level)
            row[f"tick_to_{pct}_mean"], row[f"tick_to_{pct}_sd"], row[f"reached_{pct}"] = (
                s.tick_to(level))
            row[f"distance_to_{pct}_mean"] = s.distance_to(level)[0]
        rows.append(row)
    return rows


def plot_study(st: Sequence[ConditionStats], out_png: Path, title: str) -> Path:
    """Mean curves with min-max bands: coverage, total distance, robots in contact."""
    from matplotlib.backends.backend_agg import FigureCanvasAgg
    from matplotlib.figure import Figure

    panels = (("coverage", "coverage (%)", 100.0), ("total_distance", "total distance (units)",
                                                    1.0), ("in_contact", "robots in contact", 1.0))
    fig = Figure(figsize=(18, 5), dpi=100, layout="constrained")
    FigureCanvasAgg(fig)
    for ax, (metric, ylabel, scale) in zip(fig.subplots(1, 3), panels, strict=True):
        for i, s in enumerate(st):
            band = s.bands.get(metric)
            if band is None:
                continue
            ax.plot(band.ticks, scale * band.mean, color=f"C{i % 10}", lw=1.6,
                    label=f"{s.cond.label} (n={band.n})")
            ax.fill_between(band.ticks, scale * band.lo, scale * band.hi, color=f"C{i % 10}",
                            alpha=0.18, lw=0)
        ax.set_xlabel("tick")
        ax.set_ylabel(ylabel)
        ax.grid(True, alpha=0.3)
        if ax.get_legend_handles_labels()[0]:
            ax.legend(fontsize=8, loc="best")
    fig.suptitle(f"{title}\n(mean, band = min-max over seeds)")
    buf = io.BytesIO()
    fig.savefig(buf, format="png")
    atomic_write_bytes(out_png, buf.getvalue())
    return out_png


def _reached(s: ConditionStats, level: float) -> str:
    """Mean first tick at ``level`` coverage, with the share of runs that reached it."""
    mean, _, n = s.tick_to(level)
    return _fmt(mean) if n == len(s.summaries) else f"{_fmt(mean)} ({n}/{len(s.summaries)})"


def _ratio(a: float | None, b: float | None) -> str:
    return "n/a" if a is None or b is None or b == 0 else f"{a / b:.2f}x"


def comparison_lines(st: Sequence[ConditionStats], base: str = "ghost", other: str = "rigid"
                     ) -> list[str]:
    """``other`` against ``base`` mode at each noise level: ticks and distance to each coverage
    milestone, as means over the seeds on which both reached it (paired by seed)."""
    lines = []
    for noise in dict.fromkeys(s.cond.noise for s in st):
        by_mode = {s.cond.mode: s for s in st if s.cond.noise == noise}
        ghost, rigid = by_mode.get(base), by_mode.get(other)
        if ghost is None or rigid is None:
            continue
        tag = "" if not noise else f" (noise {noise:g})"
        for level in MILESTONES:
            both = sorted(set(ghost.milestones[level]) & set(rigid.milestones[level]))
            if not both:
                continue
            tg, tr = ghost.tick_to(level, both)[0], rigid.tick_to(level, both)[0]
            dg, dr = ghost.distance_to(level, both)[0], rigid.distance_to(level, both)[0]
            lines.append(f"- {round(100 * level)} % coverage{tag}, {len(both)} "
                         f"seed{'s' if len(both) != 1 else ''} where both reached it: {other} {_fmt(tr)} ticks vs {base} {_fmt(tg)} "
                         f"({_ratio(tr, tg)}), distance moved by then {_fmt(dr)} vs {_fmt(dg)} "
                         f"({_ratio(dr, dg)})")
        cg, cr = ghost.field_stats("coverage")[0], rigid.field_stats("coverage")[0]
        lines.append(f"- final coverage{tag}: {other} "
                     f"{_fmt(None if cr is None else 100 * cr, 1)} % vs {base} "
                     f"{_fmt(None if cg is None else 100 * cg, 1)} %")
    return lines


def report_text(setup: StudySetup, reps: int, st: Sequence[ConditionStats]) -> str:
    head = [f"# Collision realism: {setup.controller} on {setup.world}", "",
            f"Robots {setup.robots or 'world default'}, groups {setup.groups or 'default'}, "
            f"d_cover {setup.d_cover or 'default'}, seeds 0..{reps - 1}, max_ticks "
            f"{setup.max_ticks or 'default'}"
            + (f", extra settings {dict(setup.extra)}" if setup.extra else "") + ".",
            ("ghost = robots pass through each other (the paper's point robots); rigid = "
             "pymunk discs that push each other. Values are mean ± sd over finished runs; ticks "
             "to a coverage level are means over the runs that reached it (how many, if not "
             "all)."), "",
            "![collisions](collisions.png)", ""]
    rows = []
    for s in st:
        ticks = " / ".join(_reached(s, m) for m in MILESTONES)
        rows.append([s.cond.label, f"{len(s.summaries)}/{len(s.cond.runs)}",
                     _mean_sd(s.field_stats("coverage"), 1, 100.0), ticks,
                     _mean_sd(s.field_stats("total_distance")),
                     _mean_sd(s.field_stats("collisions_robot_robot")),
                     _mean_sd(s.field_stats("collisions_robot_wall")),
                     _mean_sd(s.field_stats("contact_robot_ticks")),
                     _fmt(s.field_stats("max_overlap")[0], 4),
                     _fmt(s.field_stats("mean_overlap")[0], 4),
                     _fmt(s.field_stats("peak_contact_impulse")[0], 3),
                     _mean_sd(s.field_stats("settled_displaced"), 1)])
    cols = ["condition", "runs", "final coverage %",
            "ticks to " + " / ".join(f"{round(100 * m)}" for m in MILESTONES) + " %",
            "total distance", "robot-robot contacts", "robot-wall contacts",
            "robot-ticks in contact", "max overlap", "mean overlap", "peak impulse",
            "settled robots pushed out of place"]
    table = ["| " + " | ".join(cols) + " |", "|" + "---|" * len(cols)]
    table += ["| " + " | ".join(r) + " |" for r in rows]
    noisy = any(s.cond.noise for s in st)
    return "\n".join(head + table + ["", "## Rigid against ghost", ""]
                     + (comparison_lines(st) or ["- (needs both modes)"])
                     + (["", "## Noise against ideal robots", ""] + _noise_lines(st)
                        if noisy else [])) + "\n"


def _noise_lines(st: Sequence[ConditionStats]) -> list[str]:
    """Each noise level against ideal robots, per mode (as in comparison_lines)."""
    lines = []
    for mode in dict.fromkeys(s.cond.mode for s in st):
        ideal = [s for s in st if s.cond.mode == mode and not s.cond.noise]
        for s in st:
            if s.cond.mode != mode or not s.cond.noise or not ideal:
                continue
            pair = [_relabel(ideal[0], "ideal"), _relabel(s, "noisy")]
            lines += [f"{line} [{mode}, noise {s.cond.noise:g}]"
                      for line in comparison_lines(pair, "ideal", "noisy")]
    return lines


def _relabel(s: ConditionStats, mode: str) -> ConditionStats:
    cond = StudyCondition(s.cond.label, {"mode": mode, "noise": 0.0}, s.cond.runs)
    return ConditionStats(cond, s.summaries, s.curves, s.milestones, s.bands)


# ----------------------------------------------------------------------------- entry point
@dataclass
class StudyResult:
    report: Path
    sweep_line: str
    failed: int


def study_collisions(setup: StudySetup, out: str | Path, reps: int = 5,
                     workers: int | None = None, scheduler: Any = None,
                     retry_failed: bool = False, progress: bool = True) -> StudyResult:
    """Run (or resume) the study's runs, then write its table, plot and report."""
    out = Path(out)
    check_setup(setup)
    conds = conditions(setup, reps)
    sweep = Sweep([r for c in conds for r in c.runs], out)
    done = sweep.run(workers, scheduler, retry_failed, progress)
    st = analyse(sweep, conds)
    write_csv(out / "conditions.csv", condition_rows(st))
    plot_study(st, out / "collisions.png",
               f"{setup.controller} on {setup.world}: ghost vs rigid")
    path = out / "REPORT.md"
    atomic_write_text(path, report_text(setup, reps, st))
    return StudyResult(path, done.line(), done.failed)
