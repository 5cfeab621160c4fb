"""``swarmsim study realism``: what real drives, noise and radio cost a controller.

The same controller, world and seeds run under every combination of a drive (``drive=NAME``),
a physics mode (``ghost`` or ``rigid``), a noise level and a message model, plus the
*baseline*: holonomic ghost discs, noise 0, uniform messages with no loss (the paper's
robots). Every condition is compared with the baseline: completion tick, final coverage,
distance moved, contacts and stuck robots (swarmsim/metrics/stuck.py). Runs go through the
sweep machinery (``runner.Sweep``): resumable, one run store, Dask or local workers.

What each axis sets (docs/realism-study.md):

- drive NAME: ``drive=NAME``; the default drive (``holonomic``) is not written into the run's
  settings, so its runs keep the ids they have in other studies and sweeps.
- noise level x > 0: ``speed_noise = heading_noise = distance_noise = bearing_noise = x``
  (as ``swarmsim study collisions``), and the floor sensor misreads within
  :data:`FLOOR_EDGE_BAND` units of the target's edge with probability 2x
  (``floor_edge_band``, ``floor_edge_misread``); x = 0: none of these.
- message model ``uniform``: nothing set (no loss); ``logistic``: ``message_model=logistic``,
  ``message_range50`` = :data:`MESSAGE_RANGE_SHARE` x the robots' sensing range (the
  controller's, capped by ``sensing_limit``), ``message_falloff`` = :data:`MESSAGE_FALLOFF`.

Outputs in DIR: ``runs/<id>/`` (each run), ``results.csv`` (one row per run),
``conditions.csv`` (means and sds per condition, and the ratios to the baseline),
``realism.png`` (mean coverage over time with min-max bands; completion-tick ratio to the
baseline per condition) and ``REPORT.md`` (the table).
"""

from __future__ import annotations

import io
from collections.abc import Mapping, Sequence
from dataclasses import dataclass, field
from pathlib import Path
from typing import Any

from swarmsim.errors import ConfigError
from swarmsim.experiments.collisions import (
    NOISE_KEYS,
    ROW_FIELDS,
    ConditionStats,
    StudyCondition,
    StudyResult,
    _mean_sd,
    analyse,
    condition_rows,
)
from swarmsim.experiments.runner import DONE, Sweep
from swarmsim.experiments.spec import RunSpec, drop_unused_groups
from swarmsim.limits import MAX_REPS, check_count
from swarmsim.metrics.stuck import STUCK_WINDOW
from swarmsim.results.output import atomic_write_bytes, atomic_write_text, write_csv

DRIVES = ("holonomic", "diff", "kilobot")
"""The drives the study compares by default; ``holonomic`` is the engine's default drive."""
DEFAULT_DRIVE = "holonomic"
MODES = ("ghost", "rigid")
MESSAGES = ("uniform", "logistic")
FLOOR_EDGE_BAND = 1.0
"""Units from the target's edge within which a noisy robot's floor sensor may misread."""
FLOOR_MISREAD_PER_NOISE = 2.0
"""A noise level x makes the floor sensor misread near the edge with probability 2x."""
MESSAGE_RANGE_SHARE = 0.8
"""The logistic model's 50 % distance, as a share of the robots' sensing range."""
MESSAGE_FALLOFF = 1.5
"""The logistic model's fall-off width, units."""
BASELINE = {"drive": DEFAULT_DRIVE, "mode": "ghost", "noise": 0.0, "messages": "uniform"}
"""The condition every other is compared with: the paper's robots."""
VARIED = {"drive": "--drives", "mode": "--modes", **dict.fromkeys(NOISE_KEYS, "--noise"),
          "floor_edge_band": "--noise", "floor_edge_misread": "--noise",
          "message_model": "--messages", "message_range50": "--messages",
          "message_falloff": "--messages", "message_loss": "--messages"}
"""Settings the study sets itself, and the option that varies them (refused in --set)."""
SUMMARY_FIELDS = (*ROW_FIELDS, "stuck_robots", "stuck_robots_wall", "stuck_robots_robots",
                  "stuck_robot_ticks")
"""The summary fields whose means and sds conditions.csv gives."""


