"""The benches the issues' figures come from still run: bench_floor.py (a run's tick against
pymunk's bare step), bench_tick.py (the phases of a tick), bench_groups.py (a run's cost by
groups), bench_scale_runs.py (a made world's run cost by size) and bench_glue.py (compiled
code against Python in a tick), on a tiny world."""

from __future__ import annotations

import importlib.util
import math
import sys
from pathlib import Path

import pytest

BENCH = Path(__file__).resolve().parents[2] / "bench"


def load(name: str):
    sys.path.insert(0, str(BENCH))  # the benches import one another
    try:
        spec = importlib.util.spec_from_file_location(name, BENCH / f"{name}.py")
        module = importlib.util.module_from_spec(spec)
        spec.loader.exec_module(module)
        return module
    finally:
        sys.path.remove(str(BENCH))


def test_bench_floor_times_a_run_and_its_bare_step():
    floor = load("bench_floor")
    r = floor.measure("tiny", "ggc", seed=0, every=20, bare_ticks=2, max_ticks=60)
    assert r["ticks"] == 60 and r["robots"] > 0
    assert r["tick"] > 0 and r["bare"] > 0
    assert r["tick"] >= r["physics"]  # the whole tick holds its physics phase
    assert floor.seeds_of("0-2") == [0, 1, 2] and floor.seeds_of("1,4") == [1, 4]


def test_bench_tick_measures_every_phase():
    tick = load("bench_tick")
    r = tick.measure(40, "ggc", warmup=2, ticks=3, repeats=1)
    assert {"sense", "decide", "physics", "metrics", "tick", "bare_step"} <= set(r)
    assert r["tick"] > 0 and r["bare_step"] > 0 and r["awake"] > 0


def test_bench_groups_prints_a_row_per_start_and_group_count():
    groups = load("bench_groups")
    row = groups.one("tiny", 3, "random", ticks=2).split()
    assert row[:2] == ["random", "3"] and len(row) == 8
    build, ms, _state_mb, _groups_mb, message_bytes, peak = map(float, row[2:])
    assert build >= 0 and ms >= 0 and peak > 0  # times print rounded: a tiny run may be 0
    assert message_bytes == 44 + 3 * 8  # the scattered start's per-group values, 8 bytes each
    assert groups.one("tiny", 3, "formation", ticks=2).split()[6] == "44"


def test_bench_tick_compares_whole_runs_of_a_world():
    tick = load("bench_tick")
    r = tick.measure_runs("tiny", "dispersion", seeds=[0, 1], max_ticks=30)
    assert r["ticks"] == 60 and r["tick"] > 0 and r["cpu"] > 0
    assert r["tick"] >= r["decide"]
    assert 0 < r["decided"] <= 60 and r["per_robot"] > 0  # robots decided a tick, CPU each


def test_bench_scale_runs_makes_the_same_shape_at_each_size_and_runs_it():
    runs = load("bench_scale_runs")
    assert runs.world_shape(10_000) == (640.0, 16)  # the 10k world
    assert runs.world_shape(2_500) == (320.0, 4) and runs.world_shape(60)[1] == 1
    small, large = runs.make_world("K", 60), runs.make_world("K", 240)
    assert small.defaults["robots"] == 60 and large.defaults["robots"] == 240
    assert large.target_area / 240 == pytest.approx(small.target_area / 60, rel=0.01)

    rows = list(runs.measure_sizes("K", [120, 60], ticks=20, seed=0, in_process=True))
    assert [r["robots"] for r in rows] == [60, 120] and [r["groups"] for r in rows] == [1, 1]
    for r in rows:
        assert r["ticks"] == 20 and r["stop"] == "max_ticks"
        assert r["cpu"] > 0 and r["physics"] > 0 and 0 < r["awake"] <= r["robots"]
        assert 0 <= r["coverage"] <= 1 and r["peak_rss_mb"] > 0
        assert runs.format_row(r).split()[:5] == [str(r["robots"]), "1", f"{r['size']:.0f}",
                                                  "20", "max_ticks"]
    assert all(math.isfinite(slope) for slope in runs.slopes(rows))
    with pytest.raises(ValueError, match="two sizes"):
        runs.slopes(rows[:1])


def test_bench_scale_runs_runs_each_size_for_its_own_travel_floors():
    """--floors: a larger world's run is longer, in proportion to its travel floor."""
    from swarmsim.world.floor import travel_floor_ticks

    runs = load("bench_scale_runs")
    small, large = runs.make_world("K", 60), runs.make_world("K", 240)
    assert runs.run_length(small, 20, None) == 20
    short, long = runs.run_length(small, 20, 0.05), runs.run_length(large, 20, 0.05)
    assert short == math.ceil(0.05 * travel_floor_ticks(small, 0.1))
    assert long > short  # the farthest point of the larger K is farther


def test_bench_bare_scale_steps_pymunk_alone_each_way(capsys):
    bare = load("bench_bare_scale")
    ways = dict(bare.measure(60, warmup=5, ticks=2, repeats=1))
    assert set(ways) == set(bare.WAYS) and all(ms > 0 for ms in ways.values())
    bare.main(["--robots", "60", "--warmup", "3", "--ticks", "1", "--repeats", "1"])
    assert capsys.readouterr().out.splitlines()[1].startswith("     60: tree ")


def test_bench_glue_splits_a_tick_into_chipmunk_kernels_and_python():
    glue = load("bench_glue")
    import pymunk

    step = pymunk.Space.step
    r = glue.measure("tiny", "ggc", seed=0, max_ticks=40)
    assert r["ticks"] == 39 and r["wrapped"] > 10 and r["kernel_calls"] > 1
    assert r["chipmunk"] > 0 and r["kernels"] > 0 and r["python"] > 0
    assert r["chipmunk"] + r["kernels"] + r["python"] == pytest.approx(r["tick"])
    assert pymunk.Space.step is step  # the timers are taken off again
