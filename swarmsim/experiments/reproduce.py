"""``swarmsim reproduce FIG``: the paper's Section 6 experiments (Figures 17-24), resumably.

The registry (:data:`FIGURES`) says which runs each figure needs; :class:`PaperSetup` holds the
world, robot count and parameter values they share: change them there (or with the CLI's
``--world``, ``--robots`` and ``--set``). Figures that plot the same runs share them: a run's
id is a hash of its parameters and seed, and all figures keep their runs in one store
(``DIR/runs/<id>/``), so Figures 19/20/22 reuse the runs of 17/18/21, and the d_cover = 6,
3-group runs of Figure 18 are also Figure 21's K = 3 and Figure 23's 0-failure runs.

Outputs, for each figure: ``DIR/<fig>/results.csv`` (one row per run), ``conditions.csv``
(mean, sd per condition), ``<fig>.png`` (mean curves with a min-max band, on a common tick
grid; runs that stopped early hold their last value) and ``REPORT.md`` (the paper's claims next
to what was measured, with a verdict); ``DIR/REPORT.md`` collects every figure reproduced so
far in DIR, ``DIR/results.csv`` every run.

Robot counts: the paper uses 603 robots on 'K' for every figure. At d_cover = 1 or 2 a lattice
over K needs ~15,300 / ~3,800 robots, so 603 cannot fill it; we keep 603 (the world's default)
and report the coverage reached (the report lists the lattice capacity next to it).
"""

from __future__ import annotations

import math
import os
import secrets
from collections import Counter
from collections.abc import Callable, Mapping, Sequence
from dataclasses import dataclass, field, replace
from itertools import pairwise
from pathlib import Path
from typing import Any

import numpy as np

from swarmsim.errors import ConfigError
from swarmsim.experiments.runner import DONE, FAILED, RunStore, Sweep
from swarmsim.experiments.spec import RunSpec, unique_runs
from swarmsim.experiments.table import Band, mean_band, series, settle_tick, stats, write_table
from swarmsim.output import atomic_write_text, write_csv

CONSISTENT, PARTLY, NOT_CONSISTENT, NOT_MEASURED = (
    "consistent", "partly consistent", "not consistent", "not measured")


# ----------------------------------------------------------------------------- the setup
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

    def settings(self, controller: str | None = None, **values: Any) -> dict[str, Any]:
        """Run settings: robots (if set), the given values, then ``extra``.

        ``d_cover`` is dropped for controllers that have no such parameter."""
        out: dict[str, Any] = {} if self.robots is None else {"robots": self.robots}
        out.update(values)
        if "d_cover" in out and not _has_d_cover(controller or self.controller):
            del out["d_cover"]
        out.update(self.extra)
        return out


PAPER = PaperSetup()


def _has_d_cover(controller: str) -> bool:
    from swarmsim.controller import get_controller

    return "d_cover" in getattr(get_controller(controller).Params, "__dataclass_fields__", {})


def _registered(name: str) -> bool:
    from swarmsim.controller import available_controllers

    return ":" in name or name in available_controllers()


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
class Figure:
    key: str
    title: str
    build: Callable[[PaperSetup], tuple[Panel, ...]]
    claims: Callable[[Context], list[Claim]]


@dataclass(frozen=True)
class Claim:
    text: str
    measured: str
    verdict: str


def _dcover_panel(s: PaperSetup, groups: int, metric: str) -> tuple[Panel, ...]:
    conds = tuple(Condition(f"d_cover = {_num(d)}", d, s.controller,
                            s.settings(d_cover=d, groups=groups)) for d in s.d_cover_values)
    what = "coverage" if metric == "coverage" else "total distance moved"
    grouping = "not grouped" if groups == 1 else f"{groups} groups"
    return (Panel(f"{what} vs d_cover ({grouping})", "d_cover", metric, conds),)


def _groups_panel(s: PaperSetup, metric: str) -> tuple[Panel, ...]:
    conds = tuple(Condition(f"K = {k}", k, s.controller, s.settings(d_cover=s.d_cover, groups=k))
                  for k in s.group_values)
    what = "coverage" if metric == "coverage" else "total distance moved"
    return (Panel(f"{what} vs number of groups K (d_cover {_num(s.d_cover)})", "groups", metric,
                  conds),)


