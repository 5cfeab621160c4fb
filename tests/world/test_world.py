"""World files: the shipped worlds and the validation of hand-written ones."""

from __future__ import annotations

from pathlib import Path

import pytest
from shapely.geometry import Point

from swarmsim import Simulation
from swarmsim.errors import ConfigError
from swarmsim.world.world import available_worlds, load_world

SHIPPED = ["K", "K-huge", "K-large", "corridor", "house", "tiny"]
PAPER_DEFAULTS = {"K": (603, 3), "house": (942, 3), "K-large": (2000, 10), "tiny": (40, 1),
                  "K-huge": (10000, 16),
                  "corridor": (60, 2)}

# A minimal valid world; the error tests change one thing in it.
TARGET = "[target]\noutline = [[0, 20], [30, 20], [30, 44], [0, 44]]\n"
SPAWN = "[[spawn]]\noutline = [[0, 0], [30, 0], [30, 8], [0, 8]]\n"


def write(tmp_path: Path, text: str, name: str = "w.toml") -> Path:
    path = tmp_path / name
    path.write_text(text)
    return path


def world_text(*, top: str = 'name = "t"\n', target: str = TARGET, spawn: str = SPAWN,
               extra: str = "") -> str:
    return top + target + spawn + extra


def load_error(path: Path) -> str:
    with pytest.raises(ConfigError) as info:
        load_world(path)
    return str(info.value)


def assert_names(msg: str, *parts: str) -> None:
    for part in parts:
        assert part in msg, f"{part!r} not in {msg!r}"


# --- shipped worlds -------------------------------------------------------------------------

def test_all_shipped_worlds_are_available():
    assert set(SHIPPED) <= set(available_worlds())


@pytest.mark.parametrize("name", SHIPPED)
def test_shipped_world_loads_and_meets_its_sizing_rule(name):
    w = load_world(name)
    assert w.name == name
    robots, groups = PAPER_DEFAULTS[name]
    assert w.defaults["robots"] == robots
    assert w.defaults["groups"] == groups
    assert w.defaults["d_cover"] == 6
    # a d_cover = 6 lattice in the target holds 65-75 % of the robots
    ratio = w.lattice_capacity(6) / robots
    assert 0.65 <= ratio <= 0.75, ratio
    # the spawn areas take all robots at random with room to spare
    assert w.max_random_robots(1.0) >= robots
    # the beacon is inside the target; spawns are outside it, 10-20 units away
    assert w.beacon is not None
    assert w.target.contains(Point(w.beacon))
    for sp in w.spawns:
        assert 10 <= w.target.distance(sp) <= 20
    # the arena walls enclose everything
    xmin, ymin, xmax, ymax = w.arena
    for poly in (w.target, *w.spawns):
        bx0, by0, bx1, by1 = poly.bounds
        assert xmin < bx0 and ymin < by0 and bx1 < xmax and by1 < ymax


@pytest.mark.parametrize("name", ["K", "house", "K-large", "K-huge"])
def test_letter_and_house_targets_are_concave(name):
    target = load_world(name).target
    assert target.area < 0.95 * target.convex_hull.area


def test_corridor_has_spawns_on_both_sides_of_the_target():
    w = load_world("corridor")
    xmin, _, xmax, _ = w.target.bounds
    assert any(sp.bounds[2] < xmin for sp in w.spawns)
    assert any(sp.bounds[0] > xmax for sp in w.spawns)


def test_load_world_by_path(tmp_path):
    w = load_world(write(tmp_path, world_text()))
    assert w.target_area == 30 * 24
    assert w.spawn_area == 30 * 8
    assert w.beacon is None


def test_lattice_capacity_rejects_zero_spacing():
    w = load_world("tiny")
    with pytest.raises(ConfigError, match="d_cover"):
        w.lattice_capacity(0)


# --- validation errors: each names the file, the key and the value --------------------------

def test_self_intersecting_outline(tmp_path):
    path = write(tmp_path, world_text(target="[target]\noutline = [[0, 20], [30, 44], "
                                             "[30, 20], [0, 44]]\n"))
    msg = load_error(path)
    assert_names(msg, str(path), "target.outline", "[[0, 20], [30, 44], [30, 20], [0, 44]]",
                 "Self-intersection")


