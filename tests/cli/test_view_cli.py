"""`swarmsim view --out DIR --trajectories K`: the viewed run is written as far as it went, the
same files `swarmsim run` writes for the same ticks, and `swarmsim replay` draws it again."""

from __future__ import annotations

import functools
import json

import numpy as np
import pytest

from swarmsim.cli import VIEWER_CLOSED, main
from swarmsim.render import viewer as vw

RUN = ["tiny", "--controller", "ggc", "--robots", "30", "--groups", "2", "--seed", "3"]


@pytest.fixture
def frames_then_close(monkeypatch):
    """The viewer closes itself after 40 frames (one tick each), as if the user pressed q."""
    monkeypatch.setenv(vw.HEADLESS_ENV, "1")
    monkeypatch.setattr(vw, "view", functools.partial(vw.view, max_frames=40))


def test_a_viewed_run_is_written_as_run_writes_it_and_replays(frames_then_close, tmp_path,
                                                               capsys):
    viewed, ran = tmp_path / "viewed", tmp_path / "ran"
    assert main(["view", *RUN, "--width", "320", "--out", str(viewed),
                 "--trajectories", "5"]) == 0
    assert f"wrote {viewed}" in capsys.readouterr().out
    assert main(["run", *RUN, "--max-ticks", "40", "--quiet", "--out", str(ran),
                 "--trajectories", "5"]) == 0

    seen, plain = (json.loads((d / "summary.json").read_text()) for d in (viewed, ran))
    assert seen["ticks"] == plain["ticks"] == 40
    assert (seen["stop_reason"], plain["stop_reason"]) == (VIEWER_CLOSED, "max_ticks")
    for name in ("timeseries.csv", "robots.csv"):
        assert (viewed / name).read_bytes() == (ran / name).read_bytes(), name
    with np.load(viewed / "trajectories.npz") as a, np.load(ran / "trajectories.npz") as b:
        assert sorted(a.files) == sorted(b.files)
        for key in a.files:
            np.testing.assert_array_equal(a[key], b[key], err_msg=key)

    video = tmp_path / "by-group.mp4"
    assert main(["replay", str(viewed), "--video", str(video), "--color-by", "group",
                 "--width", "320"]) == 0
    assert video.stat().st_size > 0


def test_view_trajectories_need_out(frames_then_close, capsys):
    assert main(["view", *RUN, "--trajectories", "5"]) == 2
    err = capsys.readouterr().err.strip().splitlines()
    assert len(err) == 1 and "--trajectories" in err[0] and "--out" in err[0]
