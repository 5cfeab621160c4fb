"""Observers of a run: video frames, the last-frame snapshot, trajectories and the output
folder.

Rendering only reads snapshots; turning it on never changes a run's results.
"""

from __future__ import annotations

from pathlib import Path
from typing import Any, Self

from swarmsim.engine.sim import RunResult, Simulation
from swarmsim.results.output import write_npz, write_run
from swarmsim.results.runfolder import clear_run
from swarmsim.results.trajectories import FILE_NAME as TRAJECTORIES_FILE
from swarmsim.results.trajectories import Trajectories


class Recorder:
    """Streams frames of ``sim`` to an MP4 every ``frame_every`` ticks and saves the last frame;
    with ``trajectories_every`` K > 0 it also samples positions every K ticks (see
    swarmsim.results.trajectories), which :meth:`write_outputs` saves.

    Use as a context manager around ``sim.run(on_tick=recorder.on_tick)``.
    """

    def __init__(self, sim: Simulation, video: Path | None = None, snapshot: Path | None = None,
                 fps: int = 30, frame_every: int = 10, color_by: str | None = None,
                 width: int = 800, highlight_contacts: bool = False,
                 trajectories_every: int = 0):
        sim.offered_colourings(color_by)  # refuses a colouring the run does not offer
        self.sim = sim
        self.trajectories = (Trajectories(sim, trajectories_every) if trajectories_every
                             else None)
        self.video_path = video
        self.snapshot_path = snapshot
        self.fps = fps
        self.frame_every = max(1, int(frame_every))
        self._renderer = None
        self._writer = None
        self._render_kw: dict[str, Any] = {"color_by": color_by, "width": width,
                                           "highlight_contacts": highlight_contacts}
        if video is not None or snapshot is not None:
            self.renderer  # noqa: B018  its checks now, before the caller makes any folder

    @property
    def renderer(self):
        if self._renderer is None:
            self._renderer = self.sim.new_renderer(**self._render_kw)
        return self._renderer

    def __enter__(self) -> Self:
        if self.video_path is not None:
            from swarmsim.render import VideoWriter

            if self.video_path.suffix.lower() != ".mp4":
                from swarmsim.errors import ConfigError

                raise ConfigError(f"video file must end in .mp4, got {str(self.video_path)!r}",
                                  key="--video")
            self.video_path.parent.mkdir(parents=True, exist_ok=True)  # as --out does
            self._writer = VideoWriter(self.video_path, fps=self.fps).__enter__()
            self._writer.write(self.renderer.draw(self.sim.snapshot()))
        return self

    def on_tick(self, sim: Simulation) -> None:
        if self.trajectories is not None:
            self.trajectories.on_tick(sim)
        if self._writer is not None and sim.tick % self.frame_every == 0:
            self._writer.write(self.renderer.draw(sim.snapshot()))

    def __exit__(self, exc_type, exc, tb) -> None:
        if self._writer is not None:
            if exc_type is None and self.sim.tick % self.frame_every != 0:
                self._writer.write(self.renderer.draw(self.sim.snapshot()))
            self._writer.__exit__(exc_type, exc, tb)
        if exc_type is None and self.snapshot_path is not None:
            from swarmsim.render import save_png

            self.snapshot_path.parent.mkdir(parents=True, exist_ok=True)
            save_png(self.renderer.draw(self.sim.snapshot()), self.snapshot_path)

    def write_outputs(self, out_dir: Path, result: RunResult) -> Path:
        """summary.json, timeseries.csv, robots.csv, coverage.npz, coverage.png and (if
        sampled) trajectories.npz in ``out_dir`` (docs/outputs.md describes each).

        The folder holds one run: the files an earlier run wrote there (swarmsim.results.runfolder
        RUN_FILES, e.g. its trajectories.npz) are removed first, and if writing fails or is
        interrupted the files written so far are removed too. Other files are left alone."""
        clear_run(out_dir)
        try:
            return self._write_outputs(Path(out_dir), result)
        except BaseException:
            clear_run(out_dir)
            raise

    def _write_outputs(self, out_dir: Path, result: RunResult) -> Path:
        out = write_run(out_dir, result.summary, result.timeseries, result.robots)
        write_npz(out / "coverage.npz", self.sim.grid.arrays(self.sim.positions))
        if self.trajectories is not None:
            self.trajectories.save(out / TRAJECTORIES_FILE)
        from swarmsim.results.plots import plot_timeseries

        title = (f"{result.summary['world']} / {result.summary['controller']} / "
                 f"{result.summary['robots']} robots, {result.summary['groups']} groups")
        plot_timeseries(result.timeseries, out / "coverage.png", title=title,
                        completion_tick=result.summary.get("completion_tick"))
        return out
