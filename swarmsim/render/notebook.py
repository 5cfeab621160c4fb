"""A Simulation in a Jupyter notebook: its current frame inline, and a stretch of the run as an
HTML5 video (``Simulation._repr_png_``, ``Simulation.show`` and ``Simulation.video``).

Jupyter shows an object through its ``_repr_png_`` / ``_repr_html_`` methods; they need no
IPython here. Displaying explicitly (``show``) goes through IPython's display and needs the
optional extra ``notebook`` (``pip install 'swarmsim[notebook]'``: ipython, nbformat, nbclient,
ipykernel); without IPython it raises one ConfigError line naming the extra. Importing this
module imports neither IPython nor an encoder.
"""

from __future__ import annotations

import base64
import os
import tempfile
from dataclasses import dataclass
from pathlib import Path
from typing import Any

import numpy as np

from swarmsim.errors import ConfigError

Simulation = Any  # swarmsim.engine.sim.Simulation: the engine imports render, never the reverse

EXTRA = "pip install 'swarmsim[notebook]'"
NO_IPYTHON = f"showing a simulation in a notebook needs IPython: {EXTRA}"


def png_bytes(frame: np.ndarray) -> bytes:
    """An (H, W, 3) uint8 RGB frame encoded as PNG."""
    import imageio.v3 as iio

    return bytes(iio.imwrite("<bytes>", np.ascontiguousarray(frame), extension=".png"))


def ipython_display() -> Any:
    """IPython's ``IPython.display`` module; ConfigError (the NO_IPYTHON line) without it."""
    try:
        from IPython import display
    except ImportError:
        raise ConfigError(NO_IPYTHON) from None
    return display


@dataclass(frozen=True)
class InlineVideo:
    """An H.264 MP4 of a stretch of a run; Jupyter shows it as an HTML5 ``<video>``.

    Attributes:
        mp4: the video file's bytes.
        fps: frames per second it plays at.
        frames: number of frames.
        first_tick: the tick of its first frame.
        last_tick: the tick of its last frame.
    """

    mp4: bytes
    fps: float
    frames: int
    first_tick: int
    last_tick: int

    def _repr_html_(self) -> str:
        data = base64.b64encode(self.mp4).decode("ascii")
        return (f'<video controls loop autoplay muted playsinline '
                f'title="ticks {self.first_tick} to {self.last_tick}">'
                f'<source type="video/mp4" src="data:video/mp4;base64,{data}"></video>')

    def show(self) -> None:
        """Display the video in the notebook now (IPython's display)."""
        display = ipython_display()
        display.display(display.HTML(self._repr_html_()))

    def save(self, path: str | os.PathLike[str]) -> Path:
        """Write the MP4 to ``path``; returns it."""
        path = Path(path)
        path.write_bytes(self.mp4)
        return path


def show_frame(sim: Simulation, width: int, color_by: str | None) -> None:
    """Display ``sim``'s current frame (``width`` pixels wide) in the notebook now."""
    display = ipython_display()
    display.display(display.Image(data=png_bytes(sim.render(color_by=color_by, width=width))))


def record_video(sim: Simulation, ticks: int | None, every: int, width: int, fps: float,
                 color_by: str | None) -> InlineVideo:
    """Advance ``sim`` by ``ticks`` ticks (None: until its run stops), drawing its current
    state, then a frame every ``every`` ticks and the last tick; returns the video. The run
    advances exactly as ``Simulation.run`` would advance it. ConfigError for a bad
    argument."""
    _check_count("ticks", ticks, 0, allow_none=True)
    _check_count("every", every, 1)
    from swarmsim.render.video import VideoWriter

    renderer = sim.new_renderer(width=width, color_by=color_by)
    first = sim.tick
    end = None if ticks is None else first + ticks
    with tempfile.TemporaryDirectory(prefix="swarmsim-video-") as folder:
        path = Path(folder) / "run.mp4"
        with VideoWriter(path, fps=fps) as writer:
            writer.write(renderer.draw(sim.snapshot()))
            drawn = sim.tick
            while sim.stop_reason is None and (end is None or sim.tick < end):
                sim.advance()
                if (sim.tick - first) % every == 0:
                    writer.write(renderer.draw(sim.snapshot()))
                    drawn = sim.tick
            if drawn != sim.tick:
                writer.write(renderer.draw(sim.snapshot()))
            frames = writer.frames
        mp4 = path.read_bytes()
    return InlineVideo(mp4=mp4, fps=fps, frames=frames, first_tick=first, last_tick=sim.tick)


def _check_count(key: str, value: Any, least: int, allow_none: bool = False) -> None:
    if value is None and allow_none:
        return
    if isinstance(value, bool) or not isinstance(value, (int, np.integer)) or value < least:
        raise ConfigError(f"must be an integer >= {least}, got {value!r}", key=key)
