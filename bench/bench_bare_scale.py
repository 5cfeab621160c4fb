"""pymunk alone at the state of a real run, at several swarm sizes: what a robot costs the step.

For each robot count a world is made as bench_scale_runs.py makes it (K at that size, 625
robots a group), a GGC run goes --warmup ticks, and then a fresh Physics of the same robots at
the run's positions, each given its run's command of that tick, is stepped by pymunk alone
(--ticks ticks, best of --repeats), four ways: our drive as a run has it (a body, a control
body, a pivot and a gear joint a robot; Chipmunk's bounding-box tree), Chipmunk's spatial
hash instead of the tree (cell 1 and 2 units), without sleeping, with 3 pymunk steps a tick
instead of 6 (``substeps``) and with 2 solver iterations instead of 5 (``iterations``): what
each costs, not what it does to contacts (``swarmsim study realism --set`` measures that).
Prints ms a tick and microseconds a robot.

    python bench/bench_bare_scale.py                        # 2000 and 10000 robots, tick 150
    python bench/bench_bare_scale.py --robots 2000 6000 10000 --warmup 600

CPU time (process_time); the machine's noise applies (+-30 %): compare rows of one run.
"""

from __future__ import annotations

import argparse
import dataclasses
import sys
import time
from collections.abc import Iterator, Sequence
from pathlib import Path

import numpy as np

sys.path.insert(0, str(Path(__file__).resolve().parent))
from bench_scale_runs import make_world

from swarmsim import Simulation
from swarmsim.physics.physics import Physics

WAYS = {"tree": ({}, None), "hash 1": ({}, 1.0), "hash 2": ({}, 2.0),
        "no sleep": ({"physics_sleep": False}, None), "3 substeps": ({"substeps": 3}, None),
        "2 iterations": ({"iterations": 2}, None)}
"""Each way of stepping: PhysicsConfig changes, and the spatial hash's cell size (None: the
tree)."""


def step_cost(sim: Simulation, positions: np.ndarray, velocities: np.ndarray, changes: dict,
              hash_cell: float | None, ticks: int, repeats: int) -> float:
    """CPU ms a tick of a fresh Physics of ``sim``'s world and robots at ``positions``,
    commanded ``velocities`` every tick (best of ``repeats`` blocks of ``ticks``)."""
    physics = Physics(sim.world, positions, dataclasses.replace(sim.physics_config, **changes))
    if hash_cell is not None:
        physics.space.use_spatial_hash(hash_cell, 2 * len(positions))
    physics.read()
    physics.command(velocities)
    physics.step()
    best = float("inf")
    for _ in range(repeats):
        start = time.process_time()
        for _ in range(ticks):
            physics.read()
            physics.command(velocities)
            physics.step()
        best = min(best, (time.process_time() - start) / ticks * 1e3)
    return best


def measure(robots: int, warmup: int, ticks: int, repeats: int) -> Iterator[tuple[str, float]]:
    """(way, CPU ms a tick) for each of WAYS, at tick ``warmup`` of K made for ``robots``."""
    sim = Simulation(make_world("K", robots), seed=0, max_ticks=10**6)
    for _ in range(warmup):
        sim.step()
    positions, velocities = sim.positions.copy(), sim.velocities.copy()
    for way, (changes, cell) in WAYS.items():
        yield way, step_cost(sim, positions, velocities, changes, cell, ticks, repeats)


def main(argv: Sequence[str] | None = None) -> None:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--robots", type=int, nargs="+", default=[2000, 10000])
    parser.add_argument("--warmup", type=int, default=150, help="ticks of the run first")
    parser.add_argument("--ticks", type=int, default=10, help="ticks per timed block")
    parser.add_argument("--repeats", type=int, default=3, help="blocks (best of)")
    args = parser.parse_args(argv)
    if min(args.robots) < 1 or args.ticks < 1 or args.repeats < 1 or args.warmup < 0:
        parser.error("--robots, --ticks and --repeats must be positive, --warmup >= 0")
    print(f"pymunk alone at tick {args.warmup} of K made for each size: CPU ms a tick "
          "(us a robot)", flush=True)
    for robots in args.robots:
        cells = [f"{way} {ms:.2f} ({ms / robots * 1e3:.2f})"
                 for way, ms in measure(robots, args.warmup, args.ticks, args.repeats)]
        print(f"{robots:>7}: " + ", ".join(cells), flush=True)


if __name__ == "__main__":
    main()
