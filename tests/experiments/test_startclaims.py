"""Figure 14 (random start) and the gaps where groups meet: the junction measure on
hand-made layouts, the fig14 plan, and the claims on hand-made measurements."""

import csv

import numpy as np
import pytest
from shapely.geometry import box

from swarmsim.cli import main
from swarmsim.errors import ConfigError
from swarmsim.experiments import reproduce as rp
from swarmsim.experiments.junctions import (
    JunctionGaps,
    junction_band,
    junction_gaps,
    run_junction_gaps,
)
from swarmsim.experiments.startclaims import (
    StartRun,
    junction_claim,
    junction_growth_claims,
    random_start_claim,
    start_time_note,
)
from swarmsim.experiments.verdicts import CONSISTENT, NOT_CONSISTENT, NOT_MEASURED, PARTLY
from swarmsim.metrics.grid import CoverageGrid

STRIP = box(0, 0, 40, 12)


def _lattice(x0: float, x1: float, step: float = 4.0) -> np.ndarray:
    """Robots on a square lattice over x in [x0, x1] of the strip (every point of it within
    r = 4 of one of them)."""
    xs = np.arange(x0, x1 + 1e-9, step)
    ys = np.arange(0.0, 12.0 + 1e-9, step)
    return np.array([(x, y) for x in xs for y in ys])


def _gaps(positions: np.ndarray, groups: np.ndarray) -> JunctionGaps:
    grid = CoverageGrid.for_target(STRIP, radius=4.0, cols=80, rows=24)
    covered = grid.covered_grid(positions)
    return junction_gaps(grid.inside, covered, (grid.x0, grid.y0), (grid.dx, grid.dy),
                         positions, groups)


def _two_groups_with_a_gap():
    """Group 1 on x <= 12, group 2 on x >= 28: x in (16, 24) is nobody's."""
    left, right = _lattice(0, 12), _lattice(28, 40)
    positions = np.vstack([left, right])
    groups = np.array([1] * len(left) + [2] * len(right))
    return positions, groups


def test_a_gap_between_two_groups_is_a_junction_gap():
    positions, groups = _two_groups_with_a_gap()
    g = _gaps(positions, groups)
    assert g.uncovered > 0 and g.groups == 2
    assert g.band_uncovered == g.uncovered  # every uncovered pixel lies between the groups
    assert 0 < g.band < g.target  # ... and the band is the middle, not the whole strip
    assert g.junction_share == 1.0 and g.outside_density == 0.0
    assert g.own_excess() == g.band_uncovered / g.target  # nothing lost outside the band
    assert g.excess(0.9) < 0 < g.excess(0.0)


def test_one_group_has_no_junction_whatever_its_gaps():
    positions, groups = _two_groups_with_a_gap()
    g = _gaps(positions, np.ones_like(groups))
    assert g.uncovered == _gaps(positions, groups).uncovered > 0
    assert g.band == g.band_uncovered == 0 and g.band_density is None


def test_a_hole_inside_one_group_is_not_at_a_junction():
    left, right = _lattice(0, 20), _lattice(24, 40)
    hole = (left[:, 0] == 4) | (left[:, 0] == 8)  # a hole deep in group 1's part
    positions = np.vstack([left[~hole], right])
    groups = np.array([1] * int((~hole).sum()) + [2] * len(right))
    g = _gaps(positions, groups)
    assert g.uncovered > 0 and g.band > 0
    assert g.band_uncovered == 0  # the groups meet without a gap; the hole is group 1's own
    assert g.outside_density > 0


def test_ungrouped_robots_are_left_out_of_the_band():
    positions = np.array([[0.0, 0.0], [2.0, 0.0], [1.0, 2.0]])
    centres = np.array([[1.0, 1.0]])
    assert junction_band(centres, positions, np.array([1, 2, 1])).tolist() == [True]
    assert junction_band(centres, positions, np.array([1, 0, 1])).tolist() == [False]
    on_a_line = np.array([[0.0, 0.0], [1.0, 0.0], [2.0, 0.0]])  # no triangle: none at all
    assert not junction_band(np.array([[1.0, 0.0]]), on_a_line, np.array([1, 2, 1]))[0]


