"""Every verdict function judges what its claim says, weighs the spread between seeds, and
fails when the comparison is flipped."""

from __future__ import annotations

import math
from dataclasses import dataclass, field

import numpy as np
import pytest

from swarmsim.experiments import evidence as ev
from swarmsim.experiments import verdicts as vd
from swarmsim.experiments.figures import Claim, Condition, CondStats, PaperSetup
from swarmsim.experiments.report import claims_summary, tally, verdict_text

C, P, N, M = vd.CONSISTENT, vd.PARTLY, vd.NOT_CONSISTENT, vd.NOT_MEASURED
INF = math.inf


def _mean(xs):
    xs = [x for x in xs if x is not None and math.isfinite(x)]
    if not xs:
        return (None, None, 0)
    return (float(np.mean(xs)), float(np.std(xs)), len(xs))


def cs(value, label=None, coverage=(), completion=(), distance=(), settle_cov=(),
       settle_dist=(), distance_at_settle=(), curves=()) -> CondStats:
    """A condition's stats from per-seed values (completion: INF = never completed)."""
    values = {"coverage": list(coverage), "completion": list(completion),
              "distance": list(distance), "settle_cov": list(settle_cov),
              "settle_dist": list(settle_dist), "distance_at_settle": list(distance_at_settle)}
    n = max(len(v) for v in values.values())
    cond = Condition(label or f"value = {value}", value, "ggc", {})
    return CondStats(cond, n, n, 0, _mean(coverage), _mean(distance), _mean(completion),
                     _mean(settle_cov), _mean(settle_dist), {},
                     {"coverage": list(curves)}, [], distance_at_settle=_mean(distance_at_settle),
                     values=values)


@dataclass
class Ctx:
    """A stand-in for figures.Context: stats per figure key (and panel index)."""

    figures: dict
    setup: PaperSetup = field(default_factory=lambda: PaperSetup(world="K"))

    def stats(self, key, index=0, require_done=False):
        found = self.figures[key]
        return found[index] if isinstance(found, tuple) else found

    def panels(self, key):
        found = self.figures[key]
        return found if isinstance(found, tuple) else (found,)


# ----------------------------------------------------------------------------- evidence
def test_a_comparison_holds_only_beyond_the_spread_between_seeds():
    apart = ev.compare([1, 2, 3], [10, 11, 12])
    assert apart.diff == -9 and ev.less(apart) == ev.HOLDS and ev.greater(apart) == ev.CONTRADICTS
    overlap = ev.compare([1, 5, 12], [2, 6, 11])
    assert ev.less(overlap) == ev.UNRESOLVED and ev.greater(overlap) == ev.UNRESOLVED
    assert ev.less(ev.compare([1], [10])) == ev.UNRESOLVED  # one run a side: never resolved


def test_a_run_that_never_completes_is_slower_than_any_that_does():
    c = ev.compare([5000, 6000, 7000, 6500], [INF] * 4)
    assert c.method == "ranks" and c.diff == -INF and "never" in c.text()
    assert ev.less(c) == ev.HOLDS and ev.greater(c) == ev.CONTRADICTS
    # 3 runs a side: no rank test reaches 2.5 % one-sided (the smallest p is 1/20)
    assert ev.less(ev.compare([5000, 6000, 7000], [INF] * 3)) == ev.UNRESOLVED
    both_never = ev.compare([INF, INF], [INF, INF])
    assert both_never.diff == 0 and ev.less(both_never) == ev.UNRESOLVED


def test_welch_is_not_fooled_by_three_seeds_that_overlap():
    assert ev.less(ev.compare([1, 2, 5], [4, 5, 6])) == ev.UNRESOLVED
    assert ev.less(ev.compare([1, 2, 3], [10, 11, 12])) == ev.HOLDS


