"""What a drive model costs a tick: the same run under each drive, timed phase by phase.

For each drive it builds the run (world, controller, seed), steps it --ticks ticks, and
prints milliseconds per tick: the whole tick, the engine's phases (Simulation.phase_seconds),
pymunk's step, and the drive's own work (reading the body angles, the drive law, writing the
control bodies' velocities and spins; holonomic: the velocity write alone).

    python bench/bench_drives.py                          # K, GGC, seed 0, 1,000 ticks
    python bench/bench_drives.py --world tiny --ticks 3000 --drives holonomic diff

These machines are noisy (+-30 %): compare drives within one invocation.
"""

from __future__ import annotations

import argparse
import time
from collections.abc import Callable
from typing import Any

from swarmsim import Simulation
from swarmsim.robots.drives import DRIVE_NAMES

DRIVE_WORK = ("headings", "command", "command_motion")
"""The Physics calls a drive adds to (or, holonomic, keeps in) a tick."""


def timed(owner: Any, name: str, seconds: dict[str, float]) -> None:
    """Wrap ``owner.name`` so that its calls add their seconds to ``seconds[name]``."""
    call: Callable = getattr(owner, name)

    def wrapper(*args: Any, **kwargs: Any) -> Any:
        began = time.perf_counter()
        try:
            return call(*args, **kwargs)
        finally:
            seconds[name] += time.perf_counter() - began

    setattr(owner, name, wrapper)


def measure(world: str, controller: str, seed: int, drive: str, ticks: int) -> dict[str, float]:
    """Milliseconds per tick of one run's first ``ticks`` ticks under ``drive``."""
    sim = Simulation(world, controller=controller, seed=seed,
                     settings={"drive": drive, "max_ticks": 10 * ticks})
    seconds = dict.fromkeys((*DRIVE_WORK, "step", "motion"), 0.0)
    for name in (*DRIVE_WORK, "step"):
        timed(sim.physics, name, seconds)
    if sim.drive.has_heading:
        timed(sim.drive, "motion", seconds)
    began = time.perf_counter()
    for _ in range(ticks):
        sim.step()
    total = time.perf_counter() - began
    drive_work = sum(seconds[name] for name in (*DRIVE_WORK, "motion"))
    row = {"tick": total, **sim.phase_seconds, "pymunk step": seconds["step"],
           "drive work": drive_work}
    return {name: 1000 * value / ticks for name, value in row.items()}


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--world", default="K")
    parser.add_argument("--controller", default="ggc")
    parser.add_argument("--seed", type=int, default=0)
    parser.add_argument("--ticks", type=int, default=1000)
    parser.add_argument("--drives", nargs="+", default=list(DRIVE_NAMES), choices=DRIVE_NAMES)
    args = parser.parse_args()
    print(f"{args.world}, {args.controller}, seed {args.seed}, first {args.ticks} ticks: "
          "ms per tick")
    for drive in args.drives:
        row = measure(args.world, args.controller, args.seed, drive, args.ticks)
        print(f"{drive:10s} " + "  ".join(f"{name} {value:.2f}" for name, value in row.items()))


if __name__ == "__main__":
    main()
