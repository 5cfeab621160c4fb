"""`swarmsim worlds PATH`: a world's free floor, capacity, warnings and preview."""

from __future__ import annotations

from pathlib import Path

import imageio.v3 as iio
import numpy as np
import pytest

from swarmsim.cli import main
from swarmsim.errors import ConfigError
from swarmsim.world.world import load_world, world_from_dict
from swarmsim.world.worldinfo import describe_world, format_report

ODD = """
name = "odd"
[target]
outline = [[0, 0], [60, 0], [60, 40], [0, 40]]
holes = [[[10, 10], [20, 10], [20, 20], [10, 20]]]
[[obstacles]]
outline = [[30, 0], [30.5, 0], [30.5, 45], [30, 45]]
[[obstacles]]
outline = [[40, 5], [59.6, 5], [59.6, 35], [40, 35]]
[[spawn]]
outline = [[0, -10], [60, -10], [60, -1], [0, -1]]
[beacon]
position = [15, 15]
[defaults]
robots = 20
groups = 2
"""


def _square(obstacle: list[list[float]] | None = None, **extra) -> dict:
    data = {"name": "sq", "target": {"outline": [[0, 0], [30, 0], [30, 30], [0, 30]]},
            "spawn": [{"outline": [[0, -20], [30, -20], [30, -5], [0, -5]]}],
            "beacon": {"position": [15, 15]}, "defaults": {"robots": 40}, **extra}
    if obstacle:
        data["obstacles"] = [{"outline": obstacle}]
    return data


def test_a_shipped_world_without_warnings() -> None:
    world = load_world("K")
    r = describe_world(world)
    assert r.free_area == pytest.approx(13_280)
    assert r.capacity[6.0] == world.lattice_capacity(6) == 425
    assert r.free_parts == 1 and r.warnings == ()
    assert r.beacon_depth == pytest.approx(24.0)
    lines = format_report(r)
    assert max(map(len, lines)) <= 100
    assert any("warnings    none" in ln for ln in lines)


def test_free_floor_is_net_of_holes_and_obstacles_with_warnings(tmp_path: Path) -> None:
    path = tmp_path / "odd.toml"
    path.write_text(ODD)
    r = describe_world(load_world(path))
    assert r.outline_area == pytest.approx(2400)
    assert r.holes_area == pytest.approx(100)
    assert r.obstacles_area == pytest.approx(0.5 * 40 + 19.6 * 30)
    assert r.free_area == pytest.approx(2400 - 100 - 20 - 588)
    assert r.capacity[6.0] == int(r.free_area / (0.8660254 * 36))
    assert r.free_parts == 2
    assert r.narrow_area == pytest.approx(0.4 * 30, rel=1e-6)  # the strip beside the block
    text = "\n".join(r.warnings)
    assert "2 separate parts" in text
    assert "narrower than a robot" in text
    assert "in a hole" in text
    assert "1.0 units from the target" in text
    assert "20 robots are fewer than the" in text


def test_no_free_floor_and_tiny_floor_are_warned() -> None:
    with pytest.raises(ConfigError, match="free floor"):  # the loader refuses it outright
        world_from_dict(_square([[-1, -1], [31, -1], [31, 31], [-1, 31]]))
    tiny = describe_world(world_from_dict(_square([[0, 0], [30, 0], [30, 29], [0, 29]])))
    assert any(w.startswith("tiny free floor") for w in tiny.warnings)


def test_a_start_that_does_not_fit_and_a_missing_beacon_are_warned() -> None:
    data = _square()
    del data["beacon"]
    data["defaults"] = {"robots": 5000}
    r = describe_world(world_from_dict(data))
    text = "\n".join(r.warnings)
    assert "no beacon" in text
    assert "the default start (formation, 5000 robots, 1 groups) is refused" in text


def test_worlds_path_prints_and_previews(tmp_path: Path, capsys) -> None:
    path = tmp_path / "odd.toml"
    path.write_text(ODD)
    png = tmp_path / "sub" / "odd.png"
    assert main(["worlds", str(path), "--preview", str(png), "--width", "400"]) == 0
    out = capsys.readouterr().out
    assert "free floor = outline 2,400 - holes 100 - obstacles 608" in out
    img = iio.imread(png)
    assert img.shape[1] == 400 and img.shape[2] == 3
    red = (img[..., 0] > 200) & (img[..., 1] < 80) & (img[..., 2] < 80)
    assert red.sum() >= 20  # the narrow strip drawn in red
    group_blue = np.all(img == np.array([31, 119, 180], np.uint8), axis=2)
    assert group_blue.sum() > 0  # group 1's robots stand in the spawn area


def test_worlds_without_path_lists_the_shipped_worlds(capsys) -> None:
    assert main(["worlds"]) == 0
    out = capsys.readouterr().out.splitlines()
    assert out[0].split()[:2] == ["world", "area"]
    assert any(line.startswith("K ") for line in out)


@pytest.mark.parametrize("argv, needle", [
    (["worlds", "--preview", "x.png"], "needs a WORLD"),
    (["worlds", "K", "tiny", "--preview", "x.png"], "draws one world, got 2"),
    (["worlds", "K", "--preview", "x.jpg"], "must be a .png file"),
    (["worlds", "nowhere.toml"], "world file not found"),
])
def test_worlds_bad_input_is_one_line(argv, needle, capsys, tmp_path, monkeypatch) -> None:
    monkeypatch.chdir(tmp_path)
    assert main(argv) == 2
    err = capsys.readouterr().err.strip().splitlines()
    assert len(err) == 1 and needle in err[0], err
    assert not list(tmp_path.iterdir())  # nothing written


def test_the_preview_shows_seed_0s_start() -> None:
    from swarmsim.engine.sim import Simulation
    from swarmsim.render.preview import start_layout

    world = load_world("corridor")
    pos, groups, leaders, note = start_layout(describe_world(world))
    sim = Simulation(world, controller="ggc", seed=0, settings={"start": "formation"})
    assert note == ""
    np.testing.assert_allclose(pos, sim.positions, atol=1e-9)
    np.testing.assert_array_equal(groups, sim.start_groups)
    np.testing.assert_array_equal(leaders, sim.start_leaders)