def _write_run(folder, positions, groups, group_column=True):
    grid = CoverageGrid.for_target(STRIP, radius=4.0, cols=80, rows=24)
    folder.mkdir()
    np.savez(folder / "coverage.npz", **grid.arrays(positions))
    with open(folder / "robots.csv", "w", newline="") as f:
        fields = ["robot", "x", "y", "status"] + (["group"] if group_column else [])
        w = csv.DictWriter(f, fields)
        w.writeheader()
        for i, ((x, y), g) in enumerate(zip(positions, groups, strict=True)):
            w.writerow({"robot": i, "x": x, "y": y, "status": "Arrive",
                        **({"group": g} if group_column else {})})


def test_the_measure_reads_a_stored_run(tmp_path):
    positions, groups = _two_groups_with_a_gap()
    _write_run(tmp_path / "run", positions, groups)
    assert run_junction_gaps(tmp_path / "run") == _gaps(positions, groups)
    _write_run(tmp_path / "nogroups", positions, groups, group_column=False)
    with pytest.raises(ConfigError, match="no group column"):
        run_junction_gaps(tmp_path / "nogroups")
    with pytest.raises(ConfigError, match="no coverage.npz"):
        run_junction_gaps(tmp_path)


# ----------------------------------------------------------------------------- the plan
def test_fig14_plans_random_starts_of_three_groups(capsys):
    runs = rp.plan("fig14", reps=2)["fig14"]
    assert len(runs) == 2 * 2  # seeds 0, 1 under each judged rule set
    assert {r.seed for r in runs} == {0, 1} and {r.world for r in runs} == {"K"}
    assert {(r.settings["start"], r.settings["groups"], r.settings["d_cover"])
            for r in runs} == {("random", 3, 6)}
    assert main(["reproduce", "fig14", "--dry-run", "--reps", "2"]) == 0
    assert "fig14: 4 runs (0 done) over random" in capsys.readouterr().out


# ----------------------------------------------------------------------------- the claims
def _start(completion=9000, grouped=240, formed=603, formed_tick=600):
    return StartRun(robots=603, coverage=0.99 if completion else 0.9,
                    completion_tick=completion, grouped_tick=grouped, formed_robots=formed,
                    formed_tick=formed_tick)


def test_random_start_claim_needs_every_run_to_group_aggregate_and_complete():
    good = [_start(), _start(completion=12000)]
    claim = random_start_claim(good)
    assert claim.verdict == CONSISTENT and "10500 (9000-12000)" in claim.measured
    for bad in (_start(completion=None), _start(grouped=None), _start(formed=100),
                _start(formed_tick=9500)):
        assert random_start_claim([*good, bad]).verdict == NOT_CONSISTENT, bad
    assert random_start_claim([]).verdict == NOT_MEASURED
    silent = StartRun(603, 0.99, 9000, None, None, None)  # a controller without groups
    assert random_start_claim([silent]).verdict == NOT_MEASURED


def test_start_time_note_is_not_judged():
    note = start_time_note([15000, 17000], [12000, 12000])
    assert note.verdict == "note" and "ratio of means 1.33" in note.measured
    assert "reproduce fig18" in start_time_note([15000], None).measured


def _jg(uncovered, band, band_uncovered, target=1000, groups=3):
    return JunctionGaps(target, uncovered, band, band_uncovered, groups)


