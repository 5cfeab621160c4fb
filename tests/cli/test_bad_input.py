"""Bad input: one clear line, refused before anything is built, nothing left behind.

Also the metric bug found with it (obstacles inside the target counted as target floor), a
controller class given to the Python API, and groups for controllers that have none.
"""

from __future__ import annotations

import math
from pathlib import Path

import numpy as np
import pytest
import shapely

from controllers.dispersion import Dispersion
from swarmsim import ConfigError, Simulation
from swarmsim.cli import main
from swarmsim.engine.config import SimConfig
from swarmsim.experiments import load_spec, run_sweep
from swarmsim.experiments.figures import PaperSetup
from swarmsim.experiments.spec import spec_from_dict
from swarmsim.metrics import CoverageGrid
from swarmsim.world.spawn import max_formation_robots
from swarmsim.world.world import available_worlds, load_world, world_from_dict
from tests.errlines import one_error_line

TINY_TOML = (Path(__file__).parents[2] / "worlds" / "tiny.toml").read_text()


def world_dict(obstacles=(), target=((0, 0), (20, 0), (20, 20), (0, 20))) -> dict:
    """A 20 x 20 target (by default) above a spawn band, with ``obstacles``."""
    return {"name": "w", "target": {"outline": [list(p) for p in target]},
            "spawn": [{"outline": [[0, -15], [20, -15], [20, -5], [0, -5]]}],
            "obstacles": [{"outline": [list(p) for p in ob]} for ob in obstacles],
            "beacon": {"position": [10, 10]}}


def box(x0, y0, x1, y1):
    return ((x0, y0), (x1, y0), (x1, y1), (x0, y1))


@pytest.fixture
def nothing_built(monkeypatch):
    """Fail the test if a run gets as far as laying out robots or building physics."""
    def refuse(*args, **kwargs):
        raise AssertionError("a refused run built its layout or physics")

    monkeypatch.setattr(Simulation, "_setup", refuse)


# ----------------------------------------------------------------------------- non-finite
@pytest.mark.parametrize("key, value", [
    ("d_cover", math.inf), ("d_cover", math.nan), ("coverage_radius", math.inf),
    ("coverage_radius", -math.inf), ("v_max", math.nan), ("eps0", math.nan),
    ("radius", math.inf), ("spin_traction", math.nan), ("spin_traction", -math.inf),
    ("speed_noise", math.inf), ("message_loss", math.nan)])
def test_a_non_finite_value_is_refused_naming_the_key(key, value, nothing_built):
    with pytest.raises(ConfigError, match=rf"key '{key}': must be .*got {value!r}"):
        Simulation("tiny", settings={key: value})


@pytest.mark.parametrize("text", ["inf", "nan", "-inf", "Infinity"])
def test_a_non_finite_set_value_is_refused(text, nothing_built):
    with pytest.raises(ConfigError, match="key 'coverage_radius': must be a finite number"):
        Simulation("tiny", settings={"coverage_radius": float(text)})


def test_spin_traction_may_be_infinite_as_documented():
    Simulation.check("tiny", settings={"spin_traction": math.inf})


def test_simconfig_itself_refuses_non_finite_numbers():
    with pytest.raises(ConfigError, match="key 'plateau_delta': must be a finite number"):
        SimConfig(plateau_delta=math.nan)
    with pytest.raises(ConfigError, match="key 'wake_eps'"):
        SimConfig(wake_eps=math.inf)


@pytest.mark.parametrize("args", [
    ["run", "tiny", "--d-cover", "inf"],
    ["run", "tiny", "--controller", "dispersion", "--d-cover", "inf"],
    ["run", "tiny", "--set", "coverage_radius=inf"],
    ["run", "tiny", "--set", "d_cover=nan"],
    ["run", "tiny", "--set", "radius=inf"]])
def test_the_command_line_refuses_non_finite_values_in_one_line(args, tmp_path, capsys,
                                                                 nothing_built):
    out = tmp_path / "a" / "b"
    assert main([*args, "--out", str(out), "--quiet"]) == 2
    assert "must be a finite number" in one_error_line(capsys)
    assert not (tmp_path / "a").exists()


