"""Every size a user can type has an upper bound, said in one line before anything is built
(swarmsim.limits); worlds keep their coordinates in range and their beacon inside the walls;
the capacity tables stay readable with huge numbers."""

from __future__ import annotations

import math
import re
from pathlib import Path

import pytest

from swarmsim import ConfigError, Simulation
from swarmsim.cli import main
from swarmsim.engine.config import SimConfig
from swarmsim.limits import (
    MAX_COORDINATE,
    MAX_FRAME_SIDE,
    MAX_GRID_SIZE,
    MAX_GROUPS,
    MAX_ROBOTS,
    MAX_TICKS,
    field_bounds,
)
from swarmsim.physics.physics import PhysicsConfig
from swarmsim.world import makeworld
from swarmsim.world.world import world_from_dict
from swarmsim.world.worldinfo import describe_world, fit_number, format_report
from tests.errlines import one_error_line

SPEC = 'world = "tiny"\ncontroller = "dispersion"\n[params]\nmax_ticks = 5\n'


@pytest.fixture
def nothing_built(monkeypatch):
    """Fail the test if a run lays out robots or builds physics, or make-world lays out a
    world."""
    def refuse(*args, **kwargs):
        raise AssertionError("a refused input was built")

    from swarmsim.engine import sim as sim_module

    monkeypatch.setattr(sim_module.Simulation, "_setup", refuse)
    monkeypatch.setattr(makeworld, "_joined", refuse)
    monkeypatch.setattr(makeworld, "_check_start", refuse)


def tall_world(tmp_path: Path) -> Path:
    """A world 10 units wide and 2,000 high: frames of it are 200 times as high as wide."""
    path = tmp_path / "tall.toml"
    path.write_text('name = "tall"\n[target]\n'
                    'outline = [[0, 100], [10, 100], [10, 2000], [0, 2000]]\n'
                    '[[spawn]]\noutline = [[0, 0], [10, 0], [10, 50], [0, 50]]\n'
                    '[beacon]\nposition = [5, 500]\n')
    return path


@pytest.mark.parametrize("argv, key", [
    (["run", "K", "--set", "grid_size=1000000"], "grid_size"),
    (["run", "K", "--robots", "100000"], "robots"),
    (["run", "K", "--set", "groups=60000"], "groups"),
    (["run", "K", "--max-ticks", "100000000"], "max_ticks"),
    (["run", "K", "--set", "substeps=100000"], "substeps"),
    (["run", "K", "--set", "iterations=1000000"], "iterations"),
    (["run", "K", "--set", "record_every=100000000"], "record_every"),
    (["run", "K", "--set", "stall_ticks=1e12"], "stall_ticks"),
    (["run", "K", "--max-ticks", "10000000", "--set", "record_every=2"], "record_every"),
    (["run", "K", "--width", "100000", "--snapshot", "OUT/x.png"], "--width"),
    (["run", "TALL", "--width", "7680", "--snapshot", "OUT/x.png"], "--width"),
    (["run", "K", "--fps", "100000", "--video", "OUT/x.mp4"], "--fps"),
    (["run", "K", "--frame-every", "1000000000", "--video", "OUT/x.mp4"], "--frame-every"),
    (["run", "K", "--trajectories", "1000000000", "--out", "OUT/run"], "--trajectories"),
    (["run", "K", "--trajectories", "1", "--max-ticks", "10000000", "--out", "OUT/run"],
     "--trajectories"),
    (["worlds", "K", "--preview", "OUT/p.png", "--width", "100000"], "--width"),
    (["worlds", "TALL", "--preview", "OUT/p.png", "--width", "7680"], "--width"),
    (["sweep", "SPEC", "--out", "OUT/sweep", "--workers", "100000"], "--workers"),
    (["reproduce", "fig17", "--reps", "100000", "--out", "OUT/rep"], "--reps"),
    (["reproduce", "fig17", "--max-ticks", "100000000", "--out", "OUT/rep", "--dry-run"],
     "--max-ticks"),
    (["study", "collisions", "--reps", "100000", "--out", "OUT/study"], "--reps"),
    (["make-world", "--text", "GGC", "--size", "1e5", "--out", "OUT/w.toml"], "--size"),
    (["make-world", "--text", "GGC", "--size", "1e9", "--out", "OUT/w.toml"], "--size"),
    (["make-world", "--text", "GGC", "--size", "1000", "--out", "OUT/w.toml"], "--size"),
    (["make-world", "--text", "GGC", "--d-cover", "0.1", "--out", "OUT/w.toml"], "--size"),
    (["make-world", "--text", "GGC", "--size", "1e6", "--robots", "10", "--out",
      "OUT/w.toml"], "--size"),
    (["make-world", "--text", "GGC", "--robots", "100000", "--out", "OUT/w.toml"], "--robots"),
    (["make-world", "--text", "GGC", "--groups", "100000", "--out", "OUT/w.toml"], "--groups"),
])
def test_every_size_is_bounded_in_one_line_before_anything_is_built(argv, key, tmp_path,
                                                                     capsys, nothing_built):
    spec = tmp_path / "spec.toml"
    spec.write_text(SPEC)
    tall = tall_world(tmp_path)
    out = tmp_path / "out"
    argv = [str(tall) if a == "TALL" else str(spec) if a == "SPEC"
            else a.replace("OUT", str(out)) for a in argv]
    assert main(argv) == 2
    err = one_error_line(capsys)
    assert f"key '{key}'" in err and re.search(r"at most|more than|beyond", err), err
    assert not out.exists()