def test_hole_outside_the_outline_names_the_holes(tmp_path):
    path = write(tmp_path, world_text(target="[target]\noutline = [[0, 20], [30, 20], "
                                             "[30, 44], [0, 44]]\n"
                                             "holes = [[[40, 50], [41, 50], [41, 51]]]\n"))
    msg = load_error(path)
    assert_names(msg, str(path), "target.holes[0]", "[[40, 50], [41, 50], [41, 51]]",
                 "lies outside the outline")


def test_zero_area_outline(tmp_path):
    path = write(tmp_path, world_text(target="[target]\noutline = [[0, 20], [10, 30], "
                                             "[20, 40]]\n"))
    msg = load_error(path)
    assert_names(msg, str(path), "target.outline", "[[0, 20], [10, 30], [20, 40]]", "zero area")


def test_too_few_points(tmp_path):
    path = write(tmp_path, world_text(target="[target]\noutline = [[0, 20], [30, 20]]\n"))
    msg = load_error(path)
    assert_names(msg, str(path), "target.outline", "[[0, 20], [30, 20]]", "at least 3")


def test_point_not_a_number(tmp_path):
    path = write(tmp_path, world_text(target='[target]\noutline = [[0, 20], ["a", 20], '
                                             "[30, 44]]\n"))
    msg = load_error(path)
    assert_names(msg, str(path), "target.outline[1][0]", "'a'")


def test_unknown_top_level_key(tmp_path):
    path = write(tmp_path, world_text(top='name = "t"\ncolour = "blue"\n'))
    msg = load_error(path)
    assert_names(msg, str(path), "'colour'", "'blue'")


def test_unknown_key_in_target(tmp_path):
    path = write(tmp_path, world_text(target=TARGET + "colour = 7\n"))
    msg = load_error(path)
    assert_names(msg, str(path), "target.colour", "7")


def test_unknown_default(tmp_path):
    path = write(tmp_path, world_text(extra="[defaults]\nrobots = 40\nspeed = 3.5\n"))
    msg = load_error(path)
    assert_names(msg, str(path), "defaults.speed", "3.5")


def test_negative_default(tmp_path):
    path = write(tmp_path, world_text(extra="[defaults]\nrobots = -5\n"))
    msg = load_error(path)
    assert_names(msg, str(path), "defaults.robots", "-5")


def test_missing_file(tmp_path):
    path = tmp_path / "nowhere.toml"
    msg = load_error(path)
    assert_names(msg, "'world'", str(path), "not found")


def test_unknown_world_name():
    msg = load_error(Path("no-such-world"))
    assert_names(msg, "'world'", "'no-such-world'", "K", "house")


def test_spawn_overlapping_an_obstacle(tmp_path):
    obstacle = "[[obstacles]]\noutline = [[10, 4], [20, 4], [20, 12], [10, 12]]\n"
    path = write(tmp_path, world_text(extra=obstacle))
    msg = load_error(path)
    assert_names(msg, str(path), "spawn[0].outline", "obstacles[0]", "[30.0, 8.0]",
                 "[20.0, 12.0]")


def test_invalid_toml_syntax(tmp_path):
    path = write(tmp_path, 'name = "t"\n[target\noutline = [[0, 0]]\n')
    msg = load_error(path)
    assert_names(msg, str(path), "not valid TOML", "line 2")


def test_a_file_that_is_not_utf8_is_named(tmp_path):
    path = tmp_path / "latin1.toml"
    path.write_bytes('name = "Gen\xe8ve"\n'.encode("latin-1"))
    msg = load_error(path)
    assert_names(msg, str(path), "not a UTF-8 text file")


def test_a_spawn_area_overlapping_the_target_is_refused(tmp_path):
    spawn = "[[spawn]]\noutline = [[0, 0], [30, 0], [30, 25], [0, 25]]\n"  # 5 units into it
    path = write(tmp_path, world_text(spawn=spawn))
    assert_names(load_error(path), str(path), "spawn[0].outline", "overlaps the target")


def test_overlapping_spawn_areas_count_their_area_once(tmp_path):
    path = write(tmp_path, world_text(extra=SPAWN))  # the same area twice
    assert load_world(path).spawn_area == pytest.approx(30 * 8)


