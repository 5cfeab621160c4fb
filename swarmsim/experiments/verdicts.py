"""The paper's claims for Figures 17-24, each judged against what was measured.

How a claim is judged (docs/reproduction/README.md has the whole rule):

* Every comparison weighs the spread between seeds (:mod:`.evidence`): it holds only when
  it is significant at 95 % (Welch's interval wholly on the claimed side, or a rank test
  where a run never completed); a claim whose comparisons are neither all held nor
  contradicted is "not resolved at N runs".
* Completion times follow the paper's Definition 4: a run that never completes is slower
  than any that does (``math.inf``, compared by ranks).
* Claims about d_cover are judged only at the d_cover values whose hexagonal lattice the
  robots can fill, the same way for every claim; the others are shown, not judged.
* A check that geometry or the 99 % stop rule decides whatever the algorithm does is shown
  with ``evidence=False`` and not counted; a "(note)" row gets no verdict.
* Where a claim's wording is adapted from the paper, the paper's words stand beside it.
"""

from __future__ import annotations

import math
from collections.abc import Callable, Sequence
from dataclasses import dataclass
from itertools import pairwise
from typing import Any

import numpy as np

from swarmsim.experiments.evidence import (
    CONTRADICTS,
    HOLDS,
    UNRESOLVED,
    Comparison,
    compare,
    greater,
    less,
    spread_text,
    within,
)
from swarmsim.experiments.figures import Claim, CondStats, Context, num_text

CONSISTENT, PARTLY, NOT_CONSISTENT, NOT_MEASURED = (
    "consistent", "partly consistent", "not consistent", "not measured")
NOTE = "note"
"""The verdict of a row that is not a claim (not counted)."""
PAPER_BASELINES = ("kilobot", "dash", "fcdfs")
"""The methods of the paper's Fig. 24 beside GGC."""
MAP_SENSING = ("cvt", "meanshift")
"""Comparison methods that sense a local map of the floor (not in the paper's Fig. 24)."""
SAME_COVERAGE_MARGIN = 0.02
"""Fig. 18's "the same coverage": final coverages within 2 points."""
COINCIDE_MARGIN = 0.10
"""Fig. 23's "curves roughly coincide": completion within 10 % of no failures'."""
GREATLY = 0.03
"""Fig. 18's "grouping lowers the coverage greatly" at d_cover 10: by more than 3 points."""
COVERAGE_RADIUS = 4.0
"""The paper's coverage radius r (units)."""


def not_resolved(runs: int) -> str:
    """The verdict of a claim whose comparisons the spread between seeds leaves open."""
    return f"not resolved at {runs} runs"


def counted(claim: Claim) -> bool:
    """Does a claim count as evidence in a tally (not a note, not decided by construction)?"""
    return claim.verdict != NOTE and claim.evidence


# ----------------------------------------------------------------------------- texts
def _pct(x: float | None) -> str:
    return "n/a" if x is None else f"{100 * x:.1f}%"


def _tick(x: float | None) -> str:
    return "n/a" if x is None else f"{x:.0f}"


def _by_value(st: list[CondStats]) -> dict[Any, CondStats]:
    return {s.cond.value: s for s in st}


def _values(s: CondStats, metric: str) -> list[float]:
    return list(s.values.get(metric, []))


def _spreads(st: Sequence[CondStats], metric: str, scale: float = 1.0,
             fmt: str = ".0f") -> str:
    """'value: median (min-max), n=N' per condition."""
    return "; ".join(f"{num_text(s.cond.value)}: "
                     + spread_text([scale * v for v in _values(s, metric)], fmt) for s in st)


def _runs(st: Sequence[CondStats]) -> int:
    """Runs per condition behind a claim (the fewest finished)."""
    return min((s.done for s in st), default=0)


# ----------------------------------------------------------------------------- verdicts
def verdict_of(outcomes: Sequence[str], runs: int) -> str:
    """A claim's verdict from its comparisons' outcomes: all hold: consistent; some hold and
    some contradict: partly; some contradict and none hold: not consistent; otherwise not
    resolved at ``runs`` runs; no comparison at all: not measured."""
    if not outcomes or runs < 1:
        return NOT_MEASURED
    if all(o == HOLDS for o in outcomes):
        return CONSISTENT
    if CONTRADICTS in outcomes:
        return PARTLY if HOLDS in outcomes else NOT_CONSISTENT
    return not_resolved(runs)