@dataclass(frozen=True)
class RealismSetup:
    """What the study runs.

    Attributes:
        world: world name or path (default 'K', the paper's Figure 14).
        controller: controller under study.
        robots, groups, d_cover: None = the world's / controller's defaults (groups is left
            out for a controller that has no use for it: see drop_unused_groups).
        drives: drives compared (``drive`` setting).
        modes: physics modes compared ("ghost": robots pass through each other).
        noise: noise levels (0 = ideal robots; see the module docstring).
        messages: message models compared ("uniform", "logistic").
        max_ticks: tick limit of every run (None = the engine's default).
        extra: any other run setting, applied to every run.
    """

    world: str = "K"
    controller: str = "ggc"
    robots: int | None = None
    groups: int | None = 3
    d_cover: float | None = None
    drives: tuple[str, ...] = DRIVES
    modes: tuple[str, ...] = ("rigid",)
    noise: tuple[float, ...] = (0.0, 0.05)
    messages: tuple[str, ...] = MESSAGES
    max_ticks: int | None = None
    extra: Mapping[str, Any] = field(default_factory=dict)

    def common(self) -> dict[str, Any]:
        """The settings every run has (robots, groups, d_cover, max_ticks, extra)."""
        out = {key: getattr(self, key) for key in ("robots", "groups", "d_cover", "max_ticks")
               if getattr(self, key) is not None}
        out.update(self.extra)
        return drop_unused_groups(self.controller, out)  # groups 3 is ggc's default

    def settings(self, labels: Mapping[str, Any], message_range50: float) -> dict[str, Any]:
        """One condition's run settings (``labels``: drive, mode, noise, messages)."""
        out: dict[str, Any] = {"mode": labels["mode"]}
        if labels["drive"] != DEFAULT_DRIVE:
            out["drive"] = labels["drive"]
        noise = labels["noise"]
        if noise:
            out.update(dict.fromkeys(NOISE_KEYS, noise))
            out["floor_edge_band"] = FLOOR_EDGE_BAND
            out["floor_edge_misread"] = FLOOR_MISREAD_PER_NOISE * noise
        if labels["messages"] == "logistic":
            out.update(message_model="logistic", message_range50=message_range50,
                       message_falloff=MESSAGE_FALLOFF)
        return {**self.common(), **out}


def label_of(labels: Mapping[str, Any]) -> str:
    """A condition's name, e.g. "diff, rigid, noise 0.05, logistic"."""
    name = (f"{labels['drive']}, {labels['mode']}, noise {labels['noise']:g}, "
            f"{labels['messages']}")
    return f"baseline: {name}" if dict(labels) == BASELINE else name


def message_range50(setup: RealismSetup) -> float:
    """The logistic model's 50 % distance for ``setup``'s robots, units: MESSAGE_RANGE_SHARE
    of the controller's sensing range with the study's settings (capped by sensing_limit)."""
    from swarmsim.engine.config import build_configs
    from swarmsim.engine.controller_info import describe
    from swarmsim.registry import get_controller

    cls = get_controller(setup.controller)
    sim, _, params = build_configs(setup.common(), cls.Params)
    reach = describe(cls).sensing_range(params)
    if sim.sensing_limit > 0:
        reach = min(reach, sim.sensing_limit)
    return round(MESSAGE_RANGE_SHARE * reach, 6)


def grid(setup: RealismSetup) -> list[dict[str, Any]]:
    """Every condition's labels: the baseline first, then drive x mode x noise x messages
    (the baseline is not repeated when the grid holds it)."""
    out = [dict(BASELINE)]
    for drive in setup.drives:
        for mode in setup.modes:
            for noise in setup.noise:
                for messages in setup.messages:
                    labels = {"drive": drive, "mode": mode, "noise": noise,
                              "messages": messages}
                    if labels != BASELINE:
                        out.append(labels)
    return out


