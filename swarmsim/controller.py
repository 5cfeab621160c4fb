"""The controller interface: what a robot perceives, what it may do, and the registry.

A controller is one robot's brain. Each tick the engine hands it a :class:`Perception`
(its own local view: neighbours' relative positions and last broadcasts, a floor sensor and a
short-range floor probe, the beacon's bearing) and it returns an :class:`Action` (a desired
velocity, a message to broadcast, and whether it may sleep). Controllers never see pymunk, the
Space, other robots' objects or any global position: that is what makes "local only" true.

Frames and units: offsets are in the world-aligned frame (robots share a compass but have no
global position), lengths in the paper's units, velocities in units per tick.

Writing a controller::

    class MyController:
        name = "mine"
        Params = MyParams                     # frozen dataclass: every field has a default
        STATUSES = ("Idle", "Moving")         # names for the status codes it broadcasts
        MESSAGE_FIELDS = [("hops", "i4")]     # extra broadcast fields (numpy dtype spec)
        SETTLED_STATUSES = ("Idle",)          # optional: statuses meaning "done, standing
                                              # still" (default: "Arrive", "Arrived"); the
                                              # engine counts robots pushed out of place there

        @classmethod
        def message_fields_for(cls, groups) -> list: ...  # optional: MESSAGE_FIELDS for a
                                                          # run with this many groups
        @classmethod
        def prepare(cls, robots, batch: NeighbourBatch) -> None: ...  # optional: called
                    # before the robots of a chunk step, with their perceptions end to end
        @classmethod
        def decide_batch(cls, robots, batch: DecideBatch) -> list[Action]: ...  # optional:
                    # decides a chunk itself (in place of prepare and step); must give the
                    # same actions as step would (run setting batch_decide=false to compare);
                    # may return a ChunkActions (the same actions as columns) instead
        @classmethod
        def create_robots(cls, setups, params, rngs) -> list: ...  # optional: makes the
                    # run's robots together (default: cls(setup, params, rng) for each)
        @classmethod
        def warm_up(cls) -> None: ...  # optional: compile or load its kernels; the engine
                    # calls it as a run is set up, so its run clock does not count that

        @classmethod
        def sensing_range(cls, params) -> float: ...   # how far it listens, in units

        def __init__(self, setup: RobotSetup, params, rng: numpy.random.Generator): ...
        def step(self, p: Perception) -> Action: ...

Register it with ``@register`` (built-ins) or use ``module:Class`` on the command line.
A controller that steps many robots a tick may return ``make_action(...)`` instead of
``Action(...)``: the same object, made in about half the time.
"""

from __future__ import annotations

import importlib
import os
import sys
from collections.abc import Callable
from dataclasses import dataclass
from typing import Any, ClassVar, Protocol, runtime_checkable

import numpy as np

from swarmsim.errors import ConfigError

INF_GRADIENT = np.iinfo(np.int32).max
"""Gradient value that means "no gradient yet" (the paper's INFINITE)."""

BASE_MESSAGE_FIELDS: list[tuple[str, str]] = [
    ("id", "i4"),  # the sender's own id (robots know their id, like a Kilobot's UID)
    ("status", "i1"),  # index into the controller's STATUSES
    ("gradient", "i4"),  # hop gradient, INF_GRADIENT when unknown
    ("group", "i2"),  # group id, 0 = none
    ("leader", "?"),
    ("moving", "?"),  # the sender is moving on purpose (not waiting or arrived)
]
"""Fields every broadcast carries; observers (metrics, render) read these."""


NO_SENDER = -1
"""``id`` of a neighbour row whose message did not arrive (failed robot, lost message)."""


def run_message_fields(cls: Any, groups: int) -> list[tuple[str, Any]]:
    """A controller class's broadcast fields for a run with ``groups`` groups: its
    ``message_fields_for(groups)`` if it has one, else its ``MESSAGE_FIELDS``."""
    fields_for = getattr(cls, "message_fields_for", None)
    if fields_for is not None:
        return list(fields_for(groups))
    return list(getattr(cls, "MESSAGE_FIELDS", []))


def message_dtype(extra_fields: list[tuple[str, Any]] | None = None) -> np.dtype:
    """The structured dtype of a controller's broadcasts: base fields plus its own."""
    return np.dtype(BASE_MESSAGE_FIELDS + list(extra_fields or []))


