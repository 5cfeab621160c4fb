"""GGC's data, declared once: one row per datum of a robot's state and of its broadcast.

A :class:`Datum` names one value everywhere: the field of a robot's state row (``me.NAME``;
a per-group datum: of its per-group rows, ``mine.NAME[g]``), of its broadcast (when it is
broadcast) and of a rule's view of its neighbours (``view.NAME[r]``). From :data:`DATA` come
the state's dtype (state.py), the per-group arrays (:data:`PER_GROUP`), the broadcast's
fields (:func:`message_fields`, :data:`BROADCAST_NAMES`), the view's fields
(:data:`VIEW_FIELDS`, rules/common.py) and the compiled code that copies them by name
(_generated.py: the broadcast fill, the driver's view of a robot's neighbours). numba sets
a field only by a name written in the source, so that code is written from this table by
:func:`generated_source`; a test fails when _generated.py is not current. Regenerate:

    python controllers/ggc/schema.py

(a script, so that it runs without importing the package, which imports _generated.py).

Adding a broadcast field is one row here (``broadcast`` set) plus its use in a rule.
"""

from __future__ import annotations

import sys
from collections import namedtuple
from dataclasses import dataclass
from pathlib import Path

from controllers.common.gradient import INF_GRADIENT
from swarmsim.controller import BASE_MESSAGE_FIELDS, NO_SENDER

NO_WAY_SLOTS = 8
"""How many arrived robots a mover remembers having found no way in beside."""
BAN_SLOTS = 4
"""How many sites found off the target a mover remembers (rules/flow.py)."""
NO_HOLE = 127
"""Hops broadcast by a robot that knows of no hole."""
FAR = 1e9
"""Field distance of a leader not heard of yet (units)."""

BASE = "base"
"""``Datum.broadcast`` of a field the engine's base broadcast holds (id, status)."""


@dataclass(frozen=True)
class Datum:
    """One value of a robot's state.

    Attributes:
        name: its one name (state row, broadcast and view field).
        state: numpy dtype of the state field.
        meaning: what it is (units: lengths, ticks, radians).
        broadcast: numpy dtype of the broadcast field (the state's value cast to it), None
            when the robot keeps it to itself, :data:`BASE` for the engine's base fields.
        shape: entries of an array field (0: a scalar).
        per_group: one entry per group of a run that starts scattered, else none (formations
            never read them): not in the state row but in a (robots, groups) array beside it
            (:data:`PerGroup`), so that neither a row's size nor its numba type depends on
            the run's groups (one compiled driver for any count); in a broadcast, as many.
        initial: a new row's value (state.new_state sets the values a robot's setup decides).
        silent: what a neighbour that is not heard reads as, if not zero.
    """

    name: str
    state: str
    meaning: str
    broadcast: str | None = None
    shape: int = 0
    per_group: bool = False
    initial: float | int | bool = 0
    silent: int | None = None

    def state_field(self) -> tuple:
        """The field in the state's dtype (not for a per-group datum: :data:`PerGroup`)."""
        if self.per_group:
            raise ValueError(f"{self.name} is per group: not a field of the state row")
        return (self.name, self.state, (self.shape,)) if self.shape else (self.name, self.state)

    def broadcast_field(self, groups: int, scattered: bool) -> tuple:
        """The field in the broadcast dtype of a run with ``groups`` groups."""
        if self.per_group:
            return (self.name, self.broadcast, (groups if scattered else 0,))
        return (self.name, self.broadcast)


