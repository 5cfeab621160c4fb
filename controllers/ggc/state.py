"""All robots' GGC state: one structured array, one row per robot (its own memory only), and
beside it the per-group values (schema.PER_GROUP), one (robots, groups) array each.

The rules (rules/) read and write one row at a time, as a numba record (``me``), and the
robot's rows of the per-group arrays (``mine``, a schema.PerGroup); the controller
(swarm.py) owns the arrays. A robot's broadcast is a function of its rows
(:func:`broadcast_rows`).
"""

from __future__ import annotations

from collections.abc import Sequence

import numpy as np
from numba import njit

from controllers.common.gradient import INF_GRADIENT
from swarmsim.controller import RobotSetup

from ._generated import copy_broadcast, group_rows
from .schema import BROADCAST_NAMES, DATA, PER_GROUP, STATE_FIELDS, PerGroup, message_fields
from .statuses import APPROACH, FORMED, INITIAL, MOVING_STATUSES

STATE_DTYPE = np.dtype(STATE_FIELDS)
"""One robot's state (schema.DATA: each field's meaning and units)."""

__all__ = ["BROADCAST_NAMES", "STATE_DTYPE", "PerGroup", "broadcast_rows", "message_fields",
           "new_per_group", "new_state"]


def new_state(setups: Sequence[RobotSetup], orbit: int, h_max: int,
              rngs: Sequence[np.random.Generator]) -> np.ndarray:
    """The run's robots' first rows: each field's ``initial`` value (schema.DATA), then what
    each robot's setup decides."""
    n = len(setups)
    s = np.zeros(n, dtype=STATE_DTYPE)
    for datum in DATA:
        if datum.initial and not datum.per_group:
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
    s["rng"] = [int(rng.integers(1, 2**63)) for rng in rngs]
    return s


def new_per_group(setups: Sequence[RobotSetup]) -> PerGroup:
    """The run's robots' first per-group rows (schema.PER_GROUP, each datum's ``initial``
    value; a leader is at distance 0 from its own group's leader): (robots, groups) arrays
    in a run that starts scattered, (robots, 0) in a formation start (whose rules never read
    them). Their size follows the run's groups; their numba type does not."""
    n = len(setups)
    groups = setups[0].groups if setups and setups[0].scattered else 0
    values = PerGroup(*(np.full((n, groups), d.initial, dtype=d.state) for d in PER_GROUP))
    if groups:
        for i, u in enumerate(setups):
            if u.leader:
                values.ldist[i, u.group - 1] = 0.0
    return values


def broadcast_rows(state: np.ndarray, per_group: PerGroup, rows: np.ndarray,
                   dtype: np.dtype) -> np.ndarray:
    """The broadcasts (in the run's message ``dtype``: :data:`BROADCAST_NAMES`, with the
    ldist and lepoch entries :func:`message_fields` gives, from ``per_group``'s arrays) of
    the robots at ``rows``, in one compiled pass (the values of numpy's field-by-field
    gather, to the bit: the same casts to the message's types)."""
    if dtype.names != BROADCAST_NAMES:
        raise ValueError(f"GGC broadcasts have the fields {BROADCAST_NAMES}, not {dtype.names}")
    groups = dtype[PER_GROUP[0].name].shape[0]
    if any(a.shape[1] < groups for a in per_group):
        raise ValueError(f"the message dtype holds {groups} groups, the per-group arrays "
                         f"{per_group[0].shape[1]}")
    out = np.empty(len(rows), dtype=dtype)
    _fill_broadcasts(state, per_group, np.ascontiguousarray(rows, dtype=np.int64), out)
    return out


@njit(cache=True)
def _fill_broadcasts(state, per_group, rows, out):  # pragma: no cover - compiled
    for k in range(rows.shape[0]):
        me, mine, msg = state[rows[k]], group_rows(per_group, rows[k]), out[k]
        moving = False
        for code in MOVING_STATUSES:
            moving = moving or me.status == code
        msg.moving = moving
        copy_broadcast(me, mine, msg)
