"""Claims no reproduction tested before issue 71: Figure 14's random start (grouping,
aggregation, then coverage; paper Sections 4 and 6.1) and the gaps where groups meet
(Sections 6.1 and 6.2), judged on a reproduction's stored runs.

Each claim has a pure function of measured values (:func:`random_start_claim`,
:func:`start_time_note`, :func:`junction_claim`, :func:`junction_growth_claims`) and the
figure's claims read them from a :class:`.figures.Context` (:func:`claims_fig14`,
:func:`junction_claims`). The random-start claim is "consistent" only when every run holds;
comparisons between conditions weigh the spread between seeds as :mod:`.verdicts` does, and
the measured text gives the spread (min-max).
"""

from __future__ import annotations

from collections.abc import Mapping, Sequence
from dataclasses import dataclass
from itertools import pairwise
from pathlib import Path
from typing import Any

import numpy as np

from swarmsim.errors import ConfigError
from swarmsim.experiments.evidence import compare, greater
from swarmsim.experiments.figures import Claim, Context, num_text, panel_runs
from swarmsim.experiments.junctions import JunctionGaps, run_junction_gaps
from swarmsim.experiments.runner import DONE
from swarmsim.experiments.verdicts import (
    CONSISTENT,
    NOT_CONSISTENT,
    NOT_MEASURED,
    NOTE,
    verdict_of,
)

FORMED_SHARE = 0.9
"""Aggregation happened when at least this share of the working robots was in its group's
formation (Formed) at some tick: the rest cover alone after aggregation_timeout (our fallback
for a robot that never reaches its formation; the paper has none)."""

SECTION_61 = ("Section 6.1: \"some gaps cannot be completely covered at the junction of each "
              "group due to the robot conflict between the groups\"")
SECTION_62 = ("Section 6.2: \"when the coverage distance is large, the gaps caused by "
              "conflicts between groups will also become larger and larger\"")


# ----------------------------------------------------------------------------- measured values
@dataclass(frozen=True)
class StartRun:
    """What one random-start run's summary says about its grouping, aggregation and coverage
    (summary.json fields; None where the run has no value)."""

    robots: int
    coverage: float
    completion_tick: int | None
    grouped_tick: int | None
    formed_robots: int | None
    formed_tick: int | None

    @classmethod
    def of(cls, summary: Mapping[str, Any]) -> StartRun:
        return cls(int(summary["robots"]) - int(summary.get("failed_robots") or 0),
                   float(summary["coverage"]), summary.get("completion_tick"),
                   summary.get("grouped_tick"), summary.get("formed_robots"),
                   summary.get("formed_tick"))

    def holds(self) -> bool:
        """Completed (coverage 1 - eps0 reached), every robot grouped, at least
        :data:`FORMED_SHARE` of them Formed, and formed before completion."""
        return (self.completion_tick is not None and self.grouped_tick is not None
                and self.formed_robots is not None and self.formed_tick is not None
                and self.formed_robots >= FORMED_SHARE * self.robots
                and self.formed_tick < self.completion_tick)


def spread(values: Sequence[float | None], fmt: str = "{:.0f}") -> str:
    """'mean (min-max)' of the known values, 'n/a' when none; 'k of n' when some are None."""
    known = [float(v) for v in values if v is not None]
    if not known:
        return "n/a"
    text = (fmt.format(np.mean(known)) if len(known) == 1 else
            f"{fmt.format(np.mean(known))} ({fmt.format(min(known))}-{fmt.format(max(known))})")
    return text if len(known) == len(values) else f"{text} [{len(known)} of {len(values)}]"


def _pct(values: Sequence[float | None]) -> str:
    return spread([None if v is None else 100 * v for v in values], "{:.2f}") + " %"