@pytest.mark.parametrize("default, key", [('start = "grid"', "defaults.start"),
                                          ('controller = "nosuch"', "defaults.controller"),
                                          ('drive = "tank"', "defaults.drive")])
def test_a_bad_run_default_names_the_file_and_key(tmp_path, default, key):
    path = write(tmp_path, world_text(extra=f"[defaults]\n{default}\n"))
    assert_names(load_error(path), str(path), f"key '{key}'")


def test_a_world_may_choose_the_drive_and_a_run_may_override_it(tmp_path):
    path = write(tmp_path, world_text(extra='[defaults]\ndrive = "diff"\n'))
    sim = Simulation(path, controller="dispersion", robots=3, max_ticks=2)
    assert sim.physics_config.drive == "diff" and sim.drive.has_heading
    sim = Simulation(path, controller="dispersion", robots=3, max_ticks=2,
                     settings={"drive": "holonomic"})
    assert not sim.drive.has_heading


def test_a_folder_named_like_a_shipped_world_does_not_hide_it(tmp_path, monkeypatch):
    monkeypatch.chdir(tmp_path)
    (tmp_path / "K").mkdir()  # e.g. made by 'swarmsim run K --out K'
    assert load_world("K").name == "K"
    (tmp_path / "mine").mkdir()
    with pytest.raises(ConfigError, match="world file not found: 'mine'"):
        load_world("mine")


def test_formations_start_in_spawn_areas_far_apart():
    """Two small spawn squares at opposite corners: formation centres were drawn in their
    common bounding box until enough landed, which for 112 robots took minutes."""
    import numpy as np

    from swarmsim.world import spawn
    from swarmsim.world.world import world_from_dict

    def square(x0, y0, x1, y1):
        return [[x0, y0], [x1, y0], [x1, y1], [x0, y1]]

    world = world_from_dict({"name": "diagonal", "target": {"outline": square(30, 30, 70, 70)},
                             "spawn": [{"outline": square(0, 0, 10, 10)},
                                       {"outline": square(90, 90, 100, 100)}]})
    positions, groups, leaders = spawn.formation_layout(world, 112, 2, 1.0,
                                                        np.random.default_rng(0))
    assert len(positions) == 112 and sorted(set(groups.tolist())) == [1, 2]
    corner = positions[leaders] > 50  # one leader in each corner square
    assert sorted(corner.all(axis=1).tolist()) == [False, True]


def test_a_random_start_keeps_robots_clear_of_obstacles_and_walls():
    """A spawn area touching an obstacle and the arena wall: centres used to be checked
    only against the spawn area, so bodies started inside the obstacle and the wall."""
    import numpy as np
    import shapely

    from swarmsim import Simulation
    from swarmsim.world.world import world_from_dict

    def square(x0, y0, x1, y1):
        return [[x0, y0], [x1, y0], [x1, y1], [x0, y1]]

    world = world_from_dict({"name": "tight", "target": {"outline": square(0, 30, 20, 50)},
                             "spawn": [{"outline": square(0, 0, 20, 10)}],
                             "obstacles": [{"outline": square(20, 0, 25, 10)}],
                             "arena": {"margin": 0.1}})
    sim = Simulation(world, controller="dispersion", robots=100, seed=0,
                     settings={"start": "random"})
    pos, radius = sim.positions, sim.physics_config.radius
    gap = shapely.distance(world.obstacles[0], shapely.points(pos))
    x0, y0, x1, y1 = world.arena
    walls = np.minimum.reduce([pos[:, 0] - x0, pos[:, 1] - y0, x1 - pos[:, 0], y1 - pos[:, 1]])
    assert gap.min() >= radius and walls.min() >= radius


def test_a_start_spacing_below_a_body_width_is_refused():
    from swarmsim import Simulation

    with pytest.raises(ConfigError, match="key 'spawn_spacing'.*robots would start overlapping"):
        Simulation("tiny", settings={"radius": 0.6, "start": "random"})


def test_a_checkout_finds_its_worlds_without_the_package_data():
    from swarmsim.world import world as world_module

    assert (world_module.REPO_WORLDS_DIR / "K.toml").is_file()