@pytest.mark.parametrize("cls", [SimConfig, PhysicsConfig])
def test_each_declared_bound_is_refused_and_printed(cls, capsys):
    """Every field that declares a bound refuses one past it (naming the key and the bound),
    takes the bound itself where the other checks allow it, and 'swarmsim params' says it."""
    bounds = field_bounds(cls)
    assert bounds
    for name, (bound, _what) in bounds.items():
        with pytest.raises(ConfigError, match=rf"key '{name}': must be at most {bound:,}"):
            cls(**{name: bound + 1})
    assert main(["params"]) == 0
    listing = capsys.readouterr().out
    for name, (bound, _what) in bounds.items():
        entry = re.search(rf"^  {name} .*?(?=^  \S|\Z)", listing, re.MULTILINE | re.DOTALL).group(0)
        assert f"At most {bound:,}." in " ".join(entry.split()), entry


def test_the_bounds_admit_the_shipped_runs():
    assert SimConfig(robots=MAX_ROBOTS, groups=3, max_ticks=MAX_TICKS,
                     grid_size=MAX_GRID_SIZE).robots == MAX_ROBOTS
    Simulation.check("K")
    Simulation.check("K-large")


def test_make_world_a_world_file_and_run_refuse_groups_past_one_bound(tmp_path, capsys,
                                                                    nothing_built):
    """make-world's --groups, a world file's groups and run's --groups: one bound
    (MAX_GROUPS), refused in the same words naming the key and the value."""
    over = MAX_GROUPS + 1
    said = f"must be at most {MAX_GROUPS:,} (groups in one run), got {over}"
    world = tmp_path / "many.toml"
    world.write_text('name = "many"\n[target]\noutline = [[0, 0], [9, 0], [9, 9], [0, 9]]\n'
                     '[[spawn]]\noutline = [[0, -30], [9, -30], [9, -20], [0, -20]]\n'
                     f'[defaults]\nrobots = {over}\ngroups = {over}\n')
    for argv, key in [
        (["make-world", "--text", "K", "--groups", str(over), "--out", str(tmp_path / "w.toml")],
         "--groups"),
        (["run", "K", "--robots", str(over), "--groups", str(over)], "groups"),
        (["run", str(world)], "defaults.groups"),
    ]:
        assert main(argv) == 2
        err = one_error_line(capsys)
        assert f"key '{key}': {said}" in err, err


def test_a_world_make_world_writes_with_twenty_groups_is_one_run_takes(tmp_path, capsys):
    """More groups than the 16 GGC once took: make-world writes the world, and a run of it
    (formations, or the scattered start) passes every check a run makes before its start."""
    path = tmp_path / "k20.toml"
    assert main(["make-world", "--text", "K", "--robots", "400", "--groups", "20",
                 "--out", str(path)]) == 0
    assert "400 robots, 20 group(s)" in capsys.readouterr().out
    for start in ("formation", "random"):
        config, _ = Simulation.check(str(path), settings={"start": start})
        assert (config.robots, config.groups) == (400, 20)


def test_make_world_takes_the_largest_size_it_suggests(tmp_path, capsys):
    """The refusal's suggested --size is one that make-world accepts (no layout needed to
    know: the refusal comes first)."""
    assert main(["make-world", "--text", "GGC", "--size", "1000", "--out",
                 str(tmp_path / "w.toml")]) == 2
    most = int(re.search(r"give --size ([\d,]+) or less", one_error_line(capsys)).group(1)
               .replace(",", ""))
    from swarmsim.world.shapes import text_shape

    shape = text_shape("GGC")
    spec = makeworld.WorldSpec(name="g", description="", size=float(most))
    makeworld.check_size(shape, float(most), spec)  # no error


# ----------------------------------------------------------------------------- world ranges
def world(**changes) -> dict:
    data = {"name": "w", "target": {"outline": [[0, 0], [20, 0], [20, 20], [0, 20]]},
            "spawn": [{"outline": [[0, -15], [20, -15], [20, -5], [0, -5]]}],
            "beacon": {"position": [10, 10]}}
    data.update(changes)
    return data