def _failure_panels(s: PaperSetup) -> tuple[Panel, ...]:
    panels = []
    for tag, phase in (("a", "gradient"), ("b", "coverage")):
        conds = tuple(Condition(f"N = {n}", n, s.controller,
                                s.settings(d_cover=s.d_cover, groups=s.groups,
                                           **({"failures": n, "failure_phase": phase} if n
                                              else {})))
                      for n in s.failure_counts)
        panels.append(Panel(f"({tag}) failures during {phase} "
                            f"{'formation' if phase == 'gradient' else 'process'}",
                            "failures", "coverage", conds))
    return tuple(panels)


def _comparison_panel(s: PaperSetup) -> tuple[Panel, ...]:
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


def figure_runs(key: str, setup: PaperSetup = PAPER, reps: int = 3,
                max_ticks: int | None = None) -> list[RunSpec]:
    """Every run a figure needs, each once."""
    fig = get_figure(key)
    return unique_runs(run for panel in fig.build(setup)
                       for runs in panel_runs(panel, setup, reps, max_ticks) for run in runs)


def get_figure(key: str) -> Figure:
    if key not in FIGURES:
        raise ConfigError(f"unknown figure {key!r}; available: {', '.join(FIGURES)}, all",
                          key="FIG")
    return FIGURES[key]


def figure_keys(which: str | Sequence[str]) -> list[str]:
    """``"all"`` or figure names -> registry keys (validated)."""
    names = [which] if isinstance(which, str) else list(which)
    if "all" in names:
        return list(FIGURES)
    for n in names:
        get_figure(n)
    return names


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

    @property
    def all_complete(self) -> bool:
        return self.done > 0 and self.completion[2] == self.done

    def stop_text(self) -> str:
        return ", ".join(f"{k} {v}" for k, v in sorted(self.stops.items())) or "-"


class Context:
    """Measurements of a reproduction: per figure, per panel, per condition (lazy, cached)."""

    def __init__(self, sweep: Sweep, setup: PaperSetup, reps: int, max_ticks: int | None):
        self.sweep, self.setup, self.reps, self.max_ticks = sweep, setup, reps, max_ticks
        self._cache: dict[tuple[str, int], list[CondStats]] = {}

    def panels(self, key: str) -> tuple[Panel, ...]:
        return get_figure(key).build(self.setup)

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
        store = self.sweep.store
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
            errors, distance_at_settle=stats(s.get("distance_at_settle") for s in summaries))


# ----------------------------------------------------------------------------- claims
def _num(x: Any) -> str:
    if isinstance(x, float) and x.is_integer():
        return str(int(x))
    return f"{x:.3g}" if isinstance(x, float) else str(x)


def _pct(x: float | None) -> str:
    return "n/a" if x is None else f"{100 * x:.1f}%"


def _tick(x: float | None) -> str:
    return "n/a" if x is None else f"{x:.0f}"


def _by_value(st: list[CondStats]) -> dict[Any, CondStats]:
    return {s.cond.value: s for s in st}


def _series_text(st: list[CondStats], what: Callable[[CondStats], float | None],
                 fmt: Callable[[float | None], str]) -> str:
    return ", ".join(f"{_num(s.cond.value)}: {fmt(what(s))}" for s in st)


def _trend(values: list[float | None], decreasing: bool, tol: float = 0.02) -> str:
    """Verdict for a monotone trend (relative tolerance ``tol`` between neighbours)."""
    vals = [v for v in values if v is not None]
    if len(vals) < 2 or len(vals) < len(values):
        return NOT_MEASURED
    sign = -1 if decreasing else 1
    steps = [sign * (b - a) >= -tol * max(abs(a), abs(b), 1e-12) for a, b in pairwise(vals)]
    if all(steps):
        return CONSISTENT
    return PARTLY if sign * (vals[-1] - vals[0]) > 0 else NOT_CONSISTENT


def _speed(a: CondStats, b: CondStats) -> tuple[float | None, float | None, str]:
    """Comparable "how fast" of two conditions: completion tick if both always complete,
    else the tick at which coverage reaches 99% of its final value."""
    if a.all_complete and b.all_complete:
        return a.completion[0], b.completion[0], "mean completion tick"
    return a.settle_cov[0], b.settle_cov[0], "mean tick at 99% of final coverage"


