"""How a tick's cost and the memory grow with the swarm: 2,000 to 10,000 robots.

Each swarm size runs in a fresh process (so its peak resident memory is its own), in the same
square world as bench_tick.py (a target holding ~70 % of the robots at d_cover 6, a spawn band
below it). After --warmup ticks it times --ticks ticks and reports, per size:

- ms per tick (median of --repeats blocks) and microseconds per robot per tick;
- growth: (tick cost at N / tick cost at the smallest N) / (N / smallest N). At most 1.0 means
  the cost grows no worse than linearly with the robots. The same for the bare pymunk step
  alone (``bare gr.``) and for the simulator's own part of a tick, tick - bare step
  (``own gr.``): pymunk's step grows faster than linearly with a dense swarm, and how much
  faster depends on the machine's caches and load;
- peak RSS of that process, in MB (the whole Python process: interpreter, numpy, pymunk).

    python bench/bench_scale.py                          # 2000 5000 10000 robots, GGC
    python bench/bench_scale.py --robots 2000 10000 --ticks 50

These machines are noisy (+-30 %): read the growth column from one run, not across runs.
Real GGC runs of a made world at several sizes, instead of this square world:
bench_scale_runs.py.
"""

from __future__ import annotations

import argparse
import multiprocessing
import resource
import sys
from pathlib import Path

sys.path.insert(0, str(Path(__file__).resolve().parent))
from bench_tick import measure


def measure_in_fresh_process(robots: int, controller: str, warmup: int, ticks: int,
                             repeats: int) -> dict:
    """Run ``measure`` in a new interpreter; add its peak resident memory (MB)."""
    ctx = multiprocessing.get_context("spawn")
    with ctx.Pool(1) as pool:
        return pool.apply(_measure_with_memory, (robots, controller, warmup, ticks, repeats))


def _measure_with_memory(robots: int, controller: str, warmup: int, ticks: int,
                         repeats: int) -> dict:
    out = measure(robots, controller, warmup, ticks, repeats)
    out["peak_rss_mb"] = resource.getrusage(resource.RUSAGE_SELF).ru_maxrss / 1024  # KB on Linux
    return out


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--robots", type=int, nargs="+", default=[2000, 5000, 10000])
    parser.add_argument("--controller", default="ggc")
    parser.add_argument("--warmup", type=int, default=600, help="ticks before measuring")
    parser.add_argument("--ticks", type=int, default=100, help="ticks per measured block")
    parser.add_argument("--repeats", type=int, default=3, help="measured blocks (median)")
    args = parser.parse_args()
    sizes = sorted(args.robots)
    print(f"{args.controller}: ms per tick (median of blocks), after {args.warmup} ticks;"
          " growth = cost ratio / size ratio against the smallest size (<= 1: linear or better)")
    print(f"{'robots':>7}{'awake':>7}{'tick ms':>9}{'us/robot':>10}{'bare ms':>9}"
          f"{'ratio':>7}{'growth':>8}{'bare gr.':>9}{'own gr.':>8}{'peak MB':>9}")
    base = None
    for n in sizes:
        r = measure_in_fresh_process(n, args.controller, args.warmup, args.ticks, args.repeats)
        own = r["tick"] - r["bare_step"]
        base = base or (n, r["tick"], r["bare_step"], own)
        size_ratio = n / base[0]
        growth = [cost / base_cost / size_ratio
                  for cost, base_cost in zip((r["tick"], r["bare_step"], own), base[1:],
                                             strict=True)]
        print(f"{n:>7}{r['awake']:>7}{r['tick']:>9.2f}{1e3 * r['tick'] / n:>10.2f}"
              f"{r['bare_step']:>9.2f}{r['tick'] / r['bare_step']:>7.1f}{growth[0]:>8.2f}"
              f"{growth[1]:>9.2f}{growth[2]:>8.2f}{r['peak_rss_mb']:>9.0f}", flush=True)


if __name__ == "__main__":
    main()
