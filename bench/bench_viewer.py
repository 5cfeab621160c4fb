"""The live viewer's frames per second on K (603 robots, GGC, seed 0) under SDL's dummy video
driver, without the window's 30 frames-per-second cap: running one tick per frame, paused
(drawing only: the frame, the panel and a selected robot), and paused zoomed in 4x about the
selected robot (the frame magnified, the heads-up line and legend drawn over it).

    python bench/bench_viewer.py [--frames 200] [--width 800]
"""

from __future__ import annotations

import argparse
import dataclasses
import os
import time

os.environ["SWARMSIM_VIEW_HEADLESS"] = "1"

from swarmsim import Simulation
from swarmsim.render.viewer import Viewer


def frames_per_second(viewer: Viewer, frames: int) -> float:
    """Frames per second of ``frames`` calls of ``viewer.frame()`` (events, ticks, drawing)."""
    start = time.perf_counter()
    for _ in range(frames):
        viewer.frame()
    return frames / (time.perf_counter() - start)


def main() -> None:
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--frames", type=int, default=200)
    ap.add_argument("--width", type=int, default=800)
    args = ap.parse_args()
    viewer = Viewer(Simulation("K", seed=0, max_ticks=100_000), width=args.width)
    viewer.state = dataclasses.replace(viewer.state, selected=100)
    for _ in range(5):  # warm-up: fonts, the legend, the first snapshots
        viewer.frame()
    running = frames_per_second(viewer, args.frames)
    viewer.state = dataclasses.replace(viewer.state, paused=True)
    paused = frames_per_second(viewer, args.frames)
    robot = viewer.renderer.world_to_pixel(viewer.sim.positions[100])
    camera = viewer.state.camera.zoomed(4.0, (int(robot[0]), int(robot[1])))
    viewer.state = dataclasses.replace(viewer.state, camera=camera)
    zoomed = frames_per_second(viewer, args.frames)
    print(f"K, {args.width} px: running 1 tick/frame {running:.1f} frames/s; "
          f"paused (drawing only) {paused:.1f} frames/s; paused zoomed 4x {zoomed:.1f} "
          f"frames/s; ended at tick {viewer.sim.tick}")
    viewer.close()


if __name__ == "__main__":
    main()
