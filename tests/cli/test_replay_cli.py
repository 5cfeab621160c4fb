"""``swarmsim replay``: a recorded run's video and PNGs without simulating it; the replayed
MP4 decodes to the live --video's frames; refusals are one line, and leave nothing."""

from __future__ import annotations

from pathlib import Path

import imageio.v2 as iio2
import numpy as np
import pytest

from swarmsim.cli import main
from tests.errlines import one_error_line


@pytest.fixture(scope="module")
def recorded(tmp_path_factory) -> Path:
    """GGC on tiny, 70 ticks, recorded every 10 ticks with a live video a frame every 10."""
    base = tmp_path_factory.mktemp("replay")
    assert main(["run", "tiny", "--max-ticks", "70", "--out", str(base / "run"), "--quiet",
                 "--trajectories", "10", "--video", str(base / "live.mp4"),
                 "--frame-every", "10", "--width", "320"]) == 0
    return base


def decoded(path: Path) -> list[np.ndarray]:
    with iio2.get_reader(str(path), format="FFMPEG") as reader:
        return [np.asarray(f) for f in reader]


def test_the_replayed_mp4_is_the_live_one_frame_for_frame(recorded, capsys):
    out = recorded / "again.mp4"
    assert main(["replay", str(recorded / "run"), "--video", str(out), "--width", "320",
                 "--quiet"]) == 0
    assert "8 frames, ticks 0 to 70" in capsys.readouterr().out
    live, again = decoded(recorded / "live.mp4"), decoded(out)
    assert len(live) == len(again) == 8
    assert all(np.array_equal(a, b) for a, b in zip(live, again, strict=True))


def test_another_colouring_width_and_rate(recorded):
    out = recorded / "groups.mp4"
    assert main(["replay", str(recorded / "run"), "--video", str(out), "--color-by", "group",
                 "--width", "256", "--fps", "5", "--quiet"]) == 0
    frames = decoded(out)
    assert len(frames) == 8 and frames[0].shape[1] == 256
    assert iio2.get_reader(str(out), format="FFMPEG").get_meta_data()["fps"] == 5


def test_a_snapshot_at_a_recorded_tick(recorded, capsys):
    png = recorded / "t30.png"
    assert main(["replay", str(recorded / "run"), "--snapshot", str(png), "--tick", "30",
                 "--width", "320"]) == 0
    assert capsys.readouterr().out.strip().endswith("tick 30")
    live = decoded(recorded / "live.mp4")[3]  # frames at 0, 10, 20, 30
    image = iio2.imread(png)
    assert image.shape == live.shape
    assert np.abs(image.astype(int) - live.astype(int)).mean() < 3  # the video is lossy


@pytest.mark.parametrize("args, words", [
    (["--snapshot", "x.png", "--tick", "35"], ["--tick", "nearest recorded ticks are 30 and 40"]),
    (["--snapshot", "x.png", "--tick", "700"], ["--tick", "holds ticks 0 to 70"]),
    (["--video", "x.mp4", "--tick", "30"], ["--tick", "--snapshot"]),
    (["--video", "x.mp4", "--width", "63"], ["--width", "63"]),
    (["--video", "x.mp4", "--fps", "0"], ["--fps"]),
    (["--video", "x.mp4", "--color-by", "hops"], ["--color-by", "'hops'", "gradient, group"]),
    (["--video", "x.avi"], ["--video", ".mp4"]),
    (["--snapshot", "x.jpg"], ["--snapshot", ".png"]),
    (["--view", "--highlight-contacts"], ["--highlight-contacts", "--video"]),
    (["--view", "--tick", "30"], ["--tick", "--snapshot"]),
])
def test_bad_options_are_one_line_and_leave_nothing(recorded, tmp_path, monkeypatch, capsys,
                                                    args, words):
    monkeypatch.chdir(tmp_path)
    assert main(["replay", str(recorded / "run"), *args, "--quiet"]) == 2
    line = one_error_line(capsys)
    assert all(w in line for w in words), line
    assert list(tmp_path.iterdir()) == []


def test_a_run_without_trajectories_says_how_to_record_one(tmp_path, capsys):
    run = tmp_path / "run"
    assert main(["run", "tiny", "--max-ticks", "3", "--out", str(run), "--quiet"]) == 0
    assert main(["replay", str(run), "--video", str(tmp_path / "x.mp4")]) == 2
    line = one_error_line(capsys)
    assert "RUN_DIR" in line and "--trajectories K" in line
    assert main(["replay", str(tmp_path / "nowhere"), "--video", str(tmp_path / "x.mp4")]) == 2
    assert "no run folder" in one_error_line(capsys)
    assert not (tmp_path / "x.mp4").exists()


def test_a_file_from_before_replay_is_refused(tmp_path, capsys):
    np.savez(tmp_path / "trajectories.npz", ticks=np.arange(2), positions=np.zeros((2, 3, 2),
                                                                                    np.float32))
    assert main(["replay", str(tmp_path), "--snapshot", str(tmp_path / "x.png")]) == 2
    line = one_error_line(capsys)
    assert "before replay" in line and "--trajectories K" in line
    assert not (tmp_path / "x.png").exists()