def test_equivalence_needs_the_whole_interval_inside_the_margin():
    assert ev.within(ev.compare([0.99, 0.99, 0.99], [0.985, 0.99, 0.99]), 0.02) == ev.HOLDS
    assert ev.within(ev.compare([0.99, 0.99, 0.99], [0.80, 0.81, 0.82]), 0.02) == ev.CONTRADICTS
    assert ev.within(ev.compare([0.99, 0.80, 0.99], [0.98, 0.99, 0.80]), 0.02) == ev.UNRESOLVED


def test_a_comparison_is_the_same_every_time_it_is_written():
    assert ev.compare([1, 4, 9], [2, 3, 8]) == ev.compare([1, 4, 9], [2, 3, 8])


# ----------------------------------------------------------------------------- combining
@pytest.mark.parametrize("outcomes, verdict", [
    ([ev.HOLDS, ev.HOLDS], C), ([ev.HOLDS, ev.CONTRADICTS], P),
    ([ev.CONTRADICTS, ev.UNRESOLVED], N), ([ev.HOLDS, ev.UNRESOLVED], "not resolved at 3 runs"),
    ([], M)])
def test_verdict_of_combines_comparisons(outcomes, verdict):
    assert vd.verdict_of(outcomes, 3) == verdict


def test_a_claim_without_finished_runs_is_not_measured():
    assert vd.verdict_of([ev.UNRESOLVED], 0) == M


def test_steps_judge_each_neighbouring_pair():
    st = [cs(1, settle_cov=[900, 950, 1000]), cs(2, settle_cov=[500, 520, 540]),
          cs(3, settle_cov=[600, 610, 620])]
    outcomes, found = vd.steps(st, "settle_cov", decreasing=True)
    assert outcomes == [ev.HOLDS, ev.CONTRADICTS] and found[0].diff < 0 < found[1].diff


def test_the_lattice_bound_is_the_geometry_of_hexagonal_covering():
    assert vd.lattice_cover_bound(6.0) == 1.0
    assert vd.lattice_cover_bound(8.0) == pytest.approx(math.pi * 16 / (math.sqrt(3) / 2 * 64),
                                                        abs=0.005)
    assert vd.lattice_cover_bound(10.0) == pytest.approx(0.580, abs=0.005)


# ----------------------------------------------------------------------------- Figs. 17-18
def _dcover(settles, covers):
    return [cs(d, f"d_cover = {d}", coverage=c, settle_cov=s, completion=[INF] * len(c))
            for d, s, c in zip((4, 6, 8, 10), settles, covers, strict=True)]


FAST = ([9e3] * 3, [8000, 8100, 8200], [5000, 5100, 5200], [3000, 3100, 3200])
SLOW = ([9e3] * 3, [3000, 3100, 3200], [5000, 5100, 5200], [8000, 8100, 8200])
COVERS = ([0.6] * 3, [0.99] * 3, [0.84, 0.83, 0.85], [0.55, 0.54, 0.56])


def test_fig17_judges_speed_only_where_robots_fill_the_lattice_and_flips():
    claims = vd.claims_fig17(Ctx({"fig17": _dcover(FAST, COVERS)}))
    settle, falling, note = claims
    assert settle.verdict == C and "d_cover 6, 8, 10" in settle.where
    assert "4 needs ~958" in settle.where and settle.paper
    assert not falling.evidence and not vd.counted(falling) and "6.93" in falling.test
    assert note.verdict == vd.NOTE and not vd.counted(note)
    assert vd.claims_fig17(Ctx({"fig17": _dcover(SLOW, COVERS)}))[0].verdict == N


