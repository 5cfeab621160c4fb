"""The controller API: what a robot perceives, what it may do, and the protocol it follows.

A controller is one robot's brain. Each tick the engine hands it a :class:`Perception`
(its own local view: neighbours' relative positions and last broadcasts, a floor sensor and a
short-range floor probe, the beacon's bearing, its odometry) and it returns an :class:`Action`
(a desired velocity, a message to broadcast, and whether it may sleep). Controllers never see
pymunk, the Space, other robots' objects or any global position: that is what makes "local
only" true. Importing this module loads neither pymunk nor pygame.

Frames and units: offsets are in the world-aligned frame (robots share a compass but have no
global position), lengths in the paper's units, velocities in units per tick.

A controller class is one of two kinds (the whole contract: :class:`ControllerClass`):

- per-robot: ``cls(setup, params, rng)`` makes one robot's controller, whose
  ``step(perception) -> Action`` the engine calls for every awake robot (examples/my_controller.py);
- batch: ``cls.create_swarm(setups, params, rngs)`` makes a :class:`Swarm` holding every robot's
  state as arrays, whose ``decide(robots, batch) -> ChunkActions`` decides a chunk of awake
  robots from their perceptions laid end to end (:class:`DecideBatch`).

A broadcast is a tuple in the order of the run's message dtype: ``id``, ``status``, ``moving``,
then the controller's ``MESSAGE_FIELDS``; or a dict by field name (missing fields are zero).
``id`` is always the sender's own: the engine writes it, whatever the broadcast holds there.
The engine checks every Action and ChunkActions where it receives it (what it accepts: the
docstrings of :class:`Action` and :class:`ChunkActions`, docs/input-checks.md); anything else
stops the run with a ControllerError naming the controller, the robot and the tick.

Register a class with an entry point in the ``swarmsim.controllers`` group of the installing
package's pyproject.toml (swarmsim.registry), or run it unregistered: name it as
``module:Class`` or pass the class.
"""

from __future__ import annotations

import math
from collections.abc import Callable, Mapping
from dataclasses import dataclass
from typing import Any, ClassVar, Protocol, TypeAlias, cast, runtime_checkable

import numpy as np

from swarmsim.actionvalues import BadAction, action_columns, action_problem, show
from swarmsim.kernels.kernelcache import register_tree as stamp_kernels_by_code
from swarmsim.limits import MAX_GROUPS, require_non_negative, require_positive
from swarmsim.registry import available_controllers, get_controller

BASE_MESSAGE_FIELDS: list[tuple[str, str]] = [
    ("id", "i4"),  # the sender's own id (robots know their id, like a Kilobot's UID)
    ("status", "i1"),  # index into the controller's STATUSES
    ("moving", "?"),  # the sender is moving on purpose (not waiting or settled)
]
"""Fields every broadcast carries; the engine and its observers (metrics, faults, render) read
only these. A controller declares any other field it broadcasts in ``MESSAGE_FIELDS``."""


Broadcast: TypeAlias = "tuple[Any, ...] | Mapping[str, Any] | np.void"
"""What an Action may broadcast: a tuple in the order of the run's message dtype, a dict by
field name (fields it leaves out are zero) or a row of that dtype."""


NO_SENDER = -1
"""``id`` of a neighbour row whose message did not arrive (failed robot, lost message)."""


def run_message_fields(cls: Any, groups: int, scattered: bool) -> list[tuple[str, Any]]:
    """A controller class's broadcast fields for a run with ``groups`` groups, its robots
    started ``scattered`` (RobotSetup.scattered) or not: its
    ``message_fields_for(groups, scattered)`` if it has one, else its ``MESSAGE_FIELDS``."""
    fields_for = getattr(cls, "message_fields_for", None)
    if fields_for is not None:
        return list(fields_for(groups, scattered))
    return list(getattr(cls, "MESSAGE_FIELDS", []))


def message_dtype(extra_fields: list[tuple[str, Any]] | None = None) -> np.dtype:
    """The structured dtype of a controller's broadcasts: base fields plus its own."""
    return np.dtype(BASE_MESSAGE_FIELDS + list(extra_fields or []))


