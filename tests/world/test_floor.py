"""The travel floor (swarmsim/world/floor.py): the farthest target point's shortest-path
distance from the spawn areas, and that distance over v_max in ticks."""

from __future__ import annotations

import math

import pytest

from swarmsim.world.floor import travel_distance, travel_floor_ticks
from swarmsim.world.world import load_world, world_from_dict


def _world(target: list, spawns: list, obstacles: list | None = None) -> dict:
    data = {"name": "w", "target": {"outline": target},
            "spawn": [{"outline": s} for s in spawns]}
    if obstacles:
        data["obstacles"] = [{"outline": o} for o in obstacles]
    return data


RECT = [[0, 50], [40, 50], [40, 80], [0, 80]]
BAND = [[0, 0], [40, 0], [40, 10], [0, 10]]


def test_a_rectangle_above_a_band_is_its_far_corner_straight_up() -> None:
    """Target y 50..80 over a spawn band y 0..10 of the same width: the far edge is 70 away."""
    world = world_from_dict(_world(RECT, [BAND]))
    assert travel_distance(world) == pytest.approx(70.0, abs=1e-9)
    assert travel_floor_ticks(world, 0.1) == pytest.approx(700.0, abs=1e-6)
    assert travel_floor_ticks(world, 0.5) == pytest.approx(140.0, abs=1e-6)


def test_a_narrow_spawn_makes_the_far_corner_the_farthest_point() -> None:
    """Spawn square x 0..10, y 0..10: the far corner (40, 80) is hypot(30, 70) away."""
    world = world_from_dict(_world(RECT, [[[0, 0], [10, 0], [10, 10], [0, 10]]]))
    assert travel_distance(world) == pytest.approx(math.hypot(30, 70), abs=1e-9)


def test_the_farthest_point_between_two_spawns_is_found_inside_an_edge() -> None:
    """Two spawn squares at the ends of a long strip: the farthest point is the strip's far
    edge's middle (x 50), not a vertex: hypot(40, 30) from both squares' corners."""
    target = [[0, 40], [100, 40], [100, 50], [0, 50]]
    spawns = [[[0, 0], [10, 0], [10, 10], [0, 10]], [[90, 0], [100, 0], [100, 10], [90, 10]]]
    world = world_from_dict(_world(target, spawns))
    assert travel_distance(world) == pytest.approx(math.hypot(40, 40), abs=0.05)


def test_an_obstacle_in_the_way_lengthens_the_walk_round_it() -> None:
    """A wall x -20..60 at y 20..22 between a small spawn (x 15..25) and the target (x 0..40,
    y 50..80): the walk goes round one of the wall's ends, longer than the straight line. The
    two ways are equally long to the far edge's middle (20, 80), the farthest point: from the
    spawn's corner (25, 10) to the wall's corner (60, 20), up to (60, 22), on to (20, 80)."""
    spawn = [[15, 0], [25, 0], [25, 10], [15, 10]]
    straight = world_from_dict(_world(RECT, [spawn]))
    walled = world_from_dict(_world(RECT, [spawn], [[[-20, 20], [60, 20], [60, 22],
                                                     [-20, 22]]]))
    free = travel_distance(straight)
    assert free == pytest.approx(math.hypot(15, 70), abs=1e-9)
    expected = math.hypot(35, 10) + 2 + math.hypot(40, 58)
    assert travel_distance(walled) == pytest.approx(expected, abs=0.05)
    assert travel_distance(walled) > free + 20


def test_an_obstacle_off_the_way_changes_nothing() -> None:
    spawn = [[15, 0], [25, 0], [25, 10], [15, 10]]
    aside = world_from_dict(_world(RECT, [spawn], [[[100, 0], [110, 0], [110, 10], [100, 10]]]))
    assert travel_distance(aside) == pytest.approx(math.hypot(15, 70), abs=1e-9)


