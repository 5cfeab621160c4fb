"""Drawing a recorded run again, without simulating it: ``swarmsim replay``.

:class:`Recording` reads a run's trajectories.npz (swarmsim.results.trajectories writes it)
back as Snapshots; the frames are those Snapshots drawn by the same Renderer the live run
used, so a replay drawn with the run's options is the live video's frames at the recorded
ticks, pixel for pixel; any colouring the run recorded, any width and frame rate may be
chosen instead. Every Snapshot equals, in all that a Renderer reads, the one the live run drew
at that tick; its messages hold only the recorded fields (``status`` and the colouring,
leader and group fields). Loading refuses, with one ConfigError line, a missing folder or
file, a file from before replay (no ``format``), and a file that is not one.

Python API::

    from swarmsim.replay import Recording, replay_frames, replay_png, replay_video

    rec = Recording.load("out/k")              # a run folder (or its trajectories.npz)
    replay_video(rec, "k-groups.mp4", color_by="group", fps=24)
    replay_png(rec, "k-500.png", tick=500)
    for snap in rec.snapshots():               # one Snapshot per recorded sample, in order
        ...
"""

from __future__ import annotations

import dataclasses
import sys
import zipfile
from collections.abc import Callable, Iterator
from dataclasses import dataclass
from functools import cached_property
from pathlib import Path
from types import SimpleNamespace
from typing import Any

import numpy as np
import shapely

from swarmsim.errors import ConfigError, did_you_mean
from swarmsim.metrics.grid import CoverageGrid
from swarmsim.results.snapshot import Snapshot
from swarmsim.results.trajectories import FIELD_PREFIX, FILE_NAME, FORMAT
from swarmsim.world.world import World

RERUN = "run it again with --trajectories K (and --out)"
REQUIRED = ("ticks", "positions", "statuses", "status_names", "in_contact_bits", "failed_bits",
            "asleep_bits", "coverage", "covered_changes", "covered_change_offsets",
            "controller", "colouring_names", "colouring_kinds", "leader_field", "group_field",
            "radius", "start_groups", "start_leaders", "world_name", "world_arena",
            "world_target", "world_spawns", "world_obstacles", "world_beacon", "grid_inside",
            "grid_x0", "grid_y0", "grid_dx", "grid_dy", "grid_radius")
"""The arrays of a format-2 file that replay reads (swarmsim.results.trajectories)."""


def trajectories_path(run: str | Path) -> Path:
    """The trajectories file of ``run`` (a run folder, or the file itself); ConfigError when
    there is none."""
    path = Path(run)
    if not path.exists():
        raise ConfigError(f"no run folder {str(path)!r}", key="RUN_DIR")
    if path.is_dir():
        path = path / FILE_NAME
        if not path.is_file():
            raise ConfigError(f"{str(run)!r} has no {FILE_NAME} to replay: {RERUN}",
                              key="RUN_DIR")
    return path


def _read(path: Path) -> dict[str, np.ndarray]:
    try:
        with np.load(path, allow_pickle=False) as data:
            return {k: data[k] for k in data.files}
    except (OSError, ValueError, EOFError, zipfile.BadZipFile) as exc:
        raise ConfigError(f"{str(path)!r} is not a trajectories file ({exc})",
                          key="RUN_DIR") from None


def _text(value: np.ndarray) -> str:
    return str(value.item()) if value.size else ""