# ----------------------------------------------------------------------------- Figure 14
def random_start_claim(runs: Sequence[StartRun]) -> Claim:
    """"From a random start the robots group and aggregate, then cover the target": every
    run holds (:meth:`StartRun.holds`)."""
    silent = all(r.grouped_tick is None and r.formed_robots is None for r in runs)
    verdict = (NOT_MEASURED if not runs or silent else
               CONSISTENT if all(r.holds() for r in runs) else NOT_CONSISTENT)
    measured = "the controller reports no grouping" if runs and silent else (f"{len(runs)} runs: completed {sum(r.completion_tick is not None for r in runs)}"
                f" of {len(runs)}, at tick {spread([r.completion_tick for r in runs])}; "
                f"coverage {_pct([r.coverage for r in runs])}; every robot grouped by tick "
                f"{spread([r.grouped_tick for r in runs])}; robots Formed "
                f"{spread([r.formed_robots for r in runs])} of "
                f"{spread([r.robots for r in runs])}, the last at tick "
                f"{spread([r.formed_tick for r in runs])}") if runs else "no runs done"
    return Claim(
        "From a random start the robots choose groups and leaders, aggregate into formations, "
        "then cover the target",
        measured, verdict,
        test=(f"every run completes (coverage 1 - eps0), every working robot gets a group, at "
              f"least {FORMED_SHARE:.0%} of them reach their formation (Formed) and the last "
              "of these does so before completion"),
        where="K, 3 groups, d_cover 6, robots scattered in the spawn areas (start random)",
        paper=("Sections 4 and 6.1, Figure 14: the robots are randomly distributed, divided "
               "into groups, and \"the gradient-based method can self-organize the coverage "
               "of the target area\""))


def start_time_note(random: Sequence[int | None], formation: Sequence[int | None] | None
                    ) -> Claim:
    """A measured note (no verdict): completion ticks from a random start vs from
    formations (Figure 18's runs at the same d_cover and groups)."""
    if formation is None:
        text = (f"random start {spread(random)}; formation start: Figure 18's runs at this "
                "d_cover are not all done (reproduce fig18 too)")
    else:
        a = [t for t in random if t is not None]
        b = [t for t in formation if t is not None]
        ratio = f"; ratio of means {np.mean(a) / np.mean(b):.2f}" if a and b else ""
        text = f"random start {spread(random)} vs formation start {spread(formation)}{ratio}"
    return Claim("(note) Completion tick from a random start vs from formations (Figure 18's "
                 "runs): grouping and aggregation come first", text, NOTE,
                 test="shown, not judged: the paper gives no time for either start")


def claims_fig14(ctx: Context) -> list[Claim]:
    summaries = _summaries(ctx, "fig14", "random") or []
    runs = [StartRun.of(s) for s in summaries]
    formation = _summaries(ctx, "fig18", ctx.setup.d_cover, require_all=True)
    return [random_start_claim(runs),
            start_time_note([r.completion_tick for r in runs],
                            None if formation is None
                            else [s.get("completion_tick") for s in formation])]


# ----------------------------------------------------------------------------- junction gaps
def junction_claim(three: Sequence[JunctionGaps], one: Sequence[JunctionGaps],
                   d_cover: float) -> Claim:
    """"With groups, gaps remain at the junctions of groups", at one d_cover: in every
    grouped run the junction band loses a larger share of its area than the rest of the
    target does, and than any one-group run (no junctions) at the same d_cover loses."""
    base = max((g.uncovered_density for g in one), default=None)
    ok = [g.band_density is not None and g.outside_density is not None and base is not None
          and g.band_density > g.outside_density and g.band_density > base for g in three]
    band = [g.band_density for g in three if g.band_density is not None]
    outside = [g.outside_density for g in three if g.outside_density is not None]
    verdict = NOT_MEASURED if not three or not one else verdict_of(
        [greater(compare(band, outside)),
         greater(compare(band, [g.uncovered_density for g in one]))], min(len(three), len(one)))
    measured = (f"d_cover {num_text(d_cover)}, {len(three)} grouped runs: band "
                f"{_pct([g.band_share for g in three])} of the target, holding "
                f"{_pct([g.junction_share for g in three])} of the uncovered area; uncovered "
                f"in the band {_pct([g.band_density for g in three])} vs outside it "
                f"{_pct([g.outside_density for g in three])}; 1 group ({len(one)} runs) "
                f"uncovered {_pct([g.uncovered_density for g in one])}; holds in "
                f"{sum(ok)} of {len(three)}")
    return Claim(
        "With groups, gaps remain at the junctions of groups", measured, verdict,
        test=("junction band = target pixels in a Delaunay triangle of grouped robots with "
              "corners of two groups (swarmsim/experiments/junctions.py); the grouped runs' "
              "mean uncovered share in the band exceeds the mean outside it and the one-group "
              "runs' mean uncovered share, each beyond the spread between seeds"),
        where=(f"d_cover {num_text(d_cover)} (Section 6.1's setting): the lattice can cover "
               "the target and the robots suffice, so gaps are not the lattice's own holes"),
        paper=SECTION_61)


