"""The only module that owns the pymunk Space: robot bodies, walls, drive and contacts.

Units: lengths in the paper's units, time in ticks (one tick = one unit of pymunk time),
mass 1 per robot, velocities in units per tick.

Each robot is a dynamic body with a Circle shape, pulled toward its commanded velocity by a
force-limited PivotJoint (and a GearJoint against spinning, unless spin_traction is inf) to its
own kinematic control body: pymunk's tank-example pattern. Robots therefore push each other
for real and the contact solver keeps overlap tiny, while an unobstructed robot tracks its
command within a tick. Walls around the arena and obstacle outlines are static segments
(concave shapes work: pymunk.Poly would take the convex hull). Body reads go through
pymunk.batch.

With ``physics_sleep`` on (the default, see PhysicsConfig), parked robots (a zero command
for two ticks) sleep in pymunk: see swarmsim/physics/bodysleep.py. They are still pushed, and wake on contact. A sleeping
robot's contacts drop out of pymunk's arbiters; :meth:`Physics.contact_state` keeps its last
ones (they cannot change while it sleeps).
"""

from __future__ import annotations

import math
from dataclasses import dataclass, field
from typing import Literal

import numpy as np
import pymunk
import pymunk.batch as pb

from swarmsim import interrupts
from swarmsim.limits import (
    MAX_ITERATIONS,
    MAX_SUBSTEPS,
    at_most,
    check_fields,
    require_non_negative,
    require_positive,
)
from swarmsim.physics import chipmunkcalls, contactrows
from swarmsim.physics.bodysleep import BodyRows, IdTable, Parking
from swarmsim.physics.spacestate import SpaceState, read_space, write_space
from swarmsim.robots.drives import DRIVE_NAMES
from swarmsim.world.world import World

ROBOT_TYPE = 1
WALL_TYPE = 2
ROBOT_CATEGORY = 0b01
WALL_CATEGORY = 0b10
GHOST_GROUP = 1
WALL_THICKNESS = 0.5
IDLE_SPEED = 1e-9
"""Speed (units per tick) below which pymunk counts a body as resting, for sleeping. Bodies
held still by contacts keep velocities at rounding level; with pymunk's default (0 without
gravity: exactly still) a parked crowd that touches would never sleep."""


