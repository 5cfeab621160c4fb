"""The worlds GGC was never tuned on (experiments/worlds/, issue #48) load as meant, and their
sweep (experiments/ggc-unseen-worlds.toml) plans every run."""

from __future__ import annotations

from pathlib import Path

import pytest
from shapely.geometry import Point

from swarmsim.experiments.spec import load_spec
from swarmsim.world.world import load_world

ROOT = Path(__file__).resolve().parents[2]
WORLDS = ROOT / "experiments" / "worlds"
SHAPES = {"E": (250, 0, 0), "L-hole": (210, 1, 1), "ring": (300, 1, 1)}
"""name -> robots, holes, obstacles."""


@pytest.mark.parametrize("name", sorted(SHAPES))
def test_an_unseen_world_loads_with_its_shape(name):
    w = load_world(WORLDS / f"{name}.toml")
    robots, holes, obstacles = SHAPES[name]
    assert w.defaults["robots"] == robots and w.defaults["groups"] == 3
    assert len(w.target.interiors) == holes and len(w.obstacles) == obstacles
    assert w.target.area < 0.85 * w.target.convex_hull.area  # concave, or with a hole
    assert w.lattice_capacity(6) < robots  # more robots than d_cover 6 places: surplus
    assert w.free_target.contains(Point(w.beacon))
    for spawn in w.spawns:
        assert not spawn.intersects(w.target)


def test_the_unseen_worlds_sweep_runs_both_rule_sets_on_every_world():
    spec = load_spec(ROOT / "experiments" / "ggc-unseen-worlds.toml")
    runs = spec.runs()
    assert len(runs) == 3 * 2 * 5
    assert {r.settings["ruleset"] for r in runs} == {"yield-holes", "paper"}
    assert {Path(str(r.world_ref)).name for r in runs} == {"E.toml", "L-hole.toml", "ring.toml"}
