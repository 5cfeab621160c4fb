"""Replay: a recorded run drawn again from trajectories.npz equals the live video's frames,
pixel for pixel, at the recorded ticks; every recorded colouring draws; what cannot be drawn
is refused in one line."""

from __future__ import annotations

import dataclasses
import sys
from pathlib import Path
from typing import ClassVar, Self

import numpy as np
import pytest

import swarmsim.render as render_module
from swarmsim import Simulation
from swarmsim.engine.sim import TIMING_FIELDS
from swarmsim.errors import ConfigError
from swarmsim.recording import Recorder
from swarmsim.replay import Recording, new_renderer, replay_frames, replay_png, replay_video
from swarmsim.results.trajectories import (
    Trajectories,
    load_trajectories,
    memory_bytes,
    sample_cost,
)
from tests.conftest import small_world

EVERY = 20
TICKS = 250  # not a multiple of EVERY: the last frame is the final state, off the grid


class FrameCatcher:
    """Stands in for VideoWriter: keeps copies of the RGB arrays it is given."""

    caught: ClassVar[list[np.ndarray]] = []

    def __init__(self, path: Path, fps: float = 30, **_: object):
        self.path, self.frames = Path(path), 0
        FrameCatcher.caught = []

    def __enter__(self) -> Self:
        return self

    def __exit__(self, *exc: object) -> None:
        pass

    def write(self, frame: np.ndarray) -> None:
        FrameCatcher.caught.append(np.array(frame, copy=True))
        self.frames += 1


def live_run(tmp_path: Path, controller: str, monkeypatch: pytest.MonkeyPatch,
             color_by: str | None = None, **options: object
             ) -> tuple[list[np.ndarray], list[int], Path]:
    """Run ``controller`` on the small world with a live video (frames caught before
    encoding) and --trajectories EVERY; returns the frames, their ticks, the run folder."""
    monkeypatch.setattr(render_module, "VideoWriter", FrameCatcher)
    groups = {"groups": 2} if controller == "ggc" else {}
    sim = Simulation(small_world(), controller=controller, robots=30, seed=3, max_ticks=TICKS,
                     **groups)
    ticks: list[int] = []
    recorder = Recorder(sim, video=tmp_path / "live.mp4", frame_every=EVERY, color_by=color_by,
                        width=320, trajectories_every=EVERY, **options)
    with recorder:
        ticks.append(sim.tick)

        def on_tick(s: Simulation) -> None:
            recorder.on_tick(s)
            if s.tick % EVERY == 0:
                ticks.append(s.tick)

        result = sim.run(on_tick=on_tick)
    if ticks[-1] != sim.tick:
        ticks.append(sim.tick)
    out = tmp_path / "run"
    recorder.write_outputs(out, result)
    return list(FrameCatcher.caught), ticks, out


@pytest.mark.parametrize("controller, color_by", [("ggc", None), ("ggc", "group"),
                                                  ("dispersion", None)])
def test_a_replay_is_the_live_video_frame_for_frame(tmp_path, monkeypatch, controller,
                                                    color_by):
    live, ticks, out = live_run(tmp_path, controller, monkeypatch, color_by=color_by)
    rec = Recording.load(out)
    assert rec.ticks.tolist() == ticks and len(live) == len(ticks) == TICKS // EVERY + 2
    replayed = [f.copy() for f in replay_frames(rec, color_by=color_by, width=320)]
    assert len(replayed) == len(live)
    for tick, a, b in zip(ticks, live, replayed, strict=True):
        assert a.shape == b.shape and np.array_equal(a, b), f"tick {tick} differs"
    # the frames are not all alike (the run moves), so equality says something
    assert not np.array_equal(live[0], live[-1])
    # coverage was drawn: cells were covered, and (robots move on) some uncovered again
    data = load_trajectories(out / "trajectories.npz")
    assert data["coverage"][-1] > 0 and data["covered_changes"].size > 0


def test_a_replay_with_contacts_is_the_live_video(tmp_path, monkeypatch):
    """A user's controller whose robots all head for the beacon and push (contacts ringed)."""
    live, _, out = live_run(tmp_path, "tests.early_end_bots:Crowd", monkeypatch,
                            highlight_contacts=True)
    replayed = list(replay_frames(Recording.load(out), width=320, highlight_contacts=True))
    assert all(np.array_equal(a, b) for a, b in zip(live, replayed, strict=True))
    assert load_trajectories(out / "trajectories.npz")["in_contact_bits"].any()


