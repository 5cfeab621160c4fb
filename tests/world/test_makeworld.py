"""`swarmsim make-world`: worlds from text and images, validated, and their first run works."""

from __future__ import annotations

from pathlib import Path

import imageio.v3 as iio
import numpy as np
import pytest
import shapely

from swarmsim.cli import main
from swarmsim.engine.sim import Simulation
from swarmsim.world.makeworld import CAPACITY_SHARE, to_toml
from swarmsim.world.world import load_world
from swarmsim.world.worldinfo import hex_capacity


def _make(tmp_path: Path, *args: str, name: str = "w.toml") -> Path:
    out = tmp_path / name
    assert main(["make-world", *args, "--out", str(out)]) == 0
    return out


@pytest.mark.slow
def test_text_l_world_is_valid_and_its_first_run_covers_the_target(tmp_path: Path) -> None:
    world = load_world(_make(tmp_path, "--text", "L", "--size", "40"))
    _x0, y0, _x1, y1 = world.target.bounds
    assert y1 - y0 == pytest.approx(40, abs=0.05)
    robots = world.defaults["robots"]
    assert robots == round(hex_capacity(world.target_area, 6.0) / CAPACITY_SHARE)
    assert world.defaults["groups"] == 1 and world.defaults["d_cover"] == 6.0
    (spawn,) = world.spawns
    assert spawn.bounds[3] < y0  # the spawn band lies below the target, apart from it
    assert spawn.distance(world.target) >= 10
    assert world.target.contains(shapely.Point(world.beacon))
    sim = Simulation(world, seed=0, max_ticks=3000)
    s = sim.run().summary
    assert s["robots_on_target"] >= robots // 2
    assert s["coverage"] > 0.85


def test_text_keeps_holes_and_joins_glyphs_into_one_polygon(tmp_path: Path, capsys) -> None:
    world = load_world(_make(tmp_path, "--text", "OB8"))
    out = capsys.readouterr().out
    assert "joined 3 separate parts with 2 bridge(s)" in out
    assert world.target.geom_type == "Polygon"
    assert len(world.target.interiors) == 5  # O: 1, B: 2, 8: 2
    assert world.target_area == pytest.approx(13_280, rel=0.1)  # scaled like K by default
    assert world.defaults["groups"] == 3


def test_options_set_robots_groups_and_d_cover(tmp_path: Path) -> None:
    world = load_world(_make(tmp_path, "--text", "K", "--robots", "50", "--groups", "2"))
    assert (world.defaults["robots"], world.defaults["groups"]) == (50, 2)
    wide = load_world(_make(tmp_path, "--text", "K", "--d-cover", "8", name="k8.toml"))
    assert wide.defaults["d_cover"] == 8.0
    assert wide.defaults["robots"] == round(hex_capacity(wide.target_area, 8.0) / 0.7)
    assert "grid_size" not in wide.defaults  # the default raster is fine enough


def test_a_large_world_gets_coverage_cells_no_wider_than_the_coverage_radius(
        tmp_path: Path, capsys) -> None:
    path = _make(tmp_path, "--text", "K", "--size", "640", "--robots", "20")
    assert "coarsely" not in capsys.readouterr().out
    world = load_world(path)
    x0, y0, x1, y1 = world.target.bounds
    assert world.defaults["grid_size"] == 160  # 640 units / the coverage radius 4
    sim = Simulation(path, max_ticks=1)
    assert sim.config.grid_size == 160
    assert max(x1 - x0, y1 - y0) / sim.config.grid_size <= sim.config.coverage_radius


def _mask_png(path: Path) -> None:
    y, x = np.mgrid[0:120, 0:200]
    img = np.full((120, 200), 255, np.uint8)
    r = np.hypot(x - 60, y - 60)
    img[(r < 45) & (r > 20)] = 0  # a ring: one shape with a hole
    img[30:90, 120:180] = 0  # a square beside it
    img[5, 5] = 0  # a speck, dropped
    iio.imwrite(path, img)