@dataclass(frozen=True)
class PhysicsConfig:
    """Physical parameters.

    Attributes:
        radius: robot body radius, units (0.4: robots d_safe = 1 apart do not touch).
        traction: largest force the drive can apply, mass*units/tick^2 (ground friction).
        spin_traction: largest torque against spinning; inf: robots never turn (an
            infinite moment and no gear joint, which saves ~40 % of pymunk's step at
            2,000-10,000 robots; results differ from the default's).
        friction: Coulomb friction between bodies.
        substeps: pymunk steps per tick (dt = 1 / substeps).
        iterations: contact solver iterations per step.
        collision_slop: overlap pymunk tolerates before pushing apart, units.
        mode: "rigid" (robots collide) or "ghost" (robots pass through each other; walls hold).
        physics_sleep: parked robots (a zero command this tick and the last) sleep in pymunk,
            out of its solver, until something pushes them or they are commanded again.
            Same physics, contacts solved in another order. False solves every body on every
            step (the code before; docs/reports/performance-log.md compares the two).
        physics_sleep_time: how long a parked robot must rest (zero velocity) before pymunk
            puts it to sleep, ticks (pymunk's sleep_time_threshold).
        drive: the robots' drive model (swarmsim/robots/drives.py, docs/drives.md):
            "holonomic" (moves in any direction at once; the default; it ignores every
            drive setting), "diff" (differential drive) or "kilobot".
        wheel_base: diff: distance between the two wheels, units.
        wheel_speed: diff: top speed of a wheel, units/tick. Above the controllers' cruising
            speed (v_max), as on real robots: a robot going straight at v_max turns with
            wheel speed to spare.
        wheel_accel: diff: largest rise of a wheel's speed in one tick, units/tick (a drop is
            immediate: a robot told to stop stops).
        reverse: diff: the robot may drive backward (a kilobot never does).
        axle_offset: diff, kilobot: the drive holds the body at a point this far behind its
            centre (the wheel axle, the rear legs), units; a push through the centre then
            turns the robot.
        yaw_traction: diff, kilobot: largest torque with which the drive turns the body or
            holds its turn rate, mass*units^2/tick^2 (replaces spin_traction).
        kilobot_speed: kilobot: forward speed of a wheel-commanding controller's robot
            (both motors on), units/tick.
        kilobot_turn: kilobot: turn-in-place rate, rad/tick.
        kilobot_align: kilobot: the robot goes forward once its wish lies within this angle
            of its heading, else turns in place, rad.
        kilobot_bias: kilobot: standard deviation of each robot's calibration factors
            (forward speed, turn rate), relative.
        kilobot_curve: kilobot: standard deviation of each robot's turn while going
            "straight", rad/tick.
        kilobot_stick: kilobot: probability that a moving robot sticks (does not move) for
            a tick.
        kilobot_slip: kilobot: standard deviation of the factor a moving robot's motion is
            scaled by in a tick it does not stick, relative.
    """

    radius: float = 0.4
    traction: float = 0.1
    spin_traction: float = 0.5
    friction: float = 0.3
    substeps: int = field(default=6, metadata=at_most(MAX_SUBSTEPS))
    iterations: int = field(default=5, metadata=at_most(MAX_ITERATIONS))
    collision_slop: float = 0.002
    mode: Literal["rigid", "ghost"] = "rigid"
    physics_sleep: bool = True
    physics_sleep_time: float = 1.0
    drive: Literal["holonomic", "diff", "kilobot"] = "holonomic"
    wheel_base: float = 0.6
    wheel_speed: float = 0.2
    wheel_accel: float = 0.05
    reverse: bool = True
    axle_offset: float = 0.2
    yaw_traction: float = 0.01
    kilobot_speed: float = 0.1
    kilobot_turn: float = 0.325
    kilobot_align: float = 0.35
    kilobot_bias: float = 0.1
    kilobot_curve: float = 0.01
    kilobot_stick: float = 0.1
    kilobot_slip: float = 0.3

    def __post_init__(self) -> None:
        require_positive(self, "radius", "traction", "spin_traction", "collision_slop",
                         "physics_sleep_time", "wheel_base", "wheel_speed", "wheel_accel",
                         "yaw_traction", "kilobot_speed", "kilobot_turn", "kilobot_align")
        require_non_negative(self, "axle_offset", "kilobot_bias", "kilobot_curve",
                             "kilobot_stick", "kilobot_slip")
        if self.friction < 0:
            raise ValueError(f"friction must be >= 0, got {self.friction!r}")
        if self.substeps < 1 or self.iterations < 1:
            raise ValueError("substeps and iterations must be >= 1")
        if self.mode not in ("rigid", "ghost"):
            raise ValueError(f"mode must be 'rigid' or 'ghost', got {self.mode!r}")
        self._check_drive()
        check_fields(self)

    def _check_drive(self) -> None:
        """The drive's settings: a known drive; one that turns the body needs a body that can
        turn; an axle inside the body; a probability for sticking."""
        if self.drive not in DRIVE_NAMES:
            raise ValueError(f"drive must be one of {', '.join(DRIVE_NAMES)}, got "
                             f"{self.drive!r}")
        if self.drive == "holonomic":
            return
        if not math.isfinite(self.spin_traction):
            raise ValueError(f"drive {self.drive!r} turns the robots, but spin_traction = inf "
                             "gives them an infinite moment (they could never turn): leave "
                             "spin_traction finite (it is not used with this drive)")
        if self.axle_offset >= self.radius:
            raise ValueError(f"axle_offset must be less than radius ({self.radius!r}), got "
                             f"{self.axle_offset!r}: the axle lies inside the body")
        if self.kilobot_stick >= 1:
            raise ValueError(f"kilobot_stick must be < 1 (a probability; 1 would never move), "
                             f"got {self.kilobot_stick!r}")


@dataclass
class ContactStats:
    """Collision accounting accumulated over a run (counts of contact begins).

    Attributes:
        robot_robot: robot-robot contacts begun (one per touching pair and contact).
        robot_wall: robot-wall (or obstacle) contacts begun.
        per_robot: (N,) robot-robot contacts each robot took part in.
        per_robot_wall: (N,) robot-wall contacts of each robot.
    """

    robot_robot: int = 0
    robot_wall: int = 0
    per_robot: np.ndarray = field(default_factory=lambda: np.zeros(0, dtype=np.int64))
    per_robot_wall: np.ndarray = field(default_factory=lambda: np.zeros(0, dtype=np.int64))


