"""A swarm's pymunk Space as a few arrays: what a checkpoint keeps of the physics.

Everything in the Space that a run does not change (its parameters, the walls, each robot's
shape, filter, collision type, drive joints and their limits, the contact handlers) is made
again from the run's configuration, as :class:`swarmsim.physics.physics.Physics` builds it.
What a run changes is read here into arrays (:class:`SpaceState`) and written back into the
Space made again:

- every robot body and control body: position, angle, velocity, angular velocity, force,
  torque (units, radians, per tick of pymunk time);
- the Space's cached contacts (Chipmunk's arbiters, with their contact points and accumulated
  impulses: the contact solver's warm start), its time stamp and last time step.

The same as pymunk's own pickle of a Space carries (and leaves out): which bodies sleep,
their rest time, the joints' accumulated impulses and the spatial index's structure are not
kept (swarmsim/engine/checkpoint.py: saving is an event in the run).
"""

from __future__ import annotations

from collections.abc import Sequence
from dataclasses import dataclass

import numpy as np
import pymunk
import pymunk.batch as pb
from pymunk._chipmunk_cffi import ffi, lib

BODY_FIELDS = (pb.BodyFields.POSITION | pb.BodyFields.ANGLE | pb.BodyFields.VELOCITY
               | pb.BodyFields.ANGULAR_VELOCITY | pb.BodyFields.FORCE | pb.BodyFields.TORQUE)
"""The body fields kept; pymunk.batch lays them out in this (flag) order, 9 floats a body:
x, y, angle, vx, vy, angular velocity, fx, fy, torque."""
BODY_COLUMNS = 9
"""Floats per body in a :class:`SpaceState` row (see :data:`BODY_FIELDS`)."""

_CONTACT_FIELDS = ("nMass", "tMass", "bounce", "jnAcc", "jtAcc", "jBias", "bias")


@dataclass(frozen=True)
class SpaceState:
    """What a run changes in a swarm's Space (see the module's docstring).

    Attributes:
        bodies: (B, 9) float64, one row per body given to :func:`read_space` (in its order),
            the fields of :data:`BODY_FIELDS`.
        arbiters: Chipmunk's cached arbiters, ordered by their shapes (the cache's own order
            follows memory addresses, which differ from process to process; the order they
            are added back in is the order the solver first meets them), each a tuple: the
            indices of its two shapes in ``space.shapes``, then its restitution, friction,
            surface velocity (x, y), normal (x, y), swapped, stamp, state, and its contacts
            (each r1 x, y, r2 x, y, then :data:`_CONTACT_FIELDS`, then its hash).
        stamp: the Space's time stamp (steps taken; arbiters' stamps count in it).
        time_step: the Space's last time step, units of pymunk time.
    """

    bodies: np.ndarray
    arbiters: tuple
    stamp: int
    time_step: float


def _address(cdata: ffi.CData) -> int:
    return int(ffi.cast("uintptr_t", cdata))


def _body_rows(space: pymunk.Space, buf: pb.Buffer) -> tuple[dict[int, int], np.ndarray]:
    """Every body of ``space`` read by pymunk.batch into ``buf``: body id -> row, and the
    rows' (R, 9) floats (a view of ``buf``)."""
    pb.get_space_bodies(space, BODY_FIELDS | pb.BodyFields.BODY_ID, buf)
    ids = np.frombuffer(buf.int_buf(), dtype=np.uintp).tolist()
    rows = np.frombuffer(buf.float_buf(), dtype=np.float64).reshape(-1, BODY_COLUMNS)
    return {body_id: row for row, body_id in enumerate(ids)}, rows


def read_space(space: pymunk.Space, bodies: Sequence[pymunk.Body]) -> SpaceState:
    """The state of ``bodies`` (all in ``space``) and of ``space``'s cached contacts."""
    row_of, rows = _body_rows(space, pb.Buffer())
    order = np.array([row_of[b.id] for b in bodies], dtype=np.intp)
    return SpaceState(bodies=rows[order].copy(), arbiters=_read_arbiters(space),
                      stamp=int(lib.cpSpaceGetTimestamp(space._space)),
                      time_step=float(lib.cpSpaceGetCurrentTimeStep(space._space)))


def write_space(space: pymunk.Space, bodies: Sequence[pymunk.Body], state: SpaceState) -> None:
    """Give ``bodies`` (in ``space``, none asleep, as many as ``state`` has rows, in its
    order) their saved state, then give ``space`` its saved cached contacts and time stamp.
    Call before anything steps the space or puts a body to sleep."""
    buf = pb.Buffer()
    row_of, rows = _body_rows(space, buf)
    values = rows.copy()  # the other bodies (the static body) keep theirs
    values[[row_of[b.id] for b in bodies]] = state.bodies
    out = pb.Buffer()
    out.set_float_buf(values.ravel())
    pb.set_space_bodies(space, BODY_FIELDS, out)
    _add_arbiters(space, state.arbiters)
    lib.cpSpaceSetTimestamp(space._space, state.stamp)
    lib.cpSpaceSetCurrentTimeStep(space._space, state.time_step)


def _cached_arbiters(space: pymunk.Space) -> list[ffi.CData]:
    found: list[ffi.CData] = []
    lib.cpSpaceEachCachedArbiter(space._space, lib.ext_cpArbiterIteratorFunc,
                                 ffi.new_handle(found))
    return found


def _read_arbiters(space: pymunk.Space) -> tuple:
    shape_index = {_address(s._shape): i for i, s in enumerate(space.shapes)}
    arbiters = []
    for arb in _cached_arbiters(space):
        contacts = tuple(
            (c.r1.x, c.r1.y, c.r2.x, c.r2.y, *(getattr(c, f) for f in _CONTACT_FIELDS), c.hash)
            for c in (arb.contacts[k] for k in range(arb.count)))
        arbiters.append((shape_index[_address(arb.a)], shape_index[_address(arb.b)], arb.e,
                         arb.u, arb.surface_vr.x, arb.surface_vr.y, arb.n.x, arb.n.y,
                         arb.swapped, arb.stamp, arb.state, contacts))
    return tuple(sorted(arbiters, key=lambda arbiter: arbiter[:2]))


def _add_arbiters(space: pymunk.Space, arbiters: tuple) -> None:
    """Chipmunk arbiters made from :attr:`SpaceState.arbiters`, added to ``space``'s cache
    in their order, as pymunk's own unpickling of a Space adds them."""
    shapes = list(space.shapes)
    for a, b, e, u, svx, svy, nx, ny, swapped, stamp, state, contacts in arbiters:
        arb = lib.cpArbiterNew(shapes[a]._shape, shapes[b]._shape)  # sets the bodies too
        arb.e, arb.u = e, u
        arb.surface_vr.x, arb.surface_vr.y = svx, svy
        arb.count = len(contacts)
        arb.contacts = lib.cpContactArrAlloc(len(contacts))
        for k, (r1x, r1y, r2x, r2y, *values, point_hash) in enumerate(contacts):
            c = arb.contacts[k]
            c.r1.x, c.r1.y, c.r2.x, c.r2.y = r1x, r1y, r2x, r2y
            for name, value in zip(_CONTACT_FIELDS, values, strict=True):
                setattr(c, name, value)
            c.hash = point_hash
        arb.n.x, arb.n.y = nx, ny
        arb.swapped, arb.stamp, arb.state = swapped, stamp, state
        lib.cpSpaceAddCachedArbiter(space._space, arb)