@pytest.fixture(scope="module")
def ggc_run(tmp_path_factory) -> Path:
    """GGC on the small world, recorded every EVERY ticks (no video)."""
    out = tmp_path_factory.mktemp("ggc") / "run"
    sim = Simulation(small_world(), controller="ggc", robots=30, groups=2, seed=3,
                     max_ticks=TICKS)
    recorder = Recorder(sim, trajectories_every=EVERY)
    with recorder:
        result = sim.run(on_tick=recorder.on_tick)
    recorder.write_outputs(out, result)
    return out


def test_every_recorded_colouring_draws_its_own_picture(ggc_run):
    rec = Recording.load(ggc_run)
    assert rec.offered_colourings() == ("status", "gradient", "group")
    last = {c: next(iter(reversed([f.copy() for f in replay_frames(rec, color_by=c,
                                                                      width=256)])))
            for c in rec.offered_colourings()}
    assert len({f.tobytes() for f in last.values()}) == 3


def test_a_colouring_not_recorded_is_refused_naming_those_that_were(ggc_run):
    rec = Recording.load(ggc_run)
    with pytest.raises(ConfigError) as err:
        new_renderer(rec, color_by="hops")
    line = str(err.value)
    assert "\n" not in line and "'hops'" in line and "status, gradient, group" in line


def test_the_snapshot_at_a_tick_is_that_sample(ggc_run, tmp_path):
    rec = Recording.load(ggc_run)
    index = rec.index_of(100)
    snaps = list(rec.snapshots())
    one = rec.snapshot(index)
    assert one.tick == 100 and np.array_equal(one.covered, snaps[index].covered)
    assert np.array_equal(one.positions, snaps[index].positions)
    png = replay_png(rec, tmp_path / "t100.png", tick=100, width=128)
    import imageio.v3 as iio

    assert iio.imread(png).shape[1] == 128


def test_a_tick_not_recorded_names_the_nearest(ggc_run):
    rec = Recording.load(ggc_run)
    with pytest.raises(ConfigError, match="tick 105 was not recorded; the nearest recorded "
                                          "ticks are 100 and 120"):
        rec.index_of(105)
    with pytest.raises(ConfigError, match="holds ticks 0 to 250"):
        rec.index_of(900)


def test_the_covered_raster_follows_the_run(ggc_run):
    """The raster rebuilt from its changes is the run's: its covered share is the recorded
    coverage at every sample."""
    rec = Recording.load(ggc_run)
    inside = rec.grid.inside
    before = np.zeros_like(inside)
    uncovered_again = 0
    for snap in rec.snapshots():
        assert not (snap.covered & ~inside).any()
        assert snap.covered.sum() / inside.sum() == pytest.approx(snap.coverage, abs=1e-12)
        uncovered_again += int(np.count_nonzero(before & ~snap.covered))
        before = snap.covered
    assert uncovered_again > 0  # robots moved on: changes go both ways


def test_a_file_from_before_replay_is_refused(tmp_path):
    np.savez(tmp_path / "trajectories.npz", ticks=np.arange(3), positions=np.zeros((3, 2, 2)))
    with pytest.raises(ConfigError, match="written before replay") as err:
        Recording.load(tmp_path)
    assert "--trajectories K" in str(err.value)


def test_a_file_missing_an_array_is_refused_naming_it(ggc_run, tmp_path):
    data = load_trajectories(ggc_run / "trajectories.npz")
    del data["asleep_bits"], data["coverage"]
    np.savez(tmp_path / "trajectories.npz", **data)
    with pytest.raises(ConfigError, match="lacks the arrays asleep_bits, coverage"):
        Recording.load(tmp_path)


def test_the_arrays_replay_reads_are_those_a_recording_writes(ggc_run):
    from swarmsim.replay import REQUIRED

    data = load_trajectories(ggc_run / "trajectories.npz")
    assert set(REQUIRED) <= set(data)
    assert set(data) - set(REQUIRED) == {"format", "field_gradient", "field_group",
                                         "field_leader"}


def test_a_folder_without_trajectories_is_refused(tmp_path):
    with pytest.raises(ConfigError, match="no trajectories.npz .*--trajectories K"):
        Recording.load(tmp_path)
    with pytest.raises(ConfigError, match="no run folder"):
        Recording.load(tmp_path / "nowhere")
    (tmp_path / "trajectories.npz").write_text("not a zip")
    with pytest.raises(ConfigError, match="is not a trajectories file"):
        Recording.load(tmp_path)


