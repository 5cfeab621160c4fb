"""The live viewer (swarmsim.render.viewer) under SDL's dummy video driver: posted key and mouse
events pause, step, select the robot nearest a click and change the colouring; no display ->
one error line, exit 2."""

from __future__ import annotations

import os
import subprocess
import sys
from collections.abc import Iterator

import numpy as np
import pygame
import pytest

from swarmsim import Simulation
from swarmsim.render import viewer as vw


@pytest.fixture
def viewer(tmp_path, monkeypatch) -> Iterator[vw.Viewer]:
    monkeypatch.setenv(vw.HEADLESS_ENV, "1")
    sim = Simulation("tiny", controller="ggc", robots=30, groups=2, seed=0, max_ticks=500)
    v = vw.Viewer(sim, width=320, save_dir=tmp_path)
    yield v
    v.close()


def _key(key: int, text: str = "") -> None:
    pygame.event.post(pygame.event.Event(pygame.KEYDOWN, key=key, unicode=text, mod=0))


def _click(pos: tuple[int, int]) -> None:
    pygame.event.post(pygame.event.Event(pygame.MOUSEBUTTONDOWN, button=1, pos=pos))
    pygame.event.post(pygame.event.Event(pygame.MOUSEBUTTONUP, button=1, pos=pos))


def _move(pos: tuple[int, int], held: bool = False) -> None:
    pygame.event.post(pygame.event.Event(pygame.MOUSEMOTION, pos=pos, rel=(0, 0),
                                         buttons=(int(held), 0, 0)))


def _wheel(notches: float) -> None:
    pygame.event.post(pygame.event.Event(pygame.MOUSEWHEEL, x=0, y=int(notches),
                                         precise_x=0.0, precise_y=float(notches),
                                         flipped=False))


