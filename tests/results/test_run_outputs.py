"""A run's output files for researchers: robots.csv, trajectories.npz, coverage.npz and the
time series' ``moving`` column (docs/outputs.md describes each)."""

from __future__ import annotations

import csv
import json
from collections import Counter
from pathlib import Path

import numpy as np
import pytest

from controllers.common.gradient import INF_GRADIENT
from swarmsim.cli import main
from swarmsim.engine.sim import Simulation
from swarmsim.errors import ConfigError
from swarmsim.metrics import FinalState
from swarmsim.results.trajectories import Trajectories, load_trajectories

GO_TO_LIGHT = "examples.my_controller:GoToLight"


def rows_of(path: Path) -> list[dict[str, str]]:
    with path.open(newline="") as fh:
        return list(csv.DictReader(fh))


@pytest.fixture(scope="module")
def corridor_run(tmp_path_factory) -> Path:
    """GGC on corridor, 200 ticks, trajectories every 25 ticks."""
    out = tmp_path_factory.mktemp("corridor") / "out"
    assert main(["run", "corridor", "--max-ticks", "200", "--out", str(out), "--quiet",
                 "--trajectories", "25"]) == 0
    return out


@pytest.mark.slow
def test_robots_csv_has_final_state_distance_and_contacts(corridor_run):
    summary = json.loads((corridor_run / "summary.json").read_text())
    rows = rows_of(corridor_run / "robots.csv")
    assert len(rows) == summary["robots"] == 60
    assert list(rows[0])[:4] == ["robot", "x", "y", "status"]
    assert {"group", "gradient", "leader", "distance", "settle_tick", "contacts_robot",
            "contacts_wall", "contact_ticks", "settled_max_displacement"} <= set(rows[0])
    from controllers.ggc.statuses import STATUSES
    assert {r["status"] for r in rows} <= set(STATUSES)
    assert Counter(r["status"] for r in rows) == summary["status_counts"]
    assert {r["group"] for r in rows} == {"1", "2"}  # corridor: two groups
    assert sum(r["leader"] == "1" for r in rows) == 2
    # odometry: the robots' distances add up to the run's total distance
    assert sum(float(r["distance"]) for r in rows) == pytest.approx(summary["total_distance"],
                                                                   abs=0.01)
    assert all(float(r["distance"]) > 0 for r in rows)  # GGC's formations all travel
    # the final positions are the trajectories' last sample
    last = load_trajectories(corridor_run / "trajectories.npz")["positions"][-1]
    xy = np.array([[float(r["x"]), float(r["y"])] for r in rows])
    assert np.allclose(xy, last, atol=1e-3)


def test_trajectories_sample_every_k_ticks_and_the_end(corridor_run):
    data = load_trajectories(corridor_run / "trajectories.npz")
    assert data["ticks"].tolist() == list(range(0, 201, 25))
    assert data["positions"].shape == (9, 60, 2) and data["positions"].dtype == np.float64
    assert data["statuses"].shape == (9, 60) and data["statuses"].dtype == np.int8
    assert data["status_names"][0] == "Initial"
    steps = np.hypot(*np.diff(data["positions"], axis=0).T)  # (60, 8)
    assert steps.max() <= 25 * 0.1 + 1e-3  # no robot outruns v_max = 0.1 per tick
    assert steps.sum() > 0


def test_coverage_npz_recomputes_the_summary_coverage(corridor_run):
    summary = json.loads((corridor_run / "summary.json").read_text())
    grid = np.load(corridor_run / "coverage.npz")
    covered, target = grid["covered"], grid["target"]
    assert covered.shape == target.shape == (100, 100) and covered.dtype == bool
    assert not (covered & ~target).any()
    assert summary["coverage"] > 0
    assert covered.sum() / target.sum() == pytest.approx(summary["coverage"], abs=1e-6)
    # and from the geometry: cell centres within r of a robot's final position
    rows, cols = target.shape
    cx = float(grid["x0"]) + (np.arange(cols) + 0.5) * float(grid["dx"])
    cy = float(grid["y0"]) + (np.arange(rows) + 0.5) * float(grid["dy"])
    gx, gy = np.meshgrid(cx, cy)
    robots = np.array([[float(r["x"]), float(r["y"])] for r in rows_of(corridor_run /
                                                                         "robots.csv")])
    d = np.hypot(gx[..., None] - robots[:, 0], gy[..., None] - robots[:, 1]).min(axis=2)
    near = (d <= float(grid["r"])) & target
    assert np.count_nonzero(near != covered) <= 2  # positions rounded to 1e-4 in robots.csv