@pytest.mark.parametrize("controller", ["ggc", "tests.early_end_bots:Crowd"])
def test_recording_changes_nothing_in_the_run(controller):
    """GGC, and a user's controller whose robots push each other (contacts read each sample):
    the same summary, time series, robots and positions with and without recording."""
    def run(record: bool) -> dict:
        groups = {"groups": 2} if controller == "ggc" else {}
        sim = Simulation(small_world(), controller=controller, robots=30, seed=5,
                         max_ticks=TICKS, **groups)
        tracks = Trajectories(sim, every=7) if record else None
        result = sim.run(on_tick=tracks.on_tick if tracks else None)
        if tracks is not None:  # the engine's own numbers, to the last bit
            assert np.array_equal(tracks.arrays()["positions"][-1], sim.positions)
            if controller != "ggc":
                assert tracks.arrays()["in_contact_bits"].any()
        return {k: v for k, v in result.summary.items()
                if k not in TIMING_FIELDS} | {
                    "rows": result.timeseries, "robots": result.robots,
                    "positions": sim.positions.tobytes()}

    assert run(True) == run(False)


def test_the_memory_bound_holds_what_the_samples_keep():
    """The bound check_memory applies is at least what a recording holds: its arrays (data and
    headers, sys.getsizeof) and the tick and coverage objects, sampled every tick."""
    sim = Simulation(small_world(), controller="ggc", robots=30, groups=2, seed=3,
                     max_ticks=TICKS)
    cost = sample_cost(sim)
    assert cost.per_robot == 16 + 1 + 4 + 2 + 1 + 3 / 8  # GGC: gradient i4, group i2, leader
    marked = sample_cost(sim, headings=True)  # a float64 heading per robot, one more array
    assert (marked.per_robot - cost.per_robot, marked.per_sample - cost.per_sample) == (8, 136)
    tracks = Trajectories(sim, every=1)
    sim.run(on_tick=tracks.on_tick)
    kept = sum(sys.getsizeof(a) + 8 for name, rows in vars(tracks).items()
               if name.startswith("_") and isinstance(rows, list)
               for a in rows if isinstance(a, np.ndarray))
    kept += sum(sys.getsizeof(a) + 8 for rows in tracks._field_values.values() for a in rows)
    kept += sum(sys.getsizeof(v) + 8 for v in (*tracks._ticks, *tracks._coverage))
    assert tracks.samples == TICKS + 1
    assert kept <= memory_bytes(1, 30, TICKS, cost)
    # without the changed cells (bounded by the worst case) the count is close, not far above
    changes = sum(a.nbytes for a in tracks._changes)
    fixed = memory_bytes(1, 30, TICKS, dataclasses.replace(cost, max_changes=0))
    assert 0.9 * fixed <= kept - changes <= fixed


def test_replay_video_leaves_nothing_when_drawing_fails(ggc_run, tmp_path):
    with pytest.raises(ValueError):
        replay_video(Recording.load(ggc_run), tmp_path / "x.mp4", width=63)
    assert list(tmp_path.iterdir()) == []


def test_headings_are_recorded_only_when_present_and_replayed_with_their_marks(tmp_path,
                                                                              monkeypatch):
    """A drive with a heading (stood in for by a snapshot that carries one): the live video
    and the replay both draw the marks; a run without headings records none."""
    _, _, plain_out = live_run(tmp_path / "plain", "dispersion", monkeypatch)
    assert "headings" not in load_trajectories(plain_out / "trajectories.npz")
    plain_first = next(replay_frames(Recording.load(plain_out), width=1600)).copy()

    live_snapshot = Simulation.snapshot

    def with_headings(self: Simulation, with_coverage: bool = True):
        snap = live_snapshot(self, with_coverage)
        return dataclasses.replace(snap, headings=0.3 * np.arange(self.n) + 0.01 * self.tick)

    monkeypatch.setattr(Simulation, "snapshot", with_headings)
    live, ticks, out = live_run(tmp_path / "marked", "dispersion", monkeypatch)
    data = load_trajectories(out / "trajectories.npz")
    assert data["headings"].shape == (len(ticks), 30)
    assert np.allclose(data["headings"][-1], 0.3 * np.arange(30) + 0.01 * ticks[-1])
    rec = Recording.load(out)
    assert np.array_equal(rec.snapshot(1).headings, data["headings"][1])
    replayed = [f.copy() for f in replay_frames(rec, width=320)]
    assert all(np.array_equal(a, b) for a, b in zip(live, replayed, strict=True))
    # robots are a few pixels across at 320: marks show when they are drawn larger
    assert not np.array_equal(next(replay_frames(rec, width=1600)), plain_first)