@dataclass(frozen=True)
class Recording:
    """The arrays of a trajectories file of the current format (see
    swarmsim.results.trajectories for each); build it with :meth:`load`."""

    path: Path
    arrays: dict[str, np.ndarray]

    @classmethod
    def load(cls, run: str | Path) -> Recording:
        """The recording of a run folder (or of a trajectories.npz); ConfigError if there is
        none or it is from before replay."""
        path = trajectories_path(run)
        arrays = _read(path)
        if "format" not in arrays:
            raise ConfigError(f"{str(path)!r} was written before replay: it holds positions and "
                              f"statuses only, not the colourings, contacts and coverage "
                              f"replay draws; {RERUN}", key="RUN_DIR")
        if int(arrays["format"]) != FORMAT:
            raise ConfigError(f"{str(path)!r} has format {int(arrays['format'])}; this "
                              f"swarmsim reads format {FORMAT}; {RERUN}", key="RUN_DIR")
        missing = [k for k in REQUIRED if k not in arrays]
        if missing:
            raise ConfigError(f"{str(path)!r} lacks the arrays {', '.join(missing)} of format "
                              f"{FORMAT}; {RERUN}", key="RUN_DIR")
        return cls(path, arrays)

    # --- what the run was ----------------------------------------------------------------------
    @property
    def ticks(self) -> np.ndarray:
        """(T,) the recorded ticks, increasing."""
        return self.arrays["ticks"]

    @property
    def samples(self) -> int:
        return int(self.ticks.shape[0])

    @property
    def n_robots(self) -> int:
        return int(self.arrays["positions"].shape[1])

    @property
    def controller(self) -> str:
        return _text(self.arrays["controller"])

    @cached_property
    def colourings(self) -> dict[str, str]:
        """The recorded colourings (field -> "scale" / "category") the run offered."""
        names, kinds = self.arrays["colouring_names"], self.arrays["colouring_kinds"]
        return {str(n): str(k) for n, k in zip(names.tolist(), kinds.tolist(), strict=True)
                if FIELD_PREFIX + str(n) in self.arrays}

    def offered_colourings(self, color_by: str | None = None) -> tuple[str, ...]:
        """"status" and the recorded colourings; ConfigError (key --color-by) naming them when
        ``color_by`` is given and is none of them."""
        offered = ("status", *self.colourings)
        if color_by is not None and color_by not in offered:
            raise ConfigError(f"{str(self.path)!r} recorded the colourings {', '.join(offered)} "
                              f"(controller {self.controller!r}); got {color_by!r}"
                              f"{did_you_mean(color_by, offered)}", key="--color-by")
        return offered

    def _field_name(self, key: str) -> str | None:
        name = _text(self.arrays[key])
        return name if name and FIELD_PREFIX + name in self.arrays else None

    @cached_property
    def world(self) -> World:
        """The world as the run drew it (outline, spawns, obstacles, beacon, arena)."""
        a = self.arrays
        beacon = a["world_beacon"]
        return World(name=_text(a["world_name"]), source=str(self.path),
                     target=shapely.from_wkb(a["world_target"].tobytes()),
                     spawns=tuple(shapely.get_parts(shapely.from_wkb(
                         a["world_spawns"].tobytes())).tolist()),
                     obstacles=tuple(shapely.get_parts(shapely.from_wkb(
                         a["world_obstacles"].tobytes())).tolist()),
                     beacon=tuple(beacon.tolist()) if beacon.size else None,
                     arena=tuple(a["world_arena"].tolist()))

    @cached_property
    def grid(self) -> CoverageGrid:
        """The run's coverage raster."""
        a = self.arrays
        inside = a["grid_inside"]
        x0, y0, dx, dy = (float(a[f"grid_{k}"]) for k in ("x0", "y0", "dx", "dy"))
        rows, cols = inside.shape
        gx, gy = np.meshgrid(x0 + (np.arange(cols) + 0.5) * dx, y0 + (np.arange(rows) + 0.5) * dy)
        return CoverageGrid(x0, y0, dx, dy, inside, np.column_stack([gx[inside], gy[inside]]),
                            float(a["grid_radius"]))

    def renderer_arguments(self, color_by: str | None = None) -> dict[str, Any]:
        """The swarmsim.render.Renderer arguments that draw this run as its controller did:
        world, grid, colourings, leader and group fields, ``color_by``. ConfigError for a
        colouring that was not recorded."""
        self.offered_colourings(color_by)
        return {"world": self.world, "grid": self.grid, "colourings": self.colourings,
                "leader_field": self._field_name("leader_field"),
                "group_field": self._field_name("group_field"), "color_by": color_by}

    # --- samples -------------------------------------------------------------------------------
    def index_of(self, tick: Any) -> int:
        """The sample recorded at ``tick``; ConfigError (key --tick) naming the nearest
        recorded ticks when there is none."""
        ticks = self.ticks
        if isinstance(tick, bool) or not isinstance(tick, (int, np.integer)):
            raise ConfigError(f"must be a tick (an integer), got {tick!r}", key="--tick")
        hit = np.flatnonzero(ticks == tick)
        if hit.size:
            return int(hit[0])
        at = int(np.searchsorted(ticks, tick))
        near = [int(t) for t in ticks[max(0, at - 1):at + 1]]
        return _no_sample(tick, near, int(ticks[0]), int(ticks[-1]))

    def snapshot(self, index: int) -> Snapshot:
        """The Snapshot of sample ``index`` (0 .. samples - 1)."""
        changes, offsets = self.arrays["covered_changes"], self.arrays["covered_change_offsets"]
        flips = np.bincount(changes[:offsets[index + 1]].astype(np.int64),
                            minlength=self.grid.inside.size)
        return self._snapshot(index, (flips % 2).astype(bool))

    def snapshots(self, start: int = 0) -> Iterator[Snapshot]:
        """The Snapshots of samples ``start`` .. last, in order (the raster kept up to date
        from its changes, not rebuilt each time)."""
        if start >= self.samples:
            return
        covered = self.snapshot(start).covered.ravel().copy()
        changes, offsets = self.arrays["covered_changes"], self.arrays["covered_change_offsets"]
        for index in range(start, self.samples):
            if index > start:
                covered[changes[offsets[index]:offsets[index + 1]]] ^= True
            yield self._snapshot(index, covered.copy())

    def _messages(self, index: int) -> np.ndarray:
        """The recorded broadcasts of sample ``index``: ``status`` and the recorded fields."""
        a = self.arrays
        names = [k.removeprefix(FIELD_PREFIX) for k in a if k.startswith(FIELD_PREFIX)]
        dtype = np.dtype([("status", a["statuses"].dtype),
                          *((n, a[FIELD_PREFIX + n].dtype) for n in names)])
        out = np.empty(self.n_robots, dtype=dtype)
        out["status"] = a["statuses"][index]
        for n in names:
            out[n] = a[FIELD_PREFIX + n][index]
        return out

    def flags(self, key: str, index: int) -> np.ndarray:
        """(N,) bool flags ``key`` (``in_contact_bits``, ``failed_bits``, ``asleep_bits``) of
        sample ``index``."""
        return np.unpackbits(self.arrays[key][index], count=self.n_robots).astype(bool)

    def _snapshot(self, index: int, covered: np.ndarray) -> Snapshot:
        a = self.arrays
        return Snapshot(tick=int(a["ticks"][index]), positions=a["positions"][index].copy(),
                        messages=self._messages(index),
                        statuses=tuple(str(s) for s in a["status_names"].tolist()),
                        radius=float(a["radius"]), coverage=float(a["coverage"][index]),
                        covered=covered.reshape(self.grid.shape),
                        in_contact=self.flags("in_contact_bits", index),
                        failed=self.flags("failed_bits", index),
                        start_groups=a["start_groups"].astype(np.int64),
                        start_leaders=a["start_leaders"].copy(),
                        headings=a["headings"][index].copy() if "headings" in a else None)


