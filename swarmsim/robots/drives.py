"""Drive models: what a robot's wheels (or vibration motors) make of the motion it asks for.

Controllers wish a velocity (units/tick, world frame); the run's drive (``PhysicsConfig.drive``)
decides what the robot can do with it this tick and hands the physics a body motion: the
velocity of the robot's drive point (its wheel axle, ``axle_offset`` behind its centre) and a
spin (rad/tick). The drive works on numbers only; swarmsim/physics/physics.py turns the motion
into force-limited joints on the pymunk body, so contacts stay real.

* ``holonomic`` (the default): today's disc that moves in any direction at once. Its runs never
  call a drive: the engine keeps the code path it always had (same results to the bit).
* ``diff``: differential drive (two wheels ``wheel_base`` apart, each at most ``wheel_speed``
  units/tick, rising by at most ``wheel_accel`` units/tick a tick; braking is immediate). A
  wished velocity is steered with a unicycle law (:func:`diff_motion`): turn toward the wish
  at ``TURN_GAIN`` x the heading error (at most ``2 wheel_speed / wheel_base`` rad/tick) and
  drive along the heading at the wish's speed x cos(error), so a robot commanded sideways
  first turns, then moves. With ``reverse`` it drives backward to a wish behind it.
* ``kilobot``: three motions, like the Kilobot's two vibration motors: forward, turn left,
  turn right in place (:func:`kilobot_motion`). Each robot has its own calibration, drawn from
  the seed: forward and turn factors and a drift that makes its "straight" line arc; each tick
  a moving robot may stick (no motion) or slip (motion scaled at random).

A controller may command wheels instead of a velocity (``COMMANDS = "wheels"``): (left, right)
speeds, units/tick; a diff robot takes them as they are (within its limits), a kilobot reads
them as motors on or off.

Random streams (:data:`DRIVE_STREAMS`), each ``SeedSequence(seed, spawn_key=(key,))``, apart
from every other stream of a run (a run's own spawn children and the imperfections' keys), so
drawing them changes no other draw. ``drive_setup``: N start headings uniform in [-pi, pi),
once, at setup; ``drive_calibration`` (kilobot): an (N, 3) block of normals, once, at setup,
row by row, so robot i's calibration depends on the seed and i alone; ``drive``: the kilobot's
stick-slip, each tick. Holonomic draws nothing.
"""

from __future__ import annotations

import math
from typing import Protocol

import numpy as np
from numba import njit

from swarmsim.kernels.warmup import kernel_warm_up

DRIVE_NAMES = ("holonomic", "diff", "kilobot")
"""The drives a run may name (``drive=NAME``)."""

DRIVE_STREAMS = {"drive_setup": 0xD21E, "drive": 0xD21F, "drive_calibration": 0xD220}
"""Spawn keys of the drives' random streams (see the module docstring)."""

TURN_GAIN = 0.5
"""The diff drive's steering gain: commanded turn rate per radian of heading error, 1/tick.
Gain 1 overshoots (the weak yaw grip spins the body up over ~3 ticks); 0.5 settles."""

MIN_FACTOR = 0.2
"""A kilobot's calibration factors (forward, turn) are never below this."""


class DriveSettings(Protocol):
    """The settings a drive reads (swarmsim.physics.physics.PhysicsConfig has them all; see its
    docstring for each one's meaning and units)."""

    drive: str
    wheel_base: float
    wheel_speed: float
    wheel_accel: float
    reverse: bool
    kilobot_speed: float
    kilobot_turn: float
    kilobot_align: float
    kilobot_bias: float
    kilobot_curve: float
    kilobot_stick: float
    kilobot_slip: float


def drive_rng(seed: int, stream: str) -> np.random.Generator:
    """The Generator of drive stream ``stream`` (a key of :data:`DRIVE_STREAMS`) of run ``seed``."""
    return np.random.default_rng(np.random.SeedSequence(seed,
                                                        spawn_key=(DRIVE_STREAMS[stream],)))


def draw_start_headings(seed: int, n: int) -> np.ndarray:
    """The n robots' headings at the start of run ``seed`` (every steering drive's): uniform
    in [-pi, pi), radians, from the ``drive_setup`` stream."""
    return drive_rng(seed, "drive_setup").uniform(-math.pi, math.pi, n)


