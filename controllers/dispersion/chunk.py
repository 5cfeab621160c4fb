"""Dispersion's chunk kernel (numba): a chunk's robots' commands before their floor probes, in
one pass over their neighbour rows (:func:`wished`), as
:meth:`DispersionRobot.step <controllers.dispersion.robot.DispersionRobot.step>` computes
them.

The same numbers as the per-robot controller, to the bit: the same operations in the same
order (the push's rows added in order, as numpy sums a (k, 2) array over its rows; the C
library's hypot, which numba's ``math.hypot`` and numpy's ``hypot`` both call).
"""

from __future__ import annotations

import math
from collections import namedtuple

from numba import njit

Gains = namedtuple("Gains", ["d_cover", "v", "gain", "deadband", "probe_distance"])
"""DispersionParams' numbers as the kernel reads them (floats, the same names)."""


@njit(cache=True)
def wished(starts, offsets, distances, on_target, has_beacon, beacons, G, velocity, speed,
           ask, probe_at):  # pragma: no cover - compiled
    """Each robot k's velocity (units per tick) into ``velocity[k]`` and its speed into
    ``speed[k]``: the push from neighbours closer than d_cover plus, off the target, the
    beacon's pull, capped at v. ``ask[k]``: the robot is on the target and would move, so its
    floor probe at ``probe_at[k]`` (units) must say the step stays on it."""
    for k in range(starts.shape[0] - 1):
        vx = vy = 0.0
        sx = sy = 0.0
        close = False
        for j in range(starts[k], starts[k + 1]):
            if distances[j] < G.d_cover:
                d = max(distances[j], 1e-6)
                push = (G.d_cover - d) / d
                sx += offsets[j, 0] * push
                sy += offsets[j, 1] * push
                close = True
        if close:
            vx -= G.gain * sx
            vy -= G.gain * sy
        if not on_target[k] and has_beacon:
            vx += beacons[k, 0] * G.v
            vy += beacons[k, 1] * G.v
        s = math.hypot(vx, vy)
        if s > G.v:
            scale = G.v / s
            vx *= scale
            vy *= scale
            s = G.v
        velocity[k, 0], velocity[k, 1] = vx, vy
        speed[k] = s
        ask[k] = s > G.deadband and on_target[k]
        if ask[k]:
            probe_at[k, 0] = vx / s * G.probe_distance
            probe_at[k, 1] = vy / s * G.probe_distance