def test_settle_tick_is_when_a_robot_last_entered_a_settled_status():
    sim = Simulation("tiny", controller=GO_TO_LIGHT, max_ticks=400)
    tracks = Trajectories(sim, every=1)
    result = sim.run(on_tick=tracks.on_tick)
    data = tracks.arrays()
    arrived = list(data["status_names"]).index("Arrived")
    settled_rows = [r for r in result.robots if r["status"] == "Arrived"]
    assert len(settled_rows) > 10
    for row in result.robots:
        column = data["statuses"][:, row["robot"]]
        hits = np.flatnonzero(column == arrived)
        if row["status"] == "Arrived":
            entered = hits[np.concatenate(([True], np.diff(hits) > 1))]
            assert row["settle_tick"] == int(data["ticks"][entered[-1]])
            assert row["settle_tick"] > 0
        elif not len(hits):
            assert row["settle_tick"] == ""


def test_robot_columns_follow_the_message_fields_a_controller_has():
    messages = np.zeros(3, dtype=[("id", "i4"), ("status", "i1"), ("hops", "i4")])
    messages["status"] = [0, 1, -1]
    state = FinalState(np.array([[0.0, 1.0], [2.0, 3.0], [4.0, 5.0]]), messages,
                       ("Idle", "Done"), np.array([False, False, True]),
                       ("group", "gradient"), {"gradient": INF_GRADIENT})
    cols = state.columns()
    assert [c["status"] for c in cols] == ["Idle", "Done", "Failed"]
    assert all("group" not in c and "gradient" not in c for c in cols)
    with_grad = np.zeros(2, dtype=[("gradient", "i4"), ("group", "i2")])
    with_grad["gradient"] = [3, INF_GRADIENT]
    cols = FinalState(np.zeros((2, 2)), with_grad, (), np.zeros(2, bool),
                      ("group", "gradient"), {"gradient": INF_GRADIENT}).columns()
    assert [c["gradient"] for c in cols] == [3, ""] and "status" not in cols[0]


@pytest.mark.slow
def test_moving_counts_robots_that_travel_in_formation(tmp_path):
    """GGC's formations travel without broadcasting ``moving`` (the flag means a robot walks
    on its own): the column counts robots whose position changed."""
    out = tmp_path / "k"
    assert main(["run", "K", "--max-ticks", "120", "--out", str(out), "--quiet"]) == 0
    rows = [r for r in rows_of(out / "timeseries.csv") if 10 <= int(r["tick"]) <= 100]
    assert len(rows) == 10
    assert all(int(r["moving"]) > 500 for r in rows)
    assert "broadcast_moving" in rows[0]  # GGC's messages have the flag: its count is kept


@pytest.mark.parametrize("value", ["0", "-2", "2.5", "x"])
def test_a_bad_trajectories_interval_is_one_line(tmp_path, capsys, value):
    out = tmp_path / "out"
    assert main(["run", "tiny", "--max-ticks", "5", "--out", str(out), "--quiet",
                 f"--trajectories={value}"]) == 2
    err = capsys.readouterr().err.strip()
    assert err.count("\n") == 0 and "--trajectories" in err and value in err
    assert not out.exists()


def test_trajectories_need_out(capsys):
    assert main(["run", "tiny", "--max-ticks", "5", "--quiet", "--trajectories", "3"]) == 2
    assert "needs --out" in capsys.readouterr().err


def test_trajectories_api_refuses_a_bad_interval():
    sim = Simulation("tiny", controller="dispersion", max_ticks=5)
    with pytest.raises(ConfigError, match="trajectories_every"):
        Trajectories(sim, every=0)


def test_failed_robots_read_failed_and_stop_adding_distance():
    sim = Simulation("tiny", controller="dispersion", max_ticks=60,
                     settings={"failures": 3, "failure_phase": "tick", "failure_tick": 5})
    tracks = Trajectories(sim, every=5)
    result = sim.run(on_tick=tracks.on_tick)
    failed = [r for r in result.robots if r["status"] == "Failed"]
    assert len(failed) == result.summary["failed_robots"] == 3
    data = tracks.arrays()
    stopped = list(data["ticks"]).index(10)  # failed at the end of tick 5, braking in tick 6
    for row in failed:
        path = data["positions"][stopped:, row["robot"]]
        assert np.allclose(path, path[0], atol=1e-4)  # a failed robot stays put (no pushes here)
        assert row["distance"] > 0
        assert (row["x"], row["y"]) == pytest.approx(tuple(path[-1]), abs=1e-3)


@pytest.mark.slow
def test_robots_csv_agrees_with_the_distance_ledger_of_the_examples():
    """examples/where_distance_goes.py keeps its own per-robot distance and settle tick (first
    entry; GGC's settled statuses are for good, so the same as the last)."""
    from examples.where_distance_goes import Ledger

    sim = Simulation("tiny", seed=2, max_ticks=1500)
    ledger = Ledger(sim, late_from=0)
    result = sim.run(on_tick=ledger)
    distance = np.array([r["distance"] for r in result.robots])
    assert np.allclose(distance, ledger.distance, atol=1e-3)
    settle = np.array([-1 if r["settle_tick"] == "" else r["settle_tick"]
                       for r in result.robots])
    assert (settle >= 0).sum() > 10
    assert settle.tolist() == ledger.settled_at.tolist()