class Drive(Protocol):
    """A run's drive model: the engine asks it, each tick, what motion the robots' wishes give.

    Attributes:
        has_heading: False only for :class:`Holonomic` (robots have no heading that matters).
        reverse: can the robots drive backward without turning round?
    """

    has_heading: bool
    reverse: bool

    def start_headings(self) -> np.ndarray | None:
        """(N,) the robots' body angles at the start, rad (None: the bodies' default, 0)."""

    def turn_rates(self) -> np.ndarray:
        """(N,) how fast each robot turns in place at most, rad/tick (inf: holonomic)."""

    def motion(self, wish: np.ndarray | None, wheels: np.ndarray | None, heading: np.ndarray,
               active: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
        """This tick's body motion from either the wished velocities ``wish`` (N, 2),
        units/tick, or the wheel speeds ``wheels`` (N, 2) (left, right), units/tick, given the
        body angles ``heading`` (N,), rad; robots not ``active`` (N,) bool stand still.
        Returns (lin (N, 2): the drive point's velocity, units/tick; spin (N,), rad/tick)."""


class Holonomic:
    """Today's drive: any direction at once. The engine never calls :meth:`motion`."""

    has_heading = False
    reverse = True

    def __init__(self, n: int):
        self.n = n

    def start_headings(self) -> None:
        return None

    def turn_rates(self) -> np.ndarray:
        return np.full(self.n, math.inf)

    def motion(self, wish: np.ndarray | None, wheels: np.ndarray | None, heading: np.ndarray,
               active: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
        raise RuntimeError("a holonomic robot has no drive motion: the engine commands it "
                           "directly")


class DiffDrive:
    """Differential drive (see the module docstring). Keeps each robot's wheel speeds of the
    last tick (``wheels``, (N, 2) left/right, units/tick) for the acceleration limit.

    Args:
        config: the run's PhysicsConfig (wheel_base, wheel_speed, wheel_accel, reverse).
        seed: the run's seed (start headings).
        n: number of robots.
    """

    has_heading = True

    def __init__(self, config: DriveSettings, seed: int, n: int):
        self.n = n
        self.wheel_base = float(config.wheel_base)
        self.wheel_speed = float(config.wheel_speed)
        self.wheel_accel = float(config.wheel_accel)
        self.reverse = bool(config.reverse)
        self._headings = draw_start_headings(seed, n)
        self.wheels = np.zeros((n, 2))

    def start_headings(self) -> np.ndarray:
        return self._headings.copy()

    def turn_rates(self) -> np.ndarray:
        return np.full(self.n, 2 * self.wheel_speed / self.wheel_base)

    def motion(self, wish: np.ndarray | None, wheels: np.ndarray | None, heading: np.ndarray,
               active: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
        lin, spin = np.empty((self.n, 2)), np.empty(self.n)
        use_wheels = wheels is not None
        given = np.ascontiguousarray(wheels if use_wheels else wish, dtype=np.float64)
        diff_motion(given, use_wheels, np.ascontiguousarray(heading, dtype=np.float64),
                    np.ascontiguousarray(active, dtype=np.bool_), self.wheels, self.wheel_base,
                    self.wheel_speed, self.wheel_accel, self.reverse, TURN_GAIN, lin, spin)
        return lin, spin


@njit(cache=True)
def _wrap(angle):  # pragma: no cover - compiled
    """``angle`` wrapped to [-pi, pi), rad."""
    return (angle + math.pi) % (2 * math.pi) - math.pi


@njit(cache=True)
def _limit_rise(speed, last, accel):  # pragma: no cover - compiled
    """``speed`` with its magnitude at most ``|last| + accel`` (a drop is not limited)."""
    most = abs(last) + accel
    if abs(speed) > most:
        return math.copysign(most, speed)
    return speed


@njit(cache=True)
def diff_motion(given, use_wheels, heading, active, last, base, top, accel, reverse, gain,
                lin, spin):  # pragma: no cover - compiled
    """DiffDrive.motion's law, in place: ``lin`` (N, 2) and ``spin`` (N,) from ``given``
    (N, 2): wished velocities, or wheel speeds (left, right) when ``use_wheels``; ``last``
    (N, 2) the wheel speeds of last tick, updated. Units/tick and rad/tick.

    A wish w: heading error e = wrap(angle(w) - heading) (with ``reverse`` and |e| > pi/2 the
    robot drives backward: e -= pi sign(e)); turn rate = clip(gain e, +-2 top / base); speed =
    |w| max(0, cos e), cut first so the turn fits the wheels (turning has priority). Wheels:
    both scaled down together if one exceeds ``top``; each may rise by at most ``accel`` a
    tick (a drop is immediate). The body moves at the wheels' mean along its heading and
    turns at (right - left) / base."""
    half = 0.5 * base
    most_turn = top / half
    for i in range(heading.shape[0]):
        if not active[i]:
            last[i, 0] = last[i, 1] = 0.0
            lin[i, 0] = lin[i, 1] = spin[i] = 0.0
            continue
        if use_wheels:
            left, right = given[i, 0], given[i, 1]
        else:
            wx, wy = given[i, 0], given[i, 1]
            speed = math.sqrt(wx * wx + wy * wy)
            left = right = 0.0
            if speed > 0:
                err = _wrap(math.atan2(wy, wx) - heading[i])
                sign = 1.0
                if reverse and abs(err) > 0.5 * math.pi:
                    err -= math.copysign(math.pi, err)
                    sign = -1.0
                turn = min(max(gain * err, -most_turn), most_turn)
                ahead = speed * max(0.0, math.cos(err))
                ahead = min(ahead, max(0.0, top - abs(turn) * half))
                left = sign * ahead - turn * half
                right = sign * ahead + turn * half
        biggest = max(abs(left), abs(right))
        if biggest > top:
            left, right = left * top / biggest, right * top / biggest
        left = _limit_rise(left, last[i, 0], accel)
        right = _limit_rise(right, last[i, 1], accel)
        last[i, 0], last[i, 1] = left, right
        ahead = 0.5 * (left + right)
        lin[i, 0] = ahead * math.cos(heading[i])
        lin[i, 1] = ahead * math.sin(heading[i])
        spin[i] = (right - left) / base


class KilobotDrive:
    """Kilobot-like drive (see the module docstring). Each robot's calibration is drawn once
    from the seed (``drive_calibration`` stream): ``fwd_factor``,
    ``turn_factor`` (N,) relative (>= MIN_FACTOR), ``curve`` (N,) rad/tick; the stick-slip of
    each tick from the ``drive`` stream.

    Args:
        config: the run's PhysicsConfig (the kilobot_* settings).
        seed: the run's seed.
        n: number of robots.
    """

    has_heading = True
    reverse = False

    def __init__(self, config: DriveSettings, seed: int, n: int):
        self.n = n
        self.speed = float(config.kilobot_speed)
        self.turn = float(config.kilobot_turn)
        self.align = float(config.kilobot_align)
        self.stick = float(config.kilobot_stick)
        self.slip = float(config.kilobot_slip)
        self._headings = draw_start_headings(seed, n)
        z = drive_rng(seed, "drive_calibration").standard_normal((n, 3))
        self.fwd_factor = np.maximum(MIN_FACTOR, 1 + config.kilobot_bias * z[:, 0])
        self.turn_factor = np.maximum(MIN_FACTOR, 1 + config.kilobot_bias * z[:, 1])
        self.curve = config.kilobot_curve * z[:, 2]
        self._rng = drive_rng(seed, "drive")

    def start_headings(self) -> np.ndarray:
        return self._headings.copy()

    def turn_rates(self) -> np.ndarray:
        return self.turn * self.turn_factor

    def motion(self, wish: np.ndarray | None, wheels: np.ndarray | None, heading: np.ndarray,
               active: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
        lin, spin = np.empty((self.n, 2)), np.empty(self.n)
        use_wheels = wheels is not None
        given = np.ascontiguousarray(wheels if use_wheels else wish, dtype=np.float64)
        kilobot_motion(given, use_wheels, np.ascontiguousarray(heading, dtype=np.float64),
                       np.ascontiguousarray(active, dtype=np.bool_), self.speed, self.turn,
                       self.align, self.fwd_factor, self.turn_factor, self.curve, lin, spin)
        self._stick_slip(lin, spin)
        return lin, spin

    def _stick_slip(self, lin: np.ndarray, spin: np.ndarray) -> None:
        """Scale each moving robot's motion, in place: for the m moving robots (index order)
        m uniforms, then m normals, from the ``drive`` stream; a robot sticks (no motion) when
        its uniform is below kilobot_stick, else its motion is scaled by
        max(0, 1 + kilobot_slip * normal). Nothing is drawn when no robot moves or both
        settings are 0."""
        if self.stick == 0 and self.slip == 0:
            return
        moving = np.flatnonzero((lin[:, 0] != 0) | (lin[:, 1] != 0) | (spin != 0))
        if len(moving) == 0:
            return
        u = self._rng.random(len(moving))
        z = self._rng.standard_normal(len(moving))
        factor = np.where(u < self.stick, 0.0, np.maximum(0.0, 1 + self.slip * z))
        lin[moving] *= factor[:, None]
        spin[moving] *= factor


@njit(cache=True)
def kilobot_motion(given, use_wheels, heading, active, speed, turn, align, fwd_factor,
                   turn_factor, curve, lin, spin):  # pragma: no cover - compiled
    """KilobotDrive.motion's law before stick-slip, in place: ``lin`` (N, 2), ``spin`` (N,)
    from ``given`` (N, 2): wished velocities, or (when ``use_wheels``) wheel speeds read as
    motors on (> 0) or off. Units/tick and rad/tick.

    A wish w = 0: stand still. Heading error e = wrap(angle(w) - heading): |e| > ``align``:
    turn in place toward it at ``turn`` x the robot's turn factor (never past e); else go
    forward at |w| x its forward factor, turning by its ``curve``. Motors: both on, forward
    at ``speed`` x forward factor (with the curve); only the left on, turn right (clockwise);
    only the right, turn left; none, stand still."""
    for i in range(heading.shape[0]):
        lin[i, 0] = lin[i, 1] = spin[i] = 0.0
        if not active[i]:
            continue
        rate = turn * turn_factor[i]
        ahead = 0.0
        if use_wheels:
            left_on, right_on = given[i, 0] > 0, given[i, 1] > 0
            if left_on and right_on:
                ahead = speed * fwd_factor[i]
                spin[i] = curve[i]
            elif left_on:
                spin[i] = -rate
            elif right_on:
                spin[i] = rate
        else:
            wx, wy = given[i, 0], given[i, 1]
            wished = math.sqrt(wx * wx + wy * wy)
            if wished == 0:
                continue
            err = _wrap(math.atan2(wy, wx) - heading[i])
            if abs(err) > align:
                spin[i] = math.copysign(min(rate, abs(err)), err)
            else:
                ahead = wished * fwd_factor[i]
                spin[i] = curve[i]
        lin[i, 0] = ahead * math.cos(heading[i])
        lin[i, 1] = ahead * math.sin(heading[i])


def make_drive(config: DriveSettings, seed: int, n: int) -> Drive:
    """The drive ``config.drive`` names (a PhysicsConfig), for ``n`` robots of run ``seed``."""
    if config.drive == "holonomic":
        return Holonomic(n)
    if config.drive == "diff":
        return DiffDrive(config, seed, n)
    if config.drive == "kilobot":
        return KilobotDrive(config, seed, n)
    raise ValueError(f"drive must be one of {', '.join(DRIVE_NAMES)}, got {config.drive!r}")


@kernel_warm_up("drives")
def warm_up() -> None:
    """Compile (or load) the drives' kernels on two robots."""
    out, spin = np.empty((2, 2)), np.empty(2)
    given = np.array([[0.1, 0.0], [0.0, 0.1]])
    active = np.ones(2, dtype=np.bool_)
    ones = np.ones(2)
    for use_wheels in (False, True):
        diff_motion(given, use_wheels, np.zeros(2), active, np.zeros((2, 2)), 0.6, 0.1, 0.05,
                    True, TURN_GAIN, out, spin)
        kilobot_motion(given, use_wheels, np.zeros(2), active, 0.1, 0.3, 0.35, ones, ones,
                       np.zeros(2), out, spin)
