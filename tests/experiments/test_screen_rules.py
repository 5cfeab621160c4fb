"""bench/screen_rules.py: the screening protocol's table agrees with the runs' summaries."""

from __future__ import annotations

import importlib.util
import json
import re
import statistics
from pathlib import Path

import pytest

from swarmsim import Simulation

SCRIPT = Path(__file__).resolve().parents[2] / "bench" / "screen_rules.py"
ROW = re.compile(r"^  (\S+)\s+(\d+)/(\d+)\s+(\d+)\s+([\d.]+)\s+(\S+)(?: \[(\S+)\])?\s+(\S+)"
                 r"\s+(\S+)\s+(\S+)  (.*)$")


def _screen():
    spec = importlib.util.spec_from_file_location("screen_rules", SCRIPT)
    module = importlib.util.module_from_spec(spec)
    spec.loader.exec_module(module)
    return module


def test_seeds_settings_and_rates_are_read_as_documented() -> None:
    screen = _screen()
    assert screen.seed_list("0-4") == [0, 1, 2, 3, 4]
    assert screen.seed_list("0,3-4,9") == [0, 3, 4, 9]
    assert screen.setting("mode=ghost") == ("mode", "ghost")
    assert screen.setting("v_max=0.2") == ("v_max", 0.2)
    # 2 robots of 40 on target at 250 (below 10 %), 4 at 500: the phase runs 500 -> 2,500
    trace = [[0, 0, 0.0], [250, 2, 0.1], [500, 4, 0.2], [2500, 40, 0.99]]
    assert screen.delivery_rate(trace) == pytest.approx(1000 * 36 / 2000)
    base = {0: {"summary": {"completion_tick": 1000, "coverage": 0.99}},
            1: {"summary": {"completion_tick": 900, "coverage": 0.99}},
            2: {"summary": {"completion_tick": None, "coverage": 0.95}}}
    other = {0: {"summary": {"completion_tick": 800, "coverage": 0.99}},
             1: {"summary": {"completion_tick": 1000, "coverage": 0.99}},
             2: {"summary": {"completion_tick": 700, "coverage": 0.99}}}
    assert screen.paired(base, other) == ("ticks -50 [-200..+100] (-4.4 %), faster on 1/2; "
                                          "coverage +0.0000 [+0.0000..+0.0400]")
    del other[2]["summary"]["completion_tick"], other[0], other[1]
    other[2]["summary"]["completion_tick"] = None
    assert screen.paired(base, other) == "coverage +0.0400 [+0.0400..+0.0400]"


def _rows(text: str) -> dict[str, re.Match]:
    return {m[1]: m for m in map(ROW.match, text.splitlines()) if m and m[1] != "ruleset"}


