"""The paper's Section 6 setup and figure types, and the analysis of their runs.

:class:`PaperSetup` (and :data:`PAPER`) holds what the experiments share; :class:`Condition`,
:class:`Panel`, :class:`Figure` and :class:`Claim` describe a figure; the panel builders make a
figure's panels from a setup; :class:`Context` measures a reproduction's runs (:class:`CondStats`
per condition). The registry itself is in :mod:`.reproduce`, the claims in :mod:`.verdicts`.
"""

from __future__ import annotations

import math
from collections import Counter
from collections.abc import Callable, Mapping, Sequence
from dataclasses import dataclass, field, replace
from typing import Any

import numpy as np

from swarmsim.experiments.runner import DONE, FAILED, RunStore, Sweep
from swarmsim.experiments.spec import RunSpec, drop_unused_groups
from swarmsim.experiments.table import Band, mean_band, series, settle_tick, stats

# ----------------------------------------------------------------------------- the setup
PAPER_RULESET = "paper"
"""The rule set that follows the paper's rules (judged beside the controller's default)."""


@dataclass(frozen=True)
class PaperSetup:
    """What the paper's experiments share (Section 6, Table 2). Change values here.

    Attributes:
        world: the world (paper: 'K').
        controller: the controller under study (paper: GGC).
        robots: robot count; None = the world's default (K: 603, as in the paper).
        d_cover: coverage distance where it is not varied (paper: 6).
        groups: number of groups where it is not varied (paper: 3).
        d_cover_values: Figures 17-20.
        group_values: Figures 21-22.
        failure_counts: Figure 23.
        comparison: Figure 24's controllers (the first is the one under study); unregistered
            ones are skipped with a note.
        extra: any other run setting applied to every run (e.g. {"eps0": 0.02}).
        rulesets: the rule sets judged side by side, one column each, for a controller that
            has a ``ruleset`` parameter; None = its default rule set and the paper's
            (:meth:`judged_rulesets`); ignored for other controllers.
        ruleset: the rule set of this column's runs (set by :meth:`columns`); None = the
            controller's default, not named in the runs' settings.
        ghost: add a column of point robots that pass through each other (physics mode
            "ghost", as in the paper's NetLogo model) under the first rule set judged, to
            show which claims hold for points and fail only with bodies.
        mode: the physics mode of this column's runs (set by :meth:`columns`); None = the
            run's default (rigid bodies), not named in the runs' settings.
    """

    world: str = "K"
    controller: str = "ggc"
    robots: int | None = None
    d_cover: float = 6
    groups: int = 3
    d_cover_values: tuple[float, ...] = (1, 2, 4, 6, 8, 10)
    group_values: tuple[int, ...] = (1, 3, 4, 6, 8, 10)
    failure_counts: tuple[int, ...] = (0, 1, 5, 10, 20)
    comparison: tuple[str, ...] = ("ggc", "kilobot", "dash", "fcdfs", "cvt", "meanshift")
    extra: Mapping[str, Any] = field(default_factory=dict)
    rulesets: tuple[str, ...] | None = None
    ruleset: str | None = None
    ghost: bool = False
    mode: str | None = None

    def judged_rulesets(self) -> tuple[str, ...]:
        """The rule sets judged side by side: :attr:`rulesets`, or else the controller's
        default rule set (its ``ruleset`` parameter's default) and ``"paper"``; none for a
        controller without a ``ruleset`` parameter."""
        if not _has_parameter(self.controller, "ruleset"):
            return ()
        if self.rulesets is not None:
            return self.rulesets
        return (_parameter_default(self.controller, "ruleset"), PAPER_RULESET)

    def columns(self) -> list[PaperSetup]:
        """One setup per rule set judged (:meth:`judged_rulesets`), or just this one when
        there is none; then, with :attr:`ghost`, the first of them with point robots."""
        base = [replace(self, ruleset=r, ghost=False) for r in self.judged_rulesets()]
        base = base or [replace(self, ghost=False)]
        return base + ([replace(base[0], mode="ghost")] if self.ghost else [])

    @property
    def column_name(self) -> str:
        """This column's name in reports: its rule set, '(ghost)' for point robots."""
        parts = [self.ruleset or "", "(ghost)" if self.mode == "ghost" else ""]
        return " ".join(p for p in parts if p)

    def settings(self, controller: str | None = None, **values: Any) -> dict[str, Any]:
        """Run settings: robots (if set), the given values, then ``extra``.

        ``d_cover`` is dropped for controllers that have no such parameter, ``groups`` for
        controllers that have no use for groups with their start (see drop_unused_groups)."""
        out: dict[str, Any] = {} if self.robots is None else {"robots": self.robots}
        out.update(values)
        if "d_cover" in out and not _has_parameter(controller or self.controller, "d_cover"):
            del out["d_cover"]
        if self.ruleset is not None and _has_parameter(controller or self.controller, "ruleset"):
            out["ruleset"] = self.ruleset
        if self.mode is not None:
            out["mode"] = self.mode
        out.update(self.extra)
        return drop_unused_groups(controller or self.controller, out)