def _drag(start: tuple[int, int], end: tuple[int, int]) -> None:
    pygame.event.post(pygame.event.Event(pygame.MOUSEBUTTONDOWN, button=1, pos=start))
    mid = ((start[0] + end[0]) // 2, (start[1] + end[1]) // 2)
    _move(mid, held=True)
    _move(end, held=True)
    pygame.event.post(pygame.event.Event(pygame.MOUSEBUTTONUP, button=1, pos=end))


def test_frames_advance_the_run_and_space_pauses_it(viewer):
    assert viewer.frame() and viewer.sim.tick == 1
    _key(pygame.K_SPACE, " ")
    for _ in range(3):
        assert viewer.frame()
    assert viewer.state.paused and viewer.sim.tick == 1
    _key(pygame.K_SPACE, " ")
    viewer.frame()
    assert not viewer.state.paused and viewer.sim.tick == 2


def test_period_steps_exactly_one_tick(viewer):
    _key(pygame.K_SPACE, " ")
    viewer.frame()
    tick = viewer.sim.tick
    _key(pygame.K_PERIOD, ".")
    viewer.frame()
    viewer.frame()
    assert viewer.sim.tick == tick + 1
    _key(pygame.K_PERIOD, ".")
    _key(pygame.K_PERIOD, ".")
    viewer.frame()
    assert viewer.sim.tick == tick + 3


def test_plus_and_minus_change_ticks_per_frame(viewer):
    _key(pygame.K_PLUS, "+")
    _key(pygame.K_PLUS, "+")
    viewer.frame()
    assert viewer.state.ticks_per_frame == 4 and viewer.sim.tick == 4
    _key(pygame.K_MINUS, "-")
    viewer.frame()
    assert viewer.state.ticks_per_frame == 2 and viewer.sim.tick == 6


def test_click_selects_the_robot_nearest_it(viewer):
    viewer.frame()
    pixels = viewer.renderer.world_to_pixel(viewer.sim.positions)
    click = (int(pixels[7, 0]) + 1, int(pixels[7, 1]))  # beside robot 7
    _key(pygame.K_SPACE, " ")  # paused: the robots stay where the click was aimed
    viewer.frame()
    pixels = viewer.renderer.world_to_pixel(viewer.sim.positions)
    expected = int(np.argmin(np.sum((pixels - np.asarray(click, float)) ** 2, axis=1)))
    _click(click)
    viewer.frame()
    assert viewer.state.selected == expected
    lines = viewer.panel_lines(viewer.sim.snapshot())
    assert f"robot {expected}" in lines
    assert any(line.startswith("  gradient = ") for line in lines)
    assert any(line.startswith("group ") for line in lines)
    assert any(line.startswith("velocity (") for line in lines)
    assert "awake" in lines or "asleep" in lines
    sim = viewer.sim
    d = np.hypot(*(sim.positions - sim.positions[expected]).T)
    hears = int(np.count_nonzero((d <= sim.listen[expected]) & ~sim.failed)) - 1
    assert any(line.startswith(f"hears {hears} ") for line in lines)


def test_a_click_beside_the_frame_keeps_the_selection(viewer):
    _click((5, 5))
    viewer.frame()
    chosen = viewer.state.selected
    assert chosen is not None
    _click((viewer.renderer.width + 10, 5))  # on the panel
    viewer.frame()
    assert viewer.state.selected == chosen


def test_c_cycles_the_colouring_and_the_frame_changes(viewer):
    for _ in range(20):
        viewer.frame()
    assert viewer.state.colourings == ("status", "gradient", "group")
    first = viewer.state.color_by
    before = viewer.renderer.robot_colors(viewer.sim.snapshot()).copy()
    _key(pygame.K_SPACE, " ")
    _key(pygame.K_c, "c")
    viewer.frame()
    assert viewer.state.color_by != first
    assert viewer.renderer.color_by == viewer.state.color_by
    assert not np.array_equal(viewer.renderer.robot_colors(viewer.sim.snapshot()), before)
    for _ in range(2):
        _key(pygame.K_c, "c")
    viewer.frame()
    assert viewer.state.color_by == first


def test_o_toggles_the_coverage_tint(viewer):
    assert viewer.state.coverage
    _key(pygame.K_o, "o")
    viewer.frame()
    assert not viewer.state.coverage and not viewer.renderer.show_coverage
    _key(pygame.K_o, "o")
    viewer.frame()
    assert viewer.state.coverage and viewer.renderer.show_coverage


def test_s_saves_a_png_of_the_window(viewer, tmp_path):
    _key(pygame.K_s, "s")
    viewer.frame()
    assert viewer.saved == [tmp_path / f"view-tick{viewer.sim.tick}.png"]
    import imageio.v3 as iio

    image = iio.imread(viewer.saved[0])
    assert image.shape[1] == viewer.renderer.width + vw.PANEL_WIDTH


def test_q_and_closing_the_window_end_the_loop(viewer):
    _key(pygame.K_q, "q")
    assert not viewer.frame()
    state = vw.handle_event(viewer.state, pygame.event.Event(pygame.QUIT), lambda p: None)
    assert state.quit


def test_view_stops_at_max_frames_and_the_run_is_unchanged(monkeypatch):
    monkeypatch.setenv(vw.HEADLESS_ENV, "1")
    shown = Simulation("tiny", controller="ggc", robots=30, groups=2, seed=0, max_ticks=500)
    viewer = shown.view(width=320, max_frames=12)
    plain = Simulation("tiny", controller="ggc", robots=30, groups=2, seed=0, max_ticks=500)
    for _ in range(12):
        plain.advance()
    assert viewer.frames == 12 and shown.tick == 12
    np.testing.assert_array_equal(shown.positions, plain.positions)
    np.testing.assert_array_equal(shown.messages, plain.messages)


def test_display_problem_rules():
    assert vw.display_problem({}, "linux") == vw.NO_DISPLAY
    assert vw.display_problem({"DISPLAY": ":0"}, "linux") is None
    assert vw.display_problem({"WAYLAND_DISPLAY": "wayland-0"}, "linux") is None
    assert vw.display_problem({vw.HEADLESS_ENV: "1"}, "linux") is None
    assert vw.display_problem({}, "darwin") is None


@pytest.mark.skipif(not sys.platform.startswith("linux"), reason="the X11/Wayland rule")
def test_view_without_a_display_prints_one_line_and_exits_2():
    env = {k: v for k, v in os.environ.items()
           if k not in ("DISPLAY", "WAYLAND_DISPLAY", vw.HEADLESS_ENV)}
    proc = subprocess.run([sys.executable, "-m", "swarmsim", "view", "tiny"], env=env,
                          check=False, capture_output=True, text=True, timeout=120)
    assert proc.returncode == 2
    lines = proc.stderr.strip().splitlines()
    assert len(lines) == 1
    assert lines[0].startswith("swarmsim: error: no display")
    assert "--video" in lines[0] and "xvfb-run" in lines[0]


# --- zoom, pan, reset -------------------------------------------------------------------------

def test_the_wheel_zooms_about_the_pointer(viewer):
    _key(pygame.K_SPACE, " ")
    pointer = (80, 60)
    _move(pointer)
    _wheel(2)
    viewer.frame()
    camera = viewer.state.camera
    assert camera.zoom == pytest.approx(vw.ZOOM_STEP ** 2)
    # the frame pixel under the pointer stays under it
    np.testing.assert_allclose(camera.to_frame(pointer), pointer)
    np.testing.assert_allclose(camera.to_window(camera.to_frame((10, 200))), (10, 200))
    _wheel(-1)
    viewer.frame()
    assert viewer.state.camera.zoom == pytest.approx(vw.ZOOM_STEP)
    np.testing.assert_allclose(viewer.state.camera.to_frame(pointer), pointer)
    for _ in range(3):
        _wheel(-1)
    viewer.frame()
    assert viewer.state.camera.zoom == 1.0  # never below the whole frame
    for _ in range(40):
        _wheel(1)
    viewer.frame()
    assert viewer.state.camera.zoom == vw.MAX_ZOOM


def test_the_wheel_over_the_panel_does_not_zoom(viewer):
    _move((viewer.renderer.width + 20, 20))
    _wheel(1)
    viewer.frame()
    assert viewer.state.camera.zoom == 1.0


def test_a_drag_pans_and_selects_nothing(viewer):
    _key(pygame.K_SPACE, " ")
    _move((160, 100))
    _wheel(4)
    viewer.frame()
    before = viewer.state.camera
    _drag((160, 100), (200, 80))
    viewer.frame()
    after = viewer.state.camera
    assert viewer.state.selected is None and not viewer.state.dragging
    assert after.zoom == before.zoom
    np.testing.assert_allclose(np.subtract(after.centre, before.centre),
                               np.array([-40, 20]) / before.zoom)
    # the frame point under the press now lies under the release
    np.testing.assert_allclose(after.to_window(before.to_frame((160, 100))), (200, 80))


def test_a_press_that_barely_moves_is_a_click(viewer):
    _key(pygame.K_SPACE, " ")
    viewer.frame()
    pygame.event.post(pygame.event.Event(pygame.MOUSEBUTTONDOWN, button=1, pos=(100, 100)))
    _move((102, 101), held=True)
    pygame.event.post(pygame.event.Event(pygame.MOUSEBUTTONUP, button=1, pos=(102, 101)))
    viewer.frame()
    assert viewer.state.selected is not None
    assert viewer.state.camera == vw.Camera.whole_frame(viewer.renderer.size)


def test_a_pan_stays_on_the_frame(viewer):
    _drag((100, 100), (300, 200))  # at zoom 1 there is nothing to pan to
    viewer.frame()
    assert viewer.state.camera == vw.Camera.whole_frame(viewer.renderer.size)
    _move((100, 100))
    _wheel(3)
    _drag((100, 100), (319, 239))
    _drag((100, 100), (319, 239))
    viewer.frame()
    np.testing.assert_allclose(viewer.state.camera.top_left, (0, 0))


def test_zero_and_r_reset_the_view(viewer):
    for key, text in ((pygame.K_0, "0"), (pygame.K_r, "r")):
        _move((50, 50))
        _wheel(3)
        _drag((50, 50), (120, 90))
        viewer.frame()
        assert viewer.state.camera.zoom > 1
        _key(key, text)
        viewer.frame()
        assert viewer.state.camera == vw.Camera.whole_frame(viewer.renderer.size)


def _window_pixels(viewer) -> np.ndarray:
    w, h = viewer._window.get_size()
    rgb = np.frombuffer(pygame.image.tobytes(viewer._window, "RGB"), np.uint8)
    return rgb.reshape(h, w, 3)


def test_a_click_on_a_robot_drawn_zoomed_and_panned_selects_it(viewer):
    for _ in range(30):
        viewer.frame()
    _key(pygame.K_SPACE, " ")  # paused: the robots stay where the click is aimed
    viewer.frame()
    swarm = viewer.renderer.world_to_pixel(viewer.sim.positions.mean(axis=0))
    pointer = (int(swarm[0]), int(swarm[1]))
    _move(pointer)
    _wheel(6)  # zoom 3.8 about the swarm
    _drag(pointer, (pointer[0] - 30, pointer[1] + 20))
    viewer.frame()
    camera, sim, renderer = viewer.state.camera, viewer.sim, viewer.renderer
    assert camera.zoom > 3 and camera.top_left != (0, 0)
    drawn = camera.to_window(renderer.world_to_pixel(sim.positions))
    on_screen = np.flatnonzero(np.all((drawn >= 10) & (drawn < np.subtract(camera.size, 10)),
                                      axis=1))
    assert len(on_screen) >= 2
    # the robot on screen farthest from its nearest neighbour: no doubt which one a click means
    gaps = [np.sort(np.hypot(*(sim.positions - sim.positions[i]).T))[1] for i in on_screen]
    robot = int(on_screen[int(np.argmax(gaps))])
    click = (round(float(drawn[robot, 0])), round(float(drawn[robot, 1])))
    # the window shows it there, in its colour
    colour = renderer.robot_colors(sim.snapshot())[robot]
    np.testing.assert_array_equal(_window_pixels(viewer)[click[1], click[0]], colour)
    # ignoring the camera the same window pixel would name another robot
    unzoomed = vw.nearest_robot(renderer.world_to_pixel(sim.positions), click)
    assert unzoomed != robot
    _click(click)
    viewer.frame()
    assert viewer.state.selected == robot
    world = vw.frame_to_world(renderer, camera.to_frame(click))
    assert robot == int(np.argmin(np.hypot(*(sim.positions - world).T)))
    assert f"robot {robot}" in viewer.panel_lines(sim.snapshot())


def test_frame_to_world_inverts_world_to_pixel(viewer):
    points = np.array([[0.0, 0.0], [3.5, -2.25], [-7.0, 11.0]])
    np.testing.assert_allclose(
        vw.frame_to_world(viewer.renderer, viewer.renderer.world_to_pixel(points)), points)


# --- fitting the screen -------------------------------------------------------------------------

def test_the_window_fits_a_small_screen_and_keeps_its_width_on_a_large_one():
    from swarmsim.render.frame import DEFAULT_WIDTH, frame_size
    from swarmsim.world import load_world

    arena = load_world("K").arena  # taller than wide
    assert vw.fitted_width(arena, None) == DEFAULT_WIDTH
    assert vw.fitted_width(arena, (3840, 2160)) == DEFAULT_WIDTH
    width = vw.fitted_width(arena, (1366, 768))
    w, h = frame_size(arena, width)
    assert width < DEFAULT_WIDTH and h <= 768 - vw.SCREEN_MARGIN[1]
    assert w + vw.PANEL_WIDTH <= 1366 - vw.SCREEN_MARGIN[0]
    assert frame_size(arena, width + 16)[1] > 768 - vw.SCREEN_MARGIN[1]  # the widest that fits
    assert vw.fitted_width(arena, (200, 150)) == vw.MIN_FITTED_WIDTH


def test_a_field_of_no_elements_is_not_listed(viewer):
    snap = viewer.sim.snapshot()
    empty = [n for n in snap.messages.dtype.names if not np.size(snap.messages[0][n])]
    lines = vw.robot_lines(snap, 0, None, "group")
    assert empty, "GGC's per-group fields of no groups are the case this test is about"
    assert not any(line.strip().startswith(f"{n} =") for n in empty for line in lines)
    assert any(line.strip().startswith("gradient =") for line in lines)
