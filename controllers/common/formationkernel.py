"""The formation's neighbour tests, compiled (numba): one pass over a robot's heard
neighbours where numpy made a dozen calls on arrays of a few dozen rows (most of a Kilobot
robot's tick). Comparisons only, so the same answers as the numpy formulas in
:mod:`controllers.kilobot` and :mod:`controllers.common.formation`; the tests compare both ways.

Each takes the robot's neighbour ``distances`` (k,), units, and their broadcasts ``messages``
(k,) (a record array with at least ``id``, ``moving`` and ``gradient``; ``status`` for
:func:`blocked`); a sender of ``no_sender`` was not heard.
"""

from __future__ import annotations

import numpy as np
from numba import njit

from .pyhypot import py_hypot


@njit(cache=True)
def lowest_gradient(distances, messages, reach, no_sender, inf):  # pragma: no cover
    """The smallest gradient below ``inf`` broadcast by a stationary robot heard within
    ``reach`` units, or -1 for none."""
    found, best = False, 0
    for k in range(distances.shape[0]):
        m = messages[k]
        if (distances[k] <= reach and not m.moving and m.id != no_sender
                and m.gradient < inf and (not found or m.gradient < best)):
            found, best = True, m.gradient
    return best if found else -1


@njit(cache=True)
def first_parent(distances, messages, reach, gradient, no_sender):  # pragma: no cover
    """The first row (nearest) of a stationary robot heard within ``reach`` units whose
    gradient is ``gradient``, or -1 for none."""
    for k in range(distances.shape[0]):
        m = messages[k]
        if (distances[k] <= reach and not m.moving and m.id != no_sender
                and m.gradient == gradient):
            return k
    return -1


@njit(cache=True)
def blocked(distances, messages, quiet_range, start_range, gradient, me, no_sender, wait,
            travel):  # pragma: no cover - compiled
    """Kilobot's start rule: a moving robot heard within ``quiet_range`` units, or a robot
    heard within ``start_range`` whose status is ``wait`` or ``travel`` and that outranks
    robot ``me`` of ``gradient`` (a larger gradient, or the same and a larger id)."""
    for k in range(distances.shape[0]):
        m = messages[k]
        if m.id == no_sender:
            continue
        if distances[k] <= quiet_range and m.moving:
            return True
    for k in range(distances.shape[0]):
        m = messages[k]
        if m.id == no_sender or not distances[k] <= start_range:
            continue
        if ((m.status == wait or m.status == travel)
                and (m.gradient > gradient or (m.gradient == gradient and m.id > me))):
            return True
    return False


@njit(cache=True)
def unit(x, y):  # pragma: no cover - compiled
    """controllers.common.formation.unit of (x, y), compiled: (x, y) over its length (Python's
    hypot, to the bit), or (0, 0) when that is 1e-12 or less."""
    n = py_hypot(x, y)
    if n > 1e-12:
        return x / n, y / n
    return 0.0, 0.0


def warm_up(dtype: np.dtype) -> None:
    """Compile (first time on a machine) or load (from the cache) the kernels now, for
    broadcasts of ``dtype`` (read-only, as a robot's perception holds them)."""
    rows = np.zeros(1, dtype=dtype)
    rows.flags.writeable = False
    one = np.ones(1)
    lowest_gradient(one, rows, 1.0, -1, 1)
    first_parent(one, rows, 1.0, 0, -1)
    blocked(one, rows, 1.0, 1.0, 0, 0, -1, 0, 0)
