"""Where a tick's time goes: sensing, deciding, physics and metrics, against a bare pymunk step.

For each swarm size it builds a square world sized like the paper's (hexagonal capacity at
d_cover = 6 is ~70 % of the robots), runs a controller for some warm-up ticks, then measures
ticks and prints milliseconds per tick per phase. Right after, in the same process, it times
pymunk's bare step (``Space.step``) of the very same bodies with the same drive commands: the ratio
full tick / bare step says how much the simulator adds on top of pymunk.

    python bench/bench_tick.py                       # 600, 2000, 5000 robots, both controllers
    python bench/bench_tick.py --robots 2000 --controller ggc --ticks 200

With --world, each controller instead makes whole runs of that world (seeds --seeds, to its
own end or --max-ticks) and the bench prints its mean tick, wall and CPU, by phase, and the
ratio of its CPU per tick to GGC's (issue 72: every shipped controller within 3x of GGC),
and the same per decided robot-tick (a controller whose robots never sleep decides more
robots a tick):

    python bench/bench_tick.py --world K --controller ggc cvt meanshift kilobot dash fcdfs \
        dispersion --seeds 1 2

Numbers are medians over --repeats blocks of ticks; these machines are noisy (+-30 %).
"""

from __future__ import annotations

import argparse
import math
import statistics
import time

from swarmsim import Simulation
from swarmsim.engine.sim import PHASES
from swarmsim.errors import ConfigError
from swarmsim.limits import MAX_TICKS
from swarmsim.world.world import World, world_from_dict


def square_world(robots: int) -> World:
    """A square target holding ~70 % of the robots at d_cover 6, spawn band below it.

    The band is deep enough for a random start at spacing ~2 and for one hexagonal formation
    of all the robots at spacing 1 (radius ~sqrt(0.866 n / pi) + 1), GGC's start.
    """
    side = math.sqrt(0.7 * robots * 0.866 * 36)
    formation_radius = math.sqrt(0.866 * robots / math.pi) + 1.0
    band = max(20.0, 2.2 * robots / side, 2 * formation_radius + 4.0)
    return world_from_dict({
        "name": f"square{robots}",
        "target": {"outline": [[0, 0], [side, 0], [side, side], [0, side]]},
        "spawn": [{"outline": [[0, -15 - band], [side, -15 - band], [side, -15], [0, -15]]}],
        "beacon": {"position": [side / 2, side / 2]},
    })


def measure(robots: int, controller: str, warmup: int, ticks: int, repeats: int) -> dict:
    sim = Simulation(square_world(robots), controller=controller, robots=robots, seed=1,
                     max_ticks=MAX_TICKS)
    for _ in range(warmup):
        sim.step()
    blocks = []
    for _ in range(repeats):
        before = dict(sim.phase_seconds)
        start = time.perf_counter()
        for _ in range(ticks):
            sim.step()
        wall = time.perf_counter() - start
        phases = {k: (sim.phase_seconds[k] - before[k]) / ticks * 1e3 for k in PHASES}
        phases["tick"] = wall / ticks * 1e3
        space, substeps = sim.physics.space, sim.physics.config.substeps
        bare_start = time.perf_counter()
        for _ in range(ticks * substeps):
            space.step(1.0 / substeps)  # the same bodies, the same drive commands
        phases["bare_step"] = (time.perf_counter() - bare_start) / ticks * 1e3
        blocks.append(phases)
    out = {k: statistics.median(b[k] for b in blocks) for k in blocks[0]}
    out["awake"] = sim.metrics.rows[-1]["awake"] if sim.metrics.rows else robots
    return out


