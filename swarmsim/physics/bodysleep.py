"""Parked robots sleep in pymunk: the low-level parts Physics needs (pymunk body sleeping).

Not the engine's robot sleep (controllers asking not to be decided, swarmsim/engine/wakes.py): this
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
from numba import njit
from pymunk._chipmunk_cffi import lib

from swarmsim.kernels.carrays import c_array
from swarmsim.physics import chipmunkcalls

_GOLDEN = np.uint64(0x9E3779B97F4A7C15)  # Fibonacci hashing's multiplier, 2^64 / phi


class IdTable:
    """Body id -> code: an open-addressing hash table (linear probing), looked up in compiled
    code (numba): one pass over the queried ids, cheaper than numpy's searchsorted or argsort
    on ids like pymunk's (addresses).

    Args:
        ids: the distinct keys (body ids, as pymunk.batch reports them).
        codes: (same length) the value of each key (e.g. a robot index).
    """

    def __init__(self, ids: Sequence[int], codes: Sequence[int]):
        bits = max(4, int(np.ceil(np.log2(8 * max(len(ids), 1)))))
        self._shift = np.uint64(64 - bits)
        self._mask = (1 << bits) - 1
        self._keys = np.zeros(1 << bits, dtype=np.uint64)
        self._used = np.zeros(1 << bits, dtype=bool)
        self._codes = np.full(1 << bits, -1, dtype=np.intp)
        self.probes = 1  # the longest probe sequence of any key
        keys = np.asarray(ids, dtype=np.uint64)
        for key, slot, code in zip(keys.tolist(), self._slots(keys).tolist(), codes, strict=True):
            steps = 1
            while self._used[slot] and self._keys[slot] != key:
                slot, steps = (slot + 1) & self._mask, steps + 1
            if self._used[slot]:
                raise ValueError(f"body id {key} given twice")
            self._keys[slot], self._used[slot], self._codes[slot] = key, True, code
            self.probes = max(self.probes, steps)

    def _slots(self, keys: np.ndarray) -> np.ndarray:
        return ((keys >> np.uint64(4)) * _GOLDEN >> self._shift).astype(np.intp)

    @property
    def arrays(self) -> tuple:
        """(table, used, codes, shift, mask, probes): the table as :func:`lookup_ids` takes it
        after the keys, for compiled callers."""
        return self._keys, self._used, self._codes, self._shift, self._mask, self.probes

    def lookup(self, ids: np.ndarray) -> np.ndarray:
        """The code of each id (same shape); -1 for ids not in the table."""
        keys = np.ascontiguousarray(ids, dtype=np.uint64).ravel()
        out = lookup_ids(keys, *self.arrays)
        return out.reshape(np.shape(ids))


@njit(cache=True)
def lookup_ids(keys, table, used, codes, shift, mask, probes):  # pragma: no cover - compiled
    """IdTable.lookup's probing (``keys`` uint64, then :attr:`IdTable.arrays`): each key's
    slot, then the next ones, until the key, an empty slot, or ``probes`` slots (as far as any
    key lies from its own): -1, not in the table."""
    out = np.full(len(keys), -1, dtype=np.intp)
    for k in range(len(keys)):
        key = keys[k]
        slot = np.intp(((key >> np.uint64(4)) * _GOLDEN) >> shift)
        for _ in range(probes):
            if not used[slot]:
                break
            if table[slot] == key:
                out[k] = codes[slot]
                break
            slot = (slot + 1) & mask
    return out


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
        ids = list(robot_ids) + list(control_ids)
        self.n = len(robot_ids)
        self._table = IdTable(ids, range(len(ids)))  # robots (< n), then controls (>= n)
        self._row_of = np.full(len(ids), -1, dtype=np.intp)
        self._row_ids: np.ndarray | None = None

    def update(self, row_ids: np.ndarray) -> None:
        """Take the body id of every row (as pymunk.batch returned them, BODY_ID)."""
        if self._row_ids is not None and len(row_ids) == len(self._row_ids):
            changed = np.flatnonzero(row_ids != self._row_ids)
        else:
            changed = np.arange(len(row_ids))
        if len(changed):
            codes = self._table.lookup(row_ids[changed])
            found = codes >= 0
            self._row_of[codes[found]] = changed[found]
            self._row_ids = row_ids.copy()
            if self._row_of.min() < 0:
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
        self._calls = chipmunkcalls.body_calls()
        self._robot_at = chipmunkcalls.addresses(robots)
        self._control_at = chipmunkcalls.addresses(controls)
        n = len(robots)
        self.parked = np.zeros(n, dtype=bool)
        self._zero_before = np.zeros(n, dtype=bool)
        self._written = np.zeros((n, 2))  # the control bodies' velocities, units per tick
        self.written_spin = np.zeros(n)
        """The control bodies' spins written (a steering drive's, :meth:`command_spin`),
        rad/tick; a checkpoint keeps it beside :attr:`bookkeeping`."""
        self._set_spin: int | None = None  # cpBodySetAngularVelocity for compiled code

    def prepare_spin(self) -> None:
        """Make :meth:`command_spin`'s compiled calls ready (compiled or loaded, and checked:
        chipmunkcalls.spin_setter): a run with a steering drive asks before its first tick."""
        if self._calls is not None:
            self._set_spin = chipmunkcalls.spin_setter(self._calls)

    @property
    def bookkeeping(self) -> tuple[np.ndarray, np.ndarray, np.ndarray]:
        """(parked, zero command last tick, control velocities written): what a copy of the
        run needs to park and write as this one would (see :meth:`take_bookkeeping`)."""
        return self.parked, self._zero_before, self._written

    def take_bookkeeping(self, bookkeeping: tuple[np.ndarray, np.ndarray, np.ndarray]) -> None:
        """Take another Parking's :attr:`bookkeeping`, on robots none of which is parked yet
        (a Space just built): parks, in robot order, the robots it says are parked (their
        control bodies become STATIC)."""
        if self.parked.any():
            raise RuntimeError("take_bookkeeping needs robots none of which is parked")
        parked, zero_before, written = bookkeeping
        self.parked[:], self._zero_before[:], self._written[:] = parked, zero_before, written
        for i in np.flatnonzero(parked).tolist():
            lib.cpBodySetType(self._control_ptrs[i], pymunk.Body.STATIC)

    def command(self, velocities: np.ndarray) -> None:
        """Apply this tick's commands (N, 2), units per tick: park, unpark, then write."""
        v = c_array(velocities, np.float64, writeable=True)
        to_unpark, to_park, write = _plan(v, self._zero_before, self.parked, self._written)
        calls = self._calls
        if calls is not None:  # the same calls, in the same order, from compiled code
            chipmunkcalls.command(calls, self._robot_at, self._control_at, to_unpark, to_park,
                                  write, v)
            return
        self._park_and_unpark(to_unpark, to_park)
        if len(write):
            set_velocity, ptrs = lib.cpBodySetVelocity, self._control_ptrs
            rows = v[write]
            for i, vx, vy in zip(write.tolist(), rows[:, 0].tolist(), rows[:, 1].tolist(),
                                 strict=True):
                set_velocity(ptrs[i], (vx, vy))


    def _park_and_unpark(self, to_unpark: np.ndarray, to_park: np.ndarray) -> None:
        for i in to_unpark.tolist():
            lib.cpBodyActivate(self._robot_ptrs[i])  # first: its joints rejoin the solver
            lib.cpBodySetType(self._control_ptrs[i], pymunk.Body.KINEMATIC)
        for i in to_park.tolist():
            lib.cpBodySetType(self._control_ptrs[i], pymunk.Body.STATIC)  # velocity becomes 0

    def command_spin(self, lin: np.ndarray, spin: np.ndarray) -> None:
        """:meth:`command` for a steering drive: this tick's control velocities ``lin``
        (N, 2), units/tick, and spins ``spin`` (N,), rad/tick. A zero command is zero in both;
        a parked control body's velocity and spin are zero. Park, unpark, then write (velocity,
        then spin, robot by robot)."""
        v = c_array(lin, np.float64, writeable=True)
        w = c_array(spin, np.float64, writeable=True)
        to_unpark, to_park, write = _plan_spin(v, w, self._zero_before, self.parked,
                                               self._written, self.written_spin)
        if self._calls is not None and self._set_spin is not None:  # the same calls, compiled
            chipmunkcalls.command_spin(self._calls, self._set_spin, self._robot_at,
                                       self._control_at, to_unpark, to_park, write, v, w)
            return
        self._park_and_unpark(to_unpark, to_park)
        if len(write):
            set_velocity, set_spin = lib.cpBodySetVelocity, lib.cpBodySetAngularVelocity
            ptrs = self._control_ptrs
            for i, vx, vy, wi in zip(write.tolist(), v[write, 0].tolist(), v[write, 1].tolist(),
                                     w[write].tolist(), strict=True):
                set_velocity(ptrs[i], (vx, vy))
                set_spin(ptrs[i], wi)


