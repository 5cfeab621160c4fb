"""GGC is deterministic per seed: the same run in two processes writes the same summary and
time series (the robots' random streams live in their state rows, seeded from the run seed)."""

import csv
import json
import os
import subprocess
import sys
from pathlib import Path

import pytest

from swarmsim.engine.sim import TIMING_FIELDS


def run_in_process(out: Path, *args: str) -> tuple[dict, list[dict]]:
    env = {**os.environ, "SDL_VIDEODRIVER": "dummy", "MPLBACKEND": "Agg"}
    subprocess.run([sys.executable, "-m", "swarmsim", "run", "tiny", "--quiet", "--out",
                    str(out), *args], check=True, env=env, capture_output=True)
    summary = json.loads((out / "summary.json").read_text())
    for key in TIMING_FIELDS:
        summary.pop(key)
    with open(out / "timeseries.csv", newline="") as f:
        rows = [{k: v for k, v in row.items() if "second" not in k} for row in csv.DictReader(f)]
    return summary, rows


@pytest.mark.slow
def test_same_seed_same_run_in_two_processes(tmp_path):
    args = ("--controller", "ggc", "--groups", "3", "--seed", "3", "--max-ticks", "1500",
            "--set", "start=random")
    a = run_in_process(tmp_path / "a", *args)
    b = run_in_process(tmp_path / "b", *args)
    assert a == b
    summary, rows = a
    assert len(rows) > 10 and summary["ticks"] == 1500
    assert summary["status_counts"].get("Formed", 0) < summary["robots"]  # groups set out
    other = run_in_process(tmp_path / "c", "--groups", "3", "--seed", "4", "--max-ticks",
                           "1500", "--set", "start=random")
    assert other[1] != rows  # and the seed does decide the run