def steps(st: Sequence[CondStats], metric: str,
          decreasing: bool) -> tuple[list[str], list[Comparison]]:
    """Each step between neighbouring conditions of a trend: does the metric fall (rise)
    from one to the next? Returns the outcomes and the comparisons (next - previous)."""
    found = [compare(_values(b, metric), _values(a, metric)) for a, b in pairwise(st)]
    judge = less if decreasing else greater
    return [judge(c) for c in found], found


def _steps_text(st: Sequence[CondStats], found: Sequence[Comparison], fmt: str = ".0f",
                scale: float = 1.0) -> str:
    return ", ".join(f"{num_text(a.cond.value)}->{num_text(b.cond.value)}: "
                     + c.scaled(scale).text(fmt) for (a, b), c in zip(pairwise(st), found,
                                                                      strict=True))


@dataclass(frozen=True)
class Trend:
    """A claim that a measure falls (or rises) from each condition to the next.

    Attributes:
        text: the claim. measure: what is measured, for the report ("tick at 99% of final
        coverage"). metric: the :attr:`CondStats.values` key. decreasing: the claimed
        direction. step: what a step is ("to the next larger d_cover"). paper: the paper's
        words. scale, fmt: how values are shown (100 and ".1f" for coverage in %).
    """

    text: str
    measure: str
    metric: str
    decreasing: bool
    step: str
    paper: str
    scale: float = 1.0
    fmt: str = ".0f"

    def claim(self, shown: Sequence[CondStats], judged: Sequence[CondStats], where: str = "",
              evidence: bool = True, test_note: str = "") -> Claim:
        """The claim judged on ``judged`` (each step), with every condition of ``shown``
        in its measurement."""
        outcomes, found = steps(judged, self.metric, self.decreasing)
        return Claim(
            self.text,
            f"{self.measure}, median (range): "
            + _spreads(shown, self.metric, self.scale, self.fmt) + "; steps, difference [95% "
            "interval]: " + (_steps_text(judged, found, self.fmt, self.scale) or "none"),
            verdict_of(outcomes, _runs(judged)),
            test=f"each step {self.step} {'lowers' if self.decreasing else 'raises'} the "
                 f"mean {self.measure} beyond the spread between seeds" + test_note,
            where=where, paper=self.paper, evidence=evidence)


def lattice_cover_bound(d_cover: float, r: float = COVERAGE_RADIUS) -> float:
    """The largest share of the plane a hexagonal lattice of spacing ``d_cover`` covers
    with discs of radius ``r`` (1 up to d_cover = sqrt(3) r; pi r^2 / cell area from 2 r)."""
    xs = (np.arange(400) + 0.5) / 400
    u, v = np.meshgrid(xs, xs)  # one lattice cell in lattice coordinates
    px, py = d_cover * (u + 0.5 * v), d_cover * (math.sqrt(3) / 2) * v
    best = np.full(px.shape, np.inf)
    for i in (0, 1):
        for j in (0, 1):
            qx, qy = d_cover * (i + 0.5 * j), d_cover * (math.sqrt(3) / 2) * j
            best = np.minimum(best, np.hypot(px - qx, py - qy))
    return float(np.mean(best <= r))


# ----------------------------------------------------------------------------- d_cover
def _lattice_needs(ctx: Context) -> tuple[int, Callable[[float], int]]:
    from swarmsim.world.world import load_world

    world = load_world(ctx.setup.world)
    robots = ctx.setup.robots or int(world.defaults.get("robots", 100))
    return robots, world.lattice_capacity


def enough_robots(ctx: Context, st: list[CondStats]) -> tuple[list[CondStats], str]:
    """The conditions whose d_cover lattice over the target needs no more robots than are
    used, and the 'where' text that says so (the rule every d_cover claim follows)."""
    robots, needs = _lattice_needs(ctx)
    enough = [s for s in st if needs(float(s.cond.value)) <= robots]
    short = [s for s in st if s not in enough]
    where = ("d_cover " + (", ".join(num_text(s.cond.value) for s in enough) or "none")
             + f": where the lattice needs no more than the {robots} robots used")
    if short:
        where += " (not judged: " + ", ".join(
            f"{num_text(s.cond.value)} needs ~{needs(float(s.cond.value)):,}" for s in short) + ")"
    return enough, where