@dataclass(frozen=True)
class ContactState:
    """The contacts active at the end of a tick (read from pymunk's arbiters).

    Attributes:
        in_contact: (N,) bool, robots touching another robot or a wall.
        on_wall: (N,) bool, robots touching a wall or an obstacle (a subset of in_contact).
        max_overlap: deepest penetration of any contact, units (0 without contacts).
        overlap_sum: sum of the penetration depths of the robot-robot contacts, units.
        robot_pairs: number of robot-robot contacts (arbiters with a penetration).
        impulse: total contact impulse of the last substep, mass * units / tick.
        peak_impulse: largest impulse of a single contact in the last substep.
    """

    in_contact: np.ndarray
    on_wall: np.ndarray
    max_overlap: float = 0.0
    overlap_sum: float = 0.0
    robot_pairs: int = 0
    impulse: float = 0.0
    peak_impulse: float = 0.0


@dataclass(frozen=True)
class _Arbiters:
    """Contacts as rows: robots (M, 2) robot indices (-1: a wall), depth (M,) penetration,
    units (>= 0), impulse (M,) magnitude of the last substep's impulse."""

    robots: np.ndarray
    depth: np.ndarray
    impulse: np.ndarray

    @staticmethod
    def none() -> _Arbiters:
        return _Arbiters(np.zeros((0, 2), dtype=np.intp), np.zeros(0), np.zeros(0))


_ARBITER_FIELDS = (pb.ArbiterFields.BODY_A_ID | pb.ArbiterFields.BODY_B_ID
                   | pb.ArbiterFields.DISTANCE_1 | pb.ArbiterFields.TOTAL_IMPULSE)
_BODY_FIELDS = pb.BodyFields.POSITION | pb.BodyFields.VELOCITY
# pymunk.batch lays float fields out in flag order: angle, (vx, vy), spin
_MOTION_FIELDS = pb.BodyFields.ANGLE | pb.BodyFields.VELOCITY | pb.BodyFields.ANGULAR_VELOCITY
_COMMAND_FIELDS = pb.BodyFields.VELOCITY | pb.BodyFields.ANGULAR_VELOCITY


def wall_segments(world: World) -> tuple[tuple[tuple[float, float], tuple[float, float]], ...]:
    """The static wall segments of ``world`` (end points a, b, units): the arena's border,
    then each obstacle's outline, ring by ring."""
    xmin, ymin, xmax, ymax = world.arena
    corners = [(xmin, ymin), (xmax, ymin), (xmax, ymax), (xmin, ymax)]
    rings = [corners] + [list(ob.exterior.coords)[:-1] for ob in world.obstacles]
    return tuple((a, b) for ring in rings for a, b in zip(ring, ring[1:] + ring[:1],
                                                          strict=True))


