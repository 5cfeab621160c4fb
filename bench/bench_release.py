"""How fast GGC's formations release robots, and how fast robots reach the target.

Steps one GGC run and counts, tick by tick, the robots whose status changes from Detection to
Coverage (a robot leaving its formation), and samples the robots on the target every 1,000
ticks. Prints one line per run: departures per 1,000 ticks over the first --window ticks,
robots on target per 1,000 ticks (from the first sample after the first departure to the
last sample), the tick by which 90 % of all departures had happened, the completion tick (or
the coverage at --max-ticks), contacts and distance per placed robot.

    python bench/bench_release.py K --groups 3 --seeds 0 1 2 3 4 --ruleset yield-holes-trains
    python bench/bench_release.py house --groups 6 --seeds 0 --max-ticks 6000

One run at a time; the figures (not the wall time) are what it measures.
"""

from __future__ import annotations

import argparse
import math
import statistics

import numpy as np

from controllers.ggc.statuses import COVERAGE, DETECTION
from swarmsim import Simulation

SAMPLE = 1000
"""Ticks between samples of the robots on the target."""


def measure(world: str, groups: int, seed: int, ruleset: str, max_ticks: int,
            window: int) -> dict[str, float]:
    """One run's release and delivery figures (see the module docstring)."""
    sim = Simulation(world, controller="ggc", groups=groups, seed=seed, max_ticks=max_ticks,
                     settings={"ruleset": ruleset})
    status = sim.swarm.state["status"].copy()
    departures: list[int] = []
    on_target: list[tuple[int, int]] = []

    def on_tick(s: Simulation) -> None:
        now = s.swarm.state["status"]
        left = int(np.count_nonzero((status == DETECTION) & (now == COVERAGE)))
        departures.extend([s.tick] * left)
        status[:] = now
        if s.tick % SAMPLE == 0:
            on_target.append((s.tick, int(s.floor.on_target(s.positions).sum())))

    result = sim.run(on_tick=on_tick)
    summary = result.summary
    early = sum(1 for t in departures if t <= window)
    first = departures[0] if departures else 0
    samples = [(t, n) for t, n in on_target if t >= first + SAMPLE] or on_target[-1:]
    t0, n0 = samples[0]
    t1, n1 = on_target[-1] if on_target else (t0, n0)
    delivery = 1000 * (n1 - n0) / (t1 - t0) if t1 > t0 else float("nan")
    ninety = departures[int(0.9 * (len(departures) - 1))] if departures else 0
    return {"seed": seed, "release": 1000 * early / window, "delivery": delivery,
            "departures": len(departures), "ninety": ninety,
            "completion": summary.get("completion_tick") or float("nan"),
            "coverage": summary["coverage"], "contacts": summary.get("collisions_robot_robot", float("nan")),
            "per_placed": summary.get("distance_per_placed_robot") or float("nan")}


def main() -> None:
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("world")
    ap.add_argument("--groups", type=int, default=3)
    ap.add_argument("--seeds", type=int, nargs="+", default=[0])
    ap.add_argument("--ruleset", default="yield-holes")
    ap.add_argument("--max-ticks", type=int, default=12000)
    ap.add_argument("--window", type=int, default=4000)
    args = ap.parse_args()
    rows = []
    for seed in args.seeds:
        row = measure(args.world, args.groups, seed, args.ruleset, args.max_ticks, args.window)
        rows.append(row)
        print(" ".join(f"{k}={v:.4g}" if isinstance(v, float) else f"{k}={v}"
                       for k, v in row.items()), flush=True)
    for key in ("release", "delivery", "ninety", "completion", "coverage", "per_placed"):
        values = [r[key] for r in rows]
        if key == "completion":  # a run that did not complete ranks after every one that did
            values = [math.inf if math.isnan(v) else v for v in values]
        print(f"{key}: median {statistics.median(values):.4g} "
              f"min {min(values):.4g} max {max(values):.4g}")


if __name__ == "__main__":
    main()