SETTLE_SOONER = Trend(
    "With enough robots, a larger d_cover reaches its stable coverage sooner",
    "tick at 99% of final coverage", "settle_cov", True, "to the next larger d_cover",
    "If the number of robots is large enough, as the coverage distance increases, ... the "
    "time for coverage rate to reach a stable level will also decrease")
COVERAGE_FALLS = Trend(
    "Coverage falls below 100% once d_cover > r = 4, the more the larger d_cover",
    "final coverage %", "coverage", True, "to the next larger d_cover",
    "When the coverage distance of the robot increases to greater than its coverage radius "
    "(d_cover > r), it will lead to the coverage rate less than 100%. The larger the "
    "coverage distance is, the smaller the coverage rate will be.", 100, ".1f")


def _settle_claim(ctx: Context, st: list[CondStats]) -> Claim:
    enough, where = enough_robots(ctx, st)
    return SETTLE_SOONER.claim(st, enough, where)


def _falling_coverage_claim(ctx: Context, st: list[CondStats]) -> Claim:
    enough, where = enough_robots(ctx, st)
    bounds = ", ".join(f"{num_text(s.cond.value)}: "
                       f"{_pct(lattice_cover_bound(float(s.cond.value)))}" for s in enough)
    return COVERAGE_FALLS.claim(
        st, enough, where + "; a hexagonal lattice covers at most " + (bounds or "-"),
        evidence=False,
        test_note="; decided by geometry: a hexagonal lattice covers fully up to d_cover = "
                  "sqrt(3) r = 6.93 and at most 90.7% at 8 and 58.0% at 10, so the literal "
                  "'d_cover > r' is false from 4 to 6.9 and the drop from 8 on is forced")


def _robots_note(ctx: Context, st: list[CondStats]) -> Claim:
    robots, needs = _lattice_needs(ctx)
    short = [s for s in st if needs(float(s.cond.value)) > robots]
    text = "; ".join(f"d_cover {num_text(s.cond.value)} needs ~{needs(float(s.cond.value)):,} "
                     "robots, final coverage % "
                     + spread_text([100 * v for v in _values(s, "coverage")], ".1f")
                     for s in short)
    return Claim(f"(note) {robots} robots (paper: 603 on K) cannot fill the target at every "
                 "d_cover", text or "every d_cover has enough robots", NOTE)


def claims_fig17(ctx: Context) -> list[Claim]:
    st = ctx.stats("fig17")
    return [_settle_claim(ctx, st), _falling_coverage_claim(ctx, st), _robots_note(ctx, st)]


def claims_fig18(ctx: Context) -> list[Claim]:
    three = ctx.stats("fig18")
    out = [_settle_claim(ctx, three), _falling_coverage_claim(ctx, three)]
    one = ctx.stats("fig17", require_done=True)
    if one is None:
        out.append(Claim("With the same d_cover, 3 groups reach stable coverage sooner than 1 "
                         "group", "run fig17 too to compare", NOT_MEASURED))
        return out + [_robots_note(ctx, three)]
    a, b = _by_value(one), _by_value(three)
    enough, where = enough_robots(ctx, [b[d] for d in b if d in a])
    common = [s.cond.value for s in enough]
    out.append(grouping_sooner(a, b, common, where))
    out.append(same_coverage(a, b, [d for d in common if d <= 8], where))
    if 10 in b and 10 in a:
        out.append(grouping_lowers_at_10(a[10], b[10]))
    return out + [_robots_note(ctx, three)]


def by_dcover(one: dict[Any, CondStats], three: dict[Any, CondStats], values: Sequence[Any],
              metric: str) -> tuple[dict[Any, Comparison], int]:
    """3 groups against 1 group at each d_cover of ``values`` (3 groups' ``metric`` minus 1
    group's), and the runs per condition behind them (the fewest)."""
    found = {d: compare(_values(three[d], metric), _values(one[d], metric)) for d in values}
    return found, _runs([s for d in values for s in (one[d], three[d])])