def silent_message(dtype: np.dtype) -> np.void:
    """The row a robot sees for a neighbour it senses but hears nothing from.

    ``id`` is NO_SENDER, ``status`` -1, ``gradient`` INF_GRADIENT, everything else zero.
    """
    row = np.zeros((), dtype=dtype)
    row["id"] = NO_SENDER
    row["status"] = -1
    row["gradient"] = INF_GRADIENT
    return row[()]


@dataclass(frozen=True, slots=True)
class RobotSetup:
    """What a robot is told when it is switched on.

    Attributes:
        robot_id: its unique id (also broadcast in every message).
        leader: True if the robot is pre-programmed as a (group) leader.
        group: its pre-assigned group (0 = none yet).
        groups: number of groups K in this run.
        scattered: True when the robots start scattered at random (start "random"): groups
            must still be formed and gathered; False when they start in formation.
    """

    robot_id: int
    leader: bool = False
    group: int = 0
    groups: int = 1
    scattered: bool = False


@dataclass(frozen=True, slots=True)
class Perception:
    """One robot's local view at the start of a tick.

    Attributes:
        tick: the current tick (every robot has a clock).
        offsets: (k, 2) neighbours' positions relative to this robot, world-aligned frame,
            sorted by distance (nearest first); units.
        distances: (k,) their distances, units.
        messages: (k,) structured array: what each neighbour broadcast last tick.
        on_target: floor sensor: is the floor under this robot part of the target?
        probe: floor probe: ``probe(offset)`` is True when the floor at this robot's position
            plus ``offset`` (units, |offset| <= probe range) is part of the target.
        beacon: unit vector toward the world's beacon, or None when the world has none.
        moved: (2,) own displacement during the previous tick (odometry), units.
    """

    tick: int
    offsets: np.ndarray
    distances: np.ndarray
    messages: np.ndarray
    on_target: bool
    probe: Callable[[np.ndarray], bool]
    beacon: np.ndarray | None
    moved: np.ndarray


@dataclass(frozen=True)
class NeighbourBatch:
    """The perceptions of the robots deciding together (one chunk of a tick), laid end to
    end, for controller classes that vectorise work over many robots (see ``prepare``).

    Robot k of the chunk owns rows ``starts[k]:starts[k + 1]``: the very rows, in the same
    order, of its Perception's ``messages`` and ``distances``. Nothing else is in here: a
    robot's result may depend on its own rows only.

    Attributes:
        messages: (P,) structured array: every heard broadcast of the chunk.
        distances: (P,) their distances, units (each robot's rows ascending).
        starts: (R + 1,) where each robot's rows start, then P.
    """

    messages: np.ndarray
    distances: np.ndarray
    starts: np.ndarray


@dataclass(frozen=True, slots=True)
class DecideBatch:
    """A chunk of awake robots' sensing, for a controller class's optional ``decide_batch``
    (which then takes the place of ``prepare`` and each robot's ``step`` for the chunk).

    Robot k of the chunk owns rows ``neighbours.starts[k]:neighbours.starts[k + 1]`` of
    ``neighbours`` and ``offsets`` and the k-th entry of the lists: the very values of its
    Perception. Nothing else is in here: a robot's action may depend on its own rows only.

    Attributes:
        tick: the current tick.
        neighbours: the chunk's heard broadcasts and distances (units).
        offsets: (P, 2) each heard robot's position relative to the listener, units.
        on_target: each robot's floor sensor.
        moved: (R, 2) each robot's own displacement during the previous tick, units (row k
            is robot k's).
        beacons: (R, 2) each robot's unit bearing toward the beacon (Perception.beacon), or
            None in a world without a beacon.
        probe: ``probe(k)`` is robot k's floor probe (see Perception.probe).
        perceive: ``perceive(k)`` is robot k's whole Perception (for robots the batch
            does not decide itself: ``robot.step(perceive(k))``).
    """

    tick: int
    neighbours: NeighbourBatch
    offsets: np.ndarray
    on_target: list[bool]
    moved: np.ndarray
    beacons: np.ndarray | None
    probe: Callable[[int], Callable[[np.ndarray], bool]]
    perceive: Callable[[int], Perception]