def _combine(verdicts: Sequence[str]) -> str:
    """All comparisons hold: consistent; some: partly; none: not; none measured: not measured."""
    measured = [v for v in verdicts if v != NOT_MEASURED]
    if not measured:
        return NOT_MEASURED
    if len(measured) == len(verdicts) and all(v == CONSISTENT for v in measured):
        return CONSISTENT
    return PARTLY if CONSISTENT in measured else NOT_CONSISTENT


def _less(x: float | None, y: float | None, margin: float = 0.0) -> str:
    if x is None or y is None:
        return NOT_MEASURED
    return CONSISTENT if x < y - margin else NOT_CONSISTENT


def _final_cov(s: CondStats) -> float | None:
    return s.coverage[0]


def _final_dist(s: CondStats) -> float | None:
    return s.distance[0]


def _settle(s: CondStats) -> float | None:
    return s.settle_cov[0]


def _settle_d(s: CondStats) -> float | None:
    return s.settle_dist[0]


def _dist_at_settle(s: CondStats) -> float | None:
    return s.distance_at_settle[0]


def _enough_robots(ctx: Context, st: list[CondStats]) -> list[CondStats]:
    """Conditions whose d_cover lattice over the target needs no more robots than are used."""
    from swarmsim.world import load_world

    world = load_world(ctx.setup.world)
    robots = ctx.setup.robots or int(world.defaults.get("robots", 100))
    return [s for s in st if world.lattice_capacity(float(s.cond.value)) <= robots]


def _dcover_coverage_claims(ctx: Context, key: str) -> list[Claim]:
    st = ctx.stats(key)
    enough = _enough_robots(ctx, st)
    cov = _by_value(st)
    out = [Claim("With enough robots, a larger d_cover reaches its stable coverage sooner "
                 "(Section 6.2)",
                 "tick at 99% of final coverage, d_cover with enough robots: "
                 + (_series_text(enough, _settle, _tick) or "none"),
                 _trend([_settle(s) for s in enough], decreasing=True, tol=0.05))]
    high = [d for d in cov if d >= 8]
    mid = [d for d in cov if d <= 6]
    verdict = NOT_MEASURED
    if high and mid and all(_final_cov(cov[d]) is not None for d in high + mid):
        ref = _final_cov(cov[max(mid)])
        drops = [_final_cov(cov[d]) < ref - 0.01 for d in high]
        verdict = _combine([CONSISTENT if d else NOT_CONSISTENT for d in drops])
    out.append(Claim("Coverage falls below 100% once d_cover > r = 4, more the larger d_cover: "
                     "coverage drops for d_cover >= 8",
                     "final coverage: " + _series_text(st, _final_cov, _pct), verdict))
    return out


def _robots_note(ctx: Context, key: str) -> Claim:
    from swarmsim.world import load_world

    st = ctx.stats(key)
    world = load_world(ctx.setup.world)
    robots = ctx.setup.robots or int(world.defaults.get("robots", 100))
    short = [s for s in st if world.lattice_capacity(float(s.cond.value)) > robots]
    text = "; ".join(f"d_cover {_num(s.cond.value)} needs ~"
                     f"{world.lattice_capacity(float(s.cond.value))} robots, reached "
                     f"{_pct(_final_cov(s))}" for s in short)
    return Claim(f"(note, not a claim) {robots} robots (paper: 603 on K) cannot fill the target "
                 "at every d_cover", text or "every d_cover has enough robots", "note")


def claims_fig17(ctx: Context) -> list[Claim]:
    return _dcover_coverage_claims(ctx, "fig17") + [_robots_note(ctx, "fig17")]