def _no_sample(tick: int, near: list[int], first: int, last: int) -> int:
    """Refuse ``tick``, naming the recorded ticks ``near`` it."""
    if tick < first or tick > last:
        where = f"the recording holds ticks {first} to {last}"
    else:
        where = "the nearest recorded ticks are " + " and ".join(map(str, near))
    raise ConfigError(f"tick {tick} was not recorded; {where}", key="--tick")


def new_renderer(recording: Recording, color_by: str | None = None, **options: Any) -> Any:
    """A swarmsim.render.Renderer that draws ``recording``'s Snapshots as the live run drew
    them; ``options`` (width, highlight_contacts, ...) go to the Renderer. ConfigError for a
    colouring the run did not record."""
    from swarmsim.render import Renderer

    return Renderer(**recording.renderer_arguments(color_by), **options)


def replay_frames(recording: Recording, **render_options: Any) -> Iterator[np.ndarray]:
    """The (H, W, 3) uint8 frame of every recorded sample, in order; ``render_options`` go to
    the Renderer (color_by, width, highlight_contacts, ...). Each is a new read-only array
    (Renderer.draw); ``.copy()`` it to draw on it."""
    renderer = new_renderer(recording, **render_options)
    for snap in recording.snapshots():
        yield renderer.draw(snap)