class Physics:
    """A pymunk Space with N disc robots; read states and write commands in batches."""

    def __init__(self, world: World, positions: np.ndarray, config: PhysicsConfig | None = None,
                 angles: np.ndarray | None = None):
        """``angles`` (N,): the bodies' start angles, rad (None: 0, as a holonomic run's)."""
        self.config = config or PhysicsConfig()
        self.n = len(positions)
        self._walls = wall_segments(world)
        self.contacts = ContactStats(per_robot=np.zeros(self.n, dtype=np.int64),
                                     per_robot_wall=np.zeros(self.n, dtype=np.int64))
        self._sleep = self.config.physics_sleep
        self._build_space(np.asarray(positions, dtype=float), angles)
        self._index_rows()
        self._steps = 0  # physics ticks so far
        self._contacts_at = -1  # the tick self._contacts describes
        self._contacts = _Arbiters.none()
        if self._sleep:
            self._seat_parking()

    def _build_space(self, positions: np.ndarray, angles: np.ndarray | None = None) -> None:
        """A new Space with the walls and the robots at ``positions`` (N, 2) turned to
        ``angles`` (N,) rad (None: 0), each at rest, its control body on its drive point, the
        contact counters installed: the Space every run starts with, and every restore starts
        from before it takes the saved state."""
        space = pymunk.Space()
        space.gravity = (0.0, 0.0)
        space.iterations = self.config.iterations
        space.collision_slop = self.config.collision_slop
        self.space = space
        self._robots: list[pymunk.Body] = []
        self._controls: list[pymunk.Body] = []
        self._add_walls()
        self._add_robots(positions, angles)
        self._install_contact_counters()
        self._buf = pb.Buffer()
        if self._sleep:
            space.sleep_time_threshold = self.config.physics_sleep_time
            space.idle_speed_threshold = IDLE_SPEED

    @property
    def _steered(self) -> bool:
        """Does a drive steer the bodies (command_motion), holding each at its axle?"""
        return self.config.drive != "holonomic"

    def _seat_parking(self) -> None:
        """The handles that sleeping needs, on the Space's bodies (none parked)."""
        self._rows = BodyRows([b.id for b in self._robots], [b.id for b in self._controls])
        self._parking = Parking(self._robots, self._controls)
        self._rows_at = -1  # the tick self._rows describes
        self._calls = chipmunkcalls.body_calls()  # None: read through pymunk.batch
        self._robot_at = chipmunkcalls.addresses(self._robots)
        if self._steered:
            self._parking.prepare_spin()

    _REBUILT = ("space", "_robots", "_controls", "_buf", "_calls", "_robot_at", "_rows",
                "_parking", "_rows_at", "robot_rows", "control_rows", "n_rows",
                "_robot_of_body", "_robot_ids", "_cmd", "_motion_rows", "_motion_rows_at")
    """Attributes a pickle leaves out: the Space (kept as a :class:`SpaceState`), its bodies,
    and what holds cffi buffers, raw Chipmunk addresses or pymunk body ids; all made again
    on loading."""

    def __getstate__(self) -> dict:
        """The state a pickle (a checkpoint: swarmsim/engine/checkpoint.py) keeps: the run's
        bookkeeping, what varies in the Space (swarmsim/physics/spacestate.py: the bodies'
        motion, the cached contacts), which robots are parked, and which robots pymunk has
        asleep. The rest of the Space is made again from the configuration on loading."""
        state = {k: v for k, v in self.__dict__.items() if k not in self._REBUILT}
        state["_space_state"] = read_space(self.space, self._robots + self._controls)
        if self._sleep:
            state["_parking_arrays"] = self._parking.bookkeeping
            state["_asleep_at_save"] = self.bodies_asleep()
            if self._steered:
                state["_spin_written"] = self._parking.written_spin
        return state

    def __setstate__(self, state: dict) -> None:
        """Make the Space again as the constructor does (same bodies, shapes, joints and
        handlers, added in the same order), give its bodies and cached contacts their saved
        state, park the parked robots (robot order), then put back to sleep, one by one in
        robot order (``Body.sleep``: each its own sleeping group, idle time zero), the robots
        that were asleep. Every load of the same bytes does exactly this, so every load steps
        alike (not exactly like the Space that was saved: see checkpoint.py)."""
        space_state: SpaceState = state.pop("_space_state")
        parking_arrays = state.pop("_parking_arrays", None)
        asleep = state.pop("_asleep_at_save", None)
        spin_written = state.pop("_spin_written", None)
        self.__dict__.update(state)
        self._build_space(space_state.bodies[:self.n, 0:2])
        write_space(self.space, self._robots + self._controls, space_state)
        if self._sleep:
            self._seat_parking()
            self._parking.take_bookkeeping(parking_arrays)
            if spin_written is not None:
                self._parking.written_spin[:] = spin_written
        self._index_rows()
        if self._sleep:
            for i in np.flatnonzero(asleep).tolist():
                self._robots[i].sleep()

    def _add_walls(self) -> None:
        static = self.space.static_body
        wall_filter = pymunk.ShapeFilter(categories=WALL_CATEGORY)
        for a, b in self._walls:
            seg = pymunk.Segment(static, a, b, WALL_THICKNESS / 2)
            seg.friction = self.config.friction
            seg.collision_type = WALL_TYPE
            seg.filter = wall_filter
            self.space.add(seg)

    def _add_robots(self, positions: np.ndarray, angles: np.ndarray | None = None) -> None:
        """Each robot: a body (a disc), its control body, and the drive's two joints. The
        pivot matches the velocity of the body's drive point (its centre; with a steering
        drive its axle, ``axle_offset`` behind the centre) to the control body's; the gear
        matches spins (the body's to the control body's: 0 unless a drive steers)."""
        cfg = self.config
        spins = math.isfinite(cfg.spin_traction)
        moment = pymunk.moment_for_circle(1.0, 0, cfg.radius) if spins else math.inf
        group = GHOST_GROUP if cfg.mode == "ghost" else 0
        robot_filter = pymunk.ShapeFilter(group=group, categories=ROBOT_CATEGORY)
        axle = (-cfg.axle_offset, 0.0) if self._steered else (0, 0)
        grip = cfg.yaw_traction if self._steered else cfg.spin_traction
        for k, (x, y) in enumerate(positions):
            body = pymunk.Body(1.0, moment)
            body.position = (float(x), float(y))
            if angles is not None:
                body.angle = float(angles[k])
            shape = pymunk.Circle(body, cfg.radius)
            shape.friction = cfg.friction
            shape.collision_type = ROBOT_TYPE
            shape.filter = robot_filter
            ctrl = pymunk.Body(body_type=pymunk.Body.KINEMATIC)
            ctrl.position = body.local_to_world(axle) if self._steered else body.position
            pivot = pymunk.PivotJoint(ctrl, body, (0, 0), axle)
            pivot.max_bias = 0
            pivot.max_force = cfg.traction
            parts: list = [body, shape, ctrl, pivot]
            if spins:
                gear = pymunk.GearJoint(ctrl, body, 0.0, 1.0)
                gear.max_bias = 0
                gear.max_force = grip
                parts.append(gear)
            self.space.add(*parts)
            self._robots.append(body)
            self._controls.append(ctrl)

    def _install_contact_counters(self) -> None:
        stats = self.contacts

        def robot_robot(arbiter: pymunk.Arbiter, space: pymunk.Space, data: dict) -> None:
            stats.robot_robot += 1
            a, b = arbiter.bodies
            lookup = self._robot_of_body
            stats.per_robot[lookup[a.id]] += 1
            stats.per_robot[lookup[b.id]] += 1

        def robot_wall(arbiter: pymunk.Arbiter, space: pymunk.Space, data: dict) -> None:
            stats.robot_wall += 1
            for body in arbiter.bodies:
                i = self._robot_of_body.get(body.id)
                if i is not None:
                    stats.per_robot_wall[i] += 1

        self.space.on_collision(ROBOT_TYPE, ROBOT_TYPE, begin=robot_robot)
        self.space.on_collision(ROBOT_TYPE, WALL_TYPE, begin=robot_wall)

    def _index_rows(self) -> None:
        """Map pymunk.batch rows to robots (rows follow the space's internal body order)."""
        buf = pb.Buffer()
        pb.get_space_bodies(self.space, pb.BodyFields.BODY_ID, buf)
        ids = np.frombuffer(buf.int_buf(), dtype=np.uintp)
        row_of = {int(body_id): row for row, body_id in enumerate(ids)}
        self.n_rows = len(ids)
        self.robot_rows = np.array([row_of[b.id] for b in self._robots], dtype=np.intp)
        self.control_rows = np.array([row_of[b.id] for b in self._controls], dtype=np.intp)
        self._robot_of_body = {b.id: i for i, b in enumerate(self._robots)}
        self._robot_ids = IdTable([b.id for b in self._robots], range(self.n))
        self._cmd = np.zeros((self.n_rows, 2))

    def read(self) -> tuple[np.ndarray, np.ndarray]:
        """Positions and velocities of all robots, (N, 2) each, as fresh arrays."""
        if self._sleep:
            return self._read_by_id()
        self._buf.clear()
        pb.get_space_bodies(self.space, _BODY_FIELDS, self._buf)
        rows = np.frombuffer(self._buf.float_buf(), dtype=np.float64).reshape(-1, 4)
        if rows.shape[0] != self.n_rows:
            raise RuntimeError("pymunk body rows changed; bodies must not be added or removed")
        robots = np.take(rows, self.robot_rows, axis=0)  # ~10x faster than rows[robot_rows]
        self._velocity_rows = rows[:, 2:4].copy()
        return robots[:, 0:2].copy(), robots[:, 2:4].copy()

    def _read_by_id(self) -> tuple[np.ndarray, np.ndarray]:
        """read() with sleepers: each robot's body asked directly (compiled, see
        swarmsim/physics/chipmunkcalls.py), or pymunk.batch's rows matched to robots by body id."""
        calls = self._calls
        if calls is not None:
            positions, velocities = np.empty((self.n, 2)), np.empty((self.n, 2))
            chipmunkcalls.read_vects(calls.get_position, self._robot_at, positions)
            chipmunkcalls.read_vects(calls.get_velocity, self._robot_at, velocities)
            return positions, velocities
        buf = self._buf
        buf.clear()
        pb.get_space_bodies(self.space, pb.BodyFields.BODY_ID | pb.BodyFields.POSITION
                            | pb.BodyFields.VELOCITY, buf)
        rows = np.frombuffer(buf.float_buf(), dtype=np.float64).reshape(-1, 4)
        if rows.shape[0] != self.n_rows:
            raise RuntimeError("pymunk body rows changed; bodies must not be added or removed")
        self._rows.update(np.frombuffer(buf.int_buf(), dtype=np.uintp))
        self._rows_at = self._steps
        robots = np.take(rows, self._rows.robot_rows, axis=0)
        return robots[:, 0:2].copy(), robots[:, 2:4].copy()

    @property
    def parked(self) -> np.ndarray:
        """(N,) bool: robots whose control body is parked (STATIC), so pymunk may sleep them."""
        if not self._sleep:
            return np.zeros(self.n, dtype=bool)
        return self._parking.parked.copy()

    def bodies_asleep(self) -> np.ndarray:
        """(N,) bool: robots whose bodies pymunk has put to sleep (out of its solver)."""
        if not self._sleep:
            return np.zeros(self.n, dtype=bool)
        if self._calls is not None:
            asleep = np.empty(self.n, dtype=bool)
            chipmunkcalls.read_flags(self._calls.is_sleeping, self._robot_at, asleep)
            return asleep
        if self._rows_at != self._steps:
            buf = pb.Buffer()
            pb.get_space_bodies(self.space, pb.BodyFields.BODY_ID, buf)
            self._rows.update(np.frombuffer(buf.int_buf(), dtype=np.uintp))
            self._rows_at = self._steps
        return self._rows.asleep(self._parking.parked)

    def command(self, velocities: np.ndarray) -> None:
        """Set every robot's commanded velocity (N, 2), units per tick. Call after read().

        With physics_sleep, a zero command for this tick and the last parks the robot (see
        swarmsim/physics/bodysleep.py); a non-zero one unparks it.
        """
        if self._sleep:
            self._parking.command(velocities)
            self._rows_at = -1  # parking and waking reorder the rows
            return
        cmd = self._cmd
        cmd[:] = self._velocity_rows  # leave every other body's velocity as it is
        # cmd[control_rows] = velocities, with each (vx, vy) row as one complex: ~6x faster
        pairs = np.ascontiguousarray(velocities, dtype=np.float64).view(np.complex128)
        cmd.view(np.complex128)[self.control_rows, 0] = pairs[:, 0]
        buf = pb.Buffer()
        buf.set_float_buf(cmd.ravel())
        pb.set_space_bodies(self.space, pb.BodyFields.VELOCITY, buf)

    def headings(self) -> np.ndarray:
        """(N,) the robots' body angles, rad (not wrapped: a body that turned twice round
        reads 4 pi more), as a fresh array. Call after read(), before command_motion()."""
        buf = self._buf
        buf.clear()
        if self._sleep:  # rows move: matched to robots by body id
            pb.get_space_bodies(self.space, pb.BodyFields.BODY_ID | pb.BodyFields.ANGLE, buf)
            angles = np.frombuffer(buf.float_buf(), dtype=np.float64)
            robot = self._robot_ids.lookup(np.frombuffer(buf.int_buf(), dtype=np.uintp))
            found = robot >= 0
            headings = np.empty(self.n)
            headings[robot[found]] = angles[found]
            return headings
        pb.get_space_bodies(self.space, _MOTION_FIELDS, buf)
        rows = np.frombuffer(buf.float_buf(), dtype=np.float64).reshape(-1, 4)
        self._motion_rows = rows[:, 1:4].copy()  # every body's (vx, vy, spin), for the write
        self._motion_rows_at = self._steps
        return np.take(rows[:, 0], self.robot_rows)

    def command_motion(self, lin: np.ndarray, spin: np.ndarray) -> None:
        """Set every robot's drive motion (a steering drive's: swarmsim/robots/drives.py): the
        velocity of its drive point ``lin`` (N, 2), units/tick, and its spin ``spin`` (N,),
        rad/tick. Call after headings(). With physics_sleep, a robot given zero motion this
        tick and the last is parked, as :meth:`command` parks one."""
        if self._sleep:
            self._parking.command_spin(lin, spin)
            self._rows_at = -1
            return
        if getattr(self, "_motion_rows_at", -1) != self._steps:
            self.headings()
        cmd = self._motion_rows  # every other body's velocity and spin stay as they are
        cmd[self.control_rows, 0:2] = lin
        cmd[self.control_rows, 2] = spin
        buf = pb.Buffer()
        buf.set_float_buf(cmd.ravel())
        pb.set_space_bodies(self.space, _COMMAND_FIELDS, buf)
        self._motion_rows_at = -1

    def step(self) -> None:
        """Advance one tick. An interrupt during pymunk's step is raised by the caller's
        next ``interrupts.raise_pending()`` (see swarmsim.interrupts)."""
        if self._sleep and self._contacts_at != self._steps:
            self._arbiters()  # sleepers keep the contacts they have now
        dt = 1.0 / self.config.substeps
        with interrupts.shield:  # pymunk's callbacks would swallow a KeyboardInterrupt
            for _ in range(self.config.substeps):
                self.space.step(dt)
        self._steps += 1

    def contact_state(self) -> ContactState:
        """The contacts active now: who touches, overlap and impulse (see ContactState).

        Overlap is the penetration depth reported by the active contact arbiters. A robot
        asleep in pymunk keeps the contacts it had when it fell asleep.
        """
        c = self._arbiters()
        if len(c.robots) == 0:
            return ContactState(np.zeros(self.n, dtype=bool), np.zeros(self.n, dtype=bool))
        in_contact, on_wall, pair, deepest = contactrows.tally(c.robots, c.depth, self.n)
        return ContactState(in_contact, on_wall, deepest, float(c.depth[pair].sum()),
                            int(np.count_nonzero(pair)), float(c.impulse.sum()),
                            float(c.impulse.max()))

    def _arbiters(self) -> _Arbiters:
        """This tick's contacts: pymunk's arbiters, plus the last ones of sleeping robots."""
        if self._contacts_at == self._steps:
            return self._contacts
        live = self._read_arbiters()
        if self._sleep and np.count_nonzero(self._parking.parked):
            asleep = self.bodies_asleep()
            # sleepers' live arbiters are stale: they keep their last ones
            if np.count_nonzero(asleep):
                before = self._contacts
                live = _Arbiters(*contactrows.carry_over(
                    live.robots, live.depth, live.impulse, before.robots, before.depth,
                    before.impulse, asleep))
        self._contacts, self._contacts_at = live, self._steps
        return live

    def _read_arbiters(self) -> _Arbiters:
        buf = self._buf  # the rows below are copies: the buffer may be reused
        buf.clear()
        pb.get_space_arbiters(self.space, _ARBITER_FIELDS, buf)
        ids = np.frombuffer(buf.int_buf(), dtype=np.uint64)
        if len(ids) == 0:
            return _Arbiters.none()
        # pymunk.batch lays float fields out in flag order: TOTAL_IMPULSE (x, y), DISTANCE_1
        floats = np.frombuffer(buf.float_buf(), dtype=np.float64)
        return _Arbiters(*contactrows.from_batch(ids, floats, *self._robot_ids.arrays))

    def neighbours_by_query(self, i: int, radius: float) -> np.ndarray:
        """Reference sensing backend: robots whose centres lie within ``radius`` of robot i.

        Uses a pymunk point query with a robots-only filter (slow: one query per robot; kept
        to check the k-d tree backend). point_query measures to the shape surface, so the
        centre radius is ``radius - body radius``. Sorted by index.
        """
        body = self._robots[i]
        infos = self.space.point_query(body.position, radius - self.config.radius,
                                       pymunk.ShapeFilter(mask=ROBOT_CATEGORY))
        lookup = self._robot_of_body
        found = [lookup[info.shape.body.id] for info in infos if info.shape.body is not body]
        return np.array(sorted(found), dtype=np.intp)
