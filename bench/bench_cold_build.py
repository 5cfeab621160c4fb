"""What the first run's kernel build costs: CPU seconds of a cold and a warm ``swarmsim run``,
and each compiled kernel's own compile time.

    python bench/bench_cold_build.py                 # cold + warm CPU of `run K --max-ticks 300`
    python bench/bench_cold_build.py --repeat 3      # three cold builds (the median is printed)
    python bench/bench_cold_build.py --kernels       # + each kernel's compile seconds (one cold
                                                     #   build in this process, events of numba)
    python bench/bench_cold_build.py -- run house --robots 1 --max-ticks 300 --quiet

A cold build is a run with ``NUMBA_CACHE_DIR`` pointed at an empty folder (numba then neither
finds nor disturbs the kernels cached beside the sources); a warm run reuses that folder. CPU
is user + system of the child process (resource.getrusage(RUSAGE_CHILDREN)).
"""

from __future__ import annotations

import argparse
import os
import resource
import statistics
import subprocess
import sys
import tempfile
import time
from collections import defaultdict

DEFAULT_RUN = ["run", "K", "--max-ticks", "300", "--quiet"]


def child_cpu(argv: list[str], cache_dir: str) -> tuple[float, float]:
    """(CPU seconds, wall seconds) of ``swarmsim ARGV`` with numba's cache in ``cache_dir``."""
    env = dict(os.environ, NUMBA_CACHE_DIR=cache_dir, SDL_VIDEODRIVER="dummy",
               SDL_AUDIODRIVER="dummy", MPLBACKEND="Agg")
    before = resource.getrusage(resource.RUSAGE_CHILDREN)
    start = time.perf_counter()
    subprocess.run([sys.executable, "-m", "swarmsim", *argv], env=env, check=True,
                   stdout=subprocess.DEVNULL)
    wall = time.perf_counter() - start
    after = resource.getrusage(resource.RUSAGE_CHILDREN)
    cpu = (after.ru_utime - before.ru_utime) + (after.ru_stime - before.ru_stime)
    return cpu, wall


def cold_and_warm(argv: list[str], repeat: int) -> None:
    """Print each cold build's and the following warm run's CPU seconds, then the medians."""
    colds, warms = [], []
    for k in range(repeat):
        with tempfile.TemporaryDirectory(prefix="swarmsim-cold-") as cache:
            cold, cold_wall = child_cpu(argv, cache)
            warm, warm_wall = child_cpu(argv, cache)
        colds.append(cold)
        warms.append(warm)
        print(f"build {k + 1}: cold {cold:6.1f} s CPU ({cold_wall:6.1f} s wall), "
              f"warm {warm:5.1f} s CPU ({warm_wall:5.1f} s wall)", flush=True)
    print(f"median of {repeat}: cold {statistics.median(colds):.1f} s CPU, "
          f"warm {statistics.median(warms):.1f} s CPU")


def kernel_table(argv: list[str]) -> None:
    """Run ``swarmsim ARGV`` in this process on an empty cache and print each kernel's own
    compile seconds (its callees' compiles excluded), signatures and calls to the compiler."""
    from numba.core import event

    own: dict[str, float] = defaultdict(float)
    signatures: dict[str, set] = defaultdict(set)
    stack: list[list[float]] = []  # [start, seconds spent in nested compiles]

    class Timer(event.Listener):
        def on_start(self, ev):
            stack.append([time.process_time(), 0.0])

        def on_end(self, ev):
            start, nested = stack.pop()
            spent = time.process_time() - start
            if stack:
                stack[-1][1] += spent
            disp = ev.data["dispatcher"]
            name = f"{disp.py_func.__module__}.{disp.py_func.__qualname__}"
            own[name] += spent - nested
            signatures[name].add(str(ev.data["args"]))

    event.register("numba:compile", Timer())
    from swarmsim.cli import main

    start = time.process_time()
    main(argv)
    total = time.process_time() - start
    print(f"\nprocess CPU {total:.1f} s; compiles {sum(own.values()):.1f} s "
          f"in {sum(len(s) for s in signatures.values())} signatures of {len(own)} kernels")
    print(f"{'kernel':64s} {'CPU s':>7s} {'sigs':>4s}")
    for name, seconds in sorted(own.items(), key=lambda kv: -kv[1]):
        print(f"{name:64s} {seconds:7.2f} {len(signatures[name]):4d}")


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--repeat", type=int, default=1, help="cold builds (default 1)")
    parser.add_argument("--kernels", action="store_true",
                        help="print each kernel's compile seconds (one cold build, in process)")
    parser.add_argument("argv", nargs="*", help="swarmsim's arguments (default: run K ...)")
    args = parser.parse_args()
    argv = args.argv or DEFAULT_RUN
    if args.kernels:
        with tempfile.TemporaryDirectory(prefix="swarmsim-cold-") as cache:
            os.environ["NUMBA_CACHE_DIR"] = cache
            kernel_table(argv)
    else:
        cold_and_warm(argv, args.repeat)


if __name__ == "__main__":
    main()