def claims_fig18(ctx: Context) -> list[Claim]:
    out = _dcover_coverage_claims(ctx, "fig18")
    one, three = ctx.stats("fig17", require_done=True), ctx.stats("fig18")
    if one is None:
        return out + [Claim("Grouping (3 groups) reaches stable coverage sooner than 1 group",
                            "run fig17 too to compare", NOT_MEASURED), _robots_note(ctx, "fig18")]
    a, b = _by_value(one), _by_value(three)
    common = [d for d in b if d in a]
    faster = [_less(*_speed(b[d], a[d])[:2]) for d in common]
    text = "; ".join(f"d_cover {_num(d)}: {_tick(_speed(b[d], a[d])[0])} vs "
                     f"{_tick(_speed(b[d], a[d])[1])}" for d in common)
    out.append(Claim("With the same d_cover, 3 groups reach stable coverage sooner than 1 group",
                     f"3 groups vs 1 group ({_speed(b[common[0]], a[common[0]])[2]}): {text}",
                     _combine(faster)))
    same = [d for d in common if d <= 8]
    diffs = {d: abs((_final_cov(b[d]) or 0) - (_final_cov(a[d]) or 0)) for d in same}
    out.append(Claim("For d_cover <= 8 the final coverage is the same with and without groups",
                     "|3 groups - 1 group|: " + ", ".join(f"{_num(d)}: {100 * v:.1f} points"
                                                          for d, v in diffs.items()),
                     CONSISTENT if all(v <= 0.02 for v in diffs.values()) else NOT_CONSISTENT))
    if 10 in common:
        out.append(Claim("At d_cover = 10 grouping lowers the coverage greatly",
                         f"final coverage 3 groups {_pct(_final_cov(b[10]))} vs 1 group "
                         f"{_pct(_final_cov(a[10]))}",
                         _less(_final_cov(b[10]), _final_cov(a[10]), 0.03)))
    return out + [_robots_note(ctx, "fig18")]


def _dcover_distance_claims(ctx: Context, key: str) -> list[Claim]:
    """Section 6.3's distance claims.

    The paper's reason is that a larger d_cover needs fewer robots, so the claim is judged
    where the robots suffice for the lattice, on the distance moved until coverage reached
    its final level. A run's final total distance is not comparable across d_cover: a run
    that completes stops there with its surplus robots unmoved, and one that cannot complete
    also counts the walking of robots that search for a place until every robot stops."""
    st = ctx.stats(key)
    enough = _enough_robots(ctx, st)
    return [Claim("The larger d_cover, the smaller the total distance moved (Section 6.3), "
                  "where the robots suffice",
                  "distance moved until coverage reached its final level: "
                  + _series_text(st, _dist_at_settle, _tick) + "; judged on d_cover "
                  + (", ".join(_num(s.cond.value) for s in enough) or "none"),
                  _trend([_dist_at_settle(s) for s in enough], decreasing=True)),
            Claim("(note) Final total distance, every d_cover: completed runs stop at "
                  "completion, the others when every robot stands or coverage plateaus",
                  "final total distance: " + _series_text(st, _final_dist, _tick),
                  _trend([_final_dist(s) for s in st], decreasing=True)),
            Claim("The larger d_cover, the sooner the total-distance curve flattens",
                  "tick at 99% of final distance: " + _series_text(st, _settle_d, _tick),
                  _trend([_settle_d(s) for s in st], decreasing=True, tol=0.05))]


def claims_fig19(ctx: Context) -> list[Claim]:
    return _dcover_distance_claims(ctx, "fig19")


def claims_fig20(ctx: Context) -> list[Claim]:
    out = _dcover_distance_claims(ctx, "fig20")
    one = ctx.stats("fig19", require_done=True)
    if one is None:
        return out + [Claim("3 groups move much less in total than 1 group",
                            "run fig19 too to compare", NOT_MEASURED)]
    a, b = _by_value(one), _by_value(ctx.stats("fig20"))
    ratios = {d: (_final_dist(b[d]) or math.nan) / (_final_dist(a[d]) or math.nan)
              for d in b if d in a}
    less = [NOT_MEASURED if math.isnan(r) else _less(r, 1.0) for r in ratios.values()]
    out.append(Claim("The total distance of 3 groups is much smaller than of 1 group",
                     "3 groups / 1 group: " + ", ".join(f"{_num(d)}: {r:.2f}"
                                                        for d, r in ratios.items()),
                     _combine(less)))
    return out