@pytest.mark.slow
def test_the_table_agrees_with_the_runs_and_a_screen_resumes(tmp_path: Path, capsys) -> None:
    """Two rule sets on a tiny world, 2 groups, seeds 0-1, 2,200 ticks (a sweep of four
    processes): each figure of the table is the one the kept summaries give, a kept run is
    the run the public API makes, and a second screen reads the kept runs and prints the
    same table."""
    screen = _screen()
    out = tmp_path / "screen"
    argv = ["--rulesets", "yield-holes", "paper", "--worlds", "tiny", "--groups", "2",
            "--seeds", "0-1", "--max-ticks", "2200", "--out", str(out)]
    assert screen.main(argv) == 0
    printed = capsys.readouterr().out
    kept = [json.loads(p.read_text()) for p in sorted(out.glob("*.json"))]
    assert len(kept) == 4
    floors = {r["summary"]["travel_floor_ticks"] for r in kept}
    assert floors == {390.0} and "travel floor 390 ticks" in printed
    rows = _rows(printed)
    assert list(rows) == ["yield-holes", "paper"]
    for name, row in rows.items():
        runs = {r["job"]["seed"]: r for r in kept if r["job"]["ruleset"] == name}
        summaries = [r["summary"] for r in runs.values()]
        done = [s["completion_tick"] for s in summaries if s["completion_tick"] is not None]
        assert (int(row[2]), int(row[3])) == (len(done), 2)
        assert int(row[4]) == sum(s["stop_reason"] == "aborted" for s in summaries)
        assert float(row[5]) == pytest.approx(statistics.median(s["coverage"] for s in
                                                                  summaries), abs=5e-5)
        assert done, "the world should complete in 2,200 ticks on a seed"
        assert float(row[6].replace(",", "")) == pytest.approx(statistics.median(done), abs=0.5)
        ratios = [s["floor_ratio"] for s in summaries if s["floor_ratio"] is not None]
        assert float(row[8]) == pytest.approx(statistics.median(ratios), abs=0.006)
        rates = [screen.delivery_rate(r["trace"]) for r in runs.values()]
        assert float(row[9]) == pytest.approx(statistics.median(rates), abs=0.05)
        per_placed = statistics.median(s["distance_per_placed_robot"] for s in summaries)
        assert float(row[10]) == pytest.approx(per_placed, abs=0.05)
        assert all(r["trace"][-1][0] == r["summary"]["ticks"] for r in runs.values())
    base = {r["job"]["seed"]: r for r in kept if r["job"]["ruleset"] == "yield-holes"}
    other = {r["job"]["seed"]: r for r in kept if r["job"]["ruleset"] == "paper"}
    assert rows["paper"][11] == screen.paired(base, other)

    direct = Simulation("tiny", controller="ggc", groups=2, seed=1, max_ticks=2200,
                        settings={"ruleset": "paper"}).run().summary
    for key in ("ticks", "coverage", "completion_tick", "total_distance", "robots_placed"):
        assert direct[key] == other[1]["summary"][key], key

    stamps = {p: p.stat().st_mtime_ns for p in out.glob("*.json")}
    assert screen.main(argv) == 0
    assert capsys.readouterr().out == printed
    assert {p: p.stat().st_mtime_ns for p in out.glob("*.json")} == stamps


def test_a_bad_rule_set_is_refused_in_one_line(tmp_path: Path, capsys) -> None:
    screen = _screen()
    argv = ["--rulesets", "no-such-rules", "--worlds", "tiny", "--groups", "1", "--seeds", "0",
            "--max-ticks", "10", "--out", str(tmp_path / "screen")]
    assert screen.main(argv) == 2
    err = capsys.readouterr().err.strip().splitlines()
    assert len(err) == 1 and err[0].startswith("screen_rules: error: ")
    assert "no-such-rules" in err[0] and "ruleset" in err[0]
    assert not list((tmp_path / "screen").glob("*"))


def test_a_missing_world_is_refused_in_one_line_before_any_run(tmp_path: Path, capsys) -> None:
    screen = _screen()
    argv = ["--rulesets", "paper", "--worlds", str(tmp_path / "nowhere.toml"), "--out",
            str(tmp_path / "screen")]
    assert screen.main(argv) == 2
    err = capsys.readouterr().err.strip().splitlines()
    assert len(err) == 1 and err[0].startswith("screen_rules: error: ")
    assert "nowhere.toml" in err[0]
    assert not (tmp_path / "screen").exists()


def test_the_abort_rule_stops_a_run_whose_robots_on_target_rise_too_little(tmp_path: Path,
                                                                          capsys) -> None:
    """Asking for 1,000 more robots on target every 250 ticks aborts at tick 250; under a
    coverage guard of 0 it never applies and the run goes to its horizon."""
    screen = _screen()
    base = ["--rulesets", "yield-holes", "--worlds", "tiny", "--groups", "1", "--seeds", "0",
            "--max-ticks", "500", "--abort-rise", "1000", "--abort-window", "250"]
    assert screen.main([*base, "--abort-below", "1", "--out", str(tmp_path / "a")]) == 0
    assert screen.main([*base, "--abort-below", "0", "--out", str(tmp_path / "b")]) == 0
    cut, = (json.loads(p.read_text())["summary"] for p in (tmp_path / "a").glob("*.json"))
    whole, = (json.loads(p.read_text())["summary"] for p in (tmp_path / "b").glob("*.json"))
    assert (cut["stop_reason"], cut["ticks"]) == ("aborted", 250)
    assert (whole["stop_reason"], whole["ticks"]) == ("max_ticks", 500)
    assert _rows(capsys.readouterr().out)["yield-holes"][4] == "0"
