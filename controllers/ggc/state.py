"""All robots' GGC state: one structured array, one row per robot (its own memory only).

The rules (rules/) read and write one row at a time, as a numba record (``me``); the
controller (swarm.py) owns the array. A row's broadcast is a function of the row
(:func:`broadcast_rows`).
"""

from __future__ import annotations

from collections.abc import Sequence

import numpy as np
from numba import njit

from controllers.common.gradient import INF_GRADIENT
from swarmsim.controller import RobotSetup

from ._generated import copy_broadcast
from .schema import BROADCAST_NAMES, DATA, MAX_GROUPS, STATE_FIELDS, message_fields
from .statuses import APPROACH, FORMED, INITIAL, MOVING_STATUSES

STATE_DTYPE = np.dtype(STATE_FIELDS)
"""One robot's state (schema.DATA: each field's meaning and units)."""

__all__ = ["BROADCAST_NAMES", "MAX_GROUPS", "STATE_DTYPE", "broadcast_rows", "message_fields",
           "new_state"]


def new_state(setups: Sequence[RobotSetup], orbit: int, h_max: int,
              rngs: Sequence[np.random.Generator]) -> np.ndarray:
    """The run's robots' first rows: each field's ``initial`` value (schema.DATA), then what
    each robot's setup decides."""
    n = len(setups)
    s = np.zeros(n, dtype=STATE_DTYPE)
    for datum in DATA:
        if datum.initial:
            s[datum.name] = datum.initial
    s["id"] = [u.robot_id for u in setups]
    s["group"] = [u.group for u in setups]
    leader = np.array([u.leader for u in setups], dtype=bool)
    scattered = np.array([u.scattered for u in setups], dtype=bool)
    s["leader"] = leader
    s["status"] = np.where(scattered, np.where(leader, FORMED, APPROACH), INITIAL)
    s["visited"] = 1 << s["status"].astype(np.uint16)
    s["gradient"] = np.where(leader, 0, INF_GRADIENT)
    s["gradient_low"] = s["gradient"]
    s["sense"] = float(orbit)
    s["h"] = np.where(leader, h_max, 0)
    for i in np.flatnonzero(leader):
        s["ldist"][i, s["group"][i] - 1] = 0.0
    s["rng"] = [int(rng.integers(1, 2**63)) for rng in rngs]
    return s


def broadcast_rows(state: np.ndarray, rows: np.ndarray, dtype: np.dtype) -> np.ndarray:
    """The broadcasts (in the run's message ``dtype``: :data:`BROADCAST_NAMES`, with the
    ldist and lepoch entries :func:`message_fields` gives) of the robots at ``rows``, in one
    compiled pass (the values of numpy's field-by-field gather, to the bit: the same casts
    to the message's types)."""
    if dtype.names != BROADCAST_NAMES:
        raise ValueError(f"GGC broadcasts have the fields {BROADCAST_NAMES}, not {dtype.names}")
    out = np.empty(len(rows), dtype=dtype)
    _fill_broadcasts(state, np.ascontiguousarray(rows, dtype=np.int64), out)
    return out


@njit(cache=True)
def _fill_broadcasts(state, rows, out):  # pragma: no cover - compiled
    for k in range(rows.shape[0]):
        me, msg = state[rows[k]], out[k]
        moving = False
        for code in MOVING_STATUSES:
            moving = moving or me.status == code
        msg.moving = moving
        copy_broadcast(me, msg)
