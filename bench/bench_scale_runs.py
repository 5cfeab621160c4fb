"""How a real GGC run's tick grows with the swarm: the same made world at several sizes.

Issue 72 asks that from 2,000 to 10,000 robots the time per tick of a real GGC run grow with a
log-log slope of at most 1.1. bench_scale.py measures a synthetic square world; this bench
measures runs of a world made the way ``swarmsim make-world --text TEXT --size S --robots N
--groups G`` makes it (the same library call: ``build_world(text_shape(TEXT), WorldSpec(...))``,
no file written), at every size the same shape:

- size S = 640 * sqrt(N / 10,000) units high: the target's area, and so its lattice capacity,
  grows with N, and capacity / robots is the same at every size (the issue's 10k world is
  ``make-world --text K --size 640 --robots 10000 --groups 16``);
- groups G = round(N / 625), at least 1 and at most MAX_GROUPS: a fixed 625 robots per group
  (the 10k world's 16 groups), so each formation is the same size at every N.

Each size runs in a fresh process (spawn; its peak resident memory is its own; --in-process
runs them all in this process, for tests): the world is built, then a ``Simulation(world,
seed=--seed)`` with the world's defaults runs ``Simulation.run`` for --ticks ticks or until it
ends. Per size it prints: robots, groups, target height, ticks run, how the run stopped, CPU ms
per tick (``time.process_time`` over the tick loop: the run's ``cpu_seconds``), each phase's
wall ms per tick (``Simulation.phase_seconds``), the mean robots awake (decided) per tick,
the coverage reached and the peak RSS in MB. Then the log-log slope of CPU ms per tick against
robots: between the smallest and the largest size, and the least-squares fit over all sizes.

    python bench/bench_scale_runs.py                        # K: 2000 4000 6000 10000, 2000 ticks
    python bench/bench_scale_runs.py --text GGC --robots 600 1200 --ticks 200

The same number of ticks is a different stage of the run at each size: the target is larger
and farther, so at tick T a larger swarm has spread less of its way. ``--floors F`` runs each
size for F times its own travel floor instead (the ticks a robot at v_max needs from the spawn
band to the farthest target point; it grows with sqrt(N)), the same stage at every size:

    python bench/bench_scale_runs.py --floors 0.5       # each size to half its travel floor These machines are noisy
(+-30 %): read the slope from one invocation, not across invocations.
"""

from __future__ import annotations

import argparse
import math
import multiprocessing
import resource
from collections.abc import Iterator, Sequence

import numpy as np

from swarmsim import Simulation
from swarmsim.engine.config import SimConfig
from swarmsim.engine.sim import PHASES
from swarmsim.errors import ConfigError
from swarmsim.limits import MAX_GROUPS
from swarmsim.world.floor import travel_floor_ticks
from swarmsim.world.makeworld import WorldSpec, build_world
from swarmsim.world.shapes import text_shape
from swarmsim.world.world import World

REFERENCE_ROBOTS = 10_000  # the world: make-world --size 640 --robots 10000 --groups 16
REFERENCE_SIZE = 640.0  # its target's height, units
ROBOTS_PER_GROUP = 625  # its robots per group (10,000 / 16)


def world_shape(robots: int) -> tuple[float, int]:
    """(target height in units, groups) of the world for ``robots`` robots: the height grows
    with sqrt(robots) (capacity / robots fixed), groups keep ROBOTS_PER_GROUP robots each."""
    size = REFERENCE_SIZE * math.sqrt(robots / REFERENCE_ROBOTS)
    groups = min(MAX_GROUPS, max(1, round(robots / ROBOTS_PER_GROUP)))
    return size, groups


def make_world(text: str, robots: int) -> World:
    """The world ``swarmsim make-world --text TEXT --size S --robots N --groups G`` makes for
    ``robots`` = N (S and G from :func:`world_shape`), built in memory."""
    size, groups = world_shape(robots)
    spec = WorldSpec(name=f"{text.strip()} {robots}",
                     description=f"bench_scale_runs: {text.strip()!r}, {robots} robots",
                     size=size, robots=robots, groups=groups)
    return build_world(text_shape(text), spec).world


def run_length(world: World, ticks: int, floors: float | None) -> int:
    """Ticks to run ``world`` for: ``floors`` times its travel floor (rounded up), or
    ``ticks`` when ``floors`` is None."""
    if floors is None:
        return ticks
    return math.ceil(floors * travel_floor_ticks(world, SimConfig().v_max))