def test_fig18_grouping_sooner_same_coverage_and_d10_drop_and_their_flips():
    one = {d: cs(d, settle_cov=[9000, 9100, 9200], coverage=c, completion=t) for d, c, t in (
        (6, [0.99] * 3, [9000, 9100, 9200]), (8, [0.84, 0.85, 0.84], [INF] * 3),
        (10, [0.56, 0.57, 0.56], [INF] * 3))}
    three = {d: cs(d, settle_cov=[5000, 5100, 5200], coverage=c, completion=t) for d, c, t in (
        (6, [0.99] * 3, [5000, 5100, 5200]), (8, [0.84, 0.84, 0.85], [INF] * 3),
        (10, [0.45, 0.46, 0.44], [INF] * 3))}
    assert vd.grouping_sooner(one, three, [6, 8, 10], "").verdict == C
    assert vd.grouping_sooner(three, one, [6, 8, 10], "").verdict == N
    same = vd.same_coverage(one, three, [6, 8], "")
    assert same.verdict == C and same.evidence and "stop rule decides" in same.measured
    assert not vd.same_coverage(one, three, [6], "").evidence  # both stop at 99%: decided
    three[8] = cs(8, coverage=[0.70, 0.71, 0.70], completion=[INF] * 3)
    assert vd.same_coverage(one, three, [6, 8], "").verdict == N
    assert vd.grouping_lowers_at_10(one[10], three[10]).verdict == C
    assert vd.grouping_lowers_at_10(three[10], one[10]).verdict == N
    small = cs(10, coverage=[0.55, 0.56, 0.55])  # lower, but by less than 3 points
    assert vd.grouping_lowers_at_10(one[10], small).verdict == N


def test_fig18_without_fig17_is_not_measured():
    ctx = Ctx({"fig18": _dcover(FAST, COVERS)})
    ctx.stats = lambda key, index=0, require_done=False: (
        None if key == "fig17" else ctx.figures[key])
    claim = next(c for c in vd.claims_fig18(ctx) if c.text.startswith("With the same d_cover"))
    assert claim.verdict == M


# ----------------------------------------------------------------------------- Figs. 19-20
def _distance(values_at_settle, finals=None):
    return [cs(d, distance_at_settle=v, distance=(finals or values_at_settle)[i],
               settle_dist=[30000 - 1000 * i - j for j in range(3)])
            for i, (d, v) in enumerate(zip((4, 6, 8, 10), values_at_settle, strict=True))]


def test_fig19_distance_where_robots_suffice_and_its_flip():
    falling = [[160e3] * 3, [218e3, 219e3, 220e3], [150e3, 156e3, 160e3], [99e3, 100e3, 98e3]]
    claim, note, flat = vd.claims_fig19(Ctx({"fig19": _distance(falling)}))
    assert claim.verdict == C and "d_cover 6, 8, 10" in claim.where and claim.paper
    assert note.verdict == vd.NOTE and flat.verdict == C
    rising = [[160e3] * 3, [99e3, 100e3, 98e3], [150e3, 156e3, 160e3], [218e3, 219e3, 220e3]]
    assert vd.claims_fig19(Ctx({"fig19": _distance(rising)}))[0].verdict == N


def test_fig20_grouped_distance_and_its_flip():
    one = {d: cs(d, distance=[200e3, 210e3, 205e3]) for d in (6, 8)}
    three = {d: cs(d, distance=[150e3, 151e3, 149e3]) for d in (6, 8)}
    claim = vd.grouped_distance(one, three, [6, 8], "d_cover 6, 8")
    assert claim.verdict == C and "0.73" in claim.measured
    assert vd.grouped_distance(three, one, [6, 8], "").verdict == N


# ----------------------------------------------------------------------------- Figs. 21-22
def _groups(completions, coverage=None):
    return [cs(k, f"K = {k}", completion=t, coverage=(coverage or {}).get(k, [0.99] * len(t)),
               settle_cov=[x if math.isfinite(x) else 40000 for x in t],
               distance=[1e5 + 1e4 * abs(k - 6) + j for j in range(len(t))])
            for k, t in completions.items()]


