"""The paper's claims for Figures 17-24, each judged against what was measured."""

from __future__ import annotations

import math
from collections.abc import Callable, Sequence
from itertools import pairwise
from typing import Any

import numpy as np

from swarmsim.experiments.figures import Claim, CondStats, Context, num_text

CONSISTENT, PARTLY, NOT_CONSISTENT, NOT_MEASURED = (
    "consistent", "partly consistent", "not consistent", "not measured")


# ----------------------------------------------------------------------------- claims
def _pct(x: float | None) -> str:
    return "n/a" if x is None else f"{100 * x:.1f}%"


def _tick(x: float | None) -> str:
    return "n/a" if x is None else f"{x:.0f}"


def _by_value(st: list[CondStats]) -> dict[Any, CondStats]:
    return {s.cond.value: s for s in st}


def _series_text(st: list[CondStats], what: Callable[[CondStats], float | None],
                 fmt: Callable[[float | None], str]) -> str:
    return ", ".join(f"{num_text(s.cond.value)}: {fmt(what(s))}" for s in st)


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


def _speed_pairs(pairs: list[tuple[str, CondStats, CondStats]]) -> tuple[str, str, list[str]]:
    """"x vs y" texts of :func:`_speed` for labelled pairs of conditions, with the metric
    named once in front when every pair uses the same one, else after each pair; and each
    pair's verdict that the first is faster. Returns (metric, texts joined, verdicts)."""
    measured = [(label, *_speed(a, b)) for label, a, b in pairs]
    hows = {how for *_, how in measured}
    one_how = hows.pop() if len(hows) == 1 else ""
    texts = [f"{label}: {_tick(x)} vs {_tick(y)}" + ("" if one_how else f" ({how})")
             for label, x, y, how in measured]
    return one_how, "; ".join(texts), [_less(x, y) for _, x, y, _ in measured]


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
    from swarmsim.world.world import load_world

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
    from swarmsim.world.world import load_world

    st = ctx.stats(key)
    world = load_world(ctx.setup.world)
    robots = ctx.setup.robots or int(world.defaults.get("robots", 100))
    short = [s for s in st if world.lattice_capacity(float(s.cond.value)) > robots]
    text = "; ".join(f"d_cover {num_text(s.cond.value)} needs ~"
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
    how, text, faster = _speed_pairs([(f"d_cover {num_text(d)}", b[d], a[d]) for d in common])
    out.append(Claim("With the same d_cover, 3 groups reach stable coverage sooner than 1 group",
                     "3 groups vs 1 group" + (f" ({how})" if how else "") + f": {text}",
                     _combine(faster)))
    out.append(_same_coverage_claim(a, b, [d for d in common if d <= 8]))
    if 10 in common:
        out.append(Claim("At d_cover = 10 grouping lowers the coverage greatly",
                         f"final coverage 3 groups {_pct(_final_cov(b[10]))} vs 1 group "
                         f"{_pct(_final_cov(a[10]))}",
                         _less(_final_cov(b[10]), _final_cov(a[10]), 0.03)))
    return out + [_robots_note(ctx, "fig18")]


def _same_coverage_claim(one: dict[Any, CondStats], three: dict[Any, CondStats],
                         values: list[Any]) -> Claim:
    """Fig18's "for d_cover <= 8 the same final coverage with and without groups", judged
    only where both final coverages were measured (2 points of tolerance)."""
    diffs = {}
    for d in values:
        x, y = _final_cov(three[d]), _final_cov(one[d])
        diffs[d] = None if x is None or y is None else abs(x - y)
    known = [v for v in diffs.values() if v is not None]
    verdict = (NOT_MEASURED if not diffs or len(known) < len(diffs)
               else CONSISTENT if all(v <= 0.02 for v in known) else NOT_CONSISTENT)
    text = ", ".join(f"{num_text(d)}: " + ("n/a" if v is None else f"{100 * v:.1f} points")
                     for d, v in diffs.items())
    return Claim("For d_cover <= 8 the final coverage is the same with and without groups",
                 "|3 groups - 1 group|: " + (text or "none"), verdict)


def dcover_distance_claims(ctx: Context, key: str) -> list[Claim]:
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
                  + (", ".join(num_text(s.cond.value) for s in enough) or "none"),
                  _trend([_dist_at_settle(s) for s in enough], decreasing=True)),
            Claim("(note) Final total distance, every d_cover: completed runs stop at "
                  "completion, the others when every robot stands or coverage plateaus",
                  "final total distance: " + _series_text(st, _final_dist, _tick),
                  _trend([_final_dist(s) for s in st], decreasing=True)),
            Claim("The larger d_cover, the sooner the total-distance curve flattens",
                  "tick at 99% of final distance: " + _series_text(st, _settle_d, _tick),
                  _trend([_settle_d(s) for s in st], decreasing=True, tol=0.05))]