D = Datum
DATA: tuple[Datum, ...] = (
    # who I am, what I broadcast
    D("id", "i4", "my id", BASE),
    D("group", "i2", "my group (0: none yet)", "i2"),
    D("leader", "?", "I lead my group's formation", "?"),
    D("status", "i1", "my status (statuses.py)", BASE),
    D("visited", "u2", "bit s set once I have had status s"),
    D("gradient", "i4", "hops from my group's leader (INF_GRADIENT: none heard)", "i4",
      silent=INF_GRADIENT),
    D("cmd", "i1", "my formation's command (rules/travel.py: CMD_*)", "i1"),
    D("travel_x", "f8", "my formation's travel direction, x", "f4"),
    D("travel_y", "f8", "my formation's travel direction, y", "f4"),
    D("touch", "?", "my formation touched the target", "?"),
    D("stepped", "?", "I stepped onto the target", "?"),
    D("enclosed", "?", "waiting robots round me leave no way out", "?"),
    D("blocked", "i1", "the side my formation turns aside to (0: none; rules/aside.py)", "i1"),
    # travel: the route my formation took (it decides my group's orbit sense)
    D("route_x", "f8", "the route my formation took, x"),
    D("route_y", "f8", "the route my formation took, y"),
    D("has_route", "?", "route_x, route_y are known"),
    D("orbit_chosen", "?", "my orbit sense is chosen"),
    D("initial_since", "i8", "tick I entered Initial"),
    D("gradient_low", "i4", "lowest gradient I had while travelling (rules/aside.py)"),
    D("no_gradient", "?", "my gradient is lost (failure mode no_gradient): I take none from "
      "my formation until I set off to cover (rules/gradient.py)"),
    # edge following
    D("sense", "f8", "my orbit sense: +1 counter-clockwise, -1 clockwise"),
    D("head_x", "f8", "my heading, x"),
    D("head_y", "f8", "my heading, y"),
    D("stepping", "?", "I am stepping onto the target's boundary"),
    D("no_way", "i4", "arrived robots I found no way in beside", shape=NO_WAY_SLOTS,
      initial=NO_SENDER),
    D("no_way_next", "i8", "tick I forget no_way"),
    # circling and progress (Equation 3), deadlocks
    D("circ_id", "i4", "the robot I circle", initial=NO_SENDER),
    D("circled", "f8", "how far I circled it (radians)"),
    D("last_bearing", "f8", "my last bearing to it", initial=float("nan")),
    D("odo_x", "f8", "my odometry, x"),
    D("odo_y", "f8", "my odometry, y"),
    D("progress_tick", "i8", "tick of my last progress sample"),
    D("resume_tick", "i8", "tick I resume after a deadlock"),
    D("deadlocks", "i4", "deadlocks detected"),
    D("episodes", "i4", "deadlock episodes"),
    D("in_deadlock", "?", "a deadlock episode is open"),
    D("yield_count", "i4", "ticks I yielded"),
    D("collision_stops", "i4", "Stops for other groups' movers"),
    # islands off the target (rules/island.py)
    D("turned", "f8", "my heading's turn since the target floor (radians)"),
    D("leaving", "?", "I leave an island for the beacon"),
    # confined without a place (rules/confined.py)
    D("roam_ticks", "i8", "ticks searching within the reach"),
    D("roam_x", "f8", "displacement meanwhile, x"),
    D("roam_y", "f8", "displacement meanwhile, y"),
    D("roam_seen", "i4", "the most arrived robots heard meanwhile"),
    # the surplus lap
    D("away", "?", "out of hearing of my group's waiting robots"),
    D("frontier", "f8", "path walked on the target with target floor outward"),
    D("lap_whole", "?", "my lap went round the beacon", initial=True),
    D("winding", "f8", "my bearing to the beacon's turn (radians)"),
    D("beacon_angle", "f8", "my last bearing to the beacon", initial=float("nan")),
    D("surplus", "i4", "I gave up after a surplus lap"),
    # the scattered start
    D("h", "i1", "leader hand-over hops left (Algorithm 3)", "i1"),
    D("handover", "i4", "the robot I hand my leadership to", "i4", initial=NO_SENDER),
    D("handover_tick", "i8", "tick of my hand-over", initial=-1),
    D("quiet", "i4", "ticks since I heard my group still gathering", "i4"),
    D("ldist", "f8", "field distance to each group's leader (units)", "f4", per_group=True,
      initial=FAR),
    D("lepoch", "i8", "each group's leader's epoch", "i4", per_group=True),
    # holes inside the structure (rules/holes.py)
    D("hole", "i1", "hops to the nearest hole I know of", "i1", initial=NO_HOLE),
    D("hole_x", "f8", "the hole's offset from me, x (units)", "f4"),
    D("hole_y", "f8", "the hole's offset from me, y (units)", "f4"),
    D("seen_x", "f8", "where I saw a hole, x"),
    D("seen_y", "f8", "where I saw a hole, y"),
    D("seen_since", "i8", "tick I saw it", initial=-1),
    D("hole_rest", "i8", "tick I next look for holes"),
    D("path", "f8", "path walked (units)"),
    # crossings of the structure (rules/cross.py)
    D("crossing", "?", "I cross the structure"),
    D("cross_from", "f8", "path at the crossing's start"),
    D("cross_after", "f8", "path at which the next crossing may start"),
    # walking through the structure (rules/flow.py)
    D("flow_rest", "f8", "path at which I look for a way through again"),
    D("ban_x", "f8", "sites I found off the target, x (relative to me)", shape=BAN_SLOTS),
    D("ban_y", "f8", "sites I found off the target, y (relative to me)", shape=BAN_SLOTS),
    D("ban_next", "i8", "sites I found off the target so far"),
    # my own random stream (xorshift64*)
    D("rng", "u8", "my random stream's state"),
)
"""Every datum of a GGC robot, in the state's order (broadcast fields in the same order)."""
del D

STATE_FIELDS: list[tuple] = [datum.state_field() for datum in DATA if not datum.per_group]
"""The state's dtype spec (state.STATE_DTYPE): every datum but the per-group ones."""
PER_GROUP: tuple[Datum, ...] = tuple(d for d in DATA if d.per_group)
"""The per-group data, in DATA's order (one (robots, groups) array each, state.py)."""
PerGroup = namedtuple("PerGroup", [d.name for d in PER_GROUP])
"""Per-group values by name (:data:`PER_GROUP`): the run's (robots, groups) arrays, or one
robot's rows of them (``mine`` in the rules: ``mine.ldist[g]``)."""
BROADCAST: tuple[Datum, ...] = tuple(d for d in DATA if d.broadcast not in (None, BASE))
"""GGC's own broadcast fields (after the engine's base fields)."""
BASE_NAMES = tuple(name for name, _ in BASE_MESSAGE_FIELDS)
"""The engine's base broadcast fields (id, status, moving)."""
BROADCAST_NAMES = (*BASE_NAMES, *(d.name for d in BROADCAST))
"""The fields of a GGC broadcast (the engine's base fields first), in the dtype's order."""
VIEW_FIELDS = ("off", "dist", *BROADCAST_NAMES)
"""A rule's view of its neighbours: offsets (k, 2) and distances (k,), then the columns of
their last broadcasts."""
HEARD_FIELDS = ("starts", *VIEW_FIELDS)
"""A chunk's heard columns: each robot's first row, then the view's columns."""
SILENT = {d.name: d.silent for d in BROADCAST if d.silent is not None}
"""What a neighbour that is not heard reads as (fields not named: zero)."""


