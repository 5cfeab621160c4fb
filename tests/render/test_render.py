"""Rendering, video and plot tests on synthetic snapshots (no simulation needed)."""

from __future__ import annotations

import csv
import dataclasses
import re
import subprocess

import imageio.v3 as iio
import imageio_ffmpeg
import numpy as np
import pytest

from controllers.common.gradient import COLOURINGS, GRADIENT_FIELDS, INF_GRADIENT
from swarmsim.controller import message_dtype
from swarmsim.metrics import CoverageGrid
from swarmsim.render import Renderer, VideoWriter, save_png
from swarmsim.results.plots import plot_timeseries
from swarmsim.results.snapshot import Snapshot
from swarmsim.world.world import world_from_dict


def make_world(margin: float = 5.0, beacon: bool = False):
    data = {
        "name": "sq",
        "target": {"outline": [[0, 0], [10, 0], [10, 10], [0, 10]]},
        "spawn": [{"outline": [[12, 0], [15, 0], [15, 3], [12, 3]]}],
        "arena": {"margin": margin},
    }
    if beacon:
        data["beacon"] = {"position": [5, 5]}
    return world_from_dict(data)


def make_snapshot(positions, tick=0, gradient=0, group=0, status=0, leader=False, failed=None,
                  in_contact=None, radius=0.4, covered=None, coverage=0.0):
    pos = np.asarray(positions, dtype=float).reshape(-1, 2)
    n = len(pos)
    msgs = np.zeros(n, dtype=message_dtype(GRADIENT_FIELDS))
    msgs["id"] = np.arange(n)
    msgs["gradient"] = gradient
    msgs["group"] = group
    msgs["status"] = status
    msgs["leader"] = leader
    return Snapshot(tick=tick, positions=pos, messages=msgs, statuses=("Idle", "Moving", "Done"),
                    radius=radius, coverage=coverage, covered=covered,
                    in_contact=np.zeros(n, bool) if in_contact is None else in_contact,
                    failed=np.zeros(n, bool) if failed is None else failed)


def make_renderer(*args, **kw):
    """A renderer for GGC-like broadcasts (gradient and group colourings, leaders)."""
    kw.setdefault("colourings", COLOURINGS)
    kw.setdefault("leader_field", "leader")
    kw.setdefault("group_field", "group")
    return Renderer(*args, **kw)


def bare(world, **kw):
    """A renderer without text overlays, so pixel differences come from robots only."""
    return make_renderer(world, hud=False, legend=False, **kw)


def changed(a: np.ndarray, b: np.ndarray, tol: int = 0) -> np.ndarray:
    return np.abs(a.astype(int) - b.astype(int)).max(axis=2) > tol


# --- frames -------------------------------------------------------------------------------------

def test_frame_shape_dtype_default_width():
    w = make_world()  # arena (-5, -5, 20, 15): 25 x 20 units
    r = make_renderer(w)
    f = r.draw(make_snapshot([[5, 5]], gradient=3))
    assert f.dtype == np.uint8 and f.ndim == 3 and f.shape[2] == 3
    h, wd = f.shape[:2]
    assert wd == 800 and (h, wd, 3) == r.shape
    assert h % 16 == 0 and wd % 16 == 0
    assert abs(h - 800 * 20 / 25) <= 8  # the height follows the arena's aspect


def test_even_sizes_for_odd_aspect_and_non_multiple_of_16_width():
    w = make_world(margin=3.3)
    r = make_renderer(w, width=202)
    f = r.draw(make_snapshot([[1, 1]]))
    assert f.shape[1] == 202 and f.shape[0] % 2 == 0