def silent_message(dtype: np.dtype, values: Mapping[str, Any] | None = None) -> np.void:
    """The row a robot sees for a neighbour it senses but hears nothing from.

    ``id`` is NO_SENDER, ``status`` -1, the controller's declared ``SILENT`` values (e.g. an
    "unknown" gradient), everything else zero.
    """
    row = np.zeros((), dtype=dtype)
    row["id"] = NO_SENDER
    row["status"] = -1
    for name, value in (values or {}).items():
        row[name] = value
    return cast(np.void, row[()])  # numpy's stubs type a 0-d structured item as an ndarray


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
        turn_rate: the fastest its drive turns the robot in place, rad/tick; ``inf`` for a
            holonomic robot, which needs no turning to change direction. A hardware fact of
            the robot's own body, like its wheels; not world state.
        reverse: True when its drive can move backward without first turning round.
    """

    robot_id: int
    leader: bool = False
    group: int = 0
    groups: int = 1
    scattered: bool = False
    turn_rate: float = math.inf
    reverse: bool = True


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
        turned: how far the robot's body turned during the previous tick (odometry), rad,
            counter-clockwise positive, in [-pi, pi); 0.0 for a holonomic robot, whose
            heading means nothing. A robot knows how it turned, never its heading.
    """

    tick: int
    offsets: np.ndarray
    distances: np.ndarray
    messages: np.ndarray
    on_target: bool
    probe: Callable[[np.ndarray], bool]
    beacon: np.ndarray | None
    moved: np.ndarray
    turned: float = 0.0