@dataclass(frozen=True, slots=True)
class Action:
    """What a robot does this tick.

    Attributes:
        velocity: desired velocity (vx, vy) in units per tick; the engine clamps it to v.
        message: the broadcast for this tick, a tuple in the order of the controller's message
            dtype (or None to repeat the last one). Neighbours receive it next tick.
        sleep: True promises that, until its perception changes, this robot would keep
            returning this same action; the engine then skips it until a neighbour within its
            sensing range moves or changes its message, or the robot itself is moved.
        wake_range: with ``sleep``, a promise that only changes within this distance (units)
            matter, so that changes farther away need not wake it (None = sensing range).
        listen: how far (units) to sense on the next tick; a robot may listen less than its
            sensing range when it needs less (cheaper). None = the full sensing range.
        wake_on_motion: with ``sleep``, False promises that neighbours merely moving within the
            wake range cannot change this robot's action: only a changed broadcast, a
            neighbour pushed out of place (moved without being told to) or being moved itself
            wakes it.
        wake_tick: with ``sleep``, the tick at which the robot is woken whatever happens (a
            timeout of its own: its promise holds only until then). None = no such tick.
    """

    velocity: tuple[float, float] = (0.0, 0.0)
    message: tuple | None = None
    sleep: bool = False
    wake_range: float | None = None
    listen: float | None = None
    wake_on_motion: bool = True
    wake_tick: int | None = None


class ChunkActions:
    """A chunk's actions as columns: what ``decide_batch`` may return in place of a list of
    :class:`Action` (the same meaning, robot k's in row k), so that robots decided together
    need no Action objects. Start from :meth:`empty` (every robot standing still, listening
    its full range, repeating its broadcast, awake) and fill it in.

    Attributes:
        velocities: (R, 2) desired velocities, units per tick.
        listen: (R,) how far each robot senses next tick, units (NaN: its full range).
        messages: {k: robot k's new broadcast tuple} (the others repeat theirs).
        sleepers: {k: Action} the robots that ask to sleep, with their promises
            (``Action.sleep`` and its fields; honoured only where the velocity is zero).
    """

    __slots__ = ("listen", "messages", "sleepers", "velocities")

    def __init__(self, velocities: np.ndarray, listen: np.ndarray,
                 messages: dict[int, tuple], sleepers: dict[int, Action]):
        self.velocities, self.listen = velocities, listen
        self.messages, self.sleepers = messages, sleepers

    @classmethod
    def empty(cls, robots: int) -> ChunkActions:
        return cls(np.zeros((robots, 2)), np.full(robots, np.nan), {}, {})

    def put(self, k: int, action: Action) -> None:
        """Row k from a whole Action."""
        self.velocities[k] = action.velocity
        if action.listen is not None:
            self.listen[k] = action.listen
        if action.message is not None:
            self.messages[k] = action.message
        if action.sleep:
            self.sleepers[k] = action

    @classmethod
    def of(cls, actions: list[Action]) -> ChunkActions:
        """The columns of a list of Actions."""
        velocities = np.array([a.velocity for a in actions], dtype=float).reshape(-1, 2)
        listen = np.array([np.nan if a.listen is None else a.listen for a in actions],
                          dtype=float)
        return cls(velocities, listen,
                   {k: a.message for k, a in enumerate(actions) if a.message is not None},
                   {k: a for k, a in enumerate(actions) if a.sleep})


# Fast makers for the two objects made once per awake robot per tick (K with 3 groups: about
# 4.6 million of each in a run). Calling a frozen dataclass costs 1.0-1.3 us for these: the
# class call, then one object.__setattr__ per field to get past the frozen check. These set
# each slot through its descriptor (what object.__setattr__ ends up doing) at about half the
# cost: the same objects, still frozen. tests/test_controller_makers.py holds them to the
# classes' fields.
_new = object.__new__
(_p_tick, _p_offsets, _p_distances, _p_messages, _p_on_target, _p_probe, _p_beacon,
 _p_moved) = (vars(Perception)[name].__set__ for name in Perception.__slots__)
(_a_velocity, _a_message, _a_sleep, _a_wake_range, _a_listen, _a_wake_on_motion,
 _a_wake_tick) = (vars(Action)[name].__set__ for name in Action.__slots__)


def make_perception(tick: int, offsets: np.ndarray, distances: np.ndarray,
                    messages: np.ndarray, on_target: bool, probe: Callable[[np.ndarray], bool],
                    beacon: np.ndarray | None, moved: np.ndarray) -> Perception:
    """``Perception(...)``, faster."""
    p = _new(Perception)
    _p_tick(p, tick)
    _p_offsets(p, offsets)
    _p_distances(p, distances)
    _p_messages(p, messages)
    _p_on_target(p, on_target)
    _p_probe(p, probe)
    _p_beacon(p, beacon)
    _p_moved(p, moved)
    return p


