"""What deciding a chunk at a time (``batch_decide``, GGC's fastpath.py) saves, side by side.

Two copies of one run (same world, seed, settings) are advanced to --start; then they take
turns, --block ticks each, one with ``batch_decide`` on and one with it off, until each has
done --ticks. Taking turns exposes both to the same machine noise. Prints milliseconds per
tick for each (the median block) and the ratio, and checks that both copies still hold the
same positions and broadcasts (they must: the setting changes nothing but the time).

    python bench/bench_decide.py                          # K, seed 0, ticks 6,000-7,000
    python bench/bench_decide.py --world house --start 4000 --ticks 600
"""

from __future__ import annotations

import argparse
import statistics
import time

import numpy as np

from swarmsim import Simulation
from swarmsim.sim import PHASES


def main() -> None:
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--world", default="K", help="world name or TOML path (default K)")
    ap.add_argument("--seed", type=int, default=0)
    ap.add_argument("--groups", type=int, default=None, help="default: the world's")
    ap.add_argument("--start", type=int, default=6000, help="ticks before timing (6000)")
    ap.add_argument("--ticks", type=int, default=1000, help="ticks timed per copy (1000)")
    ap.add_argument("--block", type=int, default=100, help="ticks per turn (100)")
    args = ap.parse_args()
    if min(args.start, args.ticks, args.block) < 0 or args.block == 0:
        ap.error("--start and --ticks must be >= 0, --block > 0")
    sims = {on: Simulation(args.world, controller="ggc", seed=args.seed, groups=args.groups,
                           settings={"batch_decide": on, "stop_on_complete": False})
            for on in (True, False)}
    for sim in sims.values():
        for _ in range(args.start):
            sim.step()
    blocks: dict[bool, list[float]] = {True: [], False: []}
    phases = {on: dict.fromkeys(PHASES, 0.0) for on in sims}
    done = 0
    while done < args.ticks:
        n = min(args.block, args.ticks - done)
        for on, sim in sims.items():
            before = dict(sim.phase_seconds)
            began = time.perf_counter()
            for _ in range(n):
                sim.step()
            blocks[on].append((time.perf_counter() - began) * 1000 / n)
            for phase in PHASES:
                phases[on][phase] += (sim.phase_seconds[phase] - before[phase]) * 1000
        done += n
    same = (np.array_equal(sims[True].positions, sims[False].positions)
            and sims[True].messages.tobytes() == sims[False].messages.tobytes())
    print(f"{args.world} seed {args.seed}, ticks {args.start}-{args.start + args.ticks}, "
          f"awake now {int((~sims[True].asleep).sum())}")
    for on in (False, True):
        split = ", ".join(f"{p} {phases[on][p] / args.ticks:.2f}" for p in PHASES)
        print(f"  batch_decide={str(on).lower():5}  {statistics.median(blocks[on]):6.2f} ms/tick"
              f"  ({split})")
    ratio = statistics.median(blocks[False]) / statistics.median(blocks[True])
    print(f"  off / on: {ratio:.2f}x   same state: {same}")
    if not same:
        raise SystemExit("the two copies differ: batch_decide changed the run")


if __name__ == "__main__":
    main()
