"""A checkpoint's size, write time and restore time, mid-run (swarmsim/engine/checkpoint.py).

Runs GGC on a world to a tick, then times, a few times over: encoding the run (pickling the
whole state), writing the file (atomically, fsync included), re-seating the run on the bytes
written (the part of a save that loads them back), and restoring the file as a new run.

    python bench/bench_checkpoint.py [--world K] [--robots N] [--ticks 3000] [--seed 0]
        [--repeats 3]
"""

from __future__ import annotations

import argparse
import statistics
import tempfile
import time
from pathlib import Path

from swarmsim import Simulation
from swarmsim.engine import checkpoint
from swarmsim.results.output import atomic_write_bytes


def _best(seconds: list[float]) -> str:
    return f"{1000 * min(seconds):.0f} ms (median {1000 * statistics.median(seconds):.0f})"


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
    encode, write, save, restore = [], [], [], []
    with tempfile.TemporaryDirectory() as folder:
        path = Path(folder) / checkpoint.FILE_NAME
        for _ in range(args.repeats):
            start = time.perf_counter()
            data = checkpoint.dumps(sim)
            encode.append(time.perf_counter() - start)
            start = time.perf_counter()
            atomic_write_bytes(path, data)
            write.append(time.perf_counter() - start)
            start = time.perf_counter()
            sim.save(path)  # encode + write + re-seat
            save.append(time.perf_counter() - start)
            start = time.perf_counter()
            Simulation.restore(path)
            restore.append(time.perf_counter() - start)
        size = path.stat().st_size
    print(f"{args.world} robots {sim.n} tick {sim.tick} (asleep in pymunk "
          f"{int(sim.physics.bodies_asleep().sum())}): checkpoint {size / 1e6:.2f} MB; "
          f"encode {_best(encode)}, write {_best(write)}, save (encode, write, re-seat) "
          f"{_best(save)}, restore {_best(restore)}")


if __name__ == "__main__":
    main()