def test_junction_claim_holds_only_where_the_band_loses_more():
    one = [_jg(10, 0, 0, groups=1), _jg(12, 0, 0, groups=1), _jg(11, 0, 0, groups=1)]
    three = [_jg(10, 400, 8), _jg(10, 500, 9), _jg(10, 450, 9)]  # band ~2 %, outside ~0.3 %
    claim = junction_claim(three, one, 6)
    assert claim.verdict == CONSISTENT and claim.evidence and "Section 6.1" in claim.paper
    flipped = [_jg(10, 400, 1), _jg(10, 500, 1), _jg(10, 450, 1)]  # the gaps lie outside
    assert junction_claim(flipped, one, 6).verdict == NOT_CONSISTENT
    below_one_group = [_jg(2, 400, 2), _jg(2, 400, 2), _jg(2, 420, 2)]  # band ~0.5 %
    assert junction_claim(below_one_group, one, 6).verdict == PARTLY
    mixed = [_jg(10, 400, 8), _jg(10, 500, 1)]  # one run each way: the spread decides nothing
    assert junction_claim(mixed, one, 6).verdict.startswith("not resolved")
    assert junction_claim(three, [], 6).verdict == NOT_MEASURED


def test_junction_growth_needs_each_step_beyond_the_spread():
    one = {6: [_jg(10, 0, 0, groups=1)], 8: [_jg(100, 0, 0, groups=1)],
           10: [_jg(400, 0, 0, groups=1)]}
    grouped = {6: [_jg(10, 400, 8), _jg(10, 400, 9), _jg(10, 400, 8)],  # excess ~0.4 %
               8: [_jg(120, 400, 60), _jg(120, 400, 70), _jg(120, 400, 65)],  # ~2.5 %
               10: [_jg(450, 400, 250), _jg(450, 400, 260), _jg(450, 400, 255)]}  # ~9.5 %
    claim, geometry = junction_growth_claims(grouped, one)
    assert claim.verdict == CONSISTENT and claim.evidence
    assert geometry.evidence is False and geometry.verdict == CONSISTENT
    grouped[10] = [_jg(450, 400, 60), _jg(450, 400, 65), _jg(450, 400, 62)]  # 10 below 8
    assert junction_growth_claims(grouped, one)[0].verdict == PARTLY
    assert junction_growth_claims({6: grouped[6]}, one)[0].verdict == NOT_MEASURED


# ----------------------------------------------------------------------------- stored runs
def test_claims_read_the_figures_runs_from_the_store(tmp_path):
    """claims_fig14 and junction_claims find each figure's runs by their ids in the store."""
    import json
    import shutil

    from swarmsim.experiments.figures import Context
    from swarmsim.experiments.runner import Sweep
    from swarmsim.experiments.startclaims import claims_fig14, junction_claims

    setup = rp.setup_with(rp.PAPER, rulesets=["paper"]).columns()[0]
    store = tmp_path / "runs"

    def run_dir(key, value):
        panel = rp.get_figure(key).build(setup)[0]
        cond = next(i for i, c in enumerate(panel.conditions) if c.value == value)
        return store / rp.panel_runs(panel, setup, 1)[cond][0].run_id

    def done(folder, **summary):
        folder.mkdir(parents=True, exist_ok=True)
        (folder / "summary.json").write_text(json.dumps({"robots": 603, "coverage": 0.99,
                                                         **summary}))

    done(run_dir("fig14", "random"), completion_tick=15000, grouped_tick=243,
         formed_robots=603, formed_tick=610)
    done(run_dir("fig18", 6), completion_tick=12000)
    ctx = Context(Sweep([], tmp_path, runs_dir=store), setup, 1, None, rp.get_figure)
    claim, note = claims_fig14(ctx)
    assert claim.verdict == CONSISTENT and "ratio of means 1.25" in note.measured
    assert junction_claims(ctx)[0].verdict == NOT_MEASURED  # no robots.csv: not measured
    shutil.rmtree(run_dir("fig18", 6))
    _write_run(run_dir("fig18", 6), *_two_groups_with_a_gap())  # a gap between two groups
    done(run_dir("fig18", 6), completion_tick=12000)
    whole = _lattice(0, 40)  # one group, every pixel covered
    _write_run(run_dir("fig17", 6), whole, np.ones(len(whole), dtype=int))
    done(run_dir("fig17", 6), completion_tick=20000)
    found = junction_claims(ctx)[0]  # the gap is found, but one run is never resolved
    assert found.verdict == "not resolved at 1 runs" and "holds in 1 of 1" in found.measured
