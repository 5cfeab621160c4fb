"""DASH's chunk kernel (numba): a chunk's robots' spacing adjustment and commands before their
floor probes, in one pass over their state rows and neighbour rows (:func:`wished`), as
:meth:`DashRobot.step <controllers.dash.robot.DashRobot.step>` computes them.

The same numbers as the per-robot controller, to the bit: the same operations in the same
order, its very kernels for the push (controllers/common/push.py) and the neighbours' spacing
(kernel.py), and Python's ``math.hypot`` as controllers/common/pyhypot.py gives it.

A robot's state (row i): ``level[i]`` (int64) its spacing in adapt_rate steps above s_start,
``s[i]`` its spacing (units), ``status[i]`` (int8, params.STATUSES).
"""

from __future__ import annotations

import math
from collections import namedtuple

import numpy as np
from numba import njit

from controllers.common.push import push_of
from controllers.common.pyhypot import py_hypot as hypot

from .kernel import spacing_view_into
from .params import SEEKING, SPREADING

Gains = namedtuple("Gains", ["d_safe", "d_cover", "s_start", "adapt_rate", "consensus_band",
                             "tolerance", "crowd", "v", "gain", "deadband", "probe_distance"])
"""DashParams' numbers as the kernel reads them (floats, the same names)."""

Heard = namedtuple("Heard", ["starts", "offsets", "distances", "sender", "status", "spacing"])
"""A chunk's neighbour rows: where each robot's start (R + 1,), their offsets (P, 2) and
distances (P,), units, and their broadcast ``id`` (int32), ``status`` (int8) and ``spacing``
(float32, units)."""


@njit(cache=True)
def _adapt(i, a, b, heard, G, level, s, max_level, no_sender, peers
           ):  # pragma: no cover - compiled
    """DashRobot.adapt for robot row ``i`` hearing rows ``a:b``: one adapt_rate step of its
    spacing at most (``peers``: a buffer for its peers' spacings)."""
    mean, too_close = spacing_view_into(peers, heard.distances[a:b], heard.sender[a:b],
                                        heard.status[a:b], heard.spacing[a:b], 1.5 * G.d_cover,
                                        s[i] * (1 - G.tolerance), no_sender, SEEKING)
    if math.isnan(mean):  # no peer: its own
        mean = s[i]
    band, rate = G.consensus_band, G.adapt_rate
    room = too_close == 0 and s[i] + rate <= mean + band
    packed = too_close >= G.crowd and s[i] - rate >= mean - band
    step = 0
    if room or s[i] < mean - band:
        step = 1
    elif packed or s[i] > mean + band:
        step = -1
    level[i] = min(max(level[i] + step, 0), max_level)
    s[i] = G.s_start + level[i] * G.adapt_rate


@njit(cache=True)
def wished(rows, heard, on_target, has_beacon, beacons, G, max_level, no_sender, level, s,
           status, velocity, speed, settled, ask, probe_at):  # pragma: no cover - compiled
    """Each robot k of the chunk (state row ``rows[k]``): its state updated, its velocity
    (units per tick) into ``velocity[k]``, its speed into ``speed[k]``, whether its spacing
    held into ``settled[k]``. ``ask[k]``: the robot is on the target and would move, so its
    floor probe at ``probe_at[k]`` (units) must say the step stays on it."""
    peers = np.empty(heard.distances.shape[0], dtype=heard.spacing.dtype)
    for k in range(rows.shape[0]):
        i = rows[k]
        a, b = heard.starts[k], heard.starts[k + 1]
        held = False
        if not on_target[k]:
            status[i] = SEEKING
            level[i] = 0
            s[i] = G.s_start
            vx, vy = push_of(heard.offsets, heard.distances, a, b, G.d_safe * 1.5, G.gain)
            if has_beacon:
                vx = vx + beacons[k, 0] * G.v
                vy = vy + beacons[k, 1] * G.v
        else:
            before = level[i]
            _adapt(i, a, b, heard, G, level, s, max_level, no_sender, peers)
            vx, vy = push_of(heard.offsets, heard.distances, a, b, s[i], G.gain)
            status[i] = SPREADING
            held = level[i] == before
        sp = hypot(vx, vy)
        if sp > G.v:
            scale = G.v / sp
            vx *= scale
            vy *= scale
            sp = G.v
        velocity[k, 0], velocity[k, 1] = vx, vy
        speed[k] = sp
        settled[k] = held
        ask[k] = sp > G.deadband and on_target[k]
        if ask[k]:
            probe_at[k, 0] = vx / sp * G.probe_distance
            probe_at[k, 1] = vy / sp * G.probe_distance


def warm_up() -> None:
    """Compile (first time on a machine) or load (from the cache) the kernel now, for the
    argument types DashSwarm.decide passes it."""
    from .params import DashParams

    params = DashParams()
    gains = Gains(*(float(getattr(params, name)) for name in Gains._fields))
    heard = Heard(np.array([0, 1], dtype=np.int64), np.array([[1.0, 0.0]]), np.ones(1),
                  np.zeros(1, dtype=np.int32), np.ones(1, dtype=np.int8),
                  np.full(1, 2.0, dtype=np.float32))
    for on in (True, False):
        wished(np.zeros(1, dtype=np.int64), heard, np.full(1, on), True, np.zeros((1, 2)),
               gains, 10, -1, np.zeros(1, dtype=np.int64), np.full(1, 2.0),
               np.zeros(1, dtype=np.int8), np.empty((1, 2)), np.empty(1),
               np.empty(1, dtype=np.bool_), np.empty(1, dtype=np.bool_), np.empty((1, 2)))
