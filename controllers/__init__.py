"""Per-robot controllers. Each sees only its Perception and returns an Action.

Rule: nothing in this package imports pymunk or pygame, or reads global positions
(tests/test_locality.py enforces it).
"""

from pathlib import Path

from swarmsim import kernelcache

kernelcache.register_tree(Path(__file__).parent)  # each kernel stamped by its file's code
