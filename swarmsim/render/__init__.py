"""Headless rendering: snapshots -> RGB frames -> MP4 / PNG.

``Renderer`` draws with pygame-ce on an off-screen surface (no window, no audio);
``VideoWriter`` streams frames into an H.264 MP4; ``save_png`` writes one frame.
"""

from swarmsim.render.frame import Renderer
from swarmsim.render.video import VideoWriter, save_png

__all__ = ["Renderer", "VideoWriter", "save_png"]