@pytest.mark.parametrize(("name", "units"), [("K", 185.0), ("house", 175.0),
                                             ("K-large", 326.0), ("K-huge", 655.0)])
def test_the_shipped_worlds_floors(name: str, units: float) -> None:
    """K's farthest corners (10, 225) and (142, 225) stand 185 above the spawn band's top
    (y 40); the house's roof apex (90, 215) 175 above y 40; K-large's 326 (issue 70 measured
    over the coverage raster's cell centres: 1,841, 1,742 and 3,245 ticks at v = 0.1); K-huge's
    top edge (y 770.41) 655 above its spawn band's top (y 115.41)."""
    assert travel_distance(load_world(name)) == pytest.approx(units, abs=1e-6)


def test_a_bad_speed_is_refused() -> None:
    world = world_from_dict(_world(RECT, [BAND]))
    for v in (0.0, -1.0, math.nan, math.inf):
        with pytest.raises(ValueError, match="v_max"):
            travel_floor_ticks(world, v)


def test_the_world_report_states_the_floor_at_the_engines_default_speed() -> None:
    """`swarmsim worlds PATH` says K's floor: 1,850 ticks at v_max 0.1 (SimConfig's)."""
    from swarmsim.engine.config import SimConfig
    from swarmsim.world.worldinfo import V_MAX, describe_world, format_report

    assert SimConfig().v_max == V_MAX
    lines = format_report(describe_world(load_world("K")))
    assert "  floor       1,850 ticks at v_max 0.1: the farthest target point is 185.0 units" \
        in lines


def test_the_worlds_list_has_a_floor_column(capsys) -> None:
    from swarmsim.cli import main

    assert main(["worlds"]) == 0
    lines = capsys.readouterr().out.splitlines()
    head = lines[0].split()
    assert head[-1] == "floor"
    rows = {line.split()[0]: line.split() for line in lines[1:]}
    assert rows["K"][-1] == "1,850" and rows["house"][-1] == "1,750"
    assert rows["K-large"][-1] == "3,260"
    assert max(len(line) for line in lines) <= 100


def test_a_target_walled_off_has_no_floor(tmp_path, capsys) -> None:
    """Four walls round the target leave no path from the spawn: the distance is inf, the
    report says so and a run's summary has null floor fields."""
    from swarmsim import Simulation
    from swarmsim.world.worldinfo import describe_world, format_report

    walls = [[[-5, 45], [45, 45], [45, 47], [-5, 47]], [[-5, 83], [45, 83], [45, 85], [-5, 85]],
             [[-5, 45], [-3, 45], [-3, 85], [-5, 85]], [[43, 45], [45, 45], [45, 85], [43, 85]]]
    data = _world(RECT, [BAND], walls) | {"beacon": {"position": [20, 65]}}
    world = world_from_dict(data)
    assert travel_distance(world) == math.inf
    assert ("  floor       none: obstacles wall part of the target off from the spawn areas"
            in format_report(describe_world(world)))
    summary = Simulation(world, controller="dispersion", robots=5, max_ticks=2).run().summary
    assert summary["travel_floor_ticks"] is None and summary["floor_ratio"] is None


def test_a_bad_world_is_still_refused_in_one_line_by_worlds_and_run(tmp_path, capsys) -> None:
    """The floor is measured only on a valid world: a bad one is refused as before."""
    from swarmsim.cli import main

    bad = tmp_path / "bad.toml"
    bad.write_text('name = "bad"\n[target]\noutline = [[0, 0], [10, 0], [10, 10], [0, 10]]\n'
                   '[[spawn]]\noutline = [[0, -9], [10, -9], [10, "x"]]\n')
    for argv in (["worlds", str(bad)], ["run", str(bad), "--max-ticks", "5", "--quiet"]):
        assert main(argv) == 2
        err = capsys.readouterr().err.strip().splitlines()
        assert len(err) == 1 and err[0].startswith("swarmsim: error: "), err
        assert "bad.toml" in err[0] and "spawn[0].outline" in err[0], err
