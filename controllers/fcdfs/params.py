"""FCDFS's declarations: its statuses, broadcasts, lattice directions and parameters
(:class:`FCDFSParams`) and what the engine reads of an FCDFS controller class
(:class:`FCDFSDeclarations`), shared by the batch controller (controller.py) and the per-robot
reference (robot.py)."""

from __future__ import annotations

import math
from dataclasses import dataclass

from controllers.common.gradient import COLOURINGS, GRADIENT_FIELDS, SILENT
from swarmsim.controller import require_positive

TRAVEL, QUEUE, DOOR, MOVING, SETTLED = range(5)
STATUSES = ("Travel", "Queue", "Door", "Moving", "Settled")
MESSAGE_FIELDS = [*GRADIENT_FIELDS, ("cmd", "i1"), ("vx", "f4"), ("vy", "f4"), ("door", "i4"), ("pdir", "i1"),
                  ("touch", "?"), ("hops", "i4"), ("ci", "i4"), ("cj", "i4")]
AXES = ((1, 0), (0, 1), (-1, 0), (0, -1))
MIN_PROBE_RANGE = 9.0
NO_DOOR = -1
MAX_HOPS = 64


def rotate(d: tuple[int, int], turn: int) -> tuple[int, int]:
    """Lattice direction turned 90 degrees: counter-clockwise for turn = +1, else clockwise."""
    return (-d[1], d[0]) if turn > 0 else (d[1], -d[0])


def neg(d: tuple[int, int]) -> tuple[int, int]:
    return (-d[0], -d[1])


def add(a: tuple[int, int], b: tuple[int, int]) -> tuple[int, int]:
    return (a[0] + b[0], a[1] + b[1])


@dataclass(frozen=True)
class FCDFSParams:
    """Parameters of the FCDFS controller (lengths in units, times in ticks).

    Attributes:
        d_safe: safe distance (paper Table 2: 1).
        d_cover: coverage distance; the lattice spacing ``cell`` defaults to it.
        cell: lattice spacing (0 = d_cover). cell * sqrt(2) + arrive_tolerance must stay
            within the class's min_probe_range (9).
        d_min: spacing of the start formation (gradients and hops relay within 1.5 * d_min).
        v: speed (paper Table 2: 0.1 per tick).
        turn: +1: S is P turned counter-clockwise; -1: clockwise.
        queue_gap: a queued robot stops when another robot is this close ahead.
        door_depth: the door robot steps in until this much target floor lies behind it (so
            the robots entering can pass it), units (<= 2, the engine's probe range).
        door_radius: a queued robot this close to the door may enter.
        entry_clearance: a robot enters only when no moving robot is this close to the door
            (0 = 1.5 * cell: the previous one has left the entry cell).
        arrive_tolerance: a moving robot has reached a cell centre within this distance.
        avoid_range: a moving robot side-steps robots this close ahead.
        patience: a moving robot that has waited this many ticks settles where it is.
        init_timeout: a robot that has heard no gradient after this many ticks queues.
    """

    d_safe: float = 1.0
    d_cover: float = 6.0
    cell: float = 0.0
    d_min: float = 1.0
    v: float = 0.1
    turn: int = -1
    queue_gap: float = 0.95
    door_depth: float = 2.0
    door_radius: float = 2.5
    entry_clearance: float = 0.0
    arrive_tolerance: float = 0.1
    avoid_range: float = 1.2
    patience: int = 400
    init_timeout: int = 400

    def __post_init__(self) -> None:
        require_positive(self, "d_safe", "d_cover", "d_min", "v", "queue_gap", "door_depth",
                         "door_radius", "arrive_tolerance", "avoid_range", "patience",
                         "init_timeout")
        if self.cell < 0 or self.entry_clearance < 0:
            raise ValueError("cell and entry_clearance must be >= 0 (0 = default)")
        if self.turn not in (1, -1):
            raise ValueError(f"turn must be 1 or -1, got {self.turn!r}")
        if self.spacing * math.sqrt(2) + self.arrive_tolerance > MIN_PROBE_RANGE:
            raise ValueError(f"cell ({self.spacing}) too large: its diagonal must be within the "
                             f"probe range the controller requests ({MIN_PROBE_RANGE})")
        if self.spacing + self.door_radius > MIN_PROBE_RANGE:
            raise ValueError("cell + door_radius must be within the probe range "
                             f"({MIN_PROBE_RANGE})")

    @property
    def spacing(self) -> float:
        """The lattice spacing in use."""
        return self.cell if self.cell > 0 else self.d_cover

    @property
    def clearance(self) -> float:
        return self.entry_clearance if self.entry_clearance > 0 else 1.5 * self.spacing


class FCDFSDeclarations:
    """What both FCDFS classes declare (controller API): the name, parameters, statuses,
    broadcasts and sensing."""

    name = "fcdfs"
    Params = FCDFSParams
    STATUSES = STATUSES
    SETTLED_STATUSES = ("Settled",)  # done, standing still (collision instruments)
    MESSAGE_FIELDS = MESSAGE_FIELDS
    SILENT = SILENT
    COLOURINGS = COLOURINGS
    LEADER_FIELD = "leader"
    GROUP_FIELD = "group"
    default_start = "formation"
    requires_beacon = True
    min_probe_range = MIN_PROBE_RANGE

    @classmethod
    def sensing_range(cls, params: FCDFSParams) -> float:
        return max(2 * params.spacing, params.clearance + params.door_radius + 0.5)