def grouping_sooner(one: dict[Any, CondStats], three: dict[Any, CondStats],
                    common: Sequence[Any], where: str) -> Claim:
    """Fig. 18: at each d_cover, 3 groups' tick at 99% of final coverage is below 1 group's."""
    found, runs = by_dcover(one, three, common, "settle_cov")
    return Claim(
        "With the same d_cover, 3 groups reach stable coverage sooner than 1 group",
        "3 groups - 1 group, tick at 99% of final coverage, difference [95% "
        "interval]: " + (", ".join(f"{num_text(d)}: {c.text()}" for d, c in found.items())
                         or "none"),
        verdict_of([less(c) for c in found.values()], runs),
        test="at each d_cover the mean tick at 99% of final coverage of 3 groups is below 1 "
             "group's beyond the spread", where=where,
        paper="With the same coverage distance, the stable coverage time of grouping coverage "
              "is significantly less than that of without grouping coverage")


def same_coverage(one: dict[Any, CondStats], three: dict[Any, CondStats],
                  values: Sequence[Any], where: str) -> Claim:
    """Fig. 18: for d_cover <= 8, 1 and 3 groups reach the same final coverage (within
    :data:`SAME_COVERAGE_MARGIN`). Where both always complete, the stop rule decides: such
    d_cover values are judged only when there is no other (and the claim is then marked as
    no evidence)."""
    found, runs = by_dcover(one, three, values, "coverage")
    stopped = [d for d in values if one[d].all_complete and three[d].all_complete]
    return Claim(
        "For d_cover <= 8 the final coverage is the same with and without groups",
        "3 groups - 1 group, final coverage points [95% interval]: "
        + (", ".join(f"{num_text(d)}: {c.scaled(100).text('.1f')}" for d, c in found.items())
           or "none")
        + (f"; both complete every run at d_cover {', '.join(map(num_text, stopped))} (the stop "
           "rule decides there)" if stopped else ""),
        verdict_of([within(c, SAME_COVERAGE_MARGIN) for d, c in found.items()
                    if d not in stopped or len(stopped) == len(values)], runs),
        test="equivalence: the interval of the difference of mean final coverages lies within "
             f"+-{100 * SAME_COVERAGE_MARGIN:.0f} points at each d_cover",
        where=where + "; d_cover <= 8",
        paper="When the coverage distance is no more than 8, the coverage rate of the two cases "
              "is the same",
        evidence=bool(values) and len(stopped) < len(values))


def grouping_lowers_at_10(one: CondStats, three: CondStats) -> Claim:
    """Fig. 18: at d_cover 10, 3 groups' final coverage is below 1 group's by more than
    :data:`GREATLY`. Judged at 10 whatever the robots: the lattice needs fewer there."""
    c = compare(_values(three, "coverage"), _values(one, "coverage"))
    return Claim(
        "At d_cover = 10 grouping lowers the coverage greatly",
        "final coverage %: 3 groups " + spread_text([100 * v for v in _values(three, "coverage")],
                                                   ".1f")
        + ", 1 group " + spread_text([100 * v for v in _values(one, "coverage")], ".1f")
        + f"; difference {c.scaled(100).text('.1f')} points",
        verdict_of([less(c.shifted(GREATLY)) if c.method == "welch" else less(c)], _runs([one, three])),
        test=f"the mean final coverage of 3 groups is below 1 group's by more than "
             f"{100 * GREATLY:.0f} points beyond the spread",
        paper="When the coverage distance is equal to 10, it can be seen that in the case of "
              "grouping, the coverage rate decreases greatly")


# ----------------------------------------------------------------------------- distance
def dcover_distance_claims(ctx: Context, key: str) -> list[Claim]:
    """Section 6.3's distance claims, judged where the robots suffice for the lattice.

    A run's final total distance is not comparable across d_cover: a run that completes
    stops there with its surplus robots unmoved, and one that cannot complete also counts
    the walking of robots that search for a place until every robot stops. So the claim is
    judged on the distance moved until coverage reached its final level."""
    st = ctx.stats(key)
    enough, where = enough_robots(ctx, st)
    return [LESS_DISTANCE.claim(st, enough, where),
            Claim("(note) Final total distance, every d_cover: completed runs stop at "
                  "completion, the others when every robot stands or coverage plateaus",
                  "final total distance, median (range): " + _spreads(st, "distance"), NOTE),
            FLATTENS_SOONER.claim(st, enough, where)]