def measure_runs(world: str, controller: str, seeds: list[int], max_ticks: int | None) -> dict:
    """Whole runs of ``world``: ms per tick (wall, CPU and each phase's wall), over all the
    runs' ticks together."""
    ticks, decided, wall, cpu, phases = 0, 0, 0.0, 0.0, dict.fromkeys(PHASES, 0.0)
    for seed in seeds:
        sim = Simulation(world, controller=controller, seed=seed, max_ticks=max_ticks)
        start, start_cpu = time.perf_counter(), time.process_time()
        while sim.finished() is None:
            sim.step()
        wall += time.perf_counter() - start
        cpu += time.process_time() - start_cpu
        ticks += sim.tick
        decided += sim.costs.decisions
        for k in PHASES:
            phases[k] += sim.phase_seconds[k]
    out = {k: v / ticks * 1e3 for k, v in phases.items()}
    out.update(ticks=ticks, tick=wall / ticks * 1e3, cpu=cpu / ticks * 1e3,
               decided=decided / ticks, per_robot=cpu / max(decided, 1) * 1e6)
    return out


def main_world(args: argparse.Namespace) -> None:
    """Whole runs of --world per controller, against GGC's CPU per tick."""
    controllers = ["ggc", *[c for c in args.controller if c != "ggc"]]
    print(f"{args.world}, seeds {args.seeds}: ms per tick over whole runs (wall by phase)")
    print(f"{'controller':<11}{'ticks':>8}" + "".join(f"{p:>9}" for p in PHASES)
          + f"{'tick':>9}{'cpu':>9}{'x ggc':>7}{'decided':>9}{'us/robot':>9}{'x ggc':>7}")
    print("(decided: robots decided a tick, on average; us/robot: CPU a decided robot-tick)")
    base = base_robot = None
    for controller in controllers:
        r = measure_runs(args.world, controller, args.seeds, args.max_ticks)
        base, base_robot = base or r["cpu"], base_robot or r["per_robot"]
        print(f"{controller:<11}{r['ticks']:>8}" + "".join(f"{r[p]:>9.2f}" for p in PHASES)
              + f"{r['tick']:>9.2f}{r['cpu']:>9.2f}{r['cpu'] / base:>7.1f}"
              + f"{r['decided']:>9.0f}{r['per_robot']:>9.2f}{r['per_robot'] / base_robot:>7.1f}",
              flush=True)


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--robots", type=int, nargs="+", default=[600, 2000, 5000])
    parser.add_argument("--controller", nargs="+", default=["ggc", "dispersion"])
    parser.add_argument("--warmup", type=int, default=600, help="ticks before measuring")
    parser.add_argument("--ticks", type=int, default=100, help="ticks per measured block")
    parser.add_argument("--repeats", type=int, default=3, help="measured blocks (median)")
    parser.add_argument("--world", help="whole runs of this world instead (GGC first)")
    parser.add_argument("--seeds", type=int, nargs="+", default=[1], help="with --world")
    parser.add_argument("--max-ticks", type=int, dest="max_ticks", help="with --world")
    args = parser.parse_args()
    try:
        if args.world:
            main_world(args)
        else:
            main_sizes(args)
    except ConfigError as bad:  # a world, controller, seed or limit the run refuses
        parser.error(str(bad))


def main_sizes(args: argparse.Namespace) -> None:
    """Square worlds of --robots per controller: phases against the bare step."""
    head = (f"{'controller':<11}{'robots':>7}{'awake':>7}" + "".join(f"{p:>9}" for p in PHASES)
            + f"{'tick':>9}{'bare':>9}{'ratio':>8}")
    print("ms per tick (median of blocks); bare = pymunk step of the same bodies")
    print(head)
    for controller in args.controller:
        for n in args.robots:
            r = measure(n, controller, args.warmup, args.ticks, args.repeats)
            cells = "".join(f"{r[p]:>9.2f}" for p in PHASES)
            print(f"{controller:<11}{n:>7}{r['awake']:>7}{cells}{r['tick']:>9.2f}"
                  f"{r['bare_step']:>9.2f}{r['tick'] / r['bare_step']:>8.1f}", flush=True)


if __name__ == "__main__":
    main()
