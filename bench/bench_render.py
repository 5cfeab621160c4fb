"""Rendering and encoding throughput: draw fps, encode fps and end-to-end fps.

A square world, N robots at random positions that move every frame (so every frame differs, as
in a real run), coverage overlay on, colour by gradient, 800 px wide. Snapshots (and their
coverage grids) are prepared before timing, so only rendering and encoding are measured.

    python bench/bench_render.py [--frames 150] [--robots 2000] [--width 800] [--repeats 3]
"""

from __future__ import annotations

import argparse
import statistics
import tempfile
import time
from pathlib import Path

import numpy as np

from swarmsim.controller import message_dtype
from swarmsim.metrics import CoverageGrid
from swarmsim.render import Renderer, VideoWriter
from swarmsim.results.snapshot import Snapshot
from swarmsim.world.world import world_from_dict


def make_snapshots(n_robots: int, n_frames: int, step: float = 0.3, seed: int = 0):
    side = 100.0
    world = world_from_dict({
        "name": "bench",
        "target": {"outline": [[0, 0], [side, 0], [side, side], [0, side]]},
        "spawn": [{"outline": [[-8, -8], [-2, -8], [-2, -2], [-8, -2]]}],
        "beacon": {"position": [side / 2, side / 2]},
        "arena": {"margin": 10.0},
    })
    grid = CoverageGrid.for_target(world.target)
    rng = np.random.default_rng(seed)
    pos = rng.uniform(-5, side + 5, size=(n_robots, 2))
    msgs = np.zeros(n_robots, dtype=message_dtype())
    msgs["id"] = np.arange(n_robots)
    msgs["group"] = rng.integers(0, 4, n_robots)
    msgs["leader"] = rng.random(n_robots) < 0.01
    statuses = ("Idle", "Moving", "Joined", "Leader")
    snaps = []
    for t in range(n_frames):
        pos = pos + rng.normal(0, step, size=pos.shape)
        m = msgs.copy()
        m["gradient"] = (np.hypot(pos[:, 0] - side / 2, pos[:, 1] - side / 2) // 1.5 + t) % 40
        m["status"] = rng.integers(0, len(statuses), n_robots)
        snaps.append(Snapshot(tick=t, positions=pos.copy(), messages=m, statuses=statuses,
                              radius=0.4, coverage=grid.coverage(pos),
                              covered=grid.covered_grid(pos),
                              in_contact=np.zeros(n_robots, bool),
                              failed=np.zeros(n_robots, bool)))
    return world, grid, snaps


def main() -> None:
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--frames", type=int, default=150)
    ap.add_argument("--robots", type=int, default=2000)
    ap.add_argument("--width", type=int, default=800)
    ap.add_argument("--repeats", type=int, default=3, help="encode/end-to-end runs (median)")
    ap.add_argument("--preset", default="veryfast")
    ap.add_argument("--step", type=float, default=0.3,
                    help="random motion per robot per frame, world units (0.3 = ~2 px)")
    args = ap.parse_args()

    world, grid, snaps = make_snapshots(args.robots, args.frames, args.step)
    r = Renderer(world, grid, width=args.width, color_by="gradient")
    print(f"{args.robots} robots, {args.frames} frames, {r.width}x{r.height}, "
          f"robot radius {max(r.min_radius_px, 0.4 * r.scale):.1f} px, preset {args.preset}, "
          f"motion {args.step} units = {args.step * r.scale:.1f} px per frame")

    r.draw(snaps[0])  # warm up (fonts, legend cache)
    draw_ms = []
    frames = []
    for s in snaps:
        t0 = time.perf_counter()
        frames.append(r.draw(s))
        draw_ms.append((time.perf_counter() - t0) * 1e3)
    med = statistics.median(draw_ms)
    print(f"render (draw + tobytes): median {med:.2f} ms/frame = {1e3 / med:.0f} fps")

    enc_fps, e2e_fps, sizes = [], [], []
    with tempfile.TemporaryDirectory() as tmp:
        for k in range(args.repeats):
            out = Path(tmp) / f"enc{k}.mp4"
            t0 = time.perf_counter()
            with VideoWriter(out, fps=30, preset=args.preset) as vw:
                for f in frames:
                    vw.write(f)
            enc_fps.append(len(frames) / (time.perf_counter() - t0))
            sizes.append(out.stat().st_size)

            out = Path(tmp) / f"e2e{k}.mp4"
            t0 = time.perf_counter()
            with VideoWriter(out, fps=30, preset=args.preset) as vw:
                for s in snaps:
                    vw.write(r.draw(s))
            e2e_fps.append(len(snaps) / (time.perf_counter() - t0))
    print(f"encode (pre-drawn frames, incl. close): median {statistics.median(enc_fps):.1f} fps "
          f"(runs: {', '.join(f'{v:.1f}' for v in enc_fps)}), "
          f"{statistics.median(sizes) / 1e6:.2f} MB")
    print(f"end-to-end (draw + tobytes + encode): median {statistics.median(e2e_fps):.1f} fps "
          f"(runs: {', '.join(f'{v:.1f}' for v in e2e_fps)})")


if __name__ == "__main__":
    main()