def replay_video(recording: Recording, path: str | Path, fps: float = 30,
                 progress: bool = False, **render_options: Any) -> int:
    """Write every recorded sample as one frame of an MP4 at ``path`` (atomically: nothing is
    left at ``path`` if drawing fails or is interrupted); returns the number of frames.
    ``progress``: a tqdm bar on stderr."""
    from swarmsim.render import VideoWriter

    frames = replay_frames(recording, **render_options)
    first = next(frames)  # the renderer's checks (colouring, width) before any file
    bar = _progress_bar(recording.samples) if progress else None
    try:
        with VideoWriter(path, fps=fps) as writer:
            writer.write(first)
            for frame in frames:
                writer.write(frame)
                if bar is not None:
                    bar.update()
        return writer.frames
    finally:
        if bar is not None:
            bar.close()


def replay_png(recording: Recording, path: str | Path, tick: int | None = None,
               **render_options: Any) -> Path:
    """Write the recorded sample at ``tick`` (None: the last) as a PNG at ``path``
    (atomically). ConfigError when ``tick`` was not recorded (naming the nearest ones)."""
    from swarmsim.render import save_png

    index = recording.samples - 1 if tick is None else recording.index_of(tick)
    renderer = new_renderer(recording, **render_options)
    return save_png(renderer.draw(recording.snapshot(index)), path)


def _progress_bar(total: int) -> Any:
    from tqdm import tqdm

    interval = 0.5 if sys.stderr.isatty() else 30.0
    return tqdm(total=total, initial=1, unit="frame", desc="replay", file=sys.stderr,
                dynamic_ncols=True, leave=False, mininterval=interval)


END_OF_RECORDING = "end of the recording"


class ReplayRun:
    """A recording shown in the live viewer (swarmsim.render.viewer.Viewer) in place of a
    Simulation: each ``advance`` moves to the next recorded sample, so the viewer's step key
    moves one sample, ``+`` / ``-`` change the samples per frame, ``c`` cycles the recorded
    colourings and a click selects a robot, as live.

    It offers what the viewer reads of a Simulation: ``tick``, ``positions``, ``messages``,
    ``asleep``, ``stop_reason`` (END_OF_RECORDING after the last sample), ``snapshot``,
    ``advance``, ``offered_colourings``, ``new_renderer``, ``info.group_field``. A recording
    holds no commanded velocities nor listening ranges: ``velocities`` and ``listen`` are NaN
    (the panel shows nan; no lines are drawn to heard robots).
    """

    def __init__(self, recording: Recording):
        self.recording = recording
        self.world = recording.world
        self.n = recording.n_robots
        self.info = SimpleNamespace(group_field=recording.renderer_arguments()["group_field"])
        self.velocities = np.full((self.n, 2), np.nan)
        self.listen = np.full(self.n, np.nan)
        self._samples = recording.snapshots()
        self._index = 0
        self._snap = next(self._samples)
        self.stop_reason: str | None = None if recording.samples > 1 else END_OF_RECORDING

    @property
    def tick(self) -> int:
        return self._snap.tick

    @property
    def positions(self) -> np.ndarray:
        return self._snap.positions

    @property
    def messages(self) -> np.ndarray:
        return self._snap.messages

    @property
    def asleep(self) -> np.ndarray:
        return self.recording.flags("asleep_bits", self._index)

    def advance(self, on_tick: Callable[[ReplayRun], None] | None = None) -> str | None:
        """Move to the next recorded sample, then ``on_tick(self)`` if given (as
        Simulation.advance); the stop reason (END_OF_RECORDING at the last)."""
        if self.stop_reason is None:
            self._snap = next(self._samples)
            self._index += 1
            if self._index == self.recording.samples - 1:
                self.stop_reason = END_OF_RECORDING
            if on_tick is not None:
                on_tick(self)
        return self.stop_reason

    def snapshot(self, with_coverage: bool = True) -> Snapshot:
        """The current sample (without the covered raster when ``with_coverage`` is False)."""
        return self._snap if with_coverage else dataclasses.replace(self._snap, covered=None)

    def offered_colourings(self, color_by: str | None = None) -> tuple[str, ...]:
        return self.recording.offered_colourings(color_by)

    def new_renderer(self, **options: Any) -> Any:
        return new_renderer(self.recording, **options)


def replay_view(recording: Recording, width: int | None = None, color_by: str | None = None,
                max_frames: int | None = None) -> Any:
    """Open the live viewer on ``recording`` (see :class:`ReplayRun`) until the user quits
    (or ``max_frames`` frames); returns the closed Viewer. ConfigError without a display."""
    from swarmsim.render.viewer import view

    return view(ReplayRun(recording), width=width, color_by=color_by, max_frames=max_frames)