def test_robot_drawn_at_expected_pixel_with_y_flipped():
    w = make_world()
    r = bare(w, width=400)
    empty = r.draw(make_snapshot(np.zeros((0, 2))))
    # (0, 10) is the target's top-left corner: left of centre, upper half of the image
    pos = (0.0, 10.0)
    frame = r.draw(make_snapshot([pos], gradient=0))
    diff = changed(frame, empty)
    ys, xs = np.nonzero(diff)
    assert len(xs) > 0
    px, py = r.world_to_pixel(pos)
    assert abs(xs.mean() - px) <= 1.5 and abs(ys.mean() - py) <= 1.5
    # the camera: arena x in [-5, 20] maps across the width, y = 15 (top wall) near row 0
    assert abs(px - (0 + 5) / 25 * 400) <= 4
    assert abs(py - (15 - 10) / 20 * r.height) <= 4
    assert py < r.height / 2 and px < r.width / 2
    # the disc is at least 2 px in radius even though 0.4 units is tiny here
    assert diff.sum() >= 9
    assert tuple(frame[round(py), round(px)]) != tuple(empty[round(py), round(px)])


def test_robot_radius_scales_with_snapshot_radius():
    w = make_world()
    r = bare(w, width=400)
    empty = r.draw(make_snapshot(np.zeros((0, 2))))
    small = changed(r.draw(make_snapshot([[5, 5]], radius=0.1)), empty).sum()
    big = changed(r.draw(make_snapshot([[5, 5]], radius=1.5)), empty).sum()
    assert big > 4 * small


def test_color_by_changes_robot_colour():
    w = make_world()
    snap = make_snapshot([[5, 5]], gradient=4, group=1, status=1)
    colours = {}
    for cb in ("gradient", "group", "status"):
        r = bare(w, width=400, color_by=cb)
        f = r.draw(snap)
        px, py = np.rint(r.world_to_pixel((5, 5))).astype(int)
        colours[cb] = tuple(f[py, px])
        assert colours[cb] == tuple(r.robot_colors(snap)[0])
    assert len(set(colours.values())) == 3


def test_a_robot_that_has_broadcast_nothing_is_grey_by_status_as_the_legend_says():
    from swarmsim.render.palette import NONE_GREY

    r = bare(make_world(), width=400, color_by="status")
    cols = r.robot_colors(make_snapshot(np.zeros((2, 2)), status=np.array([-1, 0])))
    assert tuple(cols[0]) == NONE_GREY and tuple(cols[1]) != NONE_GREY


def test_gradient_cycle_and_infinite_gradient():
    w = make_world()
    r = bare(w, width=400, color_by="gradient")
    g = np.array([0, 14, 1, INF_GRADIENT])
    cols = r.robot_colors(make_snapshot(np.zeros((4, 2)), gradient=g))
    assert tuple(cols[0]) == tuple(cols[1])  # 14-colour cycle
    assert tuple(cols[0]) != tuple(cols[2])
    assert cols[3][0] == cols[3][1] == cols[3][2]  # INF gradient is grey


def test_failed_robot_drawn_dark_and_leader_ring():
    w = make_world()
    r = bare(w, width=400, highlight_contacts=True)
    empty = r.draw(make_snapshot(np.zeros((0, 2))))
    f = r.draw(make_snapshot([[5, 5]], gradient=2, failed=np.array([True])))
    disc = f[changed(f, empty)].astype(int)
    assert len(disc) >= 9 and disc.mean() < 100  # dark (with a light X when large enough)
    plain = changed(r.draw(make_snapshot([[5, 5]])), empty).sum()
    led = changed(r.draw(make_snapshot([[5, 5]], leader=True)), empty).sum()
    assert led > plain  # the leader's ring
    touching = changed(r.draw(make_snapshot([[5, 5]], in_contact=np.array([True]))), empty).sum()
    assert touching > plain  # the contact ring (highlight_contacts)


def test_invalid_arguments():
    w = make_world()
    with pytest.raises(ValueError, match="status.*gradient.*group"):
        make_renderer(w, color_by="colour")
    for bad in (801, 62, 0, 800.0):
        with pytest.raises(ValueError, match="width"):
            make_renderer(w, width=bad)


def test_hud_text_and_coverage_overlay():
    w = make_world(beacon=True)
    grid = CoverageGrid.for_target(w.target, radius=2.0)
    pos = np.array([[2.0, 2.0], [3.0, 3.0], [13.0, 1.0]])  # the last one is off target
    snap = make_snapshot(pos, tick=42, group=np.array([1, 2, 0]),
                         covered=grid.covered_grid(pos), coverage=grid.coverage(pos))
    r = make_renderer(w, grid)
    text = r.hud_text(snap)
    assert re.fullmatch(r"tick 42  coverage \d+\.\d %  on target 2  groups 2", text)
    with_cov = r.draw(snap)
    no_cov = make_renderer(w, grid, show_coverage=False).draw(snap)
    assert changed(with_cov, no_cov).sum() > 100


