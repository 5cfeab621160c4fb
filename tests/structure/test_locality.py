"""Local means local: controllers import neither pymunk nor pygame nor the engine's internals,
and a Perception carries no global position."""

import ast
import dataclasses
import re
from pathlib import Path
from typing import ClassVar

import numpy as np
from shapely.geometry import box

from swarmsim import Simulation
from swarmsim.controller import (
    Action,
    NeighbourBatch,
    Perception,
    available_controllers,
    get_controller,
    message_dtype,
    run_message_fields,
)
from swarmsim.sensing.sensing import FloorProbe, FloorSensor
from tests.conftest import square_world
from tests.import_graph import assert_no_circles

CONTROLLERS = Path(__file__).resolve().parents[2] / "controllers"
FORBIDDEN = ("pymunk", "pygame", "shapely", "scipy", "swarmsim.physics.physics", "swarmsim.engine.sim",
             "swarmsim.sensing.sensing", "swarmsim.world.world", "swarmsim.render", "swarmsim.metrics",
             "swarmsim.world.spawn")


def imported_modules(path: Path) -> set[str]:
    tree = ast.parse(path.read_text(), filename=str(path))
    names = set()
    for node in ast.walk(tree):
        if isinstance(node, ast.Import):
            names.update(a.name for a in node.names)
        elif isinstance(node, ast.ImportFrom) and node.module and node.level == 0:
            names.add(node.module)
    return names


def test_controllers_import_nothing_global():
    files = sorted(CONTROLLERS.rglob("*.py"))
    assert len(files) >= 2
    for f in files:
        for mod in imported_modules(f):
            assert not any(mod == bad or mod.startswith(bad + ".") for bad in FORBIDDEN), \
                f"{f.name} imports {mod}"
            if mod.startswith("swarmsim"):
                assert mod == "swarmsim.controller", f"{f.name} imports {mod}"


def test_no_controller_imports_another():
    """A controller imports what it shares only from controllers/common, never another
    controller's module or package (fcdfs once took kilobot's formation travel)."""
    for f in sorted(CONTROLLERS.rglob("*.py")):
        parts = f.relative_to(CONTROLLERS).with_suffix("").parts
        for mod in absolute_imports(f):
            if mod.startswith("controllers."):
                package = mod.split(".")[1]
                assert package in ("common", parts[0]), f"{'/'.join(parts)} imports {mod}"


def absolute_imports(path: Path) -> set[str]:
    """The modules ``path`` (a file under controllers/) imports, relative imports made
    absolute (``from .kilobot import x`` in controllers/fcdfs.py: controllers.kilobot)."""
    package = ["controllers", *path.relative_to(CONTROLLERS).parent.parts]
    names = set()
    for node in ast.walk(ast.parse(path.read_text(), filename=str(path))):
        if isinstance(node, ast.Import):
            names.update(a.name for a in node.names)
        elif isinstance(node, ast.ImportFrom):
            base = package[:len(package) - node.level + 1] if node.level else []
            module = ".".join([*base, *([node.module] if node.module else [])])
            names.update([module] if node.module else
                         [f"{module}.{a.name}" for a in node.names])
    return names


def test_absolute_imports_resolve_relative_ones():
    assert absolute_imports(CONTROLLERS / "cvt" / "robot.py") >= {
        "controllers.cvt.kernel", "controllers.common.localmap"}


def test_no_controller_module_names_global_state():
    for f in sorted(CONTROLLERS.rglob("*.py")):
        text = f.read_text()
        for word in ("space", "physics", "positions", "Simulation", "world."):
            assert not names_attribute(text.replace("p.offsets", ""), word), \
                f"{f.name} uses .{word}"


def names_attribute(text: str, word: str) -> bool:
    """Does ``text`` use the attribute ``.word`` (as a whole name: ``.spaced`` is not
    ``.space``)?"""
    end = r"\b" if word[-1].isalnum() else ""
    return re.search(r"\." + re.escape(word) + end, text) is not None


