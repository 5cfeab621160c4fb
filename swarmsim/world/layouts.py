"""Start layouts: where the robots stand at tick 0 and what each is told (its RobotSetup).

A controller declares the layouts it can start from (``LAYOUTS``, names from
:data:`LAYOUTS`) and its ``default_start``; every controller can start "random". The geometry
lives in :mod:`swarmsim.world.spawn`.
"""

from __future__ import annotations

from collections.abc import Callable
from dataclasses import dataclass

import numpy as np

from swarmsim.controller import RobotSetup
from swarmsim.world import spawn
from swarmsim.world.world import World


@dataclass(frozen=True)
class LayoutRequest:
    """What a start layout is asked for.

    Attributes:
        robots: number of robots.
        groups: number of groups (1 = no grouping).
        spawn_spacing: least centre distance at a random start, units.
        formation_spacing: lattice spacing of a formation, units.
        clearance: least distance from a robot's centre to a wall or obstacle, units.
    """

    robots: int
    groups: int
    spawn_spacing: float
    formation_spacing: float
    clearance: float


Layout = Callable[[World, LayoutRequest, np.random.Generator, np.random.Generator],
                  tuple[np.ndarray, list[RobotSetup]]]
"""``layout(world, request, layout_rng, role_rng) -> (positions (N, 2), setups)``."""


def random_start(world: World, req: LayoutRequest, layout_rng: np.random.Generator,
                 role_rng: np.random.Generator) -> tuple[np.ndarray, list[RobotSetup]]:
    """Robots scattered uniformly in the spawn areas; with groups, ``groups`` robots drawn at
    random are told they lead groups 1..groups (the others have no group yet)."""
    positions = spawn.random_layout(world, req.robots, req.spawn_spacing, layout_rng,
                                    clearance=req.clearance)
    leaders = role_rng.choice(req.robots, size=req.groups, replace=False)
    group_of = {int(r): k + 1 for k, r in enumerate(leaders)}
    setups = [RobotSetup(i, leader=i in group_of, group=group_of.get(i, 0), groups=req.groups,
                         scattered=True)
              for i in range(req.robots)]
    return positions, setups


def formation_start(world: World, req: LayoutRequest, layout_rng: np.random.Generator,
                    role_rng: np.random.Generator) -> tuple[np.ndarray, list[RobotSetup]]:
    """``groups`` hexagonal formations of about robots / groups robots each, every robot told
    its group, and the robot at each formation's centre told it leads."""
    positions, group_of, leaders = spawn.formation_layout(
        world, req.robots, req.groups, req.formation_spacing, layout_rng)
    lead = set(leaders.tolist())
    setups = [RobotSetup(i, leader=i in lead, group=int(g), groups=req.groups)
              for i, g in enumerate(group_of)]
    return positions, setups


LAYOUTS: dict[str, Layout] = {"random": random_start, "formation": formation_start}
"""Every start layout by name."""
GROUPED = ("formation",)
"""Layouts that group robots themselves (one formation per group, a leader at its centre)."""

__all__ = ["GROUPED", "LAYOUTS", "Layout", "LayoutRequest", "formation_start", "random_start"]