def measure(text: str, robots: int, ticks: int, seed: int, floors: float | None = None) -> dict:
    """One run of the made world for ``robots`` (``ticks`` long, or ``floors`` travel floors:
    :func:`run_length`): its costs per tick (ms), mean awake robots, coverage reached
    (fraction) and this process's peak RSS (MB)."""
    world = make_world(text, robots)
    ticks = run_length(world, ticks, floors)
    sim = Simulation(world, seed=seed, max_ticks=ticks)
    awake = [0]

    def count(s: Simulation) -> None:
        awake[0] += s.awake_count

    sim.run(on_tick=count)
    n = max(sim.tick, 1)
    out = {"robots": sim.n, "groups": sim.config.groups, "size": world_shape(robots)[0],
           "ticks": sim.tick, "stop": sim.stop_reason,
           "cpu": sim.cpu_seconds / n * 1e3,
           "awake": awake[0] / n, "coverage": sim.metrics.coverage,
           "peak_rss_mb": resource.getrusage(resource.RUSAGE_SELF).ru_maxrss / 1024}  # KB
    out.update({p: sim.phase_seconds[p] / n * 1e3 for p in PHASES})
    return out


def measure_in_fresh_process(text: str, robots: int, ticks: int, seed: int,
                             floors: float | None = None) -> dict:
    """:func:`measure` in a new interpreter (spawn), so that its peak memory is its own."""
    ctx = multiprocessing.get_context("spawn")
    with ctx.Pool(1) as pool:
        return pool.apply(measure, (text, robots, ticks, seed, floors))


def measure_sizes(text: str, sizes: Sequence[int], ticks: int, seed: int,
                  in_process: bool = False, floors: float | None = None) -> Iterator[dict]:
    """:func:`measure` for each robot count, smallest first, each in a fresh process unless
    ``in_process``; yields each row as soon as it is measured."""
    run = measure if in_process else measure_in_fresh_process
    for robots in sorted(set(sizes)):
        yield run(text, robots, ticks, seed, floors)


def slopes(rows: Sequence[dict]) -> tuple[float, float]:
    """Log-log slopes of CPU ms per tick against robots: (smallest to largest size, least
    squares over all sizes). 1.0 is linear growth. Needs two sizes or more."""
    if len(rows) < 2:
        raise ValueError(f"a slope needs two sizes or more, got {len(rows)}")
    x = np.log([r["robots"] for r in rows])
    y = np.log([r["cpu"] for r in rows])
    ends = float((y[-1] - y[0]) / (x[-1] - x[0]))
    fit = float(np.polyfit(x, y, 1)[0])
    return ends, fit


HEADER = (f"{'robots':>7}{'groups':>7}{'height':>7}{'ticks':>7}{'stop':>10}{'cpu ms':>9}"
          + "".join(f"{p:>9}" for p in PHASES) + f"{'awake':>8}{'cover %':>8}{'peak MB':>8}")


def format_row(r: dict) -> str:
    """One size's line of the table (columns as HEADER)."""
    return (f"{r['robots']:>7}{r['groups']:>7}{r['size']:>7.0f}{r['ticks']:>7}"
            f"{r['stop']!s:>10}{r['cpu']:>9.2f}" + "".join(f"{r[p]:>9.2f}" for p in PHASES)
            + f"{r['awake']:>8.0f}{100 * r['coverage']:>8.1f}{r['peak_rss_mb']:>8.0f}")


def main(argv: Sequence[str] | None = None) -> None:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--text", default="K", help="the target's text, as make-world --text")
    parser.add_argument("--robots", type=int, nargs="+", default=[2000, 4000, 6000, 10000])
    parser.add_argument("--ticks", type=int, default=2000, help="ticks per run (or its end)")
    parser.add_argument("--floors", type=float, default=None,
                        help="run each size this many travel floors instead of --ticks")
    parser.add_argument("--seed", type=int, default=0)
    parser.add_argument("--in-process", action="store_true", dest="in_process",
                        help="every size in this process (peak MB is then the largest so far)")
    args = parser.parse_args(argv)
    if len(set(args.robots)) < 2:
        parser.error("--robots needs two different counts or more, for a slope")
    if args.floors is not None and not (math.isfinite(args.floors) and args.floors > 0):
        parser.error(f"--floors must be a positive number, got {args.floors}")
    if min(args.robots) < 1:
        parser.error(f"--robots must be positive, got {min(args.robots)}")
    length = (f"{args.floors:g} travel floors" if args.floors is not None
              else f"{args.ticks} ticks")
    print(f"GGC on make-world --text {args.text!r}, height 640*sqrt(N/10000), {ROBOTS_PER_GROUP}"
          f" robots per group, seed {args.seed}, up to {length}: cpu ms per tick"
          " (process time), phases wall ms per tick, mean robots awake per tick", flush=True)
    print(HEADER, flush=True)
    rows = []
    try:
        for row in measure_sizes(args.text, args.robots, args.ticks, args.seed, args.in_process,
                                 args.floors):
            rows.append(row)
            print(format_row(row), flush=True)
    except ConfigError as exc:  # a world or run refused: its one line
        parser.error(str(exc))
    ends, fit = slopes(rows)
    print(f"log-log slope of cpu ms per tick against robots: {ends:.2f} from "
          f"{rows[0]['robots']} to {rows[-1]['robots']}, {fit:.2f} least squares over "
          f"{len(rows)} sizes (1.0 = linear)", flush=True)


if __name__ == "__main__":
    main()