def conditions(setup: RealismSetup, reps: int) -> list[StudyCondition]:
    """Every condition with its runs (seeds 0..reps-1), the baseline first."""
    check_count("--reps", reps, MAX_REPS, "seeds per condition")
    reach = message_range50(setup) if "logistic" in setup.messages else 0.0
    out = []
    for labels in grid(setup):
        settings = setup.settings(labels, reach)
        runs = tuple(RunSpec(setup.world, setup.controller, settings, seed, labels=labels)
                     for seed in range(reps))
        out.append(StudyCondition(label_of(labels), labels, runs))
    return out


def check_setup(setup: RealismSetup) -> None:
    """Fail early, naming the option or key, on a bad world, controller, axis value or
    setting (every condition's settings are validated as a run would)."""
    from swarmsim.engine.config import build_configs
    from swarmsim.registry import get_controller
    from swarmsim.world.world import load_world

    world = load_world(setup.world)
    for key, value in world.defaults.items():
        if key in VARIED:  # it would silently change the conditions that leave the key out
            raise ConfigError(f"sets {key}={value!r} in its [defaults], which the study varies "
                              f"({VARIED[key]}): use a world without it", source=setup.world,
                              key=f"defaults.{key}")
    cls = get_controller(setup.controller)
    for option, values, allowed in (("--drives", setup.drives, None),
                                    ("--modes", setup.modes, MODES),
                                    ("--noise", setup.noise, None),
                                    ("--messages", setup.messages, MESSAGES)):
        if not values:
            raise ConfigError("give at least one value", key=option)
        for value in values:
            if allowed is not None and value not in allowed:
                raise ConfigError(f"must be one of {', '.join(allowed)}, got {value!r}",
                                  key=option)
    for key, value in setup.extra.items():
        if key in VARIED:
            raise ConfigError(f"is what the study sets ({VARIED[key]}); leave out "
                              f"--set {key}={value!r}", key=key)
    top = 1.0 / FLOOR_MISREAD_PER_NOISE
    for noise in setup.noise:
        if not 0 <= noise <= top:
            raise ConfigError(f"must be from 0 to {top:g} (the floor misreads with "
                              f"probability {FLOOR_MISREAD_PER_NOISE:g} x LEVEL), got "
                              f"{noise!r}", key="--noise")
    if setup.d_cover is not None and "d_cover" not in cls.Params.__dataclass_fields__:
        raise ConfigError(f"controller {setup.controller!r} has no d_cover parameter "
                          f"(value {setup.d_cover!r})", key="--d-cover")
    reach = message_range50(setup) if "logistic" in setup.messages else 0.0
    for labels in grid(setup):
        build_configs(setup.settings(labels, reach), cls.Params)


# ----------------------------------------------------------------------------- comparison
def by_seed(sweep: Sweep, cond: StudyCondition, key: str) -> dict[int, float]:
    """Seed -> summary field ``key`` of each finished run of ``cond`` where it is set."""
    out = {}
    for run in cond.runs:
        if sweep.store.status(run.run_id) == DONE:
            value = sweep.store.summary(run.run_id).get(key)
            if value is not None:
                out[run.seed] = float(value)
    return out


@dataclass(frozen=True)
class VersusBaseline:
    """A condition against the baseline, on the seeds on which both completed.

    Attributes:
        seeds: how many seeds both completed.
        ticks: mean completion tick of the condition / the baseline's (None: no such seed).
        distance: mean distance moved (to completion) of the condition / the baseline's.
    """

    seeds: int
    ticks: float | None
    distance: float | None


def versus_baseline(sweep: Sweep, cond: StudyCondition, base: StudyCondition
                    ) -> VersusBaseline:
    """``cond`` against ``base``, paired by seed (both completed)."""
    done, base_done = by_seed(sweep, cond, "completion_tick"), by_seed(sweep, base,
                                                                       "completion_tick")
    both = sorted(set(done) & set(base_done))
    if not both:
        return VersusBaseline(0, None, None)
    dist, base_dist = by_seed(sweep, cond, "total_distance"), by_seed(sweep, base,
                                                                      "total_distance")

    def ratio(a: Mapping[int, float], b: Mapping[int, float]) -> float | None:
        den = sum(b[k] for k in both)
        return None if den == 0 else sum(a[k] for k in both) / den

    return VersusBaseline(len(both), ratio(done, base_done), ratio(dist, base_dist))


