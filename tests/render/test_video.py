"""Videos of real runs: H.264 MP4s read back, and rendering never changes a run."""

import json
import subprocess

import imageio.v3 as iio
import imageio_ffmpeg
import numpy as np
import pytest

from swarmsim import Simulation
from swarmsim.cli import main
from swarmsim.engine.sim import TIMING_FIELDS


@pytest.mark.slow
def test_run_video_reads_back_and_summary_unchanged(tmp_path):
    common = ["run", "tiny", "--controller", "dispersion", "--max-ticks", "60", "--seed", "4",
              "--quiet"]
    video = tmp_path / "vid" / "run.mp4"  # inside the --out folder, made by the run (README)
    assert main(common + ["--out", str(tmp_path / "plain")]) == 0
    assert main(common + ["--out", str(tmp_path / "vid"), "--video", str(video),
                          "--frame-every", "5", "--width", "320",
                          "--snapshot", str(tmp_path / "snaps" / "last.png")]) == 0
    plain = json.loads((tmp_path / "plain" / "summary.json").read_text())
    with_video = json.loads((tmp_path / "vid" / "summary.json").read_text())
    for key in TIMING_FIELDS:
        plain.pop(key), with_video.pop(key)
    assert plain == with_video
    frames = iio.imread(video, index=None)
    assert frames.shape[0] == 1 + 60 // 5  # the start frame, then one every 5 ticks
    assert frames.shape[2] == 320 and frames.shape[1] % 2 == 0 and frames.shape[3] == 3
    info = subprocess.run([imageio_ffmpeg.get_ffmpeg_exe(), "-hide_banner", "-i", str(video)],
                          capture_output=True, text=True, check=False).stderr
    assert "h264" in info and "yuv420p" in info
    assert frames[-1].std() > 5  # real content, not a blank frame
    assert iio.imread(tmp_path / "snaps" / "last.png").shape[1] == 320


def test_sim_render_shows_robots_where_they_are():
    import dataclasses

    sim = Simulation("tiny", controller="dispersion", seed=1, max_ticks=5)
    sim.run()
    before = sim.positions.copy()
    frame = sim.render(width=400, legend=False, hud=False)
    assert frame.shape[1] == 400 and frame.dtype == np.uint8
    renderer = sim._renderer
    away = dataclasses.replace(sim.snapshot(), positions=sim.positions + 1e4)
    background = renderer.draw(away).copy()
    for x, y in sim.positions[:5]:
        px, py = (round(v) for v in renderer.world_to_pixel((x, y)))
        assert np.abs(frame[py, px].astype(int) - background[py, px]).sum() > 30
    np.testing.assert_array_equal(before, sim.positions)  # drawing moved nothing


@pytest.mark.slow
def test_sigterm_during_a_video_run_ends_like_ctrl_c_and_leaves_no_partial_file(tmp_path):
    """`kill` (or a batch system's time limit) during `swarmsim run --video` removes the hidden
    partial video and exits 130, as Ctrl-C does (SIGTERM's default would leave the file)."""
    import signal
    import sys
    import time

    cmd = [sys.executable, "-m", "swarmsim", "run", "tiny", "--video", "v.mp4", "--quiet",
           "--max-ticks", "10000000", "--set", "stop_on_complete=false",
           "--set", "plateau_ticks=10000000"]
    proc = subprocess.Popen(cmd, cwd=tmp_path, stderr=subprocess.PIPE, text=True)
    deadline = time.monotonic() + 120
    while not list(tmp_path.glob(".v.mp4.*")) and time.monotonic() < deadline:
        assert proc.poll() is None, proc.stderr.read()
        time.sleep(0.1)
    assert list(tmp_path.glob(".v.mp4.*")), "no partial video appeared"
    proc.send_signal(signal.SIGTERM)
    _, err = proc.communicate(timeout=60)
    assert proc.returncode == 130, err
    assert "interrupted" in err
    assert list(tmp_path.iterdir()) == []


def _interrupted_inside_compiled_code(*_args, **_kwargs):
    """What Ctrl-C does when it arrives while numba calls back into Python (CI saw it)."""
    try:
        raise KeyboardInterrupt
    except KeyboardInterrupt as exc:
        raise SystemError("CPUDispatcher returned a result with an exception set") from exc


def test_an_interrupt_inside_compiled_code_ends_a_video_run_like_ctrl_c(tmp_path, monkeypatch,
                                                                       capsys):
    monkeypatch.chdir(tmp_path)
    monkeypatch.setattr(Simulation, "step", _interrupted_inside_compiled_code)
    assert main(["run", "tiny", "--video", "v.mp4", "--quiet"]) == 130
    assert "interrupted" in capsys.readouterr().err
    assert list(tmp_path.iterdir()) == []


def test_other_errors_inside_compiled_code_are_not_taken_for_interrupts(tmp_path, monkeypatch):
    import pytest

    def broken(*_args, **_kwargs):
        raise SystemError("a real fault")

    monkeypatch.chdir(tmp_path)
    monkeypatch.setattr(Simulation, "step", broken)
    with pytest.raises(SystemError, match="a real fault"):
        main(["run", "tiny", "--quiet"])
