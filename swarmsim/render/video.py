"""Streaming MP4 (H.264) writing and atomic PNG saving for rendered frames.

Frames go straight into an ffmpeg child process (imageio's legacy FFMPEG writer); nothing keeps
the whole video in memory. The video is written to a hidden temporary file next to ``path`` and
renamed onto ``path`` only when the writer closes cleanly, so ``path`` never holds a half-written
file; on an error the temporary file is deleted.
"""

from __future__ import annotations

import contextlib
import logging
import math
import os
import secrets
from pathlib import Path
from types import TracebackType
from typing import Any, Self

import numpy as np

log = logging.getLogger(__name__)


def _temp_path(path: Path, default_suffix: str) -> Path:
    suffix = path.suffix or default_suffix
    return path.with_name(f".{path.name}.{os.getpid()}.{secrets.token_hex(4)}.tmp{suffix}")


def _unlink_quietly(path: Path) -> None:
    try:
        path.unlink()
    except FileNotFoundError:
        pass


def _check_frame(frame: Any) -> np.ndarray:
    arr = np.asarray(frame)
    if arr.dtype != np.uint8 or arr.ndim != 3 or arr.shape[2] != 3:
        raise ValueError(f"a frame must be an (H, W, 3) uint8 RGB array, got shape "
                         f"{arr.shape} dtype {arr.dtype}")
    if arr.shape[0] == 0 or arr.shape[1] == 0:
        raise ValueError(f"empty frame, shape {arr.shape}")
    return arr


class VideoWriter:
    """Stream RGB frames into an H.264 MP4 (yuv420p), atomically.

    Use as a context manager::

        with VideoWriter("run.mp4", fps=30) as vw:
            for snap in snapshots:
                vw.write(renderer.draw(snap))

    Args:
        path: output file (its directory must exist). An existing file is replaced.
        fps: frames per second of the video (> 0).
        preset: x264 speed preset (``"veryfast"`` is ~2.5x faster than x264's default
            ``"medium"`` at almost the same size).
        quality: imageio's 0..10 quality scale (5 maps to crf 25); None leaves x264's default.

    Attributes:
        frames: number of frames written so far.
        size: (width, height) of the frames, once the first one is written.
    """

    def __init__(self, path: str | os.PathLike[str], fps: float = 30, preset: str = "veryfast",
                 quality: float | None = 5):
        if isinstance(fps, bool) or not isinstance(fps, (int, float)) or not math.isfinite(fps) \
                or fps <= 0:
            raise ValueError(f"fps must be a positive number, got {fps!r}")
        if quality is not None and (isinstance(quality, bool) or not 0 <= quality <= 10):
            raise ValueError(f"quality must be in 0..10 or None, got {quality!r}")
        if not isinstance(preset, str) or not preset:
            raise ValueError(f"preset must be an x264 preset name, got {preset!r}")
        self.path = Path(path)
        if not self.path.parent.is_dir():
            raise FileNotFoundError(f"directory does not exist: {str(self.path.parent)!r}")
        self.fps = fps
        self.preset = preset
        self.quality = quality
        self.frames = 0
        self.size: tuple[int, int] | None = None
        self._tmp = _temp_path(self.path, ".mp4")
        self._writer: Any = None
        self._closed = False

    def __enter__(self) -> Self:
        return self

    def __exit__(self, exc_type: type[BaseException] | None, exc: BaseException | None,
                 tb: TracebackType | None) -> None:
        if exc_type is None:
            self.close()
        else:
            self.abort()

    def _open(self, width: int, height: int) -> None:
        import imageio.v2 as iio2

        # 16 is x264's macroblock; with a size that is not a multiple of 16 imageio would
        # silently rescale, so use 2 (just "even") for such sizes instead.
        mbs = 16 if width % 16 == 0 and height % 16 == 0 else 2
        self._writer = iio2.get_writer(
            str(self._tmp), format="FFMPEG", fps=self.fps, codec="libx264",
            quality=self.quality, pixelformat="yuv420p", macro_block_size=mbs,
            output_params=["-preset", self.preset])

    def write(self, frame: np.ndarray) -> None:
        """Append one (H, W, 3) uint8 RGB frame. Every frame must have the same, even size."""
        if self._closed:
            raise ValueError(f"VideoWriter for {str(self.path)!r} is closed")
        arr = _check_frame(frame)
        h, w = arr.shape[:2]
        if self.size is None:
            if w % 2 or h % 2:
                raise ValueError(f"H.264 needs even frame sizes, got {w}x{h}")
            self._open(w, h)
            self.size = (w, h)
        elif (w, h) != self.size:
            raise ValueError(f"frame size changed from {self.size[0]}x{self.size[1]} to {w}x{h}")
        self._writer.append_data(np.ascontiguousarray(arr))
        self.frames += 1

    def close(self) -> None:
        """Finish the video and move it onto ``path``. Raises ValueError if no frame was written."""
        if self._closed:
            return
        self._closed = True
        writer, self._writer = self._writer, None
        if writer is None:
            _unlink_quietly(self._tmp)
            raise ValueError(f"no frames were written; {str(self.path)!r} not created")
        try:
            writer.close()
            os.replace(self._tmp, self.path)
        except BaseException:
            _unlink_quietly(self._tmp)
            raise

    def abort(self) -> None:
        """Stop writing and delete the temporary file; ``path`` is left untouched."""
        if self._closed:
            return
        self._closed = True
        writer, self._writer = self._writer, None
        try:
            if writer is not None:
                writer.close()
        except (OSError, RuntimeError, ValueError) as exc:  # ffmpeg may already be gone
            log.debug("closing aborted video writer for %s: %s", self.path, exc)
        finally:
            _unlink_quietly(self._tmp)

    def __del__(self) -> None:
        # never leave a temporary file behind when the writer is dropped unclosed
        with contextlib.suppress(Exception):
            self.abort()


def save_png(frame: np.ndarray, path: str | os.PathLike[str]) -> Path:
    """Write an (H, W, 3) uint8 RGB frame as a PNG, atomically (temp file + rename)."""
    import imageio.v3 as iio

    arr = _check_frame(frame)
    path = Path(path)
    tmp = _temp_path(path, ".png")
    try:
        iio.imwrite(tmp, np.ascontiguousarray(arr), extension=".png")
        os.replace(tmp, path)
    except BaseException:
        _unlink_quietly(tmp)
        raise
    return path