# --- video ---------------------------------------------------------------------------------------

def ffmpeg_stream_info(path) -> str:
    out = subprocess.run([imageio_ffmpeg.get_ffmpeg_exe(), "-hide_banner", "-i", str(path)],
                         check=False, capture_output=True, text=True)
    return out.stderr


def test_video_roundtrip(tmp_path):
    w = make_world(margin=5.0)  # arena 25 x 20
    r = bare(w, width=160)
    xs = np.linspace(-2, 17, 12)
    frames = [r.draw(make_snapshot([[x, 5.0]], gradient=0, radius=1.2)) for x in xs]
    empty = r.draw(make_snapshot(np.zeros((0, 2))))
    out = tmp_path / "clip.mp4"
    with VideoWriter(out, fps=12) as vw:
        for f in frames:
            vw.write(f)
        assert vw.frames == 12
    assert out.is_file() and out.stat().st_size > 0
    assert [p.name for p in tmp_path.iterdir()] == ["clip.mp4"]  # no temporary left

    video = iio.imread(out, index=None)
    assert video.shape == (12, r.height, r.width, 3)
    assert iio.improps(out).shape[1:] == (r.height, r.width, 3)
    meta = iio.immeta(out)
    assert meta["codec"] == "h264" and meta["fps"] == 12.0 and meta["size"] == (r.width, r.height)
    assert meta["pix_fmt"].startswith("yuv420p")
    info = ffmpeg_stream_info(out)
    assert re.search(r"Video: h264", info), info
    assert "yuv420p" in info

    for x, got in zip(xs, video):
        px, py = np.rint(r.world_to_pixel((x, 5.0))).astype(int)
        # the robot (red, gradient 0) is where it should be, despite lossy compression
        assert np.abs(got[py, px].astype(int) - empty[py, px].astype(int)).max() > 60
        red = got[py - 1:py + 2, px - 1:px + 2].reshape(-1, 3).astype(int)
        assert (red[:, 0] - red[:, 1]).mean() > 60


def test_video_writer_removes_everything_on_error(tmp_path):
    out = tmp_path / "broken.mp4"
    frame = np.zeros((64, 64, 3), np.uint8)
    with pytest.raises(RuntimeError, match="boom"), VideoWriter(out) as vw:
        vw.write(frame)
        vw.write(frame)
        raise RuntimeError("boom")
    assert list(tmp_path.iterdir()) == []


def test_video_writer_keeps_old_file_on_error(tmp_path):
    out = tmp_path / "keep.mp4"
    out.write_bytes(b"old")
    with pytest.raises(ValueError, match="size changed"), VideoWriter(out) as vw:
        vw.write(np.zeros((64, 64, 3), np.uint8))
        vw.write(np.zeros((64, 80, 3), np.uint8))
    assert out.read_bytes() == b"old"
    assert [p.name for p in tmp_path.iterdir()] == ["keep.mp4"]


def test_video_writer_validation(tmp_path):
    for fps in (0, -1, float("nan")):
        with pytest.raises(ValueError, match="fps"):
            VideoWriter(tmp_path / "a.mp4", fps=fps)
    vw = VideoWriter(tmp_path / "a.mp4")
    with pytest.raises(ValueError, match="even"):
        vw.write(np.zeros((63, 64, 3), np.uint8))
    with pytest.raises(ValueError, match="uint8"):
        vw.write(np.zeros((64, 64, 3), np.float32))
    vw.abort()
    with pytest.raises(ValueError, match="no frames"):
        VideoWriter(tmp_path / "b.mp4").close()
    assert list(tmp_path.iterdir()) == []


def test_save_png(tmp_path):
    w = make_world(beacon=True)
    f = make_renderer(w, width=256).draw(make_snapshot([[5, 5], [1, 9]], gradient=np.array([0, 5])))
    out = save_png(f, tmp_path / "frame.png")
    back = iio.imread(out)
    assert np.array_equal(back[..., :3], f)
    assert [p.name for p in tmp_path.iterdir()] == ["frame.png"]


