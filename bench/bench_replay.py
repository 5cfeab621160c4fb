"""What ``swarmsim replay`` costs against the run it draws again.

For each seed: the run without any output but --out (what recording adds to it); the run
recorded with ``--trajectories EVERY``; the same run with a live ``--video`` (a frame every
EVERY ticks, for comparison); then ``swarmsim replay RUN --video`` of the recording. Each is a fresh ``swarmsim`` process (start-up included, as a user would
see it); wall and CPU seconds (the child's user + system time) per seed, the ratios run /
replay, and their medians. It also says whether the replayed MP4 has the same bytes as the
live one (same frames, same encoder: it should).

    python bench/bench_replay.py                          # K, GGC, seeds 0-2, EVERY 50
    python bench/bench_replay.py --world K --seeds 0 1 2 --every 50 --max-ticks 3000

EVERY 50 is the live video's default frame interval for K (max_ticks / 600, at most 50).
"""

from __future__ import annotations

import argparse
import hashlib
import os
import statistics
import subprocess
import sys
import tempfile
import time
from pathlib import Path

SWARMSIM = str(Path(sys.executable).with_name("swarmsim"))


def timed(args: list[str]) -> tuple[float, float]:
    """(wall, CPU) seconds of ``swarmsim ARGS`` in a child process."""
    before = os.times()
    began = time.perf_counter()
    subprocess.run([SWARMSIM, *args], check=True, stdout=subprocess.DEVNULL)
    wall = time.perf_counter() - began
    after = os.times()
    cpu = (after.children_user - before.children_user) + (after.children_system
                                                          - before.children_system)
    return wall, cpu


def digest(path: Path) -> str:
    return hashlib.sha256(path.read_bytes()).hexdigest()


def bench_seed(world: str, seed: int, every: int, max_ticks: int | None, work: Path
               ) -> dict[str, tuple[float, float]]:
    """The three timings of one seed, and whether the two MP4s are the same bytes."""
    common = [world, "--seed", str(seed), "--quiet"]
    if max_ticks:
        common += ["--max-ticks", str(max_ticks)]
    run_dir, live, again = work / f"run-{seed}", work / f"live-{seed}.mp4", work / f"re-{seed}.mp4"
    out = {"run": timed(["run", *common, "--out", str(work / f"plain-{seed}")]),
           "run --trajectories": timed(["run", *common, "--out", str(run_dir),
                                         "--trajectories", str(every)]),
           "run --video": timed(["run", *common, "--out", str(work / f"v-{seed}"), "--video",
                                 str(live), "--frame-every", str(every)]),
           "replay --video": timed(["replay", str(run_dir), "--video", str(again), "--quiet"])}
    same = digest(live) == digest(again)
    size = (run_dir / "trajectories.npz").stat().st_size
    print(f"seed {seed}: " + "  ".join(f"{k} {w:.1f} s ({c:.1f} s CPU)"
                                       for k, (w, c) in out.items())
          + f"  ratio run/replay {out['run --trajectories'][1] / out['replay --video'][1]:.1f}"
          f" (CPU)  trajectories.npz {size / 2**20:.1f} MiB  same MP4 bytes: {same}",
          flush=True)
    return out


def main() -> None:
    p = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    p.add_argument("--world", default="K")
    p.add_argument("--seeds", type=int, nargs="+", default=[0, 1, 2])
    p.add_argument("--every", type=int, default=50)
    p.add_argument("--max-ticks", type=int, default=None)
    args = p.parse_args()
    with tempfile.TemporaryDirectory(prefix="bench-replay-") as tmp:
        rows = [bench_seed(args.world, s, args.every, args.max_ticks, Path(tmp))
                for s in args.seeds]
    for name in rows[0]:
        wall = statistics.median(r[name][0] for r in rows)
        cpu = statistics.median(r[name][1] for r in rows)
        print(f"median {name}: {wall:.1f} s wall, {cpu:.1f} s CPU")
    for name in ("run --trajectories", "run --video"):
        ratio = statistics.median(r[name][1] / r["replay --video"][1] for r in rows)
        print(f"median CPU ratio {name} / replay --video: {ratio:.1f}")


if __name__ == "__main__":
    main()