def claims_fig21(ctx: Context) -> list[Claim]:
    st = _by_value(ctx.stats("fig21"))
    out = []
    if 1 in st and 3 in st:
        x, y, how = _speed(st[3], st[1])
        out.append(Claim("3 groups complete faster than 1 group",
                         f"{how}: K=3 {_tick(x)} vs K=1 {_tick(y)}", _less(x, y)))
    low = [st[k] for k in sorted(st) if k < 6]
    full = all((_final_cov(s) or 0) >= 1 - 0.02 for s in low)
    trend = _trend([_settle(s) for s in low], decreasing=True, tol=0.05)
    out.append(Claim("For K < 6, more groups cover faster and coverage reaches 100%",
                     "tick at 99% of final coverage: " + _series_text(low, _settle, _tick)
                     + "; final coverage: " + _series_text(low, _final_cov, _pct),
                     trend if full or trend == NOT_MEASURED else PARTLY))
    if 6 in st and any(k > 6 for k in st):
        high = [st[k] for k in sorted(st) if k > 6]
        slower = [_less(*_speed(st[6], s)[:2]) for s in high]
        out.append(Claim("More than 6 groups slow coverage down",
                         f"{_speed(st[6], high[0])[2]}: K=6 {_tick(_speed(st[6], high[0])[0])}, "
                         + ", ".join(f"K={_num(s.cond.value)} {_tick(_speed(st[6], s)[1])}"
                                     for s in high),
                         _combine(slower)))
        top = high[-1]
        out.append(Claim("From 6 to 10 groups the coverage reached decreases",
                         f"final coverage K=6 {_pct(_final_cov(st[6]))}, "
                         f"K={_num(top.cond.value)} {_pct(_final_cov(top))}",
                         _less(_final_cov(top), _final_cov(st[6]), 0.005)))
    return out


def claims_fig22(ctx: Context) -> list[Claim]:
    st = _by_value(ctx.stats("fig22"))
    dist = {k: _final_dist(s) for k, s in st.items()}
    known = {k: v for k, v in dist.items() if v is not None}
    out = [Claim("Without grouping (K = 1) the total distance is the shortest (Section 6.5; "
                 "contradicts Section 6.3 and the next claim)",
                 "final total distance: " + _series_text(list(st.values()), _final_dist, _tick),
                 NOT_MEASURED if 1 not in known else
                 CONSISTENT if known[1] <= min(known.values()) else NOT_CONSISTENT)]
    low = [st[k] for k in sorted(st) if k < 6]
    out.append(Claim("Below 6 groups, more groups give a shorter total distance",
                     "final total distance: " + _series_text(low, _final_dist, _tick),
                     _trend([_final_dist(s) for s in low], decreasing=True)))
    high = [st[k] for k in sorted(st) if k >= 6]
    out.append(Claim("Above 6 groups, more groups give a longer total distance",
                     "final total distance: " + _series_text(high, _final_dist, _tick),
                     _trend([_final_dist(s) for s in high], decreasing=False)))
    return out


def _coincide(st: list[CondStats], tol: float = 0.05) -> tuple[str, str]:
    base = st[0].bands.get("coverage")
    if base is None:
        return "no runs", NOT_MEASURED
    gaps = {}
    for s in st[1:]:
        band = s.bands.get("coverage")
        if band is not None:
            end = max(base.ticks[-1], band.ticks[-1])
            grid = np.linspace(0, end, 400)
            gaps[s.cond.value] = float(np.max(np.abs(np.interp(grid, band.ticks, band.mean)
                                                     - np.interp(grid, base.ticks, base.mean))))
    if not gaps:
        return "no runs with failures", NOT_MEASURED
    text = (f"largest gap between the mean curve and N = {_num(st[0].cond.value)}'s: "
            + ", ".join(f"N={_num(n)}: {100 * g:.1f} points" for n, g in gaps.items()))
    return text, _combine([CONSISTENT if g <= tol else NOT_CONSISTENT for g in gaps.values()])


def claims_fig23(ctx: Context) -> list[Claim]:
    out = []
    for index, phase in ((0, "gradient formation"), (1, "coverage")):
        st = ctx.stats("fig23", index)
        text, verdict = _coincide(st)
        out.append(Claim(f"Failures during {phase}: the coverage curves of 0, 1, 5, 10, 20 "
                         "failures roughly coincide (20 failures barely change the curve)",
                         text, verdict))
        base, worst = st[0], st[-1]
        if index == 0 and base.bands.get("coverage") and worst.bands.get("coverage"):
            t = 0.25 * (_settle(base) or base.bands["coverage"].ticks[-1])
            a, b = worst.bands["coverage"].at(t), base.bands["coverage"].at(t)
            out.append(Claim(f"With {_num(worst.cond.value)} failures during gradient formation "
                             "early coverage is faster",
                             f"mean coverage at tick {t:.0f}: N={_num(worst.cond.value)} "
                             f"{_pct(a)} vs N={_num(base.cond.value)} {_pct(b)}",
                             _less(b, a)))
        if index == 1:
            x, y, how = _speed(worst, base)
            out.append(Claim(f"With {_num(worst.cond.value)} failures during coverage the swarm "
                             "is slightly slower in the later stage",
                             f"{how}: N={_num(worst.cond.value)} {_tick(x)} vs "
                             f"N={_num(base.cond.value)} {_tick(y)}", _less(y, x)))
    return out