LESS_DISTANCE = Trend(
    "The larger d_cover, the smaller the total distance moved",
    "distance moved until coverage reached its final level", "distance_at_settle", True,
    "to the next larger d_cover",
    "the larger the coverage distance is, the smaller the total moving distance of the swarm "
    "robots will be (measured on the final total distance, which runs that stop at "
    "completion and runs that walk on do not share)")
FLATTENS_SOONER = Trend(
    "The larger d_cover, the sooner the total-distance curve flattens",
    "tick at 99% of final distance", "settle_dist", True, "to the next larger d_cover",
    "the shorter the time for the curve of the total moving distance of the robot to reach "
    "a flat level")


def claims_fig19(ctx: Context) -> list[Claim]:
    return dcover_distance_claims(ctx, "fig19")


def claims_fig20(ctx: Context) -> list[Claim]:
    out = dcover_distance_claims(ctx, "fig20")
    one = ctx.stats("fig19", require_done=True)
    if one is None:
        return out + [Claim("The total distance of 3 groups is much smaller than of 1 group",
                            "run fig19 too to compare", NOT_MEASURED)]
    a, b = _by_value(one), _by_value(ctx.stats("fig20"))
    enough, where = enough_robots(ctx, [b[d] for d in b if d in a])
    return out + [grouped_distance(a, b, [s.cond.value for s in enough], where)]


def grouped_distance(one: dict[Any, CondStats], three: dict[Any, CondStats],
                     common: Sequence[Any], where: str) -> Claim:
    """Fig. 20: at each d_cover 3 groups move less in total than 1 group."""
    found, runs = by_dcover(one, three, common, "distance")

    def ratio(d: Any) -> str:
        x, y = np.mean(_values(three[d], "distance")), np.mean(_values(one[d], "distance"))
        return f"{x / y:.2f}" if y else "n/a"

    return Claim(
        "The total distance of 3 groups is much smaller than of 1 group",
        "3 groups / 1 group, mean final total distance: "
        + (", ".join(f"{num_text(d)}: {ratio(d)} (difference {c.text()})"
                     for d, c in found.items()) or "none"),
        verdict_of([less(c) for c in found.values()], runs),
        test="at each d_cover the mean final total distance of 3 groups is below 1 group's "
             "beyond the spread", where=where,
        paper="the total moving distance of the swarm robots covered by groups is much smaller "
              "than that of the robots not covered by groups")


# ----------------------------------------------------------------------------- groups
def claims_fig21(ctx: Context) -> list[Claim]:
    st = _by_value(ctx.stats("fig21"))
    out = []
    if 1 in st and 3 in st:
        c = compare(_values(st[3], "completion"), _values(st[1], "completion"))
        out.append(Claim("3 groups complete faster than 1 group",
                         "completion tick, median (range): K=3 "
                         + spread_text(_values(st[3], "completion")) + ", K=1 "
                         + spread_text(_values(st[1], "completion"))
                         + f"; difference {c.text()}",
                         verdict_of([less(c)], _runs([st[1], st[3]])),
                         test="K=3's completion ticks are below K=1's beyond the spread "
                              "(never completing counts as slower than any completion)"))
    low = [st[k] for k in sorted(st) if k < 6]
    if low:
        out.append(fewer_groups_faster(low))
    high = [st[k] for k in sorted(st) if k >= 6]
    if len(high) > 1:
        out.append(many_groups_slower(high))
        out.append(many_groups_lose_coverage(high[0], high[-1]))
    return out


def fewer_groups_faster(low: Sequence[CondStats]) -> Claim:
    """Fig. 21: below 6 groups, each step to more groups completes sooner, and every run
    completes (the paper: 'the coverage rate can reach 100%'; runs stop at 99%)."""
    outcomes, found = steps(low, "completion", decreasing=True)
    full = [HOLDS if s.all_complete else CONTRADICTS for s in low]
    return Claim(
        "For K < 6, more groups cover faster and every run completes",
        "completion tick, median (range): " + _spreads(low, "completion")
        + "; steps, difference [95% interval]: " + (_steps_text(low, found) or "none")
        + "; completed: " + ", ".join(f"{num_text(s.cond.value)}: {s.completion[2]}/{s.done}"
                                      for s in low),
        verdict_of(outcomes + full, _runs(low)),
        test="each step to more groups lowers the completion ticks beyond the spread, "
             "and every run completes (reaches 99%, where runs stop)",
        paper="when the number of groups K is less than 6, the coverage curve of the robot "
              "decreases gradually with the increase of the number of groups, and the coverage "
              "rate can reach 100%")