def test_image_world_traces_shapes_with_holes(tmp_path: Path) -> None:
    png = tmp_path / "mask.png"
    _mask_png(png)
    world = load_world(_make(tmp_path, "--image", str(png), "--size", "60"))
    assert world.name == "mask"
    assert world.target.geom_type == "Polygon" and len(world.target.interiors) == 1
    scale = 60 / 90  # the shapes span rows 15..105 of the image: 90 pixels
    ring = np.pi * (45**2 - 20**2) * scale**2
    square = 60 * 60 * scale**2
    assert world.target_area == pytest.approx(ring + square, rel=0.08)  # plus a bridge
    hole = shapely.Polygon(world.target.interiors[0])
    assert hole.area == pytest.approx(np.pi * 20**2 * scale**2, rel=0.1)
    sim = Simulation(world, seed=0, max_ticks=5)  # builds: a valid first run
    assert sim.run().summary["ticks"] == 5


def test_image_light_shapes_with_invert_and_transparency(tmp_path: Path) -> None:
    rgba = np.zeros((60, 80, 4), np.uint8)
    rgba[10:50, 10:40, 3] = 255  # an opaque black block on transparent (white) ground
    png = tmp_path / "alpha.png"
    iio.imwrite(png, rgba)
    dark = load_world(_make(tmp_path, "--image", str(png), "--size", "40", name="d.toml"))
    assert dark.target_area == pytest.approx(40 * 30, rel=0.05)
    light = load_world(_make(tmp_path, "--image", str(png), "--invert", "--size", "40",
                             name="l.toml"))
    # inverted: the light ground around the block, the block a hole in it
    scale = 40 / 60  # the ground spans the image's 60 rows
    assert len(light.target.interiors) == 1
    hole = shapely.Polygon(light.target.interiors[0])
    assert hole.area == pytest.approx(40 * 30 * scale**2, rel=0.05)
    assert light.target_area == pytest.approx((80 * 60 - 40 * 30) * scale**2, rel=0.05)


@pytest.mark.parametrize("args, needle", [
    (["--text", "   "], "no text to draw"),
    (["--text", "L", "--font", "NoSuchFontFamily"], "no font family"),
    (["--image", "nope.png"], "image not found"),
    (["--image", "bad.png"], "not an image file"),
    (["--image", "white.png"], "has no shapes: no dark pixels"),
    (["--image", "black.png"], "every pixel is dark"),
    (["--text", "L", "--size", "-3"], "must be positive"),
    (["--text", "L", "--robots", "0"], "must be >= 1"),
])
def test_bad_input_is_one_line_and_writes_nothing(args, needle, tmp_path, monkeypatch,
                                                  capsys) -> None:
    monkeypatch.chdir(tmp_path)
    (tmp_path / "bad.png").write_text("not a png")
    iio.imwrite(tmp_path / "white.png", np.full((20, 20), 255, np.uint8))
    iio.imwrite(tmp_path / "black.png", np.zeros((20, 20), np.uint8))
    assert main(["make-world", *args, "--out", "sub/w.toml"]) == 2
    err = capsys.readouterr().err.strip().splitlines()
    assert len(err) == 1 and needle in err[0], err
    assert not (tmp_path / "sub").exists()


def test_toml_text_round_trips_names_with_quotes(tmp_path: Path) -> None:
    import tomllib

    data = {"name": 'say "hi"\\', "description": "d",
            "target": {"outline": [[0, 0], [1, 0], [1, 1]], "holes": []},
            "spawn": [{"outline": [[0, -3], [1, -3], [1, -2]]}],
            "beacon": {"position": [0.5, 0.4]}, "arena": {"margin": 20.0},
            "defaults": {"robots": 3, "groups": 1, "d_cover": 6.0}}
    parsed = tomllib.loads(to_toml(data, header="two\nlines"))
    assert parsed["name"] == data["name"]
    assert parsed["target"] == {"outline": [[0, 0], [1, 0], [1, 1]]}