# --- plots ---------------------------------------------------------------------------------------

def test_plot_timeseries_rows_and_csv(tmp_path):
    rows = [{"tick": t, "coverage": min(1.0, t / 80), "total_distance": 3.5 * t}
            for t in range(0, 101, 5)]
    out = plot_timeseries(rows, tmp_path / "ts.png", title="demo", completion_tick=80)
    assert out.stat().st_size > 1000
    assert iio.imread(out).ndim == 3

    path = tmp_path / "ts.csv"
    with path.open("w", newline="") as fh:
        wr = csv.DictWriter(fh, fieldnames=["tick", "coverage", "total_distance", "extra"])
        wr.writeheader()
        for r in rows:
            wr.writerow({**r, "extra": "x"})
    out2 = plot_timeseries(path, tmp_path / "ts2.png")
    assert out2.stat().st_size > 1000
    assert sorted(p.name for p in tmp_path.iterdir()) == ["ts.csv", "ts.png", "ts2.png"]


def test_plot_timeseries_missing_column(tmp_path):
    with pytest.raises(ValueError, match="total_distance"):
        plot_timeseries([{"tick": 0, "coverage": 0.1}], tmp_path / "x.png")
    assert list(tmp_path.iterdir()) == []


def test_renders_without_fonts(monkeypatch):
    import pygame.font

    def no_font(*args, **kwargs):
        raise pygame.error("no fonts here")

    monkeypatch.setattr(pygame.font, "Font", no_font)
    w = make_world()
    f = make_renderer(w, width=128).draw(make_snapshot([[5, 5]]))
    assert f.shape == (make_renderer(w, width=128, hud=False, legend=False).shape)


# --- heading marks ------------------------------------------------------------------------------

def test_a_heading_mark_points_from_the_centre_toward_the_heading_with_y_up():
    w = make_world()
    r = bare(w, width=800)  # 32 px per unit: a robot of radius 0.4 is ~13 px across
    plain = make_snapshot([[5, 5]])
    px, py = r.world_to_pixel((5.0, 5.0))
    for heading, (dx, dy) in ((0.0, (1, 0)), (np.pi / 2, (0, -1)), (np.pi, (-1, 0))):
        marked = dataclasses.replace(plain, headings=np.array([heading]))
        ys, xs = np.nonzero(changed(r.draw(marked), r.draw(plain)))
        assert len(xs) >= 3, heading
        # the mark lies on the heading's side of the centre (image y points down)
        assert dx * (xs.mean() - px) + dy * (ys.mean() - py) > 2, heading
        assert np.hypot(xs - px, ys - py).max() <= 0.4 * 32 + 1.5  # inside the disc


def test_without_headings_no_mark_is_drawn():
    w = make_world()
    r = bare(w, width=800)
    plain = make_snapshot([[5, 5], [7, 7]])
    assert plain.headings is None
    unknown = dataclasses.replace(plain, headings=np.full(2, np.nan))
    assert np.array_equal(r.draw(plain), r.draw(unknown))
    failed = make_snapshot([[5, 5]], failed=np.array([True]))  # a failed robot: no mark
    assert np.array_equal(r.draw(failed),
                          r.draw(dataclasses.replace(failed, headings=np.array([0.0]))))


def test_a_run_with_a_steering_drive_shows_each_robots_heading_and_a_holonomic_run_none():
    from swarmsim import Simulation

    for drive in ("holonomic", "diff", "kilobot"):
        sim = Simulation("tiny", controller="ggc", seed=0, max_ticks=5,
                         settings={"drive": drive})
        for _ in range(5):
            sim.step()
        shot = sim.snapshot()
        if drive == "holonomic":
            assert shot.headings is None
            continue
        assert np.allclose(shot.headings, sim.physics.headings())
        r = make_renderer(sim.world, width=1200)  # robots large enough to carry a mark
        assert not np.array_equal(r.draw(shot), r.draw(dataclasses.replace(shot, headings=None)))
