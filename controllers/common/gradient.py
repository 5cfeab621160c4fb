"""The hop gradient that GGC, Kilobot and FCDFS broadcast.

A robot's gradient is its hop count from a source (a leader, a seed robot); robots that have
no gradient yet broadcast :data:`INF_GRADIENT`, the paper's INFINITE.
"""

from __future__ import annotations

import numpy as np

INF_GRADIENT = int(np.iinfo(np.int32).max)
"""Gradient value that means "no gradient yet" (the paper's INFINITE)."""

GRADIENT_FIELDS = [("gradient", "i4"), ("group", "i2"), ("leader", "?")]
"""Broadcast fields of a controller with a hop gradient, groups and leaders."""

SILENT = {"gradient": INF_GRADIENT}
"""A neighbour that is not heard reads as having no gradient."""

COLOURINGS = {"gradient": "scale", "group": "category"}
"""The videos may colour robots by gradient (hop count) or group."""