def test_controllers_only_ask_their_floor_probe():
    """The probe holds the robot's position (privately): a controller calls it, or its
    ``many``, and reads nothing of it."""
    for f in sorted(CONTROLLERS.rglob("*.py")):
        for use in re.findall(r"probe\.(\w+)", f.read_text()):
            assert use == "many", f"{f.name} reads probe.{use}"
    public = [name for name in FloorProbe.__slots__ if not name.startswith("_")]
    assert public == []
    assert not hasattr(FloorSensor(box(0, 0, 1, 1), 1.0).probe_at(0.5, 0.5), "x")


def test_names_attribute_matches_whole_names_only():
    assert names_attribute("sim.space.step()", "space")
    assert names_attribute("self.world.target", "world.")
    assert not names_attribute("self.p.spaced_deadlock_arrive", "space")


def test_perception_has_no_global_fields():
    names = {f.name for f in dataclasses.fields(Perception)}
    assert names == {"tick", "offsets", "distances", "messages", "on_target", "probe", "beacon",
                     "moved", "turned"}


@dataclasses.dataclass(frozen=True)
class _NoParams:
    """No parameters."""


class Circler:
    """Drives round in a slow circle (each robot its own phase) and keeps what it perceives."""

    name = "circler"
    Params = _NoParams
    STATUSES = ("Driving",)
    seen: ClassVar[list[tuple[int, Perception]]] = []

    @classmethod
    def sensing_range(cls, params) -> float:
        return 6.0

    def __init__(self, setup, params, rng):
        self.phase = setup.robot_id

    def step(self, perception: Perception) -> Action:
        Circler.seen.append((perception.tick, perception))
        angle = self.phase + 0.1 * perception.tick
        return Action((0.1 * np.cos(angle), 0.1 * np.sin(angle)), {"status": 0, "moving": True})


def test_a_steered_robot_perceives_how_it_turned_never_its_heading():
    """In a diff run, no number a robot perceives equals a body angle (any robot's, at that
    tick, wrapped), while ``turned`` reports each robot's own turn."""
    Circler.seen = []
    sim = Simulation(square_world(), controller=Circler, robots=8, max_ticks=40,
                     settings={"drive": "diff"})
    angles = []
    while sim.tick < 40:
        angles.append(sim.physics.headings())
        sim.step()
    angles = np.array(angles)
    wrapped = (angles + np.pi) % (2 * np.pi) - np.pi
    turns = np.diff(angles, axis=0)
    for tick, p in Circler.seen:
        values = np.concatenate([p.offsets.ravel(), p.distances, p.moved, [p.turned],
                                 [] if p.beacon is None else p.beacon])
        assert not np.isclose(values[:, None], wrapped[tick][None, :], rtol=0,
                              atol=1e-9).any(), f"tick {tick}: a perceived value is a heading"
    turned = np.array([[p.turned for t, p in Circler.seen if t == tick] for tick in range(1, 40)])
    np.testing.assert_allclose(turned, turns, atol=1e-12)  # robots decide in index order
    assert np.abs(turned).max() > 0.05


def test_a_neighbour_batch_holds_perception_rows_only():
    """What a swarm's ``decide`` sees of the neighbours: the chunk's perceptions end to end."""
    names = {f.name for f in dataclasses.fields(NeighbourBatch)}
    assert names == {"messages", "distances", "starts"}


def test_every_controller_is_declared_properly():
    for name in available_controllers():
        cls = get_controller(name)
        params = cls.Params()
        assert cls.sensing_range(params) > 0
        assert len(cls.STATUSES) >= 1
        assert dataclasses.is_dataclass(params) and params.__dataclass_params__.frozen
        fields = run_message_fields(cls, groups=1, scattered=False)  # [] when undeclared
        assert message_dtype(fields).names[:3] == ("id", "status", "moving")


