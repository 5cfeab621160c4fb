"""Per-robot controllers. Each sees only its Perception and returns an Action.

Rule: nothing in this package imports pymunk or pygame, or reads global positions
(tests/structure/test_locality.py enforces it).
"""

from pathlib import Path

from swarmsim.controller import stamp_kernels_by_code

stamp_kernels_by_code(Path(__file__).parent)  # each kernel stamped by its file's code