@pytest.mark.parametrize("line, bad", [("d_cover = 6.0", "d_cover = inf"),
                                       ("d_cover = 6.0", "d_cover = nan"),
                                       ("robots = 40", "robots = -inf")])
def test_a_world_file_refuses_non_finite_defaults(line, bad, tmp_path):
    path = tmp_path / "w.toml"
    path.write_text(TINY_TOML.replace(line, bad))
    with pytest.raises(ConfigError, match=rf"w.toml: key 'defaults.{bad.split()[0]}'"):
        load_world(path)


def test_a_world_file_refuses_non_finite_coordinates():
    data = world_dict(obstacles=[box(5, 5, 8, 8)])
    data["obstacles"][0]["outline"][1][0] = math.nan
    with pytest.raises(ConfigError, match=r"key 'obstacles\[0\].outline\[1\]\[0\]'"):
        world_from_dict(data)


def test_a_sweep_spec_refuses_non_finite_values(tmp_path):
    spec = tmp_path / "s.toml"
    spec.write_text('world = "tiny"\ncontroller = "dispersion"\n[grid]\nd_cover = [4, inf]\n')
    with pytest.raises(ConfigError, match=r"s.toml: key 'grid.d_cover': must be a finite"):
        load_spec(spec)
    spec.write_text('world = "tiny"\n[params]\ncoverage_radius = nan\n')
    with pytest.raises(ConfigError, match=r"key 'params.coverage_radius': must be a finite"):
        load_spec(spec)


# ----------------------------------------------------------------------------- free floor
def test_an_obstacle_covering_the_target_is_refused():
    with pytest.raises(ConfigError, match=r"key 'obstacles'.* 0 units\^2 of free floor.*the "
                                          r"obstacles cover it"):
        world_from_dict(world_dict(obstacles=[box(-1, -1, 21, 21)]))
    with pytest.raises(ConfigError, match="obstacles cover it"):  # or two halves of it
        world_from_dict(world_dict(obstacles=[box(-1, -1, 10, 21), box(10, -1, 21, 21)]))


def test_a_target_smaller_than_a_robot_is_refused():
    with pytest.raises(ConfigError, match=r"key 'target.outline'.*too small"):
        world_from_dict(world_dict(target=box(0, 0, 0.5, 0.5)))


def test_an_obstacle_covering_the_target_is_refused_on_the_command_line(tmp_path, capsys):
    path = tmp_path / "covered.toml"
    path.write_text(TINY_TOML + "\n[[obstacles]]\noutline = [[8, 28], [48, 28], [48, 56], "
                    "[8, 56]]\n")
    assert main(["run", str(path), "--quiet", "--out", str(tmp_path / "out")]) == 2
    assert "covered.toml: key 'obstacles'" in one_error_line(capsys)
    assert not (tmp_path / "out").exists()


def test_coverage_counts_free_target_floor_only():
    """An obstacle in the middle of the target is not floor to cover: robots on every free
    pixel cover 100 %, and the target area is the free floor's."""
    world = world_from_dict(world_dict(obstacles=[box(5, 5, 15, 15)]))
    assert world.target_area == 400 - 100
    assert world.lattice_capacity(2) == int(300 / (math.sqrt(3) / 2 * 4))
    grid = CoverageGrid.for_target(world.target, 0.1, 20, 20, world.obstacles)
    assert (grid.x0, grid.y0, grid.dx, grid.dy) == (0, 0, 1, 1)  # the target's bounding box
    assert grid.n_target_pixels == 400 - 100
    xs, ys = grid.centres.T
    assert not shapely.contains_xy(world.obstacles[0], xs, ys).any()
    assert grid.coverage(grid.centres) == 1.0  # the obstacle's pixels used to stay uncovered
    sim = Simulation(world, controller="dispersion", robots=10, max_ticks=1,
                     settings={"grid_size": 20})
    assert sim.grid.n_target_pixels == 300


