"""All robots' GGC state: one structured array, one row per robot (its own memory only).

The rules (rules/) read and write one row at a time, as a numba record (``me``); the
controller (swarm.py) owns the array. A row's broadcast is a function of the row
(:func:`broadcast_rows`).
"""

from __future__ import annotations

import math
from collections.abc import Sequence

import numpy as np
from numba import njit

from controllers.common.gradient import INF_GRADIENT
from swarmsim.controller import NO_SENDER, RobotSetup

from .rules.aggregation import FAR
from .rules.coverage import NO_WAY_SLOTS
from .rules.holes import NO_HOLE
from .statuses import APPROACH, FORMED, INITIAL, MOVING_STATUSES

MAX_GROUPS = 16
"""Largest number of groups a run may have (the per-group fields' size)."""

STATE_DTYPE = np.dtype([
    # who I am, what I broadcast
    ("id", "i4"), ("group", "i2"), ("leader", "?"), ("status", "i1"), ("visited", "u2"),
    ("grad", "i4"),
    ("cmd", "i1"), ("travel_x", "f8"), ("travel_y", "f8"), ("touch", "?"), ("stepped", "?"),
    ("enclosed", "?"), ("blocked", "i1"),
    # travel: the route my formation took (it decides my group's orbit sense)
    ("route_x", "f8"), ("route_y", "f8"), ("has_route", "?"), ("orbit_chosen", "?"),
    ("initial_since", "i8"), ("grad_low", "i4"),
    # edge following
    ("sense", "f8"), ("head_x", "f8"), ("head_y", "f8"), ("stepping", "?"),
    ("no_way", "i4", (NO_WAY_SLOTS,)), ("no_way_next", "i8"),
    # circling and progress (Equation 3), deadlocks
    ("circ_id", "i4"), ("circled", "f8"), ("last_bearing", "f8"),
    ("odo_x", "f8"), ("odo_y", "f8"), ("progress_tick", "i8"), ("resume_tick", "i8"),
    ("deadlocks", "i4"), ("episodes", "i4"), ("in_deadlock", "?"), ("yield_count", "i4"),
    ("collision_stops", "i4"),
    # islands off the target (rules/island.py): my heading's turn since target floor
    ("turned", "f8"), ("leaving", "?"),
    # confined without a place (rules/confined.py): ticks searching, displacement meanwhile,
    # the most arrived robots heard meanwhile
    ("roam_ticks", "i8"), ("roam_x", "f8"), ("roam_y", "f8"), ("roam_seen", "i4"),
    # the surplus lap
    ("away", "?"), ("frontier", "f8"), ("lap_whole", "?"), ("winding", "f8"),
    ("beacon_angle", "f8"), ("surplus", "i4"),
    # the scattered start
    ("h", "i1"), ("handover", "i4"), ("handover_tick", "i8"), ("quiet", "i4"),
    ("ldist", "f8", (MAX_GROUPS,)), ("lepoch", "i8", (MAX_GROUPS,)),
    # holes inside the structure (rules/holes.py): hops to the nearest, its offset (units)
    ("hole", "i1"), ("hole_x", "f8"), ("hole_y", "f8"),
    ("seen_x", "f8"), ("seen_y", "f8"), ("seen_since", "i8"), ("hole_rest", "i8"),
    ("path", "f8"),
    # crossings of the structure (rules/cross.py): on one, its start and the next's (path)
    ("crossing", "?"), ("cross_from", "f8"), ("cross_after", "f8"),
    # my own random stream (xorshift64*)
    ("rng", "u8"),
])
"""One robot's state (units: lengths, ticks, radians). ``visited``: bit s set once the robot
has had status s."""

ALL_MESSAGE_FIELDS = [("gradient", "i4"), ("group", "i2"), ("leader", "?"), ("cmd", "i1"),
                      ("vx", "f4"), ("vy", "f4"), ("touch", "?"), ("stepped", "?"),
                      ("enclosed", "?"), ("h", "i1"), ("handover", "i4"),
                      ("ldist", "f4", (MAX_GROUPS,)), ("lepoch", "i4", (MAX_GROUPS,)),
                      ("quiet", "i4"), ("hole", "i1"), ("hx", "f4"), ("hy", "f4"),
                      ("blocked", "i1")]
"""GGC's broadcast fields (beside the engine's id, status, moving) for up to MAX_GROUPS
groups; a run of the scattered start has one ldist and lepoch entry per group, a run of
formations none (:func:`message_fields`)."""


def message_fields(groups: int, scattered: bool) -> list[tuple]:
    """GGC's broadcast fields for a run with ``groups`` groups. ``ldist`` and ``lepoch`` (the
    leaders' distances of the scattered start's aggregation) have one entry per group when
    the robots start ``scattered``, else none: formations never read them, and every
    broadcast a robot hears is copied once a tick, so 80 bytes more of them per row (10
    groups) cost time on every tick."""
    per_group = groups if scattered else 0
    out = []
    for field in ALL_MESSAGE_FIELDS:
        out.append((field[0], field[1], (per_group,)) if len(field) == 3 else field)
    return out


def new_state(setups: Sequence[RobotSetup], orbit: int, h_max: int,
              rngs: Sequence[np.random.Generator]) -> np.ndarray:
    """The run's robots' first rows."""
    n = len(setups)
    s = np.zeros(n, dtype=STATE_DTYPE)
    s["id"] = [u.robot_id for u in setups]
    s["group"] = [u.group for u in setups]
    leader = np.array([u.leader for u in setups], dtype=bool)
    scattered = np.array([u.scattered for u in setups], dtype=bool)
    s["leader"] = leader
    s["status"] = np.where(scattered, np.where(leader, FORMED, APPROACH), INITIAL)
    s["visited"] = 1 << s["status"].astype(np.uint16)
    s["grad"] = np.where(leader, 0, INF_GRADIENT)
    s["grad_low"] = s["grad"]
    s["sense"] = float(orbit)
    s["no_way"] = NO_SENDER
    s["circ_id"] = NO_SENDER
    s["last_bearing"] = math.nan
    s["lap_whole"] = True
    s["beacon_angle"] = math.nan
    s["h"] = np.where(leader, h_max, 0)
    s["handover"] = NO_SENDER
    s["handover_tick"] = -1
    s["ldist"] = FAR
    s["hole"] = NO_HOLE
    s["seen_since"] = -1
    for i in np.flatnonzero(leader):
        s["ldist"][i, s["group"][i] - 1] = 0.0
    s["rng"] = [int(rng.integers(1, 2**63)) for rng in rngs]
    return s


BROADCAST_NAMES = ("id", "status", "moving", *(f[0] for f in ALL_MESSAGE_FIELDS))
"""The fields of a GGC broadcast (the engine's base fields first), in the dtype's order."""


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
        msg.id, msg.status = me.id, me.status
        moving = False
        for code in MOVING_STATUSES:
            moving = moving or me.status == code
        msg.moving = moving
        msg.gradient, msg.group, msg.leader, msg.cmd = me.grad, me.group, me.leader, me.cmd
        msg.vx, msg.vy = me.travel_x, me.travel_y
        msg.touch, msg.stepped, msg.enclosed = me.touch, me.stepped, me.enclosed
        msg.h, msg.handover, msg.quiet = me.h, me.handover, me.quiet
        for g in range(msg.ldist.shape[0]):
            msg.ldist[g], msg.lepoch[g] = me.ldist[g], me.lepoch[g]
        msg.hole, msg.hx, msg.hy = me.hole, me.hole_x, me.hole_y
        msg.blocked = me.blocked
