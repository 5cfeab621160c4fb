"""Worlds: World and load_world, shapes, start layouts, world checks and makers."""

from swarmsim.world.world import World, available_worlds, load_world

__all__ = ["World", "available_worlds", "load_world"]