def test_fig21_three_groups_faster_and_fewer_groups_faster_and_their_flips():
    good = {1: [12000, 12500, 13000], 3: [8000, 8200, 8400], 4: [7000, 7100, 7200],
            6: [6000, 6100, 6200], 8: [6500, 6600, 6700], 10: [7500, 7600, 7700]}
    claims = {c.text: c for c in vd.claims_fig21(Ctx({"fig21": _groups(good)}))}
    assert claims["3 groups complete faster than 1 group"].verdict == C
    assert claims["For K < 6, more groups cover faster and every run completes"].verdict == C
    assert claims["From 6 to 10 groups, the more groups the later coverage reaches its "
                  "plateau"].verdict == C
    flipped = {1: [7000, 7100, 7200], 3: [8000, 8200, 8400], 4: [12000, 12500, 13000],
               6: [7500, 7600, 7700], 8: [6500, 6600, 6700], 10: [6000, 6100, 6200]}
    claims = {c.text: c for c in vd.claims_fig21(Ctx({"fig21": _groups(flipped)}))}
    assert claims["3 groups complete faster than 1 group"].verdict == N
    # slower with more groups, though every run completes
    assert claims["For K < 6, more groups cover faster and every run completes"].verdict == P
    assert claims["From 6 to 10 groups, the more groups the later coverage reaches its "
                  "plateau"].verdict == N


def test_fig21_a_run_that_does_not_complete_spoils_full_coverage():
    low = _groups({1: [12000, 12500, 13000], 3: [8000, 8200, 8400], 4: [7000, 7100, INF]})
    assert vd.fewer_groups_faster(low).verdict == P


def test_fig21_coverage_loss_is_by_construction_when_every_run_completes():
    six, ten = cs(6, coverage=[0.99] * 3, completion=[6000] * 3), cs(10, coverage=[0.99] * 3,
                                                                       completion=[7000] * 3)
    assert not vd.many_groups_lose_coverage(six, ten).evidence
    lower = cs(10, coverage=[0.90, 0.91, 0.92], completion=[INF] * 3)
    assert vd.many_groups_lose_coverage(six, lower).verdict == C
    assert vd.many_groups_lose_coverage(lower, six).verdict == N


def test_fig22_distance_by_groups_and_its_flip():
    st = _groups({k: [1000] * 3 for k in (1, 3, 4, 6, 8, 10)})
    claims = vd.claims_fig22(Ctx({"fig22": st}))
    shortest, below, above = claims
    assert shortest.verdict == N  # K=1 moves the most here
    assert below.verdict == C and above.verdict == C
    for s in st:  # distance rising with K below 6, falling above: both flip
        s.values["distance"] = [2e5 - 1e4 * abs(s.cond.value - 6) + j for j in range(3)]
    shortest, below, above = vd.claims_fig22(Ctx({"fig22": st}))
    assert shortest.verdict == C and below.verdict == N and above.verdict == N


# ----------------------------------------------------------------------------- Fig. 23
def _curves(rise_by):
    t = np.array([0.0, 1000.0, 8000.0])
    return [(t, np.array([0.0, r, 0.99])) for r in rise_by]


def test_fig23_curves_coincide_within_ten_percent_and_flip_when_far():
    base = cs(0, completion=[8000, 8100, 8200])
    near = cs(20, completion=[8100, 8200, 8300])
    assert vd.coincide([base, near], "coverage").verdict == C
    far = cs(20, completion=[12000, 12100, 12200])
    assert vd.coincide([base, far], "coverage").verdict == N


def test_fig23_early_faster_and_later_slower_and_their_flips():
    base = cs(0, completion=[8000, 8000, 8000], curves=_curves([0.20, 0.21, 0.22]))
    quick = cs(20, completion=[8000, 8000, 8000], curves=_curves([0.40, 0.41, 0.42]))
    assert vd.early_faster(base, quick).verdict == C
    assert vd.early_faster(quick, base).verdict == N
    slow = cs(20, completion=[9000, 9100, 9200, INF])
    four = cs(0, completion=[8000, 8010, 8020, 8030])
    assert vd.later_slower(four, slow).verdict == C
    assert vd.later_slower(slow, four).verdict == N
    assert vd.later_slower(base, cs(20, completion=[9000, 9100, 9200])).verdict == C