def claims_fig24(ctx: Context) -> list[Claim]:
    st = ctx.stats("fig24")
    main = ctx.setup.controller
    by = _by_value(st)
    others = [s for s in st if s.cond.value != main]
    if main not in by or not others:
        return [Claim(f"{main} beats the other algorithms", "no other controller registered",
                      NOT_MEASURED)]
    m = by[main]
    wins = [_less(*_speed(m, s)[:2]) for s in others]
    out = [Claim(f"{main} completes coverage sooner than " + ", ".join(s.cond.label
                                                                        for s in others),
                 "; ".join(f"{_speed(m, s)[2]}: {main} {_tick(_speed(m, s)[0])} vs "
                           f"{s.cond.label} {_tick(_speed(m, s)[1])}" for s in others),
                 _combine(wins))]
    best = [_less(_final_cov(s), (_final_cov(m) or 0) + 0.005) if _final_cov(m) is not None
            else NOT_MEASURED for s in others]
    out.append(Claim(f"{main} reaches the highest coverage",
                     "final coverage: " + _series_text(st, _final_cov, _pct),
                     _combine(best)))
    if "fcdfs" in by:
        out.append(Claim("FCDFS does not reach full coverage",
                         f"final coverage {_pct(_final_cov(by['fcdfs']))}",
                         _less(_final_cov(by["fcdfs"]), 0.99)))
    return out


FIGURES: dict[str, Figure] = {
    "fig17": Figure("fig17", "Figure 17: coverage rate vs d_cover, not grouped",
                    lambda s: _dcover_panel(s, 1, "coverage"), claims_fig17),
    "fig18": Figure("fig18", "Figure 18: coverage rate vs d_cover, 3 groups",
                    lambda s: _dcover_panel(s, s.groups, "coverage"), claims_fig18),
    "fig19": Figure("fig19", "Figure 19: total distance vs d_cover, not grouped",
                    lambda s: _dcover_panel(s, 1, "total_distance"), claims_fig19),
    "fig20": Figure("fig20", "Figure 20: total distance vs d_cover, 3 groups",
                    lambda s: _dcover_panel(s, s.groups, "total_distance"), claims_fig20),
    "fig21": Figure("fig21", "Figure 21: coverage rate vs number of groups",
                    lambda s: _groups_panel(s, "coverage"), claims_fig21),
    "fig22": Figure("fig22", "Figure 22: total distance vs number of groups",
                    lambda s: _groups_panel(s, "total_distance"), claims_fig22),
    "fig23": Figure("fig23", "Figure 23: coverage with failed robots",
                    _failure_panels, claims_fig23),
    "fig24": Figure("fig24", "Figure 24: comparison of coverage algorithms",
                    _comparison_panel, claims_fig24),
}
"""The paper's Section 6 experiments. Figures 19/20/22 plot the runs of 17/18/21."""


# ----------------------------------------------------------------------------- outputs
def plot_figure(fig: Figure, panels: Sequence[Panel], stats_by_panel: Sequence[list[CondStats]],
                out_png: Path) -> Path:
    """Mean curves with a min-max band per condition, one axes per panel (PNG, atomic)."""
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
    mfig.suptitle(f"{fig.title} (mean, band = min-max over runs)")
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
             f"(world {ctx.setup.world}, seeds 0..{ctx.reps - 1}"
             + (f", max_ticks {ctx.max_ticks}" if ctx.max_ticks else "") + ")."]
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


