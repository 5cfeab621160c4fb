"""swarmsim: a physics-based 2-D swarm-robotics simulator for gradient-and-grouping coverage.

Quick start::

    from swarmsim import Simulation, load_world
    sim = Simulation(load_world("K"), controller="ggc", seed=1)
    result = sim.run()
    print(result.summary["coverage"], result.summary["completion_tick"])

The names below are loaded on first use, so that importing the controller API
(``swarmsim.controller``) loads neither pymunk nor pygame.
"""

from __future__ import annotations

import importlib
from pathlib import Path
from typing import TYPE_CHECKING, Any

from swarmsim.kernels import kernelcache

kernelcache.register_tree(Path(__file__).parent)  # kernels stamped by their file's code
kernelcache.install()  # before any kernel is decorated

_LAZY = {"ConfigError": "swarmsim.errors", "RunResult": "swarmsim.engine.sim",
         "Simulation": "swarmsim.engine.sim", "World": "swarmsim.world.world",
         "available_worlds": "swarmsim.world.world", "load_world": "swarmsim.world.world"}

if TYPE_CHECKING:  # _LAZY's names for a type checker (tests/structure/test_engine_structure.py: equal)
    from swarmsim.engine.sim import RunResult, Simulation
    from swarmsim.errors import ConfigError
    from swarmsim.world.world import World, available_worlds, load_world

__all__ = ["ConfigError", "RunResult", "Simulation", "World", "available_worlds", "load_world"]
__version__ = "0.1.0"


def __getattr__(name: str) -> Any:
    if name in _LAZY:
        return getattr(importlib.import_module(_LAZY[name]), name)
    raise AttributeError(f"module 'swarmsim' has no attribute {name!r}")
