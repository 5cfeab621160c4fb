"""One whole run, block by block: what a tick costs in each phase, and who is awake.

For every --block ticks of one run (world, seed, run settings) prints ms per tick of the
whole tick and of each phase (sense, decide, physics, metrics), the robots the engine decided
that block's last tick, the bodies pymunk has asleep, and the parked robots (zero command)
that pymunk keeps awake, with how many of those touch another robot (centres within the
robots' diameter + 0.005 units). Chipmunk puts touching bodies to sleep only all together, so
parked robots in a touching pack with a mover stay in its solver.

    python bench/bench_run_phases.py                          # K-large seed 1, blocks of 2,000
    python bench/bench_run_phases.py --world house --seed 0 --block 1000

Figures vary with the machine's load (+-30 %): compare phases within one run.
"""

from __future__ import annotations

import argparse
import time

import numpy as np
from scipy.spatial import cKDTree

from swarmsim import Simulation
from swarmsim.engine.config import parse_value


def awake_parked(sim: Simulation) -> tuple[int, int, int]:
    """(bodies asleep in pymunk, parked robots awake in it, those of them touching another)."""
    asleep = sim.physics.bodies_asleep()
    held = np.flatnonzero(sim.physics.parked & ~asleep)
    if len(held) == 0:
        return int(np.count_nonzero(asleep)), 0, 0
    reach = 2 * sim.physics_config.radius + 0.005
    nearest, _ = cKDTree(sim.positions).query(sim.positions[held], k=2)
    return int(np.count_nonzero(asleep)), len(held), int(np.count_nonzero(nearest[:, 1] < reach))


def main() -> None:
    ap = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    ap.add_argument("--world", default="K-large")
    ap.add_argument("--seed", type=int, default=1)
    ap.add_argument("--block", type=int, default=2000, help="ticks per printed line")
    ap.add_argument("--settings", nargs="*", default=[], help="key=value run settings")
    args = ap.parse_args()
    settings = {k: parse_value(v) for k, v in (kv.split("=", 1) for kv in args.settings)}
    sim = Simulation(args.world, seed=args.seed, settings=settings or None)
    last = {"t": time.perf_counter(), "tick": 0, "phases": dict(sim.phase_seconds)}
    print("ticks | ms/tick: whole sense decide physics metrics | decided | asleep in pymunk"
          " | parked but awake (touching)")

    def report(s: Simulation) -> None:
        """Print the block that ends at this tick."""
        now, n = time.perf_counter(), s.tick - last["tick"]
        ms = [1000 * (s.phase_seconds[k] - last["phases"].get(k, 0.0)) / n
              for k in ("sense", "decide", "physics", "metrics")]
        asleep, held, touching = awake_parked(s)
        print(f"{last['tick']:>6}-{s.tick:<6} | {1000 * (now - last['t']) / n:6.2f} "
              + " ".join(f"{m:6.2f}" for m in ms)
              + f" | {int(np.count_nonzero(~s.asleep)):5d} | {asleep:5d} | {held} ({touching})",
              flush=True)
        last.update(t=time.perf_counter(), tick=s.tick, phases=dict(s.phase_seconds))

    began = time.perf_counter()
    result = sim.run(on_tick=lambda s: None if s.tick % args.block else report(s))
    if sim.tick > last["tick"]:  # the last, shorter block
        report(sim)
    print(f"{result.summary['ticks']} ticks, {result.summary['stop_reason']}, "
          f"{time.perf_counter() - began:.1f} s")

if __name__ == "__main__":
    main()
