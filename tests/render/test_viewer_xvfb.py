"""The live viewer in a real X window: under a virtual X server (Xvfb) the viewer runs a small
world with a robot selected, and a screenshot of the X screen (taken by this test, not the
viewer) shows the robots in their colours, the target, the ring on the selected robot and the
panel's text down to the selected robot's lines. Skips when Xvfb is not installed
(.ci/run installs it when it can)."""

from __future__ import annotations

import os
import select
import shutil
import subprocess
import sys
from collections.abc import Iterator

import numpy as np
import pygame
import pytest
import shapely

from swarmsim import Simulation
from swarmsim.render import Renderer
from swarmsim.render import viewer as vw
from swarmsim.render.palette import COVER_FILL, TARGET_FILL

XVFB = shutil.which("Xvfb")
pytestmark = pytest.mark.skipif(XVFB is None, reason="Xvfb is not installed (Debian: xvfb)")

WIDTH = 480  # the frame's width in pixels
TICKS = 400  # ticks run before the screenshot
ROBOT = 5  # the robot selected
RUN = {"world": "tiny", "controller": "ggc", "robots": 30, "groups": 2, "seed": 0,
       "max_ticks": 500}

# The viewer, in its own process on the X server: run TICKS ticks, pause, select ROBOT, draw
# until the test closes its stdin.
SHOW = f"""
import dataclasses, sys, threading
from swarmsim import Simulation
from swarmsim.render.viewer import Viewer
sim = Simulation(**{RUN!r})
for _ in range({TICKS}):
    sim.advance()
viewer = Viewer(sim, width={WIDTH})
viewer.state = dataclasses.replace(viewer.state, paused=True, selected={ROBOT})
closed = threading.Event()
threading.Thread(target=lambda: (sys.stdin.read(), closed.set()), daemon=True).start()
for frame in range(100000):
    viewer.frame()
    if frame == 3:
        print("shown", flush=True)
    if closed.wait(0.05):
        break
viewer.close()
"""


@pytest.fixture
def x_display() -> Iterator[str]:
    """A fresh Xvfb screen (1024 x 768, 24 bit); yields its name (":N")."""
    assert XVFB is not None
    read_end, write_end = os.pipe()
    server = subprocess.Popen([XVFB, "-displayfd", str(write_end), "-screen", "0",
                               "1024x768x24", "-nolisten", "tcp"], pass_fds=(write_end,),
                              stdout=subprocess.DEVNULL, stderr=subprocess.DEVNULL)
    os.close(write_end)
    try:
        ready, _, _ = select.select([read_end], [], [], 30)
        number = os.read(read_end, 16).decode().strip() if ready else ""
        if not number:
            pytest.fail("Xvfb did not report its display number within 30 s")
        yield f":{number}"
    finally:
        os.close(read_end)
        server.terminate()
        server.wait(timeout=10)


def _screenshot(display: str) -> np.ndarray:
    """The X screen ``display`` as an (H, W, 3) uint8 array: PIL's ImageGrab over XCB, else
    xwd (the x11-apps package) read by PIL."""
    from PIL import Image, ImageGrab, features

    if features.check("xcb"):
        return np.asarray(ImageGrab.grab(xdisplay=display).convert("RGB"))
    xwd = shutil.which("xwd")
    if xwd is None:
        pytest.skip("no way to grab the X screen: Pillow without XCB and no xwd")
    raw = subprocess.run([xwd, "-root", "-silent", "-display", display], check=True,
                         capture_output=True, timeout=30).stdout
    import io

    return np.asarray(Image.open(io.BytesIO(raw)).convert("RGB"))


def _expected() -> tuple[Simulation, Renderer]:
    """The same run and frame geometry in this process (dummy driver), for what the screen
    should show."""
    sim = Simulation(**RUN)
    for _ in range(TICKS):
        sim.advance()
    return sim, sim.new_renderer(width=WIDTH)