PAPER = PaperSetup()


def _has_parameter(controller: str, name: str) -> bool:
    from swarmsim.controller import get_controller

    return name in getattr(get_controller(controller).Params, "__dataclass_fields__", {})


def _parameter_default(controller: str, name: str) -> Any:
    from swarmsim.controller import get_controller

    return get_controller(controller).Params.__dataclass_fields__[name].default


def _registered(name: str) -> bool:
    from swarmsim.controller import available_controllers

    return ":" in name or name in available_controllers()


def num_text(x: Any) -> str:
    if isinstance(x, float) and x.is_integer():
        return str(int(x))
    return f"{x:.3g}" if isinstance(x, float) else str(x)


# ----------------------------------------------------------------------------- registry
@dataclass(frozen=True)
class Condition:
    """One curve of a figure: a controller and its settings, repeated over the seeds."""

    label: str
    value: Any
    controller: str
    settings: Mapping[str, Any]


@dataclass(frozen=True)
class Panel:
    """One plot: conditions that differ in ``vary``, showing ``metric`` over time."""

    title: str
    vary: str
    metric: str  # "coverage" or "total_distance"
    conditions: tuple[Condition, ...]
    notes: tuple[str, ...] = ()


@dataclass(frozen=True)
class FigureTable:
    """A table a figure shows instead of its curves (the paper's Table 3).

    Attributes:
        rows: DIR/<fig>/table.csv's rows, one per condition.
        markdown: the table as the figure's REPORT.md shows it.
    """

    rows: tuple[Mapping[str, Any], ...]
    markdown: str


@dataclass(frozen=True)
class Figure:
    """One of the paper's figures (or tables): its runs (``build``'s panels) and claims.

    ``table``, if given, makes it a table: its report shows ``table(context)`` for each rule
    set instead of the curves and the conditions' coverage, and no plot is drawn.
    """

    key: str
    title: str
    build: Callable[[PaperSetup], tuple[Panel, ...]]
    claims: Callable[[Context], list[Claim]]
    table: Callable[[Context], FigureTable] | None = None


@dataclass(frozen=True)
class Claim:
    """One of the paper's claims, judged on a reproduction's runs.

    Attributes:
        text: the claim as judged.
        measured: what was measured, with the spread between seeds.
        verdict: one of the verdicts of :mod:`.verdicts` (``"note"`` for a row that is not
            a claim: it gets no verdict and is not counted).
        test: how it is tested (the comparison and its rule), in one sentence.
        where: where it is judged and why (e.g. the d_cover values whose lattice the robots
            fill); "" = every condition of the figure.
        paper: the paper's own words where ``text`` adapts them ("" = ``text`` is the
            paper's claim as stated).
        evidence: False for a check that geometry or the stop rule decides whatever the
            algorithm does: shown, marked so, and not counted as evidence.
    """

    text: str
    measured: str
    verdict: str
    test: str = ""
    where: str = ""
    paper: str = ""
    evidence: bool = True


def dcover_panel(s: PaperSetup, groups: int, metric: str) -> tuple[Panel, ...]:
    conds = tuple(Condition(f"d_cover = {num_text(d)}", d, s.controller,
                            s.settings(d_cover=d, groups=groups)) for d in s.d_cover_values)
    what = "coverage" if metric == "coverage" else "total distance moved"
    grouping = "not grouped" if groups == 1 else f"{groups} groups"
    return (Panel(f"{what} vs d_cover ({grouping})", "d_cover", metric, conds),)


def groups_panel(s: PaperSetup, metric: str) -> tuple[Panel, ...]:
    conds = tuple(Condition(f"K = {k}", k, s.controller, s.settings(d_cover=s.d_cover, groups=k))
                  for k in s.group_values)
    what = "coverage" if metric == "coverage" else "total distance moved"
    return (Panel(f"{what} vs number of groups K (d_cover {num_text(s.d_cover)})", "groups", metric,
                  conds),)


