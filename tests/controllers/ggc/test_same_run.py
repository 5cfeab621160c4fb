"""Runs that are the same by construction share one run id (spec.run_id, a controller's
``same_run_settings``): GGC's rule sets whose extra rules act nowhere in a run."""

from __future__ import annotations

import pytest

from controllers.ggc.params import GGCParams
from controllers.ggc.rules.rulesets import BESIDE, HOLES, RULESETS, SURPLUS, YIELD
from controllers.ggc.swarm import acting_flags, same_run_ruleset
from swarmsim.engine.sim import Simulation
from swarmsim.experiments.spec import RunSpec, run_id, same_run_settings, spec_from_dict

# Run ids of the paper's reproduction (world K, seed 0) made before runs that are the same by
# construction shared one id (the store of a full `reproduce all`): these runs are not the
# same as any other, so their ids must not change, or old stores would remake them.
KNOWN_IDS = [
    ({"d_cover": 6, "groups": 1, "ruleset": "yield-holes"}, "678d376ef7038c95"),
    ({"d_cover": 6, "groups": 1, "ruleset": "paper"}, "07da42e4880d2fa7"),
    ({"d_cover": 8, "groups": 1, "ruleset": "paper"}, "30caab18c943e82a"),
    ({"d_cover": 6, "groups": 3, "ruleset": "yield-holes"}, "dcae31c063b5a1ee"),
    ({"d_cover": 8, "groups": 3, "ruleset": "yield-holes"}, "b2d8f39758dcfc93"),
    ({"d_cover": 6, "groups": 3, "ruleset": "paper"}, "fe4c7d79a6138bd5"),
    ({"d_cover": 8, "groups": 3, "ruleset": "paper"}, "b30a5636a02527a7"),
]


@pytest.mark.parametrize(("settings", "known"), KNOWN_IDS)
def test_runs_not_the_same_as_another_keep_their_ids(settings, known):
    assert run_id("K", "ggc", settings, 0) == known
    assert RunSpec("K", "ggc", settings, 0).run_id == known


def test_a_controller_that_declares_no_same_runs_keeps_its_ids():
    assert run_id("K", "kilobot", {"d_cover": 6, "groups": 3}, 0) == "1975bd5ffebc22ab"


def test_rule_sets_that_act_alike_in_a_run_share_its_id():
    def rid(d_cover, groups, ruleset):
        return run_id("K", "ggc", {"d_cover": d_cover, "groups": groups, "ruleset": ruleset}, 0)

    # one group, d_cover 8 and 10: holes are not filled there (rule_flags), and YIELD and
    # SURPLUS act only between groups: our rule sets make the paper's run
    for d_cover in (8, 10):
        paper = rid(d_cover, 1, "paper")
        assert rid(d_cover, 1, "yield-holes") == rid(d_cover, 1, "yield") == paper
    assert rid(8, 1, "paper") == "30caab18c943e82a"  # the paper's keeps its id
    assert rid(8, 1, "yield-holes") != "540bfd6610270e19"  # its id before
    # with groups, YIELD acts; at d_cover 6 HOLES acts; CROSS may act with one group
    assert rid(8, 3, "yield-holes") != rid(8, 3, "paper")
    assert rid(6, 1, "yield-holes") != rid(6, 1, "paper")
    assert rid(8, 1, "yield-holes-cross") != rid(8, 1, "paper")
    # ... but HOLES alone is dropped at d_cover 8 whatever the groups
    assert rid(8, 3, "paper-holes") == rid(8, 3, "paper")
    # the seed is still part of the id
    assert run_id("K", "ggc", {"d_cover": 8, "groups": 1, "ruleset": "yield"}, 1) != rid(
        8, 1, "yield")


