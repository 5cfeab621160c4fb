"""A sweep's aggregates per condition: conditions.csv, curves.csv and coverage.png."""

from __future__ import annotations

import json
from dataclasses import dataclass

import numpy as np
import pytest

from swarmsim.cli import main
from swarmsim.controller import Action
from swarmsim.experiments import run_sweep, spec_from_dict
from swarmsim.experiments.aggregate import conditions, tick_grid
from swarmsim.experiments.table import read_table

TINY = {"world": "tiny", "controller": "dispersion", "params": {"max_ticks": 40}}


def summaries_by_d_cover(out) -> dict[str, list[dict]]:
    found: dict[str, list[dict]] = {}
    for path in out.glob("runs/*/summary.json"):
        run = json.loads((path.parent / "run.json").read_text())
        found.setdefault(str(run["settings"]["d_cover"]), []).append(
            json.loads(path.read_text()))
    return found


@pytest.mark.slow
def test_an_interrupted_sweep_aggregates_every_run_once_resumed(tmp_path):
    runs = spec_from_dict({**TINY, "reps": 3, "grid": {"d_cover": [4, 6]}}).runs()
    out = tmp_path / "out"

    def stop_after_two(run, status, seen=[]):  # noqa: B006 - a counter for this test
        seen.append(run)
        if len(seen) == 2:
            raise KeyboardInterrupt

    with pytest.raises(KeyboardInterrupt):
        run_sweep(runs, out, workers=1, progress=False, on_result=stop_after_two)
    assert not (out / "aggregate").exists()  # nothing half-aggregated
    run_sweep(runs, out, workers=1, progress=False)

    table = read_table(out / "aggregate" / "conditions.csv")
    assert [r["condition"] for r in table] == ["d_cover=4", "d_cover=6"]
    by_d = summaries_by_d_cover(out)
    for row in table:
        mine = by_d[row["d_cover"]]
        assert row["runs"] == row["done"] == "3" and row["failed"] == "0"
        cov = [s["coverage"] for s in mine]
        assert float(row["coverage_mean"]) == pytest.approx(np.mean(cov), abs=1e-6)
        assert float(row["coverage_sd"]) == pytest.approx(np.std(cov), abs=1e-6)
        dist = [s["total_distance"] for s in mine]
        assert float(row["total_distance_mean"]) == pytest.approx(np.mean(dist), abs=1e-3)
        assert row["stop_reasons"] == "max_ticks 3" and row["completed"] == "0"

    curves = read_table(out / "aggregate" / "curves.csv")
    for cond in ("d_cover=4", "d_cover=6"):
        rows = [r for r in curves if r["condition"] == cond]
        ticks = [int(r["tick"]) for r in rows]
        assert ticks == list(range(41))  # whole ticks, 0 to the runs' end
        for r in rows:
            assert (float(r["coverage_min"]) <= float(r["coverage_mean"])
                    <= float(r["coverage_max"]))
        mine = by_d[cond.split("=")[1]]
        assert float(rows[-1]["coverage_mean"]) == pytest.approx(
            np.mean([s["coverage"] for s in mine]), abs=1e-6)
        assert float(rows[-1]["total_distance_max"]) == pytest.approx(
            max(s["total_distance"] for s in mine), abs=1e-3)
    assert (out / "aggregate" / "coverage.png").stat().st_size > 5000


@pytest.mark.slow
def test_every_finished_sweep_run_keeps_its_coverage_grid(tmp_path):
    runs = spec_from_dict({**TINY, "params": {"max_ticks": 150}, "reps": 2}).runs()
    run_sweep(runs, tmp_path, workers=1, progress=False)
    for run in runs:
        folder = tmp_path / "runs" / run.run_id
        summary = json.loads((folder / "summary.json").read_text())
        grid = np.load(folder / "coverage.npz")
        assert summary["coverage"] > 0
        assert grid["covered"].sum() / grid["target"].sum() == pytest.approx(
            summary["coverage"], abs=1e-6)


@dataclass(frozen=True)
class FlakyParams:
    """fail: the robots raise on their third tick (a run that fails while it runs)."""

    fail: bool = False


class Flaky:
    """Test controller: stands still, or breaks at tick 2 when told to."""

    name = "flaky"
    Params = FlakyParams
    STATUSES = ("Standing",)

    @classmethod
    def sensing_range(cls, params) -> float:
        return 2.0

    def __init__(self, setup, params: FlakyParams, rng):
        self.params = params

    def step(self, perception):
        if self.params.fail and perception.tick >= 2:
            raise RuntimeError("flaky robot broke")
        return Action((0.0, 0.0), {"status": 0, "moving": False})


def test_cli_sweep_writes_the_aggregate_with_failed_runs_counted_apart(tmp_path, capsys):
    spec = tmp_path / "spec.toml"
    spec.write_text('world = "tiny"\ncontroller = "tests.experiments.test_sweep_aggregate:Flaky"\n'
                    "reps = 2\n[params]\nmax_ticks = 10\nrobots = 20\n[grid]\n"
                    "fail = [false, true]\n")
    out = tmp_path / "out"
    assert main(["sweep", str(spec), "--out", str(out), "--workers", "1", "--quiet"]) == 1
    table = read_table(out / "aggregate" / "conditions.csv")
    assert [(r["fail"], r["done"], r["failed"]) for r in table] == [("False", "2", "0"),
                                                                   ("True", "0", "2")]
    assert table[1]["coverage_mean"] == ""
    curves = read_table(out / "aggregate" / "curves.csv")
    assert {r["condition"] for r in curves} == {"fail=False"}


def test_conditions_are_every_setting_but_the_seed():
    runs = spec_from_dict({**TINY, "seeds": [3, 9], "grid": {"d_cover": [4, 6],
                                                              "robots": [20, 30]}}).runs()
    groups = conditions(runs)
    assert [c.label for c, _ in groups] == ["d_cover=4, robots=20", "d_cover=4, robots=30",
                                            "d_cover=6, robots=20", "d_cover=6, robots=30"]
    assert all([r.seed for r in rs] == [3, 9] for _, rs in groups)
    one = spec_from_dict({**TINY, "reps": 2}).runs()
    assert [(c.label, len(rs)) for c, rs in conditions(one)] == [("all runs", 2)]


@pytest.mark.parametrize("last,points,end", [(40, 41, 40.0), (0, 2, 1.0), (1000, 201, 1000.0),
                                             (18537, 201, 18600.0)])
def test_the_curve_grid_is_whole_ticks(last, points, end):
    assert tick_grid(last) == (points, end)
