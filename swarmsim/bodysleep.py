"""Parked robots sleep in pymunk: the low-level parts Physics needs (pymunk body sleeping).

Not the engine's robot sleep (controllers asking not to be decided, swarmsim/wakes.py): this
is Chipmunk's own sleeping of bodies at rest, which takes them out of its solver.

Chipmunk keeps every body jointed to a KINEMATIC body awake, so a robot's control body is made
STATIC while the robot is parked (joints kept: the drive still holds it like floor friction,
and it is still pushed by others, which wakes it). Three things break once bodies sleep, and
this module handles them:

- pymunk.batch walks awake bodies, then static bodies, then sleeping ones, and sleeping, waking
  and type changes swap bodies around in those arrays: :class:`BodyRows` maps rows to robots by
  body id on every read.
- Setting a sleeping body's velocity wakes it (and a batch write skips some): :class:`Parking`
  writes velocities only to the control bodies of robots that move, one by one.
- pymunk's ``Body.body_type`` setter refuses ``STATIC`` for a body jointed to a dynamic body
  (its assertion is inverted): :class:`Parking` calls Chipmunk's ``cpBodySetType`` directly.
"""

from __future__ import annotations

from collections.abc import Sequence

import numpy as np
import pymunk
from pymunk._chipmunk_cffi import lib


class BodyRows:
    """Which pymunk.batch row holds which robot body and which control body.

    Rows follow the space's internal arrays, which sleeping and type changes reorder, so
    :meth:`update` is given the rows' body ids after every step. Only rows whose id changed
    are looked up again.

    Args:
        robot_ids: (N,) body ids of the robots' bodies.
        control_ids: (N,) body ids of their control bodies.
    """

    def __init__(self, robot_ids: Sequence[int], control_ids: Sequence[int]):
        ids = np.array(list(robot_ids) + list(control_ids), dtype=np.uintp)
        self.n = len(robot_ids)
        order = np.argsort(ids, kind="stable")
        self._sorted = ids[order]
        self._code = order  # index into robots (< n) and then controls (>= n)
        self._row_of = np.full(len(ids), -1, dtype=np.intp)
        self._row_ids: np.ndarray | None = None

    def update(self, row_ids: np.ndarray) -> None:
        """Take the body id of every row (as pymunk.batch returned them, BODY_ID)."""
        if self._row_ids is not None and len(row_ids) == len(self._row_ids):
            changed = np.flatnonzero(row_ids != self._row_ids)
        else:
            changed = np.arange(len(row_ids))
        if len(changed):
            ids = row_ids[changed]
            at = np.searchsorted(self._sorted, ids).clip(0, len(self._sorted) - 1)
            found = self._sorted[at] == ids
            self._row_of[self._code[at[found]]] = changed[found]
            self._row_ids = row_ids.copy()
        if (self._row_of < 0).any():
            raise RuntimeError("a robot's body is missing from the space's rows")

    @property
    def robot_rows(self) -> np.ndarray:
        """(N,) the row of each robot's body."""
        return self._row_of[:self.n]

    @property
    def control_rows(self) -> np.ndarray:
        """(N,) the row of each robot's control body."""
        return self._row_of[self.n:]

    def asleep(self, parked: np.ndarray) -> np.ndarray:
        """(N,) bool: robots whose bodies pymunk has put to sleep.

        Sleeping bodies come last in the rows, after the static bodies, among which are the
        control bodies of the ``parked`` robots; awake bodies come first. So a robot sleeps
        exactly when its row lies beyond every parked control body's row (only a parked robot
        can sleep: a KINEMATIC control body keeps its robot awake).
        """
        if not parked.any():
            return np.zeros(self.n, dtype=bool)
        return self.robot_rows > self.control_rows[parked].max()


class Parking:
    """Parks and unparks robots, and writes the movers' commanded velocities.

    A robot whose command was zero for this tick and the one before is parked: its control
    body becomes STATIC, and pymunk may put it to sleep once it rests (``sleep_time_threshold``
    on the space). A parked robot given a non-zero command is unparked: its body is woken
    FIRST, and only then its control body made KINEMATIC again (the other way round, waking
    would leave its joints out of the solver). A STATIC control body at rest and a KINEMATIC one
    commanded to stand still drive the robot alike; only sleeping differs.

    Args:
        robots: the robots' dynamic bodies (in the space).
        controls: their control bodies (KINEMATIC, in the space).
    """

    def __init__(self, robots: Sequence[pymunk.Body], controls: Sequence[pymunk.Body]):
        self._robot_ptrs = [b._body for b in robots]
        self._control_ptrs = [b._body for b in controls]
        n = len(robots)
        self.parked = np.zeros(n, dtype=bool)
        self._zero_before = np.zeros(n, dtype=bool)
        self._written = np.zeros((n, 2))  # the control bodies' velocities, units per tick

    def command(self, velocities: np.ndarray) -> None:
        """Apply this tick's commands (N, 2), units per tick: park, unpark, then write."""
        v = np.asarray(velocities, dtype=np.float64)
        zero = ~(v != 0.0).any(axis=1)
        to_park = np.flatnonzero(zero & self._zero_before & ~self.parked)
        to_unpark = np.flatnonzero(~zero & self.parked)
        self._zero_before = zero
        for i in to_unpark.tolist():
            lib.cpBodyActivate(self._robot_ptrs[i])  # first: its joints rejoin the solver
            lib.cpBodySetType(self._control_ptrs[i], pymunk.Body.KINEMATIC)
        for i in to_park.tolist():
            lib.cpBodySetType(self._control_ptrs[i], pymunk.Body.STATIC)  # velocity becomes 0
        self.parked[to_unpark] = False
        self.parked[to_park] = True
        self._written[to_park] = 0.0
        write = np.flatnonzero((v != self._written).any(axis=1))  # parked robots: v == 0
        if len(write):
            set_velocity, ptrs = lib.cpBodySetVelocity, self._control_ptrs
            rows = v[write]
            for i, vx, vy in zip(write.tolist(), rows[:, 0].tolist(), rows[:, 1].tolist(),
                                 strict=True):
                set_velocity(ptrs[i], (vx, vy))
            self._written[write] = rows