PLATEAU_LATER = Trend(
    "From 6 to 10 groups, the more groups the later coverage reaches its plateau",
    "tick at 99% of final coverage", "settle_cov", False, "to more groups",
    "When the number of groups K varies from 6 to 10, the time when the robot's coverage "
    "curve reaches a plateau increases")


def many_groups_slower(high: Sequence[CondStats]) -> Claim:
    """Fig. 21: from 6 groups up, each step to more groups plateaus later."""
    return PLATEAU_LATER.claim(high, high)


def many_groups_lose_coverage(six: CondStats, top: CondStats) -> Claim:
    """Fig. 21: the final coverage at the most groups is below 6 groups'. Where both
    always complete the stop rule decides (both stop at 99%)."""
    c = compare(_values(top, "coverage"), _values(six, "coverage"))
    stopped = six.all_complete and top.all_complete
    return Claim(
        f"From 6 to {num_text(top.cond.value)} groups the coverage reached decreases",
        f"final coverage %: K=6 {spread_text([100 * v for v in _values(six, 'coverage')], '.1f')}"
        f", K={num_text(top.cond.value)} "
        f"{spread_text([100 * v for v in _values(top, 'coverage')], '.1f')}"
        + ("; both complete every run (the stop rule decides)" if stopped else ""),
        verdict_of([less(c)], _runs([six, top])),
        test="the mean final coverage with the most groups is below 6 groups' beyond the "
             "spread; where both complete every run it cannot be (both stop at 99%)",
        paper="When the number of groups K varies from 6 to 10, ... the coverage rate decreases",
        evidence=not stopped)


def claims_fig22(ctx: Context) -> list[Claim]:
    st = _by_value(ctx.stats("fig22"))
    out = []
    if 1 in st and len(st) > 1:
        found = {k: compare(_values(st[1], "distance"), _values(s, "distance"))
                 for k, s in st.items() if k != 1}
        out.append(Claim(
            "Without grouping (K = 1) the total distance is the shortest (Section 6.5; "
            "contradicts Section 6.3 and the next claim)",
            "final total distance, median (range): " + _spreads(list(st.values()), "distance")
            + "; K=1 - K=k [95% interval]: "
            + ", ".join(f"{num_text(k)}: {c.text()}" for k, c in found.items()),
            verdict_of([less(c) for c in found.values()], _runs(list(st.values()))),
            test="K=1's mean final total distance is below every other K's beyond the spread",
            paper="when the swarm robots are not grouped ... The total distance moved by the "
                  "swarm robotic system is the shortest"))
    low = [st[k] for k in sorted(st) if k < 6]
    high = [st[k] for k in sorted(st) if k >= 6]
    return [*out, FEWER_GROUPS_SHORTER.claim(low, low), MORE_GROUPS_LONGER.claim(high, high)]


FEWER_GROUPS_SHORTER = Trend(
    "Below 6 groups, more groups give a shorter total distance", "final total distance",
    "distance", True, "to more groups",
    "When the number of groups is less than 6, the total moving distance of the swarm robots "
    "will be shorter with the increase in the number of groups")
MORE_GROUPS_LONGER = Trend(
    "Above 6 groups, more groups give a longer total distance", "final total distance",
    "distance", False, "to more groups",
    "When the number of robot groups is greater than 6, with the increase of the number of "
    "groups ... the increase of the total moving distance")