def test_the_canonical_rule_set_is_the_first_with_the_same_acting_flags():
    def canonical(ruleset, d_cover, groups):
        return same_run_ruleset(GGCParams(ruleset=ruleset, d_cover=d_cover), groups)

    assert {canonical(r, 8, 1) for r in ("paper", "yield", "yield-holes", "paper-holes")} \
        == {"paper"}
    assert canonical("yield-holes-cross", 8, 1) == "yield-holes-cross"
    for name in RULESETS:  # with groups at d_cover 6 every rule set is its own
        assert canonical(name, 6, 3) == name
    assert canonical("yield", 6, 1) == "paper" and canonical("yield-holes", 6, 1) != "paper"
    assert acting_flags(GGCParams(d_cover=8), 1) == 0
    # at d_cover <= yield_release SURPLUS is kept with one group (a rule of one group may
    # read it there), so the default rule set is not taken for "paper-holes"
    assert acting_flags(GGCParams(d_cover=4), 1) == HOLES | SURPLUS
    assert canonical("paper-holes", 4, 1) == "paper-holes"
    assert canonical("paper-holes", 6, 1) == "yield-holes"  # the first with HOLES alone
    assert acting_flags(GGCParams(d_cover=8), 3) == YIELD | SURPLUS | BESIDE  # no HOLES at 8
    # ASIDE and BESIDE act only on another group's robots: with one group, gone
    assert acting_flags(GGCParams(d_cover=6, ruleset="yield-holes-aside"), 1) == HOLES
    assert acting_flags(GGCParams(d_cover=6), 1) == HOLES
    assert acting_flags(GGCParams(d_cover=6), 3) == YIELD | HOLES | SURPLUS | BESIDE
    assert canonical("yield-holes-aside", 6, 1) == "yield-holes"  # one group: no other to meet
    assert canonical("yield-holes-push", 6, 1) == "yield-holes"
    assert canonical("yield-holes-push", 6, 3) == "yield-holes-push"


def test_the_world_defaults_count_and_a_run_that_does_not_check_keeps_its_settings():
    # tiny: one group and d_cover 6 by default
    assert same_run_settings("tiny", "ggc", {"d_cover": 8}) == {"ruleset": "paper"}
    assert same_run_settings("tiny", "ggc", {}) == {}  # d_cover 6: holes are filled
    assert same_run_settings("tiny", "ggc", {"d_cover": 8, "groups": 2}) == {}
    assert same_run_settings("tiny", "ggc", {"d_cover": 8, "groups": 0}) == {}  # refused
    assert same_run_settings("no-such-world", "ggc", {"d_cover": 8}) == {}
    assert same_run_settings("tiny", "dispersion", {"d_cover": 8}) == {}  # declares none
    assert run_id("tiny", "ggc", {"d_cover": 8}, 0) == run_id(
        "tiny", "ggc", {"d_cover": 8, "ruleset": "paper"}, 0)
    runs = spec_from_dict({"world": "tiny", "params": {"d_cover": 8, "max_ticks": 10},
                           "grid": {"ruleset": ["yield-holes", "yield", "paper"]}}).runs()
    # the same run, once: as the settings that name it (the paper's rule set)
    assert len(runs) == 1 and runs[0].settings["ruleset"] == "paper"


@pytest.mark.slow
def test_runs_that_share_an_id_are_the_same_tick_for_tick():
    """What the shared id claims, on whole runs: under the paper's rules and the default
    ones, one group at d_cover 8 makes the same run (at d_cover 6, where holes are filled,
    the two differ before the end)."""
    def run(ruleset):
        sim = Simulation("tiny", "ggc", seed=3, d_cover=8, max_ticks=20000,
                         settings={"ruleset": ruleset})
        result = sim.run(progress=False)
        return result.timeseries, result.robots, result.summary["stop_reason"]

    paper, ours = run("paper"), run("yield-holes")
    assert paper[2] != "max_ticks"  # the run ended by itself
    assert paper == ours


@pytest.mark.slow
def test_a_sweep_makes_a_shared_run_once_and_shows_it_for_each_grid_point(tmp_path):
    from swarmsim.cli import main
    from swarmsim.experiments.table import read_table

    spec = tmp_path / "spec.toml"
    spec.write_text('world = "tiny"\ncontroller = "ggc"\n[params]\nmax_ticks = 20\n'
                    '[grid]\nd_cover = [6, 8]\nruleset = ["yield-holes", "paper"]\n')
    out = tmp_path / "out"
    assert main(["sweep", str(spec), "--out", str(out), "--workers", "1", "--quiet"]) == 0
    made = read_table(out / "results.csv")  # d_cover 8: one run for both rule sets
    assert sorted((r["d_cover"], r["ruleset"]) for r in made) == [
        ("6", "paper"), ("6", "yield-holes"), ("8", "paper")]
    shown = read_table(out / "aggregate" / "conditions.csv")
    assert sorted((r["d_cover"], r["ruleset"], r["done"]) for r in shown) == [
        ("6", "paper", "1"), ("6", "yield-holes", "1"), ("8", "paper", "1"),
        ("8", "yield-holes", "1")]