@dataclass(frozen=True)
class NeighbourBatch:
    """The perceptions of the robots deciding together (one chunk of a tick), laid end to
    end (:attr:`DecideBatch.neighbours`), for a swarm that vectorises work over many robots.

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
    """A chunk of awake robots' sensing: what a :class:`Swarm`'s ``decide`` is given.

    Robot k of the chunk owns rows ``neighbours.starts[k]:neighbours.starts[k + 1]`` of
    ``neighbours`` and ``offsets`` and the k-th entry of the lists: the very values of its
    Perception. Nothing else is in here: a robot's action may depend on its own rows only.

    Attributes:
        tick: the current tick.
        neighbours: the chunk's heard broadcasts and distances (units).
        offsets: (P, 2) each heard robot's position relative to the listener, units.
        on_target: (R,) bool, each robot's floor sensor.
        moved: (R, 2) each robot's own displacement during the previous tick, units (row k
            is robot k's).
        beacons: (R, 2) each robot's unit bearing toward the beacon (Perception.beacon), or
            None in a world without a beacon.
        probe: ``probe(k)`` is robot k's floor probe (see Perception.probe).
        perceive: ``perceive(k)`` is robot k's whole Perception (for robots the swarm
            decides one at a time: ``robot.step(perceive(k))``).
        probe_many: ``probe_many(ks, offsets)`` asks many probes at once: (M,) bool, entry j
            is robot ``ks[j]``'s probe at ``offsets[j]`` (units, each within the probe range).
        turned: (R,) each robot's Perception.turned, rad (a run's batches always have it;
            None only in a batch made by hand, meaning zeros).
    """

    tick: int
    neighbours: NeighbourBatch
    offsets: np.ndarray
    on_target: np.ndarray
    moved: np.ndarray
    beacons: np.ndarray | None
    probe: Callable[[int], Callable[[np.ndarray], bool]]
    perceive: Callable[[int], Perception]
    probe_many: Callable[[np.ndarray, np.ndarray], np.ndarray] | None = None
    turned: np.ndarray | None = None


@dataclass(frozen=True, slots=True)
class Action:
    """What a robot does this tick.

    What the engine accepts (anything else stops the run with a ControllerError naming the
    controller, the robot and the tick; see docs/input-checks.md): ``step`` returns an Action
    (not None, not a tuple); ``velocity`` two finite numbers; ``message`` None, a tuple of one
    value per field of the run's message dtype (``id``, ``status``, ``moving``, then the
    controller's fields), a dict by field name (fields it leaves out are zero) or a row of
    that dtype, each value fitting its field as given (no rounding, no wrapping, no text;
    ``status`` an index into STATUSES; ``id`` is replaced by the sender's own id);
    ``sleep`` True or False (or 1, 0) and ``wake_on_motion`` True or False; ``listen`` and
    ``wake_range`` None or a distance >= 0 (not NaN); ``wake_tick`` None or an integer >= 0
    (one past int64's range is never, like None).
    The sleep promises are checked when ``sleep`` is True (they mean nothing otherwise).

    Attributes:
        velocity: desired velocity (vx, vy) in units per tick; the engine clamps it to v.
            A controller that declares ``COMMANDS = "wheels"`` gives its wheel speeds here
            instead: (left, right), units per tick, each clamped to the drive's wheel_speed.
        message: the broadcast for this tick, a tuple in the order of the controller's message
            dtype, or a dict by field name (or None to repeat the last one). Neighbours
            receive it next tick.
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
    message: Broadcast | None = None
    sleep: bool = False
    wake_range: float | None = None
    listen: float | None = None
    wake_on_motion: bool = True
    wake_tick: int | None = None


class ChunkActions:
    """A chunk's actions as columns: what a swarm's ``decide`` returns (robot k's in row k),
    so that robots decided together need no Action objects.

    Two forms, one meaning. Sparse (from :meth:`empty`, filled by :meth:`put`): ``messages``
    holds only the robots with a new broadcast and ``sleepers`` only the robots that ask to
    sleep. Dense (:meth:`columns`, for compiled controllers): ``broadcast`` holds every robot's
    broadcast row and ``sleep``, ``wake_range``, ``wake_on_motion`` and ``wake_tick`` every
    robot's sleep request.

    What the engine accepts (anything else stops the run with a ControllerError): every column
    a numpy array of numbers (converted as numpy converts them to the dtypes below) with one
    row per robot of the chunk (R rows); velocities finite; listen and wake_range NaN or
    >= 0; broadcast rows with the run's message fields (``batch.neighbours.messages.dtype``),
    whose ``status`` is an index into STATUSES (``id`` is replaced by each sender's own id);
    ``messages`` and ``sleepers`` keyed by rows 0..R-1, their values as :class:`Action` says.
    :meth:`put` checks the Action it is given.

    Attributes:
        velocities: (R, 2) desired velocities, units per tick (float or integer).
        listen: (R,) how far each robot senses next tick, units (NaN: its full range).
        messages: {k: robot k's new broadcast} (the others repeat theirs).
        sleepers: {k: Action} the robots that ask to sleep, with their promises
            (``Action.sleep`` and its fields; honoured only where the velocity is zero).
        broadcast: (R,) structured rows in the run's message dtype, or None (sparse form).
        sleep: (R,) bool, or None (sparse form); honoured only where the velocity is zero.
        wake_range: (R,) float, units, NaN = the sensing range (see Action.wake_range).
        wake_on_motion: (R,) bool (see Action.wake_on_motion).
        wake_tick: (R,) integer, negative = no timeout (see Action.wake_tick).
    """

    __slots__ = ("broadcast", "listen", "messages", "sleep", "sleepers", "velocities",
                 "wake_on_motion", "wake_range", "wake_tick")

    def __init__(self, velocities: np.ndarray, listen: np.ndarray,
                 messages: dict[int, Broadcast] | None = None,
                 sleepers: dict[int, Action] | None = None):
        self.velocities, self.listen = velocities, listen
        self.messages = {} if messages is None else messages
        self.sleepers = {} if sleepers is None else sleepers
        self.broadcast: np.ndarray | None = None
        self.sleep: np.ndarray | None = None
        self.wake_range: np.ndarray | None = None
        self.wake_on_motion: np.ndarray | None = None
        self.wake_tick: np.ndarray | None = None

    @classmethod
    def empty(cls, robots: int) -> ChunkActions:
        """Every robot standing still, listening its full range, repeating its broadcast."""
        return cls(np.zeros((robots, 2)), np.full(robots, np.nan))

    @classmethod
    def columns(cls, velocities: np.ndarray, listen: np.ndarray, broadcast: np.ndarray,
                sleep: np.ndarray, wake_range: np.ndarray, wake_on_motion: np.ndarray,
                wake_tick: np.ndarray) -> ChunkActions:
        """The dense form: every robot's broadcast and sleep request as columns."""
        out = cls(velocities, listen)
        out.broadcast, out.sleep, out.wake_range = broadcast, sleep, wake_range
        out.wake_on_motion, out.wake_tick = wake_on_motion, wake_tick
        return out

    def put(self, k: int, action: Action) -> None:
        """Row k from a whole Action (sparse form); an Action the engine would refuse raises
        swarmsim.actionvalues.BadAction (the run names the robot)."""
        problem = (action_problem(action) if isinstance(action, Action) else
                   f"{show(action)}; expected an Action")
        if problem:
            raise BadAction(k, problem)
        self.velocities[k] = action.velocity
        if action.listen is not None:
            self.listen[k] = action.listen
        if action.message is not None:
            self.messages[k] = action.message
        if action.sleep:
            self.sleepers[k] = action

    @classmethod
    def of(cls, actions: list[Action]) -> ChunkActions:
        """The columns of a list of Actions (BadAction, swarmsim.actionvalues, naming the first
        the engine would refuse; finiteness and broadcasts are checked when they are written).
        """
        return cls(*action_columns(actions, len(actions), Action))


# Fast makers for the two objects made once per awake robot per tick. Calling a frozen
# dataclass runs one object.__setattr__ per field to get past the frozen check; these set each
# slot through its descriptor (what object.__setattr__ ends up doing) directly: the same
# objects, still frozen. tests/engine/test_controller_makers.py holds them to the classes' fields.
_new = object.__new__
(_p_tick, _p_offsets, _p_distances, _p_messages, _p_on_target, _p_probe, _p_beacon,
 _p_moved, _p_turned) = (vars(Perception)[name].__set__ for name in Perception.__slots__)
(_a_velocity, _a_message, _a_sleep, _a_wake_range, _a_listen, _a_wake_on_motion,
 _a_wake_tick) = (vars(Action)[name].__set__ for name in Action.__slots__)


def make_perception(tick: int, offsets: np.ndarray, distances: np.ndarray,
                    messages: np.ndarray, on_target: bool, probe: Callable[[np.ndarray], bool],
                    beacon: np.ndarray | None, moved: np.ndarray, turned: float = 0.0
                    ) -> Perception:
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
    _p_turned(p, turned)
    return p


def make_action(velocity: tuple[float, float] = (0.0, 0.0), message: Broadcast | None = None,
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


# ----------------------------------------------------------------------------- the protocol
@runtime_checkable
class Controller(Protocol):
    """One robot's controller: ``step(perception) -> action``."""

    def step(self, perception: Perception) -> Action: ...


@runtime_checkable
class Swarm(Protocol):
    """All robots' controllers of one run, deciding a chunk of awake robots at a time.

    A batch controller class makes one with ``create_swarm``; per-robot controllers are driven
    through :class:`swarmsim.engine.swarm.RobotSwarm`, which calls each robot's ``step``. Optional:
    ``warm_up()``, compile or load the kernels this swarm's run uses (called once, after the
    class's ``warm_up``, before the run's clock starts: no kernel is then compiled mid-run);
    ``fail(robots, mode)``, for a class that declares ``FAILURE_MODES`` (:class:`FailingSwarm`).
    """

    def decide(self, robots: np.ndarray, batch: DecideBatch) -> ChunkActions | list[Action]:
        """The actions of the chunk's robots (their indices, ascending; row k of the batch is
        robot ``robots[k]``). A robot's action may depend on its own rows only."""
        ...

    def summarize(self, failed: np.ndarray) -> dict[str, Any]:
        """The controller's own summary figures (failed: (N,) bool, robots failed by the run:
        counted as "Failed" in any status count)."""
        ...


@runtime_checkable
class FailingController(Protocol):
    """A per-robot controller whose class declares ``FAILURE_MODES`` (ControllerClass)."""

    def fail(self, mode: str) -> None:
        """This robot fails now, as ``mode`` (one of its class's FAILURE_MODES) says: change
        the robot's own state so that its next ``step`` acts as a robot failed so would."""
        ...


@runtime_checkable
class FailingSwarm(Protocol):
    """A batch controller's Swarm whose class declares ``FAILURE_MODES`` (ControllerClass)."""

    def fail(self, robots: np.ndarray, mode: str) -> None:
        """The robots at ``robots`` (indices, ascending) fail now, as ``mode`` (one of its
        class's FAILURE_MODES) says: change their own state rows so that their next
        decisions act as robots failed so would."""
        ...


class ControllerClass(Protocol):
    """What a controller class declares. Only the first five are required.

    Required: ``name``, ``Params`` (a frozen dataclass whose fields all have defaults),
    ``STATUSES`` (names of the status codes it broadcasts), ``sensing_range(params)`` (units),
    and either ``step`` (a per-robot controller: ``cls(setup, params, rng).step(perception)``)
    or ``create_swarm(setups, params, rngs) -> Swarm`` (a batch controller).

    Optional declarations (defaults in brackets), read once by
    :func:`swarmsim.engine.controller_info.describe`:

    - ``MESSAGE_FIELDS`` ([]: no fields of its own): broadcast fields beyond ``id``,
      ``status``, ``moving`` (a list of (name, numpy type)); ``message_fields_for(groups,
      scattered)`` if they depend on the run's group count or start (RobotSetup.scattered).
    - ``COMMANDS`` ("velocity"): what ``Action.velocity`` / ``ChunkActions.velocities``
      hold: "velocity", a wished velocity that the run's drive carries out as it can, or
      "wheels", the (left, right) wheel speeds of a robot with a drive that has wheels
      (``drive=diff`` or ``kilobot``; a run with ``drive=holonomic`` is refused). docs/drives.md.
    - ``SILENT`` ({}): values of those fields in the row of a neighbour that is not heard.
    - ``SETTLED_STATUSES`` (()): statuses meaning "done, standing still" (metrics count robots
      pushed out of place there; faults fail them last).
    - ``INITIAL_STATUSES`` / ``COVERING_STATUSES`` (()): statuses before any robot starts
      covering, and while covering (the fault phases "gradient" and "coverage").
    - ``COLOURINGS`` ({}): message fields a video may colour robots by: "scale" (an ordered
      value, e.g. a hop count) or "category" (e.g. a group id). "status" is always offered.
    - ``LEADER_FIELD`` (None): a bool message field marking leaders (drawn with a ring;
      faults fail them last); ``GROUP_FIELD`` (None): the field holding a robot's group.
    - ``LAYOUTS`` (every layout of :data:`swarmsim.world.layouts.LAYOUTS`: "random", "formation"):
      the start layouts it can start from, if not all; ``default_start`` is one of them.
    - ``default_start`` ("random"), ``requires_beacon`` (False), ``max_groups`` (None: it
      forms no groups of its own; at most :data:`MAX_GROUPS`, every run's bound, which GGC
      declares),
      ``probe_params`` (()), ``min_probe_range`` (0.0), ``warm_up()`` (compile kernels;
      a package of numba kernels calls ``stamp_kernels_by_code(its_folder)`` before it
      defines them, so that numba's cache survives edits of docstrings and comments).
    - ``same_run_settings(params, config)`` (none): settings that make the run of ``params``
      and ``config`` (SimConfig) tick for tick by construction, named canonically (e.g. a
      rule set whose extra rules act nowhere in this run -> the plain one), or {}. Runs that
      name the same canonical settings share one run id, so a sweep or reproduction makes
      them once (swarmsim.experiments.spec.run_id). It must give {} for a run that is
      canonical already, and the same answer for every run that is the same.
    - ``FAILURE_MODES`` ({}: only the engine's "dead"): the ways its robots can fail that it
      simulates itself, name -> meaning (e.g. GGC's ``{"no_gradient": "its gradient is lost
      ..."}``), chosen by a run's ``failure_mode`` setting. At the failure moment (the end of
      a tick, swarmsim/engine/faults.py) the engine tells the failing robots' controllers,
      once: a per-robot controller's ``fail(mode)`` (:class:`FailingController`), a batch
      controller's swarm's ``fail(robots, mode)`` (:class:`FailingSwarm`). From then on the
      robot is decided as before, woken if it slept, and its new state is its own to act on:
      it keeps moving and broadcasting as its controller decides (unlike "dead", which
      silences it). A name may not be "dead"; the run refuses a mode the class does not
      declare, and a class that declares modes without ``fail``.
    - Per-robot controllers only: ``summarize(robots)`` (the controller's own summary
      figures from its robots' controllers).
    """

    name: ClassVar[str]
    Params: ClassVar[type]
    STATUSES: ClassVar[tuple[str, ...]]

    @classmethod
    def sensing_range(cls, params: Any) -> float: ...


__all__ = ["BASE_MESSAGE_FIELDS", "MAX_GROUPS", "NO_SENDER", "Action", "ChunkActions", "Controller",
           "ControllerClass", "DecideBatch", "FailingController", "FailingSwarm",
           "NeighbourBatch", "Perception", "RobotSetup", "Swarm", "available_controllers",
           "get_controller", "make_action", "make_perception", "message_dtype",
           "require_non_negative", "require_positive", "run_message_fields", "silent_message",
           "stamp_kernels_by_code"]