# ----------------------------------------------------------------------------- failures
def coincide(st: Sequence[CondStats], phase: str) -> Claim:
    """Fig. 23: with each number of failures the completion is within
    :data:`COINCIDE_MARGIN` of no failures' median (an equivalence test)."""
    base = st[0]
    base_median = float(np.median(_values(base, "completion"))) if base.done else math.nan
    found = {s.cond.value: compare(_values(s, "completion"), _values(base, "completion"))
 for s in st[1:]}
    margin = COINCIDE_MARGIN * base_median
    outcomes = ([within(c, margin) for c in found.values()] if math.isfinite(margin)
                else [UNRESOLVED] * len(found))
    return Claim(
        f"Failures during {phase}: the coverage curves of "
        + ", ".join(num_text(s.cond.value) for s in st) + " failures roughly coincide",
        "completion tick, median (range): " + _spreads(st, "completion")
        + f"; N - {num_text(base.cond.value)}, difference [95% interval]: "
        + ", ".join(f"N={num_text(n)}: {c.text()}" for n, c in found.items()),
        verdict_of(outcomes, _runs(st)),
        test=f"equivalence: each 95% interval of the difference of mean completion ticks lies "
             f"within +-{100 * COINCIDE_MARGIN:.0f}% of no failures' median (with a run that "
             "never completes: not resolved, or contradicted when the ranks differ)",
        paper="The coverage rate curves shown in the figure roughly coincide")


def early_faster(base: CondStats, worst: CondStats) -> Claim:
    """Fig. 23a: with the most failures during gradient formation, coverage at a quarter
    of no failures' median completion is higher."""
    done = _values(base, "completion")
    finite = [v for v in done if math.isfinite(v)]
    t = 0.25 * float(np.median(finite)) if finite else math.nan
    a, b = _coverage_at(worst, t), _coverage_at(base, t)
    c = compare(a, b)
    n = num_text(worst.cond.value)
    return Claim(
        f"With {n} failures during gradient formation early coverage is faster",
        f"coverage % at tick {_tick(t if math.isfinite(t) else None)}: N={n} "
        + spread_text([100 * v for v in a], ".1f") + f", N={num_text(base.cond.value)} "
        + spread_text([100 * v for v in b], ".1f"),
        verdict_of([greater(c)], _runs([base, worst])),
        test="the mean coverage at a quarter of no failures' median completion tick is higher "
             "with the most failures, beyond the spread",
        paper="When there are 20 robots with failures, the early coverage speed is faster")


def _coverage_at(s: CondStats, tick: float) -> list[float]:
    if not math.isfinite(tick):
        return []
    return [float(np.interp(tick, t, v)) for t, v in s.curves.get("coverage", []) if len(t)]


def later_slower(base: CondStats, worst: CondStats) -> Claim:
    """Fig. 23b: with the most failures during coverage the completion comes later."""
    c = compare(_values(worst, "completion"), _values(base, "completion"))
    n = num_text(worst.cond.value)
    return Claim(
        f"With {n} failures during coverage the swarm is slightly slower in the later stage",
        f"completion tick, median (range): N={n} " + spread_text(_values(worst, "completion"))
        + f", N={num_text(base.cond.value)} " + spread_text(_values(base, "completion"))
        + f"; difference {c.text()}",
        verdict_of([greater(c)], _runs([base, worst])),
        test="the completion ticks with the most failures are above no failures' beyond "
             "the spread",
        paper="when N is 20, the coverage speed of the swarm robot is slightly slower in the "
              "later stage")


def claims_fig23(ctx: Context) -> list[Claim]:
    grad, cov = ctx.stats("fig23", 0), ctx.stats("fig23", 1)
    out = [coincide(grad, "gradient formation"), early_faster(grad[0], grad[-1]),
           coincide(cov, "coverage"), later_slower(cov[0], cov[-1])]
    if len(ctx.panels("fig23")) > 2:  # (c): gradient-phase failures as dead bodies
        dead = ctx.stats("fig23", 2)
        for claim in (coincide(dead, "gradient formation"), early_faster(dead[0], dead[-1])):
            out.append(Claim(f"(note) {claim.text}, with dead bodies instead of the paper's "
                             "robots without a gradient",
                             f"{claim.measured} (would be: {claim.verdict})", NOTE))
    return out


# ----------------------------------------------------------------------------- methods
def claims_fig24(ctx: Context) -> list[Claim]:
    st = ctx.stats("fig24")
    main = ctx.setup.controller
    by = _by_value(st)
    rivals = [by[c] for c in PAPER_BASELINES if c in by and c != main]
    if main not in by or not rivals:
        return [Claim(f"{main} completes coverage sooner than "
                      + ", ".join(PAPER_BASELINES), "none of them registered", NOT_MEASURED)]
    m = by[main]
    out = [fastest(m, rivals), highest_coverage(m, rivals)]
    if "fcdfs" in by:
        out.append(fcdfs_short(by["fcdfs"]))
    out += [map_sensing_note(m, s) for s in st
            if s.cond.value != main and s.cond.value not in PAPER_BASELINES]
    return out