def write_report(out: Path, setup: PaperSetup, versions: Mapping[str, int] | None = None,
                 run_seconds: float | None = None) -> Path:
    """DIR/REPORT.md: every figure reproduced so far in DIR, in the paper's order."""
    sections = [(out / k / "section.md").read_text() for k in FIGURES
                if (out / k / "section.md").is_file()]
    head = ["# Reproduction of the paper's Section 6 experiments", "",
            f"World {setup.world!r}, controller {setup.controller!r}, robots "
            f"{setup.robots or 'world default'}, d_cover {_num(setup.d_cover)} and "
            f"{setup.groups} groups where not varied"
            + (f", extra settings {dict(setup.extra)}" if setup.extra else "") + ".",
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


# ----------------------------------------------------------------------------- entry point
@dataclass
class ReproduceResult:
    figures: list[str]
    report: Path | None
    sweep_line: str
    runs: int
    failed: int = 0


def plan(which: str | Sequence[str], setup: PaperSetup = PAPER, reps: int = 3,
         max_ticks: int | None = None) -> dict[str, list[RunSpec]]:
    """The runs of each requested figure (the registry expanded)."""
    if reps < 1:
        raise ConfigError(f"must be >= 1, got {reps!r}", key="--reps")
    if max_ticks is not None and max_ticks < 1:
        raise ConfigError(f"must be >= 1, got {max_ticks!r}", key="--max-ticks")
    return {k: figure_runs(k, setup, reps, max_ticks) for k in figure_keys(which)}


def reproduce(which: str | Sequence[str], out: str | Path, setup: PaperSetup = PAPER,
              reps: int = 3, max_ticks: int | None = None, workers: int | None = None,
              scheduler: Any = None, retry_failed: bool = False, progress: bool = True,
              on_result: Callable | None = None) -> ReproduceResult:
    """Run (or resume) the figures' runs, then write their tables, plots and reports."""
    out = Path(out)
    runs = plan(which, setup, reps, max_ticks)
    all_runs = unique_runs(r for rs in runs.values() for r in rs)
    sweep = Sweep(all_runs, out, runs_dir=out / "runs", table_path=out / "results.csv")
    report = sweep.run(workers, scheduler, retry_failed, progress, on_result)
    ctx = Context(sweep, setup, reps, max_ticks)
    for key in runs:
        write_figure(FIGURES[key], ctx, out)
    path = write_report(out, setup, sweep.code_versions(), sweep.run_seconds())
    return ReproduceResult(list(runs), path, report.line(), len(all_runs), report.failed)


def describe_plan(runs: Mapping[str, list[RunSpec]], out: str | Path | None = None) -> str:
    """One line per figure: runs, and how many are already done in ``out``; with ``out``,
    a rough estimate of the CPU time still to go."""
    store = RunStore(Path(out) / "runs") if out else None
    lines = []
    for key, rs in runs.items():
        done = sum(store.status(r.run_id) == DONE for r in rs) if store else 0
        labels = dict.fromkeys(_num(v) for r in rs for v in r.labels.values())
        lines.append(f"{key}: {len(rs)} runs ({done} done) over {', '.join(labels)}")
    total = unique_runs(r for rs in runs.values() for r in rs)
    lines.append(f"total: {len(total)} distinct runs" + (_time_to_go(store, total) if store else ""))
    return "\n".join(lines)


def _time_to_go(store: RunStore, runs: Sequence[RunSpec]) -> str:
    """', N done, M to run: about H CPU-hours at the mean of the finished runs' wall time'
    (runs of different conditions differ a lot: a rough guide)."""
    seconds = [float(store.summary(r.run_id).get("wall_seconds") or 0.0)
               for r in runs if store.status(r.run_id) == DONE]
    left = len(runs) - len(seconds)
    text = f", {len(seconds)} done, {left} to run"
    if seconds and left:
        mean = sum(seconds) / len(seconds)
        text += (f": about {left * mean / 3600:.1f} CPU-hours at the finished runs' mean "
                 f"({mean:.0f} s a run)")
    return text


def setup_with(setup: PaperSetup = PAPER, world: str | None = None, robots: int | None = None,
               extra: Mapping[str, Any] | None = None) -> PaperSetup:
    """A copy of ``setup`` with another world, robot count or extra settings."""
    changes: dict[str, Any] = {}
    if world is not None:
        changes["world"] = world
    if robots is not None:
        if robots < 1:
            raise ConfigError(f"must be >= 1, got {robots!r}", key="--robots")
        changes["robots"] = robots
    if extra:
        changes["extra"] = {**setup.extra, **extra}
    return replace(setup, **changes)