def random_start_panel(s: PaperSetup) -> tuple[Panel, ...]:
    """Figure 14's run: the robots start scattered ("random" start), choose groups and
    leaders, aggregate into formations, then cover (d_cover and groups of the setup)."""
    cond = Condition("random start", "random", s.controller,
                     s.settings(d_cover=s.d_cover, groups=s.groups, start="random"))
    return (Panel(f"coverage from a random start ({s.groups} groups, d_cover "
                  f"{num_text(s.d_cover)})", "start", "coverage", (cond,)),)


PAPER_GRADIENT_FAILURE = "no_gradient"
"""The failure mode of the paper's gradient-phase failures (Sections 5 and 6.6): a robot that
cannot obtain a gradient, for a controller that declares it (its FAILURE_MODES)."""


def failure_panels(s: PaperSetup) -> tuple[Panel, ...]:
    """Figure 23's panels: (a) failures during gradient formation, (b) during coverage, each
    for N in ``s.failure_counts``. Failed robots are dead bodies (failure_mode "dead"), but in
    (a) for a controller that declares the paper's gradient-phase failure
    (:data:`PAPER_GRADIENT_FAILURE`): then (a) uses it, and (c) adds the gradient phase with
    dead bodies, for comparison. Panels 0 and 1 are always the paper's (a) and (b)."""
    paper_mode = _declares_failure_mode(s.controller, PAPER_GRADIENT_FAILURE)
    kinds = [("a", "gradient", PAPER_GRADIENT_FAILURE if paper_mode else None),
             ("b", "coverage", None)]
    if paper_mode:
        kinds.append(("c", "gradient", "dead"))
    return tuple(_failure_panel(s, tag, phase, mode) for tag, phase, mode in kinds)


def _failure_panel(s: PaperSetup, tag: str, phase: str, mode: str | None) -> Panel:
    """One panel of Figure 23: failures in ``phase``, in failure ``mode`` (None: the default,
    "dead", not named in the runs' settings, so their ids are the runs' without the setting;
    "dead" named is the same run)."""
    named = {} if mode is None or mode == "dead" else {"failure_mode": mode}
    conds = tuple(Condition(f"N = {n}", n, s.controller,
                            s.settings(d_cover=s.d_cover, groups=s.groups,
                                       **({"failures": n, "failure_phase": phase, **named}
                                          if n else {})))
                  for n in s.failure_counts)
    what = "formation" if phase == "gradient" else "process"
    how = {None: "", "dead": ", dead bodies"}.get(mode, f", failure mode {mode}")
    return Panel(f"({tag}) failures during {phase} {what}{how}", "failures", "coverage", conds)


def _declares_failure_mode(controller: str, mode: str) -> bool:
    """Does the controller (a name or module:Class) declare failure mode ``mode``?"""
    from swarmsim.controller import get_controller

    return mode in getattr(get_controller(controller), "FAILURE_MODES", {})


def comparison_panel(s: PaperSetup) -> tuple[Panel, ...]:
    names = [s.controller] + [c for c in s.comparison if c != s.controller]
    ok = [c for c in names if _registered(c)]
    skipped = [c for c in names if c not in ok]
    conds = tuple(Condition(c, c, c, s.settings(controller=c, d_cover=s.d_cover,
                                                groups=s.groups)) for c in ok)
    notes = (f"not registered, skipped: {', '.join(skipped)}",) if skipped else ()
    return (Panel("coverage of different algorithms", "controller", "coverage", conds, notes),)


# ----------------------------------------------------------------------------- runs
def panel_runs(panel: Panel, setup: PaperSetup, reps: int,
               max_ticks: int | None = None) -> list[list[RunSpec]]:
    """The runs of each condition of a panel (seeds 0..reps-1)."""
    out = []
    for cond in panel.conditions:
        settings = dict(cond.settings)
        if max_ticks is not None:
            settings["max_ticks"] = max_ticks
        out.append([RunSpec(setup.world, cond.controller, settings, seed,
                            labels={panel.vary: cond.value}) for seed in range(reps)])
    return out


# ----------------------------------------------------------------------------- analysis
@dataclass
class CondStats:
    """What was measured for one condition (means, sds and counts over its finished runs).

    ``settle_*`` is the tick at which a run's curve reaches 99% of its final value (when it
    becomes flat); runs stopped by max_ticks have not settled and are left out of it.
    """

    cond: Condition
    runs: int
    done: int
    failed: int
    coverage: tuple[float | None, float | None, int]  # final: mean, sd, n
    distance: tuple[float | None, float | None, int]
    completion: tuple[float | None, float | None, int]  # over runs that completed
    settle_cov: tuple[float | None, float | None, int]
    settle_dist: tuple[float | None, float | None, int]
    stops: dict[str, int]
    curves: dict[str, list[tuple[np.ndarray, np.ndarray]]]
    errors: list[str]
    bands: dict[str, Band | None] = field(default_factory=dict)
    distance_at_settle: tuple[float | None, float | None, int] = (None, None, 0)
    values: dict[str, list[float]] = field(default_factory=dict)
    """Per finished run, in seed order: "coverage" (final), "distance" (final total),
    "completion" (tick; ``math.inf`` for a run that never completed: the paper's Definition
    4), "settle_cov", "settle_dist", "distance_at_settle" (runs where it is known)."""

    @property
    def all_complete(self) -> bool:
        return self.done > 0 and self.completion[2] == self.done

    def stop_text(self) -> str:
        return ", ".join(f"{k} {v}" for k, v in sorted(self.stops.items())) or "-"