def test_a_screenshot_under_xvfb_shows_robots_target_and_panel(x_display, tmp_path):
    env = {k: v for k, v in os.environ.items() if k not in (vw.HEADLESS_ENV, "WAYLAND_DISPLAY")}
    env.update(DISPLAY=x_display, SDL_VIDEODRIVER="x11", SDL_VIDEO_WINDOW_POS="0,0")
    shown = subprocess.Popen([sys.executable, "-c", SHOW], env=env, stdin=subprocess.PIPE,
                             stdout=subprocess.PIPE, stderr=subprocess.PIPE, text=True)
    try:
        ready, _, _ = select.select([shown.stdout], [], [], 300)
        line = shown.stdout.readline() if ready else ""
        if line.strip() != "shown":
            shown.kill()
            pytest.fail(f"the viewer did not show a frame: {shown.stderr.read()[-2000:]}")
        screen = _screenshot(x_display)
    finally:
        if shown.poll() is None:
            shown.communicate("", timeout=60)
    assert shown.returncode == 0, shown.stderr
    from PIL import Image

    shot = tmp_path / "xvfb-viewer.png"
    Image.fromarray(screen).save(shot)
    print(f"screenshot: {shot}")
    _check_screen(screen)


def _check_screen(screen: np.ndarray) -> None:
    sim, renderer = _expected()
    width, height = renderer.size
    frame = screen[:height, :width]
    snap = sim.snapshot()
    # robots: most centres show the robot's colour (lines to the robots the selected one
    # hears cross some of them)
    centres = np.rint(renderer.world_to_pixel(snap.positions)).astype(int)
    colours = renderer.robot_colors(snap)
    seen = np.all(frame[centres[:, 1], centres[:, 0]] == colours, axis=1)
    assert seen.mean() >= 0.6, f"only {seen.sum()} of {len(seen)} robots seen"
    # the target: sampled points inside it, away from robots, show its fill or coverage tint
    xmin, ymin, xmax, ymax = sim.world.target.bounds
    gx, gy = np.meshgrid(np.linspace(xmin, xmax, 25)[1:-1], np.linspace(ymin, ymax, 25)[1:-1])
    points = np.column_stack([gx.ravel(), gy.ravel()])
    inside = shapely.contains_xy(sim.world.target, points[:, 0], points[:, 1])
    far = np.min(np.hypot(*(points[:, None, :] - snap.positions[None]).transpose(2, 0, 1)),
                 axis=1) > 3 * snap.radius
    pixels = np.rint(renderer.world_to_pixel(points[inside & far])).astype(int)
    shades = frame[pixels[:, 1], pixels[:, 0]]
    target = np.all(shades == TARGET_FILL, axis=1) | np.all(shades == COVER_FILL, axis=1)
    assert len(shades) > 50 and target.mean() >= 0.8, f"target seen at {target.mean():.0%}"
    # the selected robot's ring (yellow) around its centre
    cx, cy = centres[ROBOT]
    around = frame[max(0, cy - 20):cy + 21, max(0, cx - 20):cx + 21].reshape(-1, 3)
    assert np.count_nonzero(np.all(around == (255, 200, 0), axis=1)) >= 20
    # the panel: light text on the dark panel, down past the lines shown with no selection
    panel = screen[:height, width:width + vw.PANEL_WIDTH]
    text_rows = np.flatnonzero(np.any(panel.min(axis=2) >= 180, axis=1))
    pygame.font.init()
    line = pygame.font.Font(None, 18).get_linesize()
    unselected = 5 + 1 + len(vw.HELP_LINES) + 1  # heads-up, blank, help, blank
    # the selected robot's id, status, group, awake, position, velocity, hears, broadcast:
    # and its fields (GGC broadcasts more than ten)
    assert len(text_rows) > 0 and text_rows.max() > 8 + (unselected + 12) * line, (
        "the panel does not show the selected robot's lines")