def _completed(s: ConditionStats) -> int:
    return s.field_stats("completion_tick")[2]


def realism_rows(st: Sequence[ConditionStats], versus: Sequence[VersusBaseline]
                 ) -> list[dict[str, Any]]:
    """conditions.csv: condition_rows' columns plus the stuck fields and the ratios."""
    rows = condition_rows(st, SUMMARY_FIELDS)
    for row, v in zip(rows, versus, strict=True):
        row.update(seeds_vs_baseline=v.seeds, ticks_vs_baseline=v.ticks,
                   distance_vs_baseline=v.distance)
    return rows


# ----------------------------------------------------------------------------- outputs
def plot_realism(st: Sequence[ConditionStats], versus: Sequence[VersusBaseline],
                 out_png: Path, title: str) -> Path:
    """Left: mean coverage over time per condition (min-max bands). Right: completion-tick
    ratio to the baseline per condition, hatched where not every seed completed."""
    from matplotlib import colormaps
    from matplotlib.backends.backend_agg import FigureCanvasAgg
    from matplotlib.figure import Figure

    colours = colormaps["tab20"].colors
    height = max(6.0, 0.42 * len(st) + 2.5)
    fig = Figure(figsize=(17, height), dpi=100, layout="constrained")
    FigureCanvasAgg(fig)
    left, right = fig.subplots(1, 2, width_ratios=(1.35, 1))
    for i, s in enumerate(st):
        band = s.bands.get("coverage")
        if band is None:
            continue
        colour = colours[i % len(colours)]
        left.plot(band.ticks, 100 * band.mean, color=colour, lw=2.4 if i == 0 else 1.4,
                  ls="--" if s.cond.labels["messages"] == "logistic" else "-",
                  label=f"{s.cond.label} (n={band.n})")
        left.fill_between(band.ticks, 100 * band.lo, 100 * band.hi, color=colour, alpha=0.12,
                          lw=0)
    left.set_xlabel("tick")
    left.set_ylabel("coverage (%)")
    left.set_title("coverage over time (mean, band = min-max over seeds; dashed: logistic)")
    left.grid(True, alpha=0.3)
    if left.get_legend_handles_labels()[0]:
        left.legend(fontsize=8, loc="lower right")
    rows = list(range(len(st)))[::-1]  # the baseline on top
    for y, (i, s, v) in zip(rows, ((i, s, v) for i, (s, v) in enumerate(
            zip(st, versus, strict=True))), strict=True):
        every = _completed(s) == len(s.cond.runs)
        if v.ticks is None:
            right.text(0.02, y, "n/a (no seed completed in both)", va="center", fontsize=9,
                       transform=right.get_yaxis_transform())
            continue
        right.barh(y, v.ticks, color=colours[i % len(colours)], edgecolor="black",
                   hatch=None if every else "//", height=0.7)
        right.text(v.ticks, y, f" {v.ticks:.2f}x ({_completed(s)}/{len(s.cond.runs)} done)",
                   va="center", fontsize=9)
    right.axvline(1.0, color="black", lw=1, ls=":")
    right.set_ylim(-0.6, len(st) - 0.4)
    right.set_yticks(rows, [s.cond.label for s in st], fontsize=9)
    right.set_xlabel("completion tick / baseline's (seeds both completed)")
    right.set_title("cost against the baseline (hatched: not every seed completed)")
    right.grid(True, axis="x", alpha=0.3)
    top = max((v.ticks for v in versus if v.ticks is not None), default=1.0)
    right.set_xlim(0, 1.3 * max(top, 1.0))
    fig.suptitle(title)
    buf = io.BytesIO()
    fig.savefig(buf, format="png")
    atomic_write_bytes(out_png, buf.getvalue())
    return out_png


def _ratio(x: float | None) -> str:
    return "n/a" if x is None else f"{x:.2f}x"


def _pair(s: ConditionStats, a: str, b: str, digits: int = 0) -> str:
    return f"{_mean_sd(s.field_stats(a), digits)} / {_mean_sd(s.field_stats(b), digits)}"