def message_fields(groups: int, scattered: bool) -> list[tuple]:
    """GGC's broadcast fields for a run with ``groups`` groups (per-group fields: one entry
    per group when the robots start ``scattered``, else none: formations never read them,
    and every broadcast a robot hears is copied once a tick, so 80 bytes more of them per
    row (10 groups) cost time on every tick)."""
    return [d.broadcast_field(groups, scattered) for d in BROADCAST]


def _missing_base() -> list[str]:
    """Base broadcast fields the state does not hold (filled by hand: ``moving``)."""
    return [name for name in BASE_NAMES if name not in {d.name for d in DATA}]


GENERATED = Path(__file__).with_name("_generated.py")
"""The generated module."""
REGENERATE = "python controllers/ggc/schema.py"
"""The command that writes it."""


def generated_source() -> str:
    """The source of _generated.py, written from :data:`DATA`."""
    copied = [d for d in DATA if d.broadcast is not None]
    lines = [
        '"""Written by controllers/ggc/schema.py from its DATA: do not edit.',
        "",
        f"Regenerate: {REGENERATE}",
        '(tests/controllers/ggc/test_ggc_schema.py fails while this file is not current)."""',
        "",
        "from __future__ import annotations",
        "",
        "from numba import njit",
        "",
        "from .borrow import borrowed",
        "from .heard import Heard",
        "from .rules.common import View",
        "from .schema import PerGroup",
        "",
        "",
        '@njit(inline="always")',
        "def borrow_heard(heard):  # pragma: no cover - compiled",
        '    """``heard`` (a Heard of the driver\'s arguments) with borrowed columns."""',
        "    return Heard(",
        *(f"        borrowed(heard.{n})," for n in HEARD_FIELDS),
        "    )",
        "",
        "",
        '@njit(inline="always")',
        "def empty_view(heard):  # pragma: no cover - compiled",
        '    """A View of no neighbours, of the types of ``heard``\'s columns."""',
        "    return View(",
        *(f"        heard.{n}[:0]," for n in VIEW_FIELDS),
        "    )",
        "",
        "",
        '@njit(inline="always")',
        "def point_view(view, heard, a, b):  # pragma: no cover - compiled",
        '    """Point ``view`` at rows ``a:b`` of ``heard``\'s columns."""',
        *(f"    view.{n} = heard.{n}[a:b]" for n in VIEW_FIELDS),
        "",
        "",
        '@njit(inline="always")',
        "def borrow_per_group(values):  # pragma: no cover - compiled",
        '    """``values`` (a PerGroup of the driver\'s arguments) with borrowed arrays."""',
        "    return PerGroup(",
        *(f"        borrowed(values.{d.name})," for d in PER_GROUP),
        "    )",
        "",
        "",
        '@njit(inline="always")',
        "def group_rows(values, i):  # pragma: no cover - compiled",
        '    """Robot ``i``\'s rows of the PerGroup arrays ``values`` (views)."""',
        "    return PerGroup(",
        *(f"        values.{d.name}[i]," for d in PER_GROUP),
        "    )",
        "",
        "",
        '@njit(inline="always")',
        "def copy_group_rows(source, a, target, b):  # pragma: no cover - compiled",
        '    """Copy row ``a`` of the PerGroup arrays ``source`` into row ``b`` of ``target``."""',
        *(f"    target.{d.name}[b, :] = source.{d.name}[a, :]" for d in PER_GROUP),
        "",
        "",
        '@njit(inline="always")',
        "def copy_broadcast(me, mine, msg):  # pragma: no cover - compiled",
        '    """Copy the broadcast fields of state row ``me`` and per-group rows ``mine`` (a',
        "    PerGroup) into broadcast ``msg`` (cast to the broadcast's types; "
        + ", ".join(_missing_base()) + ': not here)."""',
    ]
    for d in copied:
        if d.per_group:
            lines += [f"    for g in range(msg.{d.name}.shape[0]):",
                      f"        msg.{d.name}[g] = mine.{d.name}[g]"]
        else:
            lines.append(f"    msg.{d.name} = me.{d.name}")
    return "\n".join(lines) + "\n"


def write_generated() -> None:
    """Write _generated.py from :data:`DATA`."""
    GENERATED.write_text(generated_source())
    print(f"wrote {GENERATED}", file=sys.stderr)


if __name__ == "__main__":
    write_generated()
