"""Table 3 (swarmsim/experiments/costs.py): Figure 24's runs, no run of its own; its verdicts
hold only beyond the spread between seeds."""

from __future__ import annotations

from swarmsim.cli import main
from swarmsim.experiments import reproduce as rp
from swarmsim.experiments.costs import (
    COMMUNICATION,
    COMPUTING,
    HEARD,
    MEASURES,
    ControllerCosts,
    combine,
    communication_claim,
    computing_claim,
    cost_markdown,
    cost_rows,
    less_beyond_spread,
    not_resolved,
    run_costs,
)
from swarmsim.experiments.table import read_table
from swarmsim.experiments.verdicts import CONSISTENT, NOT_CONSISTENT, NOT_MEASURED, PARTLY


def _costs(name: str, heard: list[float], size: float, ms: list[float]) -> ControllerCosts:
    """A controller's hand-made measures, one value per seed."""
    return ControllerCosts(name, len(heard), {
        HEARD: tuple(heard), "message_bytes": (size,) * len(heard),
        COMMUNICATION: tuple(h * size for h in heard), COMPUTING: tuple(ms)})


def test_table3_plans_exactly_figure_24s_runs():
    for setup in (rp.PAPER, rp.setup_with(rp.PAPER, world="tiny", rulesets=["paper"])):
        plan = rp.plan(["fig24", "table3"], setup, reps=3)
        assert plan["table3"] and [r.run_id for r in plan["table3"]] == [
            r.run_id for r in plan["fig24"]]


def test_less_beyond_spread_needs_ranges_apart():
    assert less_beyond_spread([1, 2, 3], [4, 5, 6]) == CONSISTENT
    assert less_beyond_spread([4, 5, 6], [1, 2, 3]) == NOT_CONSISTENT  # flipped
    assert less_beyond_spread([1, 2, 5], [4, 5, 6]) == not_resolved(3) == "not resolved at 3 runs"
    assert less_beyond_spread([1], [9]) == "not resolved at 1 runs"  # no spread to judge by
    assert less_beyond_spread([], [9, 10]) == NOT_MEASURED


def test_combine_reports_the_least_resolved_or_a_contradiction():
    assert combine([CONSISTENT, CONSISTENT]) == CONSISTENT
    assert combine([CONSISTENT, not_resolved(5), not_resolved(3)]) == not_resolved(3)
    assert combine([CONSISTENT, NOT_CONSISTENT, not_resolved(3)]) == PARTLY
    assert combine([NOT_CONSISTENT, not_resolved(3)]) == NOT_CONSISTENT
    assert combine([CONSISTENT, NOT_MEASURED]) == NOT_MEASURED


def _field(cvt_heard: list[float], cvt_ms: list[float]) -> list[ControllerCosts]:
    """GGC, Table 3's small-cost baselines and CVT; GGC hears 4-6 rows of 44 bytes a tick."""
    return [_costs("ggc", [5, 4, 6], 44, [0.002, 0.003, 0.0025]),
            _costs("kilobot", [5, 5, 5], 22, [0.01, 0.01, 0.01]),
            _costs("dash", [2, 2, 3], 10, [0.08, 0.09, 0.08]),
            _costs("fcdfs", [5, 6, 5], 40, [0.02, 0.02, 0.02]),
            _costs("cvt", cvt_heard, 6, cvt_ms)]


def test_claims_hold_when_cvt_costs_more_in_every_seed():
    costs = _field([100, 110, 120], [0.5, 0.6, 0.55])
    comm, comp = communication_claim(costs), computing_claim(costs)
    assert comm.verdict == CONSISTENT and comp.verdict == CONSISTENT
    assert "cvt/ggc" in comm.measured and "ggc 0.0025 [0.0020, 0.0030]" in comp.measured
    assert comm.paper and comm.test and comp.where


def test_claims_fail_when_the_comparison_is_flipped():
    """CVT hearing fewer bytes and computing less than every other method in every seed:
    both claims contradicted."""
    costs = _field([1, 1, 1], [0.0001, 0.0002, 0.0001])
    assert communication_claim(costs).verdict == NOT_CONSISTENT
    assert computing_claim(costs).verdict == NOT_CONSISTENT


