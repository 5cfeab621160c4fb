"""Per-robot controllers. Each sees only its Perception and returns an Action.

Rule: nothing in this package imports pymunk or pygame, or reads global positions
(tests/test_locality.py enforces it).
"""