@pytest.mark.parametrize("changes, key", [
    ({"target": {"outline": [[0, 0], [1e12, 0], [0, 50]]}}, "target.outline[1][0]"),
    ({"target": {"outline": [[0, 0], [20, 0], [20, -2e6], [0, 20]]}}, "target.outline[2][1]"),
    ({"spawn": [{"outline": [[0, -15], [20, -15], [20, -5e7], [0, -5]]}]},
     "spawn[0].outline[2][1]"),
    ({"obstacles": [{"outline": [[30, 30], [1.5e6, 30], [30, 40]]}]}, "obstacles[0].outline[1][0]"),
    ({"beacon": {"position": [10, 1e7]}}, "beacon.position[1]"),
    ({"arena": {"margin": 1e9}}, "arena.margin"),
])
def test_coordinates_beyond_the_world_range_are_refused(changes, key):
    with pytest.raises(ConfigError, match=rf"key '{re.escape(key)}': must be within "
                                          rf"\+-{MAX_COORDINATE:,.0f} units"):
        world_from_dict(world(**changes))


@pytest.mark.parametrize("position", [[500, 10], [-40, 10], [10, 41], [10, -36], [40, 40]])
def test_a_beacon_outside_the_walls_is_refused(position):
    """The walls are 20 units (the default margin) round the target and the spawn band:
    x -20..40, y -35..40."""
    with pytest.raises(ConfigError, match=r"key 'beacon.position': .* is outside the arena "
                                          r"walls"):
        world_from_dict(world(beacon={"position": position}))


def test_a_beacon_off_the_target_inside_the_walls_is_a_warning():
    w = world_from_dict(world(beacon={"position": [30, 30]}))
    assert any("beacon" in line for line in describe_world(w).warnings)


@pytest.mark.parametrize("value", [0, 7, 999_999, 12_345_678, 4.6e12, 2.3e12 + 0.4])
@pytest.mark.parametrize("width", [7, 8, 9])
def test_numbers_fit_their_column(value, width):
    text = fit_number(value, width)
    assert len(text) == width, text
    # two significant digits at width 7
    assert math.isclose(float(text.replace(",", "")), value, rel_tol=0.05, abs_tol=0.5)


def test_the_capacity_of_a_huge_world_stays_in_columns():
    w = world_from_dict(world(target={"outline": [[-1e6, 0], [1e6, 0], [1e6, 1e6],
                                                  [-1e6, 1e6]]}, beacon={"position": [0, 5e5]}))
    lines = format_report(describe_world(w))
    head = next(line for line in lines if "d_cover " in line)
    robots = lines[lines.index(head) + 1]
    assert len(robots) == len(head)
    assert len(robots.split()) == 1 + len(head.split()) - 2  # one number under each d_cover
    assert all(len(line) <= 100 for line in lines if "warning" not in line)


def test_the_frame_bound_is_the_renderers():
    from swarmsim.render.frame import check_width

    check_width(MAX_FRAME_SIDE)
    with pytest.raises(ValueError):
        check_width(MAX_FRAME_SIDE + 2)


@pytest.mark.parametrize("side, warned", [(40, False), (400, False), (401, True), (1e5, True),
                                          (1e6, True)])
def test_coverage_cells_wider_than_the_coverage_radius_are_a_warning(side, warned):
    """The default raster is 100 x 100 cells over the target's box; cells wider than the
    coverage radius (4 units) measure coverage coarsely."""
    w = world_from_dict(world(target={"outline": [[0, 0], [side, 0], [side, 20], [0, 20]]},
                              beacon={"position": [10, 10]}))
    found = [x for x in describe_world(w).warnings if "coverage cells are" in x]
    assert bool(found) == warned, found
    if warned and side <= 8000:
        assert f"set grid_size={math.ceil(side / 4)}" in found[0]
    fine = world_from_dict(world(target={"outline": [[0, 0], [side, 0], [side, 20], [0, 20]]},
                                 beacon={"position": [10, 10]},
                                 defaults={"grid_size": min(2000, math.ceil(side / 4))}))
    found = [x for x in describe_world(fine).warnings if "coverage cells are" in x]
    assert bool(found) == (side > 8000), found  # a world's own grid_size is what counts


@pytest.mark.parametrize("controller", ["cvt", "meanshift"])
@pytest.mark.parametrize("map_cell", [0.001, 0.05])
def test_a_floor_lattice_too_fine_is_refused(controller, map_cell, nothing_built):
    """CVT and mean shift keep a lattice of floor points per robot: ~(2 r / map_cell)^2."""
    with pytest.raises(ConfigError, match=r"key 'map_cell': .*must be at least 0.1"):
        Simulation.check("corridor", controller=controller, settings={"map_cell": map_cell})