def test_an_obstacle_partly_over_the_targets_edge_keeps_the_grid_on_the_outlines_box():
    world = world_from_dict(world_dict(obstacles=[box(15, -2, 25, 22)]))  # the right quarter
    assert world.target_area == pytest.approx(300)
    grid = CoverageGrid.for_target(world.target, 1.0, 20, 20, world.obstacles)
    assert (grid.dx, grid.dy) == (1, 1) and grid.inside[:, 15:].sum() == 0
    assert grid.inside[:, :15].all()


def test_a_grid_with_no_cell_on_free_floor_is_refused():
    with pytest.raises(ConfigError, match="key 'grid_size': no cell"):
        CoverageGrid.for_target(shapely.box(0, 0, 10, 10), 1.0, 2, 2,
                                obstacles=[shapely.box(1, 1, 9, 9)])


@pytest.mark.parametrize("name", available_worlds())
def test_shipped_worlds_coverage_grid_is_unchanged_by_obstacle_handling(name):
    world = load_world(name)
    assert world.free_target is world.target and world.target_area == world.target.area
    with_obstacles = CoverageGrid.for_target(world.target, 4.0, 100, 100, world.obstacles)
    plain = CoverageGrid.for_target(world.target, 4.0, 100, 100)
    assert np.array_equal(with_obstacles.inside, plain.inside)


# ----------------------------------------------------------------------------- robot counts
@pytest.mark.parametrize("settings, message", [
    ({}, r"50000 robots cannot start in formation at spacing 1: .* holds at most \d+"),
    ({"start": "random"}, r"spawn areas \(total area 3960\) cannot hold 50000 robots")])
def test_an_impossible_robot_count_is_refused_before_anything_is_built(settings, message,
                                                                       nothing_built):
    with pytest.raises(ConfigError, match=rf"K.toml: key 'robots': {message}"):
        Simulation.check("K", robots=50_000, settings=settings)  # at most MAX_ROBOTS
    with pytest.raises(ConfigError, match=message):
        Simulation("K", robots=50_000, settings=settings)


def test_the_formation_bound_admits_what_fits():
    """The bound is an upper bound: counts that lay out (K's 603; 600 robots spilling over
    the floor round a small spawn square, as in test_sim) pass it."""
    assert max_formation_robots(load_world("K"), 1.0) > 603 * 10
    from tests.conftest import square_world

    world = square_world(margin=10.0)
    assert max_formation_robots(world, 1.0) >= 600
    Simulation.check(world, controller="ggc", robots=600, groups=1)


def test_an_impossible_robot_count_on_the_command_line(tmp_path, capsys, nothing_built):
    for extra in ([], ["--set", "start=random"]):
        assert main(["run", "K", "--robots", "10000000", "--quiet", "--out",
                     str(tmp_path / "x" / "y"), *extra]) == 2
        assert "key 'robots'" in one_error_line(capsys)
    assert not (tmp_path / "x").exists()


def test_a_sweep_refuses_an_impossible_count_before_any_run(tmp_path):
    spec = {"world": "tiny", "controller": "dispersion", "params": {"max_ticks": 30},
            "grid": {"robots": [20, 500]}}
    with pytest.raises(ConfigError, match=r"cannot hold 500 robots.*\(in the run with "
                                          r"robots=500"):
        spec_from_dict(spec)


# ----------------------------------------------------------------------------- files left
def test_sweep_with_zero_workers_writes_nothing(tmp_path, capsys):
    spec = tmp_path / "s.toml"
    spec.write_text('world = "tiny"\ncontroller = "dispersion"\n[params]\nmax_ticks = 5\n')
    out = tmp_path / "out" / "sweep"
    assert main(["sweep", str(spec), "--out", str(out), "--workers", "0", "--quiet"]) == 2
    assert one_error_line(capsys) == "swarmsim: error: key '--workers': must be >= 1, got 0"
    assert not (tmp_path / "out").exists()
    with pytest.raises(ConfigError, match="--workers"):  # the Python API too
        run_sweep(load_spec(spec).runs(), out, workers=0, progress=False)
    assert not (tmp_path / "out").exists()


