"""The engine's structure: it knows no controller, has no import circles, and its controller
API loads no physics or drawing library."""

from __future__ import annotations

import ast
import subprocess
import sys
from dataclasses import dataclass
from pathlib import Path

import numpy as np
import pytest

from swarmsim.controller import Action, Perception, RobotSetup
from swarmsim.engine.sim import Simulation
from swarmsim.errors import ConfigError
from swarmsim.registry import available_controllers, get_controller
from swarmsim.results.summary import SummaryCollector
from tests.conftest import square_world
from tests.import_graph import assert_no_circles

ROOT = Path(__file__).resolve().parents[2]
ENGINE = ROOT / "swarmsim"


def engine_imports() -> dict[str, set[str]]:
    """Each engine module (dotted name) -> the swarmsim/controllers modules it imports, at any
    depth of the file (function-level imports too; TYPE_CHECKING ones included)."""
    graph: dict[str, set[str]] = {}
    for path in ENGINE.rglob("*.py"):
        rel = path.relative_to(ROOT).with_suffix("")
        name = ".".join(rel.parts).removesuffix(".__init__")
        found: set[str] = set()
        for node in ast.walk(ast.parse(path.read_text())):
            if isinstance(node, ast.Import):
                found.update(a.name for a in node.names)
            elif isinstance(node, ast.ImportFrom) and node.module and node.level == 0:
                for a in node.names:  # "from package import submodule" is the submodule
                    sub = f"{node.module}.{a.name}"
                    found.add(sub if _is_module(sub) else node.module)
        graph[name] = {m for m in found if m.split(".")[0] in ("swarmsim", "controllers")}
    return graph


def _is_module(dotted: str) -> bool:
    path = ROOT.joinpath(*dotted.split("."))
    return path.with_suffix(".py").exists() or (path / "__init__.py").exists()


def test_the_engine_imports_nothing_from_controllers():
    offenders = {mod: sorted(m for m in deps if m.split(".")[0] == "controllers")
                 for mod, deps in engine_imports().items()}
    assert not {k: v for k, v in offenders.items() if v}


def test_the_engine_has_no_import_circles():
    graph = engine_imports()
    modules = set(graph)
    assert_no_circles({m: {d for d in deps if d in modules and d != m}
                       for m, deps in graph.items()})


def test_the_public_names_are_typed_as_they_are_loaded():
    """swarmsim/__init__.py loads its names on first use (_LAZY) and imports them again under
    TYPE_CHECKING, so that a type checker sees their types: the two agree, name for name and
    module for module, and __all__ lists them."""
    import swarmsim

    typed: dict[str, str | None] = {}
    for node in ast.walk(ast.parse((ENGINE / "__init__.py").read_text())):
        if isinstance(node, ast.If) and ast.unparse(node.test) == "TYPE_CHECKING":
            for imported in node.body:
                assert isinstance(imported, ast.ImportFrom)
                typed.update({a.name: imported.module for a in imported.names})
    assert typed == swarmsim._LAZY
    assert sorted(swarmsim.__all__) == sorted(typed)


def package_of(module: str) -> str:
    """The package of swarmsim/ that holds ``module`` (swarmsim.engine.sim -> swarmsim.engine);
    a module of swarmsim/ itself (swarmsim.cli, swarmsim.controller) stands alone."""
    parts = module.split(".")
    if len(parts) > 2 and parts[0] == "swarmsim" and (ENGINE / parts[1]).is_dir():
        return ".".join(parts[:2])
    return module


def test_the_engine_packages_import_each_other_in_one_direction():
    """No circle between the packages of swarmsim/ (engine, physics, world, ...) and its own
    modules: each stands above all it imports (docs/internals.md, "Where the code lives")."""
    packages: dict[str, set[str]] = {}
    for mod, deps in engine_imports().items():
        home = package_of(mod)
        packages.setdefault(home, set()).update(
            package_of(d) for d in deps if d.startswith("swarmsim") and package_of(d) != home)
    assert {f"swarmsim.{name}" for name in ("engine", "physics", "world")} <= set(packages)
    assert_no_circles(packages)


