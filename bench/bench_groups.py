"""What a run's groups cost: GGC's first ticks and memory by number of groups and start.

For each start and group count, in a process of its own (one after the other, so that each
peak memory is its own): builds the run, steps --ticks ticks and prints the build time, CPU
ms per tick, GGC's state rows and per-group arrays (MB), one broadcast row (bytes) and the
process's peak resident memory. A scattered start's first ticks are its costliest in groups
(leader selection: every robot updates a distance field per group from every neighbour).

    swarmsim make-world --text K --size 640 --robots 10000 --groups 16 --out k10k.toml
    python bench/bench_groups.py k10k.toml --groups 16 64 256 --starts formation random

Figures vary with the machine's load (+-30 %): compare rows of one call.
"""

from __future__ import annotations

import argparse
import resource
import subprocess
import sys
import time


def one(world: str, groups: int, start: str, ticks: int) -> str:
    """One run's row (this process: its peak memory is the run's)."""
    from swarmsim import Simulation

    began = time.perf_counter()
    sim = Simulation(world, groups=groups, seed=0, settings={"start": start})
    built = time.perf_counter() - began
    cpu = time.process_time()
    for _ in range(ticks):
        sim.step()
    ms = 1000 * (time.process_time() - cpu) / ticks
    swarm = sim.swarm
    per_group = sum(a.nbytes for a in getattr(swarm, "per_group", ()))
    peak = resource.getrusage(resource.RUSAGE_SELF).ru_maxrss / 1024
    return (f"{start:>9} {groups:>6} {built:7.1f} {ms:8.0f} {swarm.state.nbytes / 1e6:8.1f} "
            f"{per_group / 1e6:9.1f} {sim.messages.dtype.itemsize:8d} {peak:8.0f}")


def main() -> None:
    ap = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    ap.add_argument("world", help="world file or shipped name")
    ap.add_argument("--groups", type=int, nargs="+", default=[16, 64])
    ap.add_argument("--starts", nargs="+", default=["formation", "random"])
    ap.add_argument("--ticks", type=int, default=10, help="ticks timed per run")
    ap.add_argument("--one", action="store_true", help=argparse.SUPPRESS)
    args = ap.parse_args()
    if args.one:
        print(one(args.world, args.groups[0], args.starts[0], args.ticks), flush=True)
        return
    print("    start groups build_s ms/tick state_MB groups_MB msg_B peak_MB")
    for start in args.starts:
        for groups in args.groups:
            subprocess.run([sys.executable, __file__, args.world, "--one", "--groups",
                            str(groups), "--starts", start, "--ticks", str(args.ticks)],
                           check=True)


if __name__ == "__main__":
    main()
