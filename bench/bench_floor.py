"""A whole run's tick against pymunk's bare step of the same robots, all awake (issue 72).

For each seed, one whole run of the world (GGC by default). Every --every ticks the run is
paused and a bare copy is timed: a fresh Physics of the same world with the robots at the
run's positions, all dynamic and awake (pymunk sleeping off, nothing parked), each commanded
with the velocity the run gave it that tick, stepped --bare-ticks ticks (substeps each) by
pymunk alone. The run's own ticks are timed without those pauses.

Prints per seed: ticks, the run's whole tick (wall ms per tick, every phase and all the glue),
the bare step (ms per tick, mean over the copies), their ratio and the run's phases; then
the median and range of the ratio over the seeds. The two are measured in one process, turn
about, so the machine's load meets both.

    python bench/bench_floor.py                              # K, seeds 0-9
    python bench/bench_floor.py --world house --seeds 0-2 --every 500
    python bench/bench_floor.py --controller cvt --seeds 1

Holonomic robots only (a steering drive's bare step needs its motion commands). These
machines are noisy (+-30 %): quote the ratio, measured with nothing else running.
"""

from __future__ import annotations

import argparse
import statistics
import time
from dataclasses import replace

import numpy as np

from swarmsim import Simulation
from swarmsim.engine.sim import PHASES
from swarmsim.errors import ConfigError
from swarmsim.physics.physics import Physics


def bare_step_ms(sim: Simulation, ticks: int) -> float:
    """ms per tick of pymunk stepping the run's robots, as they stand now, all awake."""
    config = replace(sim.physics_config, physics_sleep=False)
    bare = Physics(sim.world, np.array(sim.positions), config)
    bare.read()  # (command() writes over the velocities read)
    bare.command(np.array(sim.velocities))
    dt, substeps, space = 1.0 / config.substeps, config.substeps, bare.space
    start = time.perf_counter()
    for _ in range(ticks * substeps):
        space.step(dt)
    return (time.perf_counter() - start) / ticks * 1e3


def measure(world: str, controller: str, seed: int, every: int, bare_ticks: int,
            max_ticks: int | None) -> dict:
    """One run: its tick and phases (ms per tick) and the bare step, ms per tick."""
    sim = Simulation(world, controller=controller, seed=seed, max_ticks=max_ticks)
    if sim.physics_config.drive != "holonomic":
        raise SystemExit(f"bench_floor: holonomic robots only, this run's drive is "
                         f"{sim.physics_config.drive!r}")
    run_s, bare = 0.0, []
    while sim.finished() is None:
        start = time.perf_counter()
        for _ in range(every):
            sim.step()
            if sim.finished() is not None:
                break
        run_s += time.perf_counter() - start
        bare.append(bare_step_ms(sim, bare_ticks))
    out = {k: sim.phase_seconds[k] / sim.tick * 1e3 for k in PHASES}
    out.update(ticks=sim.tick, tick=run_s / sim.tick * 1e3, bare=statistics.fmean(bare),
               robots=sim.n, end=sim.finished())
    return out


def seeds_of(text: str) -> list[int]:
    """'0-9' or '1,3,5' -> seeds."""
    if "-" in text:
        lo, hi = text.split("-")
        return list(range(int(lo), int(hi) + 1))
    return [int(s) for s in text.split(",")]


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--world", default="K")
    parser.add_argument("--controller", default="ggc")
    parser.add_argument("--seeds", type=seeds_of, default=list(range(10)),
                        help="'0-9' (default) or '1,3'")
    parser.add_argument("--every", type=int, default=1000,
                        help="ticks of the run between bare copies")
    parser.add_argument("--bare-ticks", type=int, default=50, dest="bare_ticks",
                        help="ticks each bare copy is stepped")
    parser.add_argument("--max-ticks", type=int, dest="max_ticks")
    args = parser.parse_args()
    print(f"{args.world}, {args.controller}: ms per tick; bare = pymunk's step of the same "
          "robots, all awake")
    print(f"{'seed':>4}{'ticks':>8}{'tick':>8}{'bare':>8}{'ratio':>7}"
          + "".join(f"{p:>9}" for p in PHASES))
    ratios = []
    for seed in args.seeds:
        try:
            r = measure(args.world, args.controller, seed, args.every, args.bare_ticks,
                        args.max_ticks)
        except ConfigError as bad:  # a world, controller, seed or limit the run refuses
            parser.error(str(bad))
        ratios.append(r["tick"] / r["bare"])
        print(f"{seed:>4}{r['ticks']:>8}{r['tick']:>8.3f}{r['bare']:>8.3f}{ratios[-1]:>7.2f}"
              + "".join(f"{r[p]:>9.3f}" for p in PHASES), flush=True)
    print(f"ratio tick / bare: median {statistics.median(ratios):.2f}, "
          f"range {min(ratios):.2f}-{max(ratios):.2f} over {len(ratios)} seeds")


if __name__ == "__main__":
    main()