def junction_growth_claims(grouped: Mapping[float, Sequence[JunctionGaps]],
                           one: Mapping[float, Sequence[JunctionGaps]]) -> list[Claim]:
    """"The junction gaps grow with d_cover": the excess junction gap (JunctionGaps.excess
    over the mean uncovered share of the one-group runs at the same d_cover) of every run at
    each larger d_cover above every run's at the smaller one. A second row, the raw junction
    gaps' share of the target, grows with the lattice's own holes (d_cover > sqrt(3) r):
    geometry decides it, so it is shown and not counted (evidence False)."""
    values = sorted(d for d in grouped if d in one and grouped[d] and one[d])
    excess = {d: [g.excess(float(np.mean([u.uncovered_density for u in one[d]])))
                  for g in grouped[d]] for d in values}
    raw = {d: [g.band_uncovered / g.target for g in grouped[d]] for d in values}
    own = {d: [g.own_excess() for g in grouped[d]] for d in values}
    return [
        Claim("The gaps at the junctions of groups grow with d_cover",
              "junction gaps beyond the one-group uncovered share, % of the target: "
              + _by_dcover(excess) + " (beyond the same run's uncovered share outside the "
              "band, not judged: " + _by_dcover(own) + ")", _ordered(excess),
              test=("per run (band uncovered - band x the one-group runs' mean uncovered "
                    "share) / target; each step to a larger d_cover raises its mean beyond "
                    "the spread between seeds"),
              where="d_cover " + ", ".join(num_text(d) for d in values)
                    + ", 3 groups vs 1 group at each",
              paper=SECTION_62),
        Claim("(geometry) The junction band's uncovered area grows with d_cover",
              "band uncovered, % of the target: " + _by_dcover(raw), _ordered(raw),
              test="each step to a larger d_cover raises the mean beyond the spread",
              where="as above; a lattice wider than sqrt(3) r = 6.9 leaves holes everywhere, "
                    "the band included, so this follows from geometry",
              paper=SECTION_62, evidence=False)]


def _by_dcover(values: Mapping[float, Sequence[float]]) -> str:
    return "; ".join(f"{num_text(d)}: {_pct(v)}" for d, v in values.items()) or "none"


def _ordered(values: Mapping[float, Sequence[float]]) -> str:
    """Each step to the next larger key raises the mean beyond the spread between seeds
    (verdicts.verdict_of over the steps); not measured with fewer than two keys."""
    keys = sorted(values)
    if len(keys) < 2:
        return NOT_MEASURED
    return verdict_of([greater(compare(values[b], values[a])) for a, b in pairwise(keys)],
                      min(len(v) for v in values.values()))


def junction_claims(ctx: Context) -> list[Claim]:
    """Figure 18's junction claims: its grouped runs against Figure 17's one-group runs."""
    grouped = {d: _gaps(ctx, "fig18", d) for d in ctx.setup.d_cover_values}
    one = {d: _gaps(ctx, "fig17", d) for d in ctx.setup.d_cover_values}
    d = ctx.setup.d_cover
    first = junction_claim(grouped.get(d) or [], one.get(d) or [], d)
    high = {v: g for v, g in grouped.items() if v >= d and g}
    return [first, *junction_growth_claims(high, {v: g for v, g in one.items() if g})]


# ----------------------------------------------------------------------------- stored runs
def _runs(ctx: Context, key: str, value: Any) -> list[Any]:
    for panel in ctx.panels(key):
        for cond, runs in zip(panel.conditions,
                              panel_runs(panel, ctx.setup, ctx.reps, ctx.max_ticks),
                              strict=True):
            if cond.value == value:
                return runs
    return []


def _done_dirs(ctx: Context, key: str, value: Any, require_all: bool = False
               ) -> list[Path] | None:
    runs = _runs(ctx, key, value)
    store = ctx.sweep.store
    done = [store.path(r.run_id) for r in runs if store.status(r.run_id) == DONE]
    if not runs or (require_all and len(done) < len(runs)):
        return None
    return done


def _summaries(ctx: Context, key: str, value: Any, require_all: bool = False
               ) -> list[dict[str, Any]] | None:
    dirs = _done_dirs(ctx, key, value, require_all)
    return None if dirs is None else [ctx.sweep.store.summary(p.name) for p in dirs]


def _gaps(ctx: Context, key: str, value: Any) -> list[JunctionGaps]:
    """The junction gaps of a condition's finished runs; none when a run has no robots.csv,
    coverage.npz or group column (a controller without groups)."""
    try:
        return [run_junction_gaps(p) for p in _done_dirs(ctx, key, value) or []]
    except ConfigError:
        return []


__all__ = ["FORMED_SHARE", "StartRun", "claims_fig14", "junction_claim", "junction_claims",
           "junction_growth_claims", "random_start_claim", "spread", "start_time_note"]