def fastest(main: CondStats, rivals: Sequence[CondStats]) -> Claim:
    """Fig. 24 by the paper's rule: the method under study completes sooner than each of
    the paper's baselines, completion per Definition 4 (never completing is slower)."""
    found = {s.cond.label: compare(_values(main, "completion"), _values(s, "completion"))
 for s in rivals}
    name = main.cond.label
    return Claim(
        f"{name} completes coverage sooner than " + ", ".join(s.cond.label for s in rivals)
        + " (the paper's Fig. 24)",
        "completion tick, median (range): " + "; ".join(
            f"{s.cond.label}: {spread_text(_values(s, 'completion'))}" for s in (main, *rivals))
        + f"; {name} - rival, difference [95% interval]: "
        + ", ".join(f"{k}: {c.text()}" for k, c in found.items()),
        verdict_of([less(c) for c in found.values()], _runs([main, *rivals])),
        test="the completion ticks are below each baseline's beyond the spread; a run "
             "that never completes is slower than any that does (Definition 4)",
        where="the paper's Fig. 24 methods; CVT and mean-shift, which sense a local map, in "
              "rows of their own",
        paper="We intuitively found that the GGC algorithm was optimal in both coverage "
              "completion time and coverage")


def highest_coverage(main: CondStats, rivals: Sequence[CondStats]) -> Claim:
    """Fig. 24: no baseline's final coverage is above the method's. Against a baseline
    that completes every run, as the method does, the stop rule decides (a tie)."""
    open_ = [s for s in rivals if not (s.all_complete and main.all_complete)]
    found = {s.cond.label: compare(_values(main, "coverage"), _values(s, "coverage"))
             for s in open_}
    return Claim(
        f"{main.cond.label} reaches the highest coverage",
        "final coverage %, median (range): " + "; ".join(
            f"{s.cond.label}: {spread_text([100 * v for v in _values(s, 'coverage')], '.1f')}"
            for s in (main, *rivals)),
        verdict_of([greater(c) for c in found.values()] or [HOLDS], _runs([main, *rivals])),
        test="the mean final coverage is above each baseline's beyond the spread, against the "
             "baselines that do not complete every run (those that do tie at 99%, where runs "
             "stop)",
        where="the paper's Fig. 24 methods",
        paper="the GGC algorithm was optimal in both coverage completion time and coverage",
        evidence=bool(open_))


def fcdfs_short(fcdfs: CondStats) -> Claim:
    """Fig. 24: FCDFS never completes (its lattice leaves intervals between robots)."""
    done = fcdfs.completion[2]
    return Claim(
        "FCDFS does not reach full coverage",
        "final coverage %: " + spread_text([100 * v for v in _values(fcdfs, "coverage")], ".1f")
        + f"; completed {done}/{fcdfs.done}",
        verdict_of([] if not fcdfs.done else [CONTRADICTS if done else HOLDS], fcdfs.done),
        test="no FCDFS run completes (reaches 99%)",
        paper="resulting in the coverage rate cannot reach 1")


def map_sensing_note(main: CondStats, other: CondStats) -> Claim:
    """A comparison method outside the paper's Fig. 24 (CVT, mean-shift: they sense a local
    map of the floor): its completion beside the method's, as a ratio."""
    a, b = _values(main, "completion"), _values(other, "completion")
    ratio = "n/a"
    if a and b:
        ma, mb = float(np.median(a)), float(np.median(b))
        ratio = f"{mb / ma:.2f}" if math.isfinite(ma) and math.isfinite(mb) else "n/a"
    kind = "senses a local map" if other.cond.value in MAP_SENSING else "not in the paper"
    return Claim(f"(note) {other.cond.label} ({kind}, not in the paper's Fig. 24) beside "
                 f"{main.cond.label}",
                 f"completion tick, median (range): {spread_text(b)}; its median / "
                 f"{main.cond.label}'s: {ratio}", NOTE)
