"""swarmsim: a physics-based 2-D swarm-robotics simulator for gradient-and-grouping coverage.

Quick start::

    from swarmsim import Simulation, load_world
    sim = Simulation(load_world("K"), controller="ggc", seed=1)
    result = sim.run()
    print(result.summary["coverage"], result.summary["completion_tick"])
"""

from swarmsim.errors import ConfigError
from swarmsim.sim import RunResult, Simulation
from swarmsim.world import World, available_worlds, load_world

__all__ = ["ConfigError", "RunResult", "Simulation", "World", "available_worlds", "load_world"]
__version__ = "0.1.0"
