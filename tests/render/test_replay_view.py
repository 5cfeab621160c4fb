"""``swarmsim replay --view``: the live viewer on a recording (swarmsim.replay.ReplayRun),
under SDL's dummy video driver: each frame moves one recorded sample, space pauses, ``.``
steps one sample, ``c`` cycles the recorded colourings, the run ends at the last sample."""

from __future__ import annotations

from collections.abc import Iterator
from pathlib import Path

import numpy as np
import pygame
import pytest

from swarmsim import Simulation
from swarmsim.cli import main
from swarmsim.recording import Recorder
from swarmsim.render import viewer as vw
from swarmsim.replay import END_OF_RECORDING, Recording, ReplayRun, new_renderer
from tests.conftest import small_world
from tests.errlines import one_error_line

EVERY = 10


@pytest.fixture(scope="module")
def run_dir(tmp_path_factory) -> Path:
    out = tmp_path_factory.mktemp("view") / "run"
    sim = Simulation(small_world(), controller="ggc", robots=20, groups=2, seed=1, max_ticks=60)
    recorder = Recorder(sim, trajectories_every=EVERY)
    with recorder:
        result = sim.run(on_tick=recorder.on_tick)
    recorder.write_outputs(out, result)
    return out


@pytest.fixture
def viewer(run_dir, tmp_path, monkeypatch) -> Iterator[vw.Viewer]:
    monkeypatch.setenv(vw.HEADLESS_ENV, "1")
    v = vw.Viewer(ReplayRun(Recording.load(run_dir)), width=320, save_dir=tmp_path)
    yield v
    v.close()


def _key(key: int, text: str = "") -> None:
    pygame.event.post(pygame.event.Event(pygame.KEYDOWN, key=key, unicode=text, mod=0))


def test_a_frame_moves_one_sample_and_space_pauses(viewer):
    assert viewer.sim.tick == 0
    assert viewer.frame() and viewer.sim.tick == EVERY
    _key(pygame.K_SPACE, " ")
    viewer.frame()
    viewer.frame()
    assert viewer.state.paused and viewer.sim.tick == EVERY
    _key(pygame.K_PERIOD, ".")
    viewer.frame()
    assert viewer.sim.tick == 2 * EVERY


def test_the_window_shows_the_recorded_frame(viewer, run_dir):
    viewer.frame()
    rec = Recording.load(run_dir)
    expected = new_renderer(rec, width=320).draw(rec.snapshot(1))
    window = pygame.surfarray.array3d(viewer._window).swapaxes(0, 1)
    assert np.array_equal(window[:expected.shape[0], :expected.shape[1]], expected)


def test_c_cycles_the_recorded_colourings(viewer):
    seen = []
    for _ in range(3):
        seen.append(viewer.state.color_by)
        _key(pygame.K_c, "c")
        viewer.frame()
    assert seen == ["gradient", "group", "status"]


def test_the_replay_ends_at_the_last_sample(viewer):
    for _ in range(20):
        viewer.frame()
    assert viewer.sim.tick == 60 and viewer.sim.stop_reason == END_OF_RECORDING
    assert any(END_OF_RECORDING in line for line in viewer.panel_lines(viewer.sim.snapshot()))


def test_without_a_display_replay_view_is_one_line(run_dir, monkeypatch, capsys):
    monkeypatch.delenv(vw.HEADLESS_ENV, raising=False)
    monkeypatch.delenv("DISPLAY", raising=False)
    monkeypatch.delenv("WAYLAND_DISPLAY", raising=False)
    assert main(["replay", str(run_dir), "--view"]) == 2
    line = one_error_line(capsys)
    assert "no display" in line and f"xvfb-run swarmsim replay {run_dir} --view" in line
    assert f"swarmsim replay {run_dir} --video FILE.mp4" in line


def test_a_selected_robot_shows_its_recorded_state(viewer, run_dir):
    import dataclasses

    viewer.state = dataclasses.replace(viewer.state, selected=3)
    viewer.frame()
    lines = viewer.panel_lines(viewer.sim.snapshot())
    rec = Recording.load(run_dir)
    snap = rec.snapshot(1)
    asleep = rec.flags("asleep_bits", 1)[3]
    assert "robot 3" in lines and ("asleep" if asleep else "awake") in lines
    assert f"  gradient = {int(snap.messages['gradient'][3])}" in lines