def test_communication_is_partly_consistent_only_where_ggc_beats_cvt():
    costs = _field([100, 110, 120], [0.5, 0.6, 0.55])
    costs[3] = _costs("fcdfs", [500, 600, 500], 40, [0.02, 0.02, 0.02])  # a baseline above CVT
    assert communication_claim(costs).verdict == PARTLY
    costs[0] = _costs("ggc", [500, 400, 600], 44, [0.002, 0.003, 0.0025])  # GGC above CVT
    assert communication_claim(costs).verdict == NOT_CONSISTENT


def test_claims_unresolved_within_the_spread_or_unmeasured():
    costs = _field([30, 40, 50], [0.002, 0.1, 0.2])  # GGC's bytes 176-264: inside CVT's 180-300
    assert communication_claim(costs).verdict == "not resolved at 3 runs"
    assert computing_claim(costs).verdict == "not resolved at 3 runs"
    assert communication_claim(costs[:4]).verdict == NOT_MEASURED  # no CVT
    one_seed = [_costs("ggc", [5], 44, [0.002]), _costs("cvt", [100], 6, [0.5])]
    assert computing_claim(one_seed).verdict == "not resolved at 1 runs"


def test_cost_table_rows_and_ratios():
    costs = _field([100, 110, 120], [0.5, 0.6, 0.55])
    rows = {r["controller"]: r for r in cost_rows(costs, "ggc")}
    assert rows["ggc"][f"{COMMUNICATION}_vs_ggc"] == 1
    assert rows["cvt"][f"{COMMUNICATION}_mean"] == 660
    assert rows["cvt"][f"{COMMUNICATION}_vs_ggc"] == round(660 / 220, 4)
    assert rows["cvt"][f"{COMPUTING}_min"] == 0.5 and rows["cvt"][f"{COMPUTING}_max"] == 0.6
    text = cost_markdown(costs, "ggc")
    assert all(m.label in text for m in MEASURES) and "| cvt | 3/3 |" in text


def test_runs_made_before_the_cost_fields_measure_nothing():
    assert run_costs({"coverage": 0.9}) is None
    got = run_costs({HEARD: 2.5, "message_bytes": 10, COMPUTING: 0.01})
    assert got == {HEARD: 2.5, "message_bytes": 10.0, COMMUNICATION: 25.0, COMPUTING: 0.01}


def test_table3_after_figure_24_runs_nothing_new_and_writes_its_table(tmp_path, capsys):
    """On 'tiny', one seed, 8 ticks: Figure 24's 7 runs (GGC under two rule sets, five
    baselines), then Table 3 from them."""
    out = tmp_path / "repro"
    common = ["--world", "tiny", "--reps", "1", "--max-ticks", "8", "--out", str(out)]
    assert main(["reproduce", "fig24", *common, "--workers", "1", "--quiet"]) == 0
    capsys.readouterr()
    assert main(["reproduce", "table3", *common, "--dry-run"]) == 0
    plan = capsys.readouterr().out
    assert "table3: 7 runs (7 done)" in plan and "7 done, 0 to run" in plan
    assert main(["reproduce", "table3", *common, "--workers", "1", "--quiet"]) == 0
    assert "7 runs: 7 done (0 run now" in capsys.readouterr().out
    rows = read_table(out / "table3" / "table.csv")
    assert {r["controller"] for r in rows} == set(rp.PAPER.comparison)
    assert {r["ruleset"] for r in rows} == set(rp.PAPER.judged_rulesets())
    assert all(r["measured"] == "1" and float(r["message_bytes_mean"]) > 0 for r in rows)
    assert not (out / "table3" / "table3.png").exists()
    report = (out / "table3" / "REPORT.md").read_text()
    assert "bytes heard / robot-tick" in report and "GGC's computing cost is small" in report
    claims = read_table(out / "table3" / "claims.csv")
    assert {c["verdict"] for c in claims} == {"not resolved at 1 runs"}
    assert "Table 3" in (out / "REPORT.md").read_text()