def test_message_fields_are_optional():
    """A controller that broadcasts nothing of its own declares no MESSAGE_FIELDS."""

    class Quiet:
        name = "quiet"
        Params = get_controller("dispersion").Params
        STATUSES = ("Still",)

        @classmethod
        def sensing_range(cls, params):
            return 3.0

        def __init__(self, setup, params, rng):
            pass

        def step(self, perception):
            return Action()

    assert not hasattr(Quiet, "MESSAGE_FIELDS")
    sim = Simulation("tiny", controller=Quiet, robots=4, max_ticks=3)
    sim.run()
    assert sim.messages.dtype.names == ("id", "status", "moving")


RULE_PARAMETERS = {
    "view", "me", "sense", "pb", "P",  # my neighbours, my state row, my sensors, my probe
    "mine",  # my per-group values (my rows of them, beside my state row)
    "nearest", "a", "b", "r", "reach", "status", "whole", "sender", "waiting", "max_gap",
    "side", "grad", "stuck_now",  # rows, numbers, codes, flags
    "ox", "oy", "d", "x", "y", "vx", "vy", "length", "before", "after", "angles", "count",
    "dist", "wake_range", "wake_on_motion", "wake_tick",
    "px", "py", "bx", "by", "cx", "cy", "hx", "hy",  # points relative to me
    "ux", "uy"}  # a unit heading in my frame
"""Every parameter name a GGC rule function may take: none is anyone's position."""


def test_ggc_rules_take_only_local_arguments():
    """Locality by signature: the rules (controllers/ggc/rules) get one robot's view, state
    row, sensors and probe, and import nothing but numerics and the controller API."""
    import importlib
    import inspect

    rules = sorted((CONTROLLERS / "ggc" / "rules").glob("*.py"))
    seen = set()
    for f in rules:
        allowed = {"__future__", "math", "numpy", "numba", "numba.experimental", "collections",
                   "controllers.common.gradient", "swarmsim.controller"}
        assert imported_modules(f) <= allowed, f.name
        module = importlib.import_module(f"controllers.ggc.rules.{f.stem}")
        for name, fn in vars(module).items():
            py = getattr(fn, "py_func", None)
            if py is None or py.__module__ != module.__name__:
                continue
            params = set(inspect.signature(py).parameters)
            assert params <= RULE_PARAMETERS, (f.name, name, params - RULE_PARAMETERS)
            seen.add(name)
    assert {"coverage", "detection", "initial", "gather", "stops", "should_arrive", "stuck",
            "is_surplus", "formation_gradient"} <= seen


def ggc_imports() -> dict[str, set[str]]:
    """Each module of controllers/ggc (dotted) -> the controllers.ggc modules it imports
    (relative imports resolved; "from . import x" is the module x)."""
    root = CONTROLLERS.parent
    graph: dict[str, set[str]] = {}
    for path in (CONTROLLERS / "ggc").rglob("*.py"):
        parts = path.relative_to(root).with_suffix("").parts
        name = ".".join(parts).removesuffix(".__init__")
        package = name.split(".") if path.name == "__init__.py" else name.split(".")[:-1]
        found = set()
        for node in ast.walk(ast.parse(path.read_text())):
            if isinstance(node, ast.ImportFrom):
                base = package[:len(package) - node.level + 1] if node.level else []
                module = ".".join([*base, *(node.module.split(".") if node.module else [])])
                for a in node.names:
                    sub = f"{module}.{a.name}"
                    as_file = root.joinpath(*sub.split("."))
                    is_module = (as_file.with_suffix(".py").exists()
                                 or (as_file / "__init__.py").exists())
                    found.add(sub if is_module else module)
            elif isinstance(node, ast.Import):
                found.update(a.name for a in node.names)
        graph[name] = {m for m in found if m.startswith("controllers.ggc") and m != name}
    return graph


def test_ggc_has_no_import_circles():
    graph = ggc_imports()
    assert "controllers.ggc.rules.coverage" in graph
    # a package's own __init__ runs first: importing it is not a circle
    assert_no_circles({m: {d for d in deps if not m.startswith(d + ".")}
                       for m, deps in graph.items()})