class Context:
    """Measurements of a reproduction: per figure, per panel, per condition (lazy, cached).

    ``get_figure`` looks a figure up by key (the registry's, :func:`.reproduce.get_figure`)."""

    def __init__(self, sweep: Sweep, setup: PaperSetup, reps: int, max_ticks: int | None,
                 get_figure: Callable[[str], Figure]):
        self.sweep, self.setup, self.reps, self.max_ticks = sweep, setup, reps, max_ticks
        self.get_figure = get_figure
        self._cache: dict[tuple[str, int], list[CondStats]] = {}

    def panels(self, key: str) -> tuple[Panel, ...]:
        return self.get_figure(key).build(self.setup)

    def stats(self, key: str, index: int = 0, require_done: bool = False
              ) -> list[CondStats] | None:
        """Stats of a figure's panel (None with ``require_done`` if some run never ran).

        Mean curves share one tick grid per panel: to the end of its longest run."""
        if (key, index) not in self._cache:
            panel = self.panels(key)[index]
            runs = panel_runs(panel, self.setup, self.reps, self.max_ticks)
            st = [self._cond(c, r) for c, r in zip(panel.conditions, runs, strict=True)]
            ends = [float(t[-1]) for s in st for cs in s.curves.values() for t, _ in cs
                    if len(t)]
            for s in st:
                s.bands = {m: mean_band(c, end=max(ends) if ends else None)
                           for m, c in s.curves.items()}
            self._cache[(key, index)] = st
        out = self._cache[(key, index)]
        if require_done and any(s.done + s.failed < s.runs for s in out):
            return None
        return out

    def _cond(self, cond: Condition, runs: list[RunSpec]) -> CondStats:
        return condition_stats(self.sweep.store, cond, runs)


def condition_stats(store: RunStore, cond: Condition, runs: Sequence[RunSpec]) -> CondStats:
    """What the finished runs of one condition measured (curves, means, sds), read from the
    run ``store``; failed runs count apart, runs not run yet not at all."""
    summaries, curves, errors = [], {"coverage": [], "total_distance": []}, []
    settle: dict[str, list[float | None]] = {m: [] for m in curves}
    for run in runs:
        status = store.status(run.run_id)
        if status == FAILED:
            errors.append(store.error(run.run_id))
        if status != DONE:
            continue
        summary = store.summary(run.run_id)
        summaries.append(summary)
        rows = store.timeseries(run.run_id)
        for metric, found in curves.items():
            t, v = series(rows, metric)
            found.append((t, v))
            flat = summary.get("stop_reason") != "max_ticks"
            settle[metric].append(settle_tick(t, v) if flat else None)
    stops = Counter(str(s.get("stop_reason")) for s in summaries)
    return CondStats(
        cond, len(runs), len(summaries), len(errors),
        stats(s.get("coverage") for s in summaries),
        stats(s.get("total_distance") for s in summaries),
        stats(s.get("completion_tick") for s in summaries),
        stats(settle["coverage"]), stats(settle["total_distance"]), dict(stops), curves,
        errors, distance_at_settle=stats(s.get("distance_at_settle") for s in summaries),
        values=run_values(summaries, settle))


def run_values(summaries: Sequence[Mapping[str, Any]],
               settle: Mapping[str, Sequence[float | None]]) -> dict[str, list[float]]:
    """:attr:`CondStats.values` of finished runs' summaries and settle ticks (per metric)."""
    def known(xs: Any) -> list[float]:
        return [float(x) for x in xs if x is not None]

    return {"coverage": known(s.get("coverage") for s in summaries),
            "distance": known(s.get("total_distance") for s in summaries),
            "completion": [math.inf if s.get("completion_tick") is None
                           else float(s["completion_tick"]) for s in summaries],
            "settle_cov": known(settle.get("coverage", ())),
            "settle_dist": known(settle.get("total_distance", ())),
            "distance_at_settle": known(s.get("distance_at_settle") for s in summaries)}