@njit(cache=True)
def _plan_spin(v, w, zero_before, parked, written, written_spin):  # pragma: no cover
    """:func:`_plan` with spins ``w`` (N,) beside the velocities ``v`` (N, 2): zero means
    both zero, and a robot is written when either differs from what was written last."""
    n = v.shape[0]
    to_unpark, to_park, write = (np.empty(n, dtype=np.int64), np.empty(n, dtype=np.int64),
                                 np.empty(n, dtype=np.int64))
    u = p = k = 0
    for i in range(n):
        zero = v[i, 0] == 0 and v[i, 1] == 0 and w[i] == 0
        if zero and zero_before[i] and not parked[i]:
            to_park[p], p = i, p + 1
            parked[i] = True
            written[i, 0], written[i, 1], written_spin[i] = 0.0, 0.0, 0.0
        elif not zero and parked[i]:
            to_unpark[u], u = i, u + 1
            parked[i] = False
        zero_before[i] = zero
        if v[i, 0] != written[i, 0] or v[i, 1] != written[i, 1] or w[i] != written_spin[i]:
            write[k], k = i, k + 1
            written[i, 0], written[i, 1], written_spin[i] = v[i, 0], v[i, 1], w[i]
    return to_unpark[:u], to_park[:p], write[:k]


@njit(cache=True)
def _plan(v, zero_before, parked, written):  # pragma: no cover - compiled
    """Parking.command's bookkeeping, in place: robots to unpark (a non-zero command while
    parked), to park (zero now and last tick), and whose control velocity to write (the
    command differs from the velocity written last; a parked robot's is zero)."""
    n = v.shape[0]
    to_unpark, to_park, write = (np.empty(n, dtype=np.int64), np.empty(n, dtype=np.int64),
                                 np.empty(n, dtype=np.int64))
    u = p = w = 0
    for i in range(n):
        zero = v[i, 0] == 0 and v[i, 1] == 0
        if zero and zero_before[i] and not parked[i]:
            to_park[p], p = i, p + 1
            parked[i] = True
            written[i, 0], written[i, 1] = 0.0, 0.0
        elif not zero and parked[i]:
            to_unpark[u], u = i, u + 1
            parked[i] = False
        zero_before[i] = zero
        if v[i, 0] != written[i, 0] or v[i, 1] != written[i, 1]:
            write[w], w = i, w + 1
            written[i, 0], written[i, 1] = v[i, 0], v[i, 1]
    return to_unpark[:u], to_park[:p], write[:w]