def test_every_package_is_installed():
    """pyproject.toml names every folder of swarmsim/ and controllers/ that holds an
    __init__.py (a package left out would be missing from an installed copy)."""
    import tomllib

    listed = set(tomllib.loads((ROOT / "pyproject.toml").read_text())
                 ["tool"]["setuptools"]["packages"])
    found = {".".join(p.parent.relative_to(ROOT).parts)
             for top in ("swarmsim", "controllers") for p in (ROOT / top).rglob("__init__.py")}
    assert found | {"swarmsim.worlds"} == listed


def test_importing_the_controller_api_loads_no_physics_or_drawing():
    code = ("import sys, controllers.ggc, controllers.kilobot, swarmsim.controller; "
            "print(sorted(m for m in ('pymunk', 'pygame') if m in sys.modules))")
    out = subprocess.run([sys.executable, "-c", code], capture_output=True, text=True,
                         check=True, cwd=ROOT)
    assert out.stdout.strip() == "[]"


def test_builtin_controllers_are_found_by_entry_point():
    names = available_controllers()
    assert {"ggc", "dispersion", "kilobot", "cvt", "meanshift", "dash", "fcdfs"} <= set(names)
    assert get_controller("dispersion").name == "dispersion"


@dataclass(frozen=True)
class StillParams:
    """No parameters."""


class Still:
    """A per-robot controller that stands still and says so by field name."""

    name = "still"
    Params = StillParams
    STATUSES = ("Standing",)
    SETTLED_STATUSES = ("Standing",)

    @classmethod
    def sensing_range(cls, params) -> float:
        return 2.0

    def __init__(self, setup: RobotSetup, params, rng: np.random.Generator):
        pass

    def step(self, perception: Perception) -> Action:
        return Action((0.0, 0.0), {"status": 0, "moving": False})


def test_a_controller_class_runs_as_given_and_its_broadcasts_by_name():
    sim = Simulation(square_world(), controller=Still, robots=5, max_ticks=3)
    result = sim.run()
    assert result.summary["controller"] == "tests.structure.test_engine_structure:Still"
    assert result.summary["groups"] == 1  # no groups: the world's default does not apply
    assert sim.messages["id"].tolist() == list(range(5))  # the engine fills each robot's id
    assert (sim.messages["status"] == 0).all()


def test_a_controller_without_groups_refuses_groups():
    with pytest.raises(ConfigError, match="has no groups"):
        Simulation.check(square_world(), controller="dispersion", groups=3)


def test_summary_sources_refuse_a_field_written_twice():
    c = SummaryCollector()
    c.add("a", lambda: {"x": 1})
    c.add("b", lambda: {"x": 2})
    with pytest.raises(ValueError, match="'x' written by both 'a' and 'b'"):
        c.collect()


def test_no_test_file_imports_another():
    """Shared helpers live in tests/conftest.py or a helper module (tests/ggc_bot.py, ...),
    never in a test file that others import: a test file is collected, not imported."""
    offenders = {}
    for path in sorted((ROOT / "tests").rglob("test_*.py")):
        imported: set[str] = set()
        for node in ast.walk(ast.parse(path.read_text(encoding="utf-8"))):
            if isinstance(node, ast.Import):
                imported.update(a.name for a in node.names)
            elif isinstance(node, ast.ImportFrom):
                module = node.module or ""
                imported.add(module)
                imported.update(f"{module}.{a.name}" for a in node.names)
        tests = sorted(m for m in imported if any(p.startswith("test_") for p in m.split(".")))
        if tests:
            offenders[str(path.relative_to(ROOT))] = tests
    assert not offenders


def test_every_engine_kernel_registers_its_warm_up():
    """A kernel module's warm_up is registered (swarmsim.kernels.warmup), so Simulation warms it up
    before the run's clock starts; one that is not would compile mid-run."""
    import importlib

    from swarmsim.kernels.warmup import registered_warm_ups

    kernels = [path for path in ENGINE.rglob("*.py")
               if any(isinstance(node, ast.FunctionDef) and node.name == "warm_up"
                      for node in ast.parse(path.read_text()).body)]
    assert len(kernels) >= 5
    registered = [fn for _, fn in registered_warm_ups()]
    for path in kernels:
        name = ".".join(path.relative_to(ROOT).with_suffix("").parts)
        assert importlib.import_module(name).warm_up in registered, name
