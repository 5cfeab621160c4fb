"""A checkpoint's size, write time and restore time, mid-run (swarmsim/engine/checkpoint.py).

Runs GGC on a world to a tick, then times, a few times over: encoding the run (pickling the
whole state), writing the file (atomically, fsync included), re-seating the run on the bytes
written (the part of a save that loads them back), and restoring the file as a new run.
Each part starts after a full garbage collection (``gc.collect()``), so that none pays for
collecting the copies the parts before it left (in a run, the copy a save replaces is
collected later, by a full collection of the whole process, whose time is printed too).

    python bench/bench_checkpoint.py [--world K] [--robots N] [--ticks 3000] [--seed 0]
        [--repeats 3]
"""

from __future__ import annotations

import argparse
import gc
import statistics
import tempfile
import time
from collections.abc import Callable
from pathlib import Path

from swarmsim import Simulation
from swarmsim.engine import checkpoint
from swarmsim.results.output import atomic_write_bytes


def _best(seconds: list[float]) -> str:
    return f"{1000 * min(seconds):.0f} ms (median {1000 * statistics.median(seconds):.0f})"


def _timed(seconds: list[float], part: Callable[[], object]) -> object:
    """Run ``part`` after a full garbage collection; append its time to ``seconds``."""
    gc.collect()
    start = time.perf_counter()
    out = part()
    seconds.append(time.perf_counter() - start)
    return out


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--world", default="K")
    parser.add_argument("--robots", type=int, default=None)
    parser.add_argument("--ticks", type=int, default=3000)
    parser.add_argument("--seed", type=int, default=0)
    parser.add_argument("--repeats", type=int, default=3)
    args = parser.parse_args()
    sim = Simulation(args.world, robots=args.robots, seed=args.seed,
                     max_ticks=10 * args.ticks)
    while sim.tick < args.ticks and sim.stop_reason is None:
        sim.advance()
    encode, write, save, restore, collect = [], [], [], [], []
    with tempfile.TemporaryDirectory() as folder:
        path = Path(folder) / checkpoint.FILE_NAME
        for _ in range(args.repeats):
            data = _timed(encode, lambda: checkpoint.dumps(sim))
            _timed(write, lambda: atomic_write_bytes(path, data))  # noqa: B023 - called now
            _timed(save, lambda: sim.save(path))  # encode + write + re-seat
            _timed(restore, lambda: Simulation.restore(path))
            start = time.perf_counter()  # the copies left: the restored run, the save's
            gc.collect()
            collect.append(time.perf_counter() - start)
        size = path.stat().st_size
    print(f"{args.world} robots {sim.n} tick {sim.tick} (asleep in pymunk "
          f"{int(sim.physics.bodies_asleep().sum())}): checkpoint {size / 1e6:.2f} MB; "
          f"encode {_best(encode)}, write {_best(write)}, save (encode, write, re-seat) "
          f"{_best(save)}, restore {_best(restore)}; full garbage collection after them "
          f"{_best(collect)}")


if __name__ == "__main__":
    main()