def test_fig23_dead_body_panel_gives_notes_only():
    panel = [cs(0, completion=[8000] * 3, curves=_curves([0.2] * 3)),
             cs(20, completion=[8100] * 3, curves=_curves([0.2] * 3))]
    claims = vd.claims_fig23(Ctx({"fig23": (panel, panel, panel)}))
    assert len(claims) == 6 and all(c.verdict == vd.NOTE for c in claims[4:])
    assert len(vd.claims_fig23(Ctx({"fig23": (panel, panel)}))) == 4


# ----------------------------------------------------------------------------- Fig. 24
def _methods(ggc, others):
    return [cs(name, name, completion=t, coverage=c) for name, (t, c) in
            {"ggc": ggc, **others}.items()]


DONE = ([6000, 6100, 6200, 6300], [0.99] * 4)
NEVER = ([INF] * 4, [0.80, 0.81, 0.82, 0.81])


def test_fig24_follows_the_papers_rule_and_its_flip():
    st = _methods(DONE, {"kilobot": ([9000, 9500, INF, INF], [0.95, 0.96, 0.97, 0.96]),
                         "dash": NEVER, "fcdfs": NEVER,
                         "cvt": ([2000, 2100, 2200, 2150], [0.99] * 4)})
    claims = vd.claims_fig24(Ctx({"fig24": st}))
    fastest, highest, fcdfs, cvt = claims
    assert fastest.verdict == C and "cvt" not in fastest.text
    assert highest.verdict == C and highest.evidence
    assert fcdfs.verdict == C
    assert cvt.verdict == vd.NOTE and "0.35" in cvt.measured and "local map" in cvt.text
    # DASH levelling off early no longer wins: it never completes
    flipped = _methods(NEVER, {"kilobot": DONE, "dash": DONE, "fcdfs": DONE})
    fastest, highest, fcdfs = vd.claims_fig24(Ctx({"fig24": flipped}))
    assert fastest.verdict == N and highest.verdict == N and fcdfs.verdict == N


def test_fig24_highest_coverage_is_by_construction_when_every_method_completes():
    st = _methods(DONE, {"kilobot": DONE, "dash": DONE, "fcdfs": DONE})
    assert not vd.claims_fig24(Ctx({"fig24": st}))[1].evidence


# ----------------------------------------------------------------------------- the report
def test_the_tally_counts_only_claims_that_are_evidence():
    rows = [{"ruleset": "a", "verdict": C, "counted": "True"},
            {"ruleset": "a", "verdict": "not resolved at 3 runs", "counted": "True"},
            {"ruleset": "a", "verdict": C, "counted": "False"},
            {"ruleset": "a", "verdict": vd.NOTE, "counted": "False"}]
    found = tally(rows)["a"]
    assert found[C] == 1 and found["not resolved"] == 1 and sum(found.values()) == 2


def test_verdict_text_marks_what_is_not_evidence():
    assert verdict_text(Claim("x", "m", C)) == f"**{C}**"
    assert "not counted" in verdict_text(Claim("x", "m", C, evidence=False))
    assert verdict_text(Claim("(note) x", "m", vd.NOTE)) == "note"


def test_the_report_summary_tallies_from_claims_csv(tmp_path):
    fig = tmp_path / "fig21"
    fig.mkdir()
    (fig / "claims.csv").write_text(
        "figure,ruleset,claim,measured,verdict,counted,test,where,paper\n"
        "fig21,d,A,m,consistent,True,t,,\nfig21,d,B,m,not consistent,False,t,,\n")
    text = claims_summary(tmp_path, ["fig21"])
    assert "| d | 1 | 0 | 0 | 0 | 0 |" in text and "not consistent (not counted)" in text