def make_action(velocity: tuple[float, float] = (0.0, 0.0), message: tuple | None = None,
                sleep: bool = False, wake_range: float | None = None,
                listen: float | None = None, wake_on_motion: bool = True,
                wake_tick: int | None = None) -> Action:
    """``Action(...)``, faster."""
    a = _new(Action)
    _a_velocity(a, velocity)
    _a_message(a, message)
    _a_sleep(a, sleep)
    _a_wake_range(a, wake_range)
    _a_listen(a, listen)
    _a_wake_on_motion(a, wake_on_motion)
    _a_wake_tick(a, wake_tick)
    return a


@runtime_checkable
class Controller(Protocol):
    """One robot's controller: ``step(perception) -> action``."""

    def step(self, p: Perception) -> Action: ...


class ControllerClass(Protocol):
    """What the engine needs from a controller class."""

    name: ClassVar[str]
    Params: ClassVar[type]
    STATUSES: ClassVar[tuple[str, ...]]
    MESSAGE_FIELDS: ClassVar[list[tuple[str, Any]]]

    @classmethod
    def sensing_range(cls, params: Any) -> float: ...

    def __call__(self, setup: RobotSetup, params: Any, rng: np.random.Generator) -> Controller: ...


_REGISTRY: dict[str, type] = {}
_BUILTIN_MODULES = ("controllers.dispersion", "controllers.ggc", "controllers.kilobot",
                    "controllers.cvt", "controllers.meanshift", "controllers.dash",
                    "controllers.fcdfs")


def register(cls: type) -> type:
    """Class decorator: make a controller available by its ``name``."""
    _REGISTRY[cls.name] = cls
    return cls


def _load_builtins() -> None:
    for mod in _BUILTIN_MODULES:
        try:
            importlib.import_module(mod)
        except ModuleNotFoundError as exc:
            if exc.name != mod:
                raise


def available_controllers() -> list[str]:
    """Names of the registered controllers."""
    _load_builtins()
    return sorted(_REGISTRY)


def get_controller(name: str) -> type:
    """A controller class by registered name or ``module:Class``."""
    if ":" in name:
        mod_name, _, cls_name = name.partition(":")
        _importable_from_here()
        try:
            mod = importlib.import_module(mod_name)
        except ImportError as exc:
            raise ConfigError(f"cannot import module {mod_name!r}: {exc}",
                              key="controller") from None
        cls = getattr(mod, cls_name, None)
        if cls is None:
            raise ConfigError(f"module {mod_name!r} has no {cls_name!r}", key="controller")
        _check_controller_class(cls, name)
        return cls
    _load_builtins()
    if name not in _REGISTRY:
        raise ConfigError(f"unknown controller {name!r}; available: {', '.join(sorted(_REGISTRY))}"
                          " (or module:Class)", key="controller")
    return _REGISTRY[name]


def resolve_controller(controller: str | type) -> tuple[type, str]:
    """A run's controller class and the name its summary reports, from a registered name, a
    ``"module:Class"`` string or a class (checked like a ``module:Class`` class). A class is
    reported by its registered name if it is the class registered under its ``name``, else as
    ``"module:Class"``."""
    if isinstance(controller, str):
        return get_controller(controller), controller
    if not isinstance(controller, type):
        raise ConfigError(f"expected a controller name, 'module:Class' or a controller class, "
                          f"got {controller!r}", key="controller")
    _load_builtins()
    name = getattr(controller, "name", None)
    if not (isinstance(name, str) and _REGISTRY.get(name) is controller):
        name = f"{controller.__module__}:{controller.__qualname__}"
    _check_controller_class(controller, name)
    return controller, name


def uses_groups(cls: type, start: str = "") -> bool:
    """Whether the number of groups means anything to a run of controller class ``cls`` with
    this ``start`` ("" = the class's ``default_start``, else "random"): the class declares
    ``max_groups`` (its robots form and keep groups: GGC), or the robots start in formation
    (one formation per group, its centre robot the group's leader). Otherwise a run has one
    group."""
    start = start or getattr(cls, "default_start", "random")
    return hasattr(cls, "max_groups") or start == "formation"


def _importable_from_here() -> None:
    """Let ``module:Class`` name a module in the current folder, as ``python -m swarmsim``
    does (the installed ``swarmsim`` command does not put the current folder on sys.path).
    Appended, so that it never shadows an installed module."""
    here = os.getcwd()
    if here not in sys.path and "" not in sys.path:
        sys.path.append(here)


def _check_controller_class(cls: Any, name: str) -> None:
    missing = [a for a in ("Params", "STATUSES", "sensing_range", "step") if not hasattr(cls, a)]
    if missing:
        raise ConfigError(f"{name!r} is not a controller class (missing {missing})",
                          key="controller")