def claims_fig19(ctx: Context) -> list[Claim]:
    return dcover_distance_claims(ctx, "fig19")


def claims_fig20(ctx: Context) -> list[Claim]:
    out = dcover_distance_claims(ctx, "fig20")
    one = ctx.stats("fig19", require_done=True)
    if one is None:
        return out + [Claim("3 groups move much less in total than 1 group",
                            "run fig19 too to compare", NOT_MEASURED)]
    a, b = _by_value(one), _by_value(ctx.stats("fig20"))
    ratios = {d: (_final_dist(b[d]) or math.nan) / (_final_dist(a[d]) or math.nan)
              for d in b if d in a}
    less = [NOT_MEASURED if math.isnan(r) else _less(r, 1.0) for r in ratios.values()]
    out.append(Claim("The total distance of 3 groups is much smaller than of 1 group",
                     "3 groups / 1 group: " + ", ".join(f"{num_text(d)}: {r:.2f}"
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
    trend = _trend([_settle(s) for s in low], decreasing=True, tol=0.05)
    covs = [_final_cov(s) for s in low]
    full = (NOT_MEASURED if None in covs
            else CONSISTENT if all(c >= 1 - 0.02 for c in covs) else NOT_CONSISTENT)
    out.append(Claim("For K < 6, more groups cover faster and coverage reaches 100%",
                     "tick at 99% of final coverage: " + _series_text(low, _settle, _tick)
                     + "; final coverage: " + _series_text(low, _final_cov, _pct),
                     NOT_MEASURED if trend == NOT_MEASURED else _combine([trend, full])))
    if 6 in st and any(k > 6 for k in st):
        high = [st[k] for k in sorted(st) if k > 6]
        how, text, slower = _speed_pairs([(f"K=6 vs K={num_text(s.cond.value)}", st[6], s)
                                          for s in high])
        out.append(Claim("More than 6 groups slow coverage down",
                         (f"{how}: " if how else "") + text, _combine(slower)))
        top = high[-1]
        out.append(Claim("From 6 to 10 groups the coverage reached decreases",
                         f"final coverage K=6 {_pct(_final_cov(st[6]))}, "
                         f"K={num_text(top.cond.value)} {_pct(_final_cov(top))}",
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
    text = (f"largest gap between the mean curve and N = {num_text(st[0].cond.value)}'s: "
            + ", ".join(f"N={num_text(n)}: {100 * g:.1f} points" for n, g in gaps.items()))
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
            out.append(Claim(f"With {num_text(worst.cond.value)} failures during gradient formation "
                             "early coverage is faster",
                             f"mean coverage at tick {t:.0f}: N={num_text(worst.cond.value)} "
                             f"{_pct(a)} vs N={num_text(base.cond.value)} {_pct(b)}",
                             _less(b, a)))
        if index == 1:
            x, y, how = _speed(worst, base)
            out.append(Claim(f"With {num_text(worst.cond.value)} failures during coverage the swarm "
                             "is slightly slower in the later stage",
                             f"{how}: N={num_text(worst.cond.value)} {_tick(x)} vs "
                             f"N={num_text(base.cond.value)} {_tick(y)}", _less(y, x)))
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