@pytest.mark.parametrize("command", [["reproduce", "fig17"], ["study", "collisions"]])
def test_reproduce_and_study_with_zero_workers_write_nothing(command, tmp_path, capsys):
    out = tmp_path / "out"
    assert main([*command, "--out", str(out), "--workers", "0", "--quiet"]) == 2
    assert "key '--workers'" in one_error_line(capsys)
    assert not out.exists()


@pytest.mark.parametrize("bad", [["--robots", "0"], ["--controller", "no-such"],
                                 ["--set", "nope=1"], ["--groups", "0"]])
def test_a_refused_run_leaves_no_folder(bad, tmp_path, capsys):
    args = ["run", "tiny", "--quiet", "--out", str(tmp_path / "o" / "p"),
            "--video", str(tmp_path / "v" / "w" / "x.mp4"),
            "--snapshot", str(tmp_path / "s" / "x.png"), *bad]
    assert main(args) == 2
    one_error_line(capsys)
    assert list(tmp_path.iterdir()) == []


def test_a_video_that_is_not_mp4_is_refused_before_the_run(tmp_path, capsys, nothing_built):
    assert main(["run", "tiny", "--video", str(tmp_path / "v" / "x.avi"), "--out",
                 str(tmp_path / "o")]) == 2
    assert "key '--video': must be an .mp4 file" in one_error_line(capsys)
    assert list(tmp_path.iterdir()) == []


@pytest.mark.slow
def test_a_valid_run_makes_its_folders(tmp_path, capsys):
    out = tmp_path / "o" / "p"
    assert main(["run", "tiny", "--quiet", "--max-ticks", "3", "--out", str(out)]) == 0
    assert (out / "summary.json").is_file()


# ----------------------------------------------------------------------------- API
def test_a_controller_class_is_accepted_and_named():
    sim = Simulation("tiny", controller=Dispersion, max_ticks=3)
    assert sim.controller_name == "dispersion"  # registered under its name
    assert sim.run().summary["controller"] == "dispersion"
    from examples.my_controller import GoToLight

    sim = Simulation("tiny", controller=GoToLight, max_ticks=3)
    assert sim.run().summary["controller"] == "examples.my_controller:GoToLight"
    Simulation.check("tiny", controller=GoToLight)


def test_a_subclass_of_a_registered_controller_is_named_by_module_and_class():
    class Mine(Dispersion):
        pass

    assert Simulation("tiny", controller=Mine, max_ticks=1).controller_name.endswith(
        ":test_a_subclass_of_a_registered_controller_is_named_by_module_and_class.<locals>"
        ".Mine")


@pytest.mark.parametrize("bad, message", [
    (type("NotOne", (), {}), r"key 'controller': '.*NotOne' is not a controller class"),
    (42, (r"key 'controller': expected a controller name, 'module:Class' or a controller "
          r"class, got 42"))])
def test_something_that_is_not_a_controller_class_is_refused(bad, message, nothing_built):
    with pytest.raises(ConfigError, match=message):
        Simulation("tiny", controller=bad)


# ----------------------------------------------------------------------------- groups
@pytest.fixture
def three_group_world(tmp_path) -> str:
    """tiny with the world default groups = 3 (as K and house have)."""
    path = tmp_path / "w3.toml"
    path.write_text(TINY_TOML.replace("groups = 1", "groups = 3"))
    return str(path)


def test_the_worlds_groups_apply_only_where_they_are_used(three_group_world):
    sim = Simulation(three_group_world, controller="dispersion", max_ticks=2)
    assert sim.config.groups == 1 and sim.run().summary["groups"] == 1
    assert sum(sim.start_groups > 0) == 1  # one leader, of group 1
    assert Simulation(three_group_world, controller="ggc", max_ticks=1).config.groups == 3
    # a formation start makes one formation per group, whatever the controller
    sim = Simulation(three_group_world, controller="dispersion", max_ticks=1,
                     settings={"start": "formation"})
    assert sim.config.groups == 3 and set(sim.start_groups.tolist()) == {1, 2, 3}