def table_lines(st: Sequence[ConditionStats], versus: Sequence[VersusBaseline]) -> list[str]:
    """REPORT.md's table: one row per condition, the baseline first."""
    cols = ["condition", "completed", "completion tick", "final coverage %", "distance",
            "contacts (robot-robot / wall)", "stuck robots (against wall / against robots)",
            "stuck robot-ticks", "ticks vs baseline", "distance vs baseline"]
    lines = ["| " + " | ".join(cols) + " |", "|" + "---|" * len(cols)]
    for s, v in zip(st, versus, strict=True):
        row = [s.cond.label, f"{_completed(s)}/{len(s.cond.runs)}",
               _mean_sd(s.field_stats("completion_tick")),
               _mean_sd(s.field_stats("coverage"), 1, 100.0),
               _mean_sd(s.field_stats("total_distance")),
               _pair(s, "collisions_robot_robot", "collisions_robot_wall"),
               _pair(s, "stuck_robots_wall", "stuck_robots_robots", 1),
               _mean_sd(s.field_stats("stuck_robot_ticks")),
               _ratio(v.ticks), _ratio(v.distance)]
        lines.append("| " + " | ".join(row) + " |")
    return lines


def report_text(setup: RealismSetup, reps: int, reach: float, st: Sequence[ConditionStats],
                versus: Sequence[VersusBaseline]) -> str:
    logistic = (f"logistic = `message_model=logistic`, `message_range50={reach:g}` "
                f"({MESSAGE_RANGE_SHARE:g} x the sensing range), "
                f"`message_falloff={MESSAGE_FALLOFF:g}`" if reach else "")
    head = [f"# Realism: {setup.controller} on {setup.world}", "",
            f"Robots {setup.robots or 'world default'}, groups {setup.groups or 'default'}, "
            f"d_cover {setup.d_cover or 'default'}, seeds 0..{reps - 1}, max_ticks "
            f"{setup.max_ticks or 'default'}"
            + (f", extra settings {dict(setup.extra)}" if setup.extra else "") + ".", "",
            "Baseline: holonomic ghost discs (robots pass through each other), noise 0, "
            "uniform messages without loss. A noise level x sets speed, heading, distance "
            f"and bearing noise to x and a floor misread of {FLOOR_MISREAD_PER_NOISE:g}x "
            f"within {FLOOR_EDGE_BAND:g} unit of the target's edge; uniform = no message "
            "loss" + (f"; {logistic}" if logistic else "") + ".", "",
            ("Values are mean ± sd over finished runs (completion tick: over the runs that "
             "completed). Contacts are contacts begun; a robot is stuck when it pressed "
             f"against something for {STUCK_WINDOW} ticks in a row without getting anywhere "
             "(docs/realism-study.md). Ticks and distance vs baseline: ratio of the means "
             "over the seeds on which both the condition and the baseline completed."), "",
            "![realism](realism.png)", ""]
    return "\n".join(head + table_lines(st, versus)) + "\n"


# ----------------------------------------------------------------------------- entry point
def study_realism(setup: RealismSetup, out: str | Path, reps: int = 5,
                  workers: int | None = None, scheduler: Any = None,
                  retry_failed: bool = False, progress: bool = True) -> StudyResult:
    """Run (or resume) the study's runs, then write conditions.csv, realism.png and
    REPORT.md."""
    out = Path(out)
    check_setup(setup)
    conds = conditions(setup, reps)
    sweep = Sweep([r for c in conds for r in c.runs], out)
    done = sweep.run(workers, scheduler, retry_failed, progress)
    st = analyse(sweep, conds, ("coverage",))
    versus = [versus_baseline(sweep, c, conds[0]) for c in conds]
    write_csv(out / "conditions.csv", realism_rows(st, versus))
    plot_realism(st, versus, out / "realism.png",
                 f"{setup.controller} on {setup.world}: realism against the baseline")
    reach = message_range50(setup) if "logistic" in setup.messages else 0.0
    path = out / "REPORT.md"
    atomic_write_text(path, report_text(setup, reps, reach, st, versus))
    return StudyResult(path, done.line(), done.failed)


__all__ = ["BASELINE", "DRIVES", "RealismSetup", "check_setup", "conditions", "study_realism"]
