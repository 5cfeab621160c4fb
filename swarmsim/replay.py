"""Drawing a recorded run again, without simulating it: ``swarmsim replay``.

The frames come from the Snapshots of the run's trajectories.npz (swarmsim.results.replay)
through the same Renderer the live run used, so a replay drawn with the run's options is the
live video's frames at the recorded ticks, pixel for pixel; any colouring the run recorded,
any width and frame rate may be chosen instead.

Python API::

    from swarmsim.replay import replay_video, replay_png
    from swarmsim.results.replay import Recording

    rec = Recording.load("out/k")
    replay_video(rec, "k-groups.mp4", color_by="group", fps=24)
    replay_png(rec, "k-500.png", tick=500)
"""

from __future__ import annotations

import sys
from collections.abc import Iterator
from pathlib import Path
from typing import Any

import numpy as np

from swarmsim.results.replay import Recording


def new_renderer(recording: Recording, color_by: str | None = None, **options: Any) -> Any:
    """A swarmsim.render.Renderer that draws ``recording``'s Snapshots as the live run drew
    them; ``options`` (width, highlight_contacts, ...) go to the Renderer. ConfigError for a
    colouring the run did not record."""
    from swarmsim.render import Renderer

    return Renderer(**recording.renderer_arguments(color_by), **options)


def replay_frames(recording: Recording, **render_options: Any) -> Iterator[np.ndarray]:
    """The (H, W, 3) uint8 frame of every recorded sample, in order; ``render_options`` go to
    the Renderer (color_by, width, highlight_contacts, ...). Each array is read-only and valid
    until the next one is drawn (copy it to keep it)."""
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