@pytest.mark.parametrize("how", ["argument", "setting"])
def test_asking_a_controller_without_groups_for_groups_is_an_error(how, nothing_built):
    kw = {"groups": 3} if how == "argument" else {"settings": {"groups": 3}}
    with pytest.raises(ConfigError, match=r"key 'groups': controller 'dispersion' has no "
                                          r"groups \(value 3\)"):
        Simulation("tiny", controller="dispersion", **kw)
    Simulation.check("tiny", controller="dispersion", groups=1)


def test_groups_for_a_controller_without_groups_on_the_command_line(capsys):
    assert main(["run", "tiny", "--controller", "dispersion", "--groups", "3"]) == 2
    assert "has no groups (value 3)" in one_error_line(capsys)


def test_figures_and_studies_leave_groups_out_for_controllers_without_them():
    setup = PaperSetup()
    assert setup.settings("ggc", groups=3)["groups"] == 3
    assert setup.settings("kilobot", groups=3)["groups"] == 3  # formations: one per group
    assert "groups" not in setup.settings("cvt", groups=3)
    assert setup.settings("cvt", groups=3, start="formation")["groups"] == 3
    from swarmsim.experiments.collisions import StudySetup

    assert StudySetup().settings("rigid", 0.0)["groups"] == 3
    assert "groups" not in StudySetup(controller="dispersion").settings("rigid", 0.0)


def test_huge_finite_values_are_refused_or_run_never_a_traceback(nothing_built):
    for key, start in (("spawn_spacing", "random"), ("formation_spacing", "formation")):
        with pytest.raises(ConfigError, match=r"key 'robots'.*at most 0"):
            Simulation.check("tiny", settings={key: 1e300, "start": start})
    assert load_world("tiny").lattice_capacity(1e300) == 0


def test_a_huge_coverage_radius_covers_everything_without_overflow():
    sim = Simulation("tiny", controller="dispersion", max_ticks=2,
                     settings={"coverage_radius": 1e300})
    assert sim.run().summary["coverage"] == 1.0
    assert sim.grid.coverage(sim.positions) == 1.0  # the tree's rule agrees


def test_a_sweep_whose_executor_cannot_start_writes_nothing(tmp_path, monkeypatch, capsys):
    """A scheduler that cannot be reached (here: no dask.distributed to reach it with) is
    refused before the sweep writes its folder or results.csv."""
    import builtins

    real_import = builtins.__import__

    def no_dask(name, *args, **kwargs):
        if name.startswith("dask"):
            raise ImportError(name)
        return real_import(name, *args, **kwargs)

    monkeypatch.setattr(builtins, "__import__", no_dask)
    spec = tmp_path / "s.toml"
    spec.write_text('world = "tiny"\ncontroller = "dispersion"\n[params]\nmax_ticks = 5\n')
    out = tmp_path / "out"
    assert main(["sweep", str(spec), "--out", str(out), "--scheduler", "tcp://127.0.0.1:1",
                 "--quiet"]) == 2
    assert "key '--scheduler'" in one_error_line(capsys)
    assert not out.exists()


def test_robots_larger_than_the_free_floor_are_refused(nothing_built):
    world = world_from_dict(world_dict(target=box(0, 0, 2, 2)))  # 4 units^2: fine for 0.4
    Simulation.check(world, controller="dispersion", robots=1)
    with pytest.raises(ConfigError, match=r"key 'radius': 1.5: one robot's disc is larger than "
                                          r"the target's free floor \(4 units\^2\)"):
        Simulation.check(world, controller="dispersion", robots=1,
                         settings={"radius": 1.5, "spawn_spacing": 3.0,
                                   "formation_spacing": 3.0})
