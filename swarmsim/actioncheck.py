"""The engine's checks of what a controller hands it: Actions, ChunkActions and broadcasts.

Everything a controller returns is checked where the engine receives it, before the run uses
it (the contract: docs/input-checks.md, "A controller's mistakes"). A problem raises
:class:`BadAction` naming the row of the chunk; :func:`blame` turns it, or an exception the
controller raised, into a :class:`~swarmsim.errors.ControllerError` naming the controller,
the robot and the tick.

What it costs: a batch controller's dense columns (GGC's) are checked by their shapes and
dtypes (a few attribute reads a chunk), their values inside the compiled passes that write
them (swarmsim.tickrows: finite velocities, listening and wake ranges not negative, status
codes in range); a list of Actions with one vectorised pass per column, and robot by robot
only to name the robot once a column is found wrong.
"""

from __future__ import annotations

import functools
import math
import numbers
import reprlib
from collections.abc import Mapping, Sequence
from dataclasses import dataclass
from typing import Any

import numpy as np

from swarmsim.controller import Action, ChunkActions
from swarmsim.errors import ControllerError, raised

LEGACY_FIELDS = ("gradient", "group", "leader")
"""Base broadcast fields of earlier versions, third to fifth in a tuple: a controller that
still sends them (``(id, status, gradient, group, leader, moving, ...)``) keeps working, and
they are dropped."""

BOOLS = frozenset({bool, np.bool_})
"""The types a flag (``sleep``, ``wake_on_motion``) may have."""

_short = reprlib.Repr()
_short.maxstring = _short.maxother = 40
_short.maxlevel, _short.maxtuple, _short.maxlist, _short.maxdict = 2, 6, 6, 4


class BadAction(Exception):
    """What a controller returned breaks the controller API.

    Attributes:
        row: the row of the chunk (robot ``robots[row]``), or None when no one robot's.
        problem: what it returned and what was expected, to follow "step() returned", e.g.
            "a velocity of shape (3,); expected (vx, vy)".
    """

    def __init__(self, row: int | None, problem: str):
        self.row, self.problem = row, problem
        super().__init__(problem)


def show(value: Any) -> str:
    """A short one-line repr of ``value`` (with its type where the repr hides it)."""
    text = " ".join(_short.repr(value).split())
    if isinstance(value, (str, bytes, tuple, list, dict, np.ndarray)) or value is None:
        return text
    if isinstance(value, (bool, int, float)):
        return text
    return f"{text} (a {type(value).__name__})"


def blame(exc: Exception, controller: str, call: str, tick: int | None,
          robots: Sequence[int] | np.ndarray | None = None) -> ControllerError:
    """The ControllerError of ``exc``: raised by the controller's ``call`` (e.g. "step()"),
    or a BadAction of what it returned (its row: robot ``robots[row]``), or a ControllerError
    that lacks the controller's name. Its ``__cause__`` is the controller's own exception
    (None for a BadAction): ``raise blame(...)`` shows that one, not the engine's."""
    cause: BaseException | None
    if isinstance(exc, BadAction):
        robot = None if exc.row is None or robots is None else int(robots[exc.row])
        error = ControllerError(f"{call} returned {exc.problem}", controller=controller,
                                robot=robot, tick=tick)
        cause = None
    elif isinstance(exc, ControllerError):
        error, cause = exc.where(controller, tick), exc.__cause__
    else:
        error, cause = ControllerError(raised(call, exc), controller=controller, tick=tick), exc
    error.__cause__ = cause  # also suppresses the context: the engine's frames are not shown
    return error


# ----------------------------------------------------------------------------- Actions
def columns_of(actions: Sequence[Any], robots: int) -> ChunkActions:
    """The checked columns (sparse form) of a chunk's ``robots`` Actions. Velocities are
    checked here for their shape and type; that they are finite, and that ``listen`` is not
    negative, by the compiled pass that writes them (:func:`move_problem`); broadcasts by
    :class:`Broadcasts`. Raises BadAction."""
    if len(actions) != robots:
        raise BadAction(None, f"{len(actions)} actions for a chunk of {robots} robots")
    if robots and set(map(type, actions)) != {Action}:
        for k, action in enumerate(actions):
            if not isinstance(action, Action):
                raise BadAction(k, f"{show(action)}; expected an Action")
    velocities = _velocities([a.velocity for a in actions])
    listen = _distances([a.listen for a in actions], "listen")
    sleeps = [a.sleep for a in actions]
    if robots and not set(map(type, sleeps)) <= BOOLS:
        k = next(k for k, s in enumerate(sleeps) if type(s) not in BOOLS)
        raise BadAction(k, f"sleep={show(sleeps[k])}; expected True or False")
    sleepers = {k: actions[k] for k, s in enumerate(sleeps) if s}
    if sleepers and not _sleepers_fit(list(sleepers.values())):
        for k, action in sleepers.items():
            problem = sleep_problem(action)
            if problem:
                raise BadAction(k, problem)
    messages = {k: a.message for k, a in enumerate(actions) if a.message is not None}
    return ChunkActions(velocities, listen, messages, sleepers)


def action_problem(action: Any) -> str | None:
    """What is wrong with one robot's Action (None: nothing); its broadcast's values are
    checked when it is written (:class:`Broadcasts`)."""
    if not isinstance(action, Action):
        return f"{show(action)}; expected an Action"
    velocity = _velocity_problem(action.velocity)
    if velocity:
        return velocity
    if not _is_distance(action.listen):
        return listen_problem(action.listen)
    if type(action.sleep) not in BOOLS:
        return f"sleep={show(action.sleep)}; expected True or False"
    if action.message is not None and not isinstance(action.message, (tuple, Mapping,
                                                                         np.void)):
        return _message_type_problem(action.message)
    return sleep_problem(action) if action.sleep else None


def sleep_problem(action: Action) -> str | None:
    """What is wrong with a sleeping robot's promises (None: nothing)."""
    if not _is_distance(action.wake_range):
        return (f"wake_range={show(action.wake_range)}; expected a distance >= 0, units "
                "(None: the sensing range)")
    if type(action.wake_on_motion) not in BOOLS:
        return f"wake_on_motion={show(action.wake_on_motion)}; expected True or False"
    tick = action.wake_tick
    if tick is not None and not (_is_integer(tick) and tick >= 0):
        return f"wake_tick={show(tick)}; expected a tick: an integer >= 0 (None: no timeout)"
    return None


def _sleepers_fit(sleepers: list[Action]) -> bool:
    """Whether no sleeper's promises have a problem (sleep_problem), a column at a time."""
    ranges = [a.wake_range for a in sleepers]
    if ranges.count(None) != len(ranges):
        if not all(t is type(None) or _real_type(t) for t in set(map(type, ranges))):
            return False
        try:
            given = np.array([np.nan if r is None else r for r in ranges], dtype=float)
        except OverflowError:
            return False
        if np.count_nonzero(np.isnan(given)) != ranges.count(None) or (given < 0).any():
            return False
    if not set(map(type, (a.wake_on_motion for a in sleepers))) <= BOOLS:
        return False
    ticks = [a.wake_tick for a in sleepers if a.wake_tick is not None]
    return not ticks or (set(map(type, ticks)) <= _TICK_TYPES and min(ticks) >= 0)


_TICK_TYPES = frozenset({int, np.int64, np.int32})
"""The types of a wake_tick checked a column at a time (others, one by one)."""


def move_problem(velocity: np.ndarray, listen: float) -> str:
    """Why the compiled pass refused a robot's move: (2,) velocity, units per tick, not
    finite, or a negative ``listen`` (units)."""
    if not np.isfinite(velocity).all():
        return (f"the velocity ({float(velocity[0])!r}, {float(velocity[1])!r}); expected finite numbers "
                "(vx, vy), units per tick")
    return listen_problem(float(listen))


def listen_problem(value: Any) -> str:
    return f"listen={show(value)}; expected a distance >= 0, units (None: the sensing range)"


def wake_range_problem(value: float) -> str:
    return f"wake_range={float(value)!r}; expected a distance >= 0, units (NaN: the sensing range)"


def _velocities(values: list) -> np.ndarray:
    """(R, 2) float velocities from R Actions' (BadAction naming the first that is not two
    numbers; finiteness is checked where they are written)."""
    try:
        v = np.array(values)
    except (ValueError, TypeError, OverflowError):
        v = None
    if v is not None and v.shape == (len(values), 2) and v.dtype.kind in "iuf":
        return v.astype(float, copy=False)
    for k, value in enumerate(values):
        problem = _velocity_problem(value)
        if problem:
            raise BadAction(k, problem)
    return np.array(values, dtype=float).reshape(-1, 2)  # pragma: no cover - each row fits


def _velocity_problem(value: Any) -> str | None:
    """What is wrong with one robot's velocity (None: nothing)."""
    try:
        v = np.asarray(value)
    except (ValueError, TypeError, OverflowError):
        v = None
    if v is None or v.dtype.kind not in "iuf":
        return f"the velocity {show(value)}; expected two numbers (vx, vy), units per tick"
    if v.shape != (2,):
        return f"a velocity of shape {v.shape}; expected (vx, vy), units per tick"
    if not np.isfinite(v).all():
        return f"the velocity {show(value)}; expected finite numbers (vx, vy), units per tick"
    return None


def _distances(values: list, name: str) -> np.ndarray:
    """(R,) float distances, NaN for None, from R Actions' ``name`` (BadAction naming the first
    that is neither None nor a number, or is NaN; a negative one is refused where it is
    written)."""
    nones = values.count(None)
    if nones == len(values):
        return np.full(len(values), np.nan)
    if not nones:  # numbers only (numpy finds their type: text and bools are not numbers)
        try:
            out = np.array(values)
        except (ValueError, TypeError, OverflowError):
            out = None
        if (out is not None and out.dtype.kind in "iuf" and out.shape == (len(values),)
                and not np.isnan(out).any()):
            return out.astype(float, copy=False)
    elif all(t is type(None) or _real_type(t) for t in set(map(type, values))):
        try:
            out = np.array([np.nan if x is None else x for x in values], dtype=float)
        except OverflowError:
            out = None
        if out is not None and np.count_nonzero(np.isnan(out)) == nones:
            return out
    k = next(k for k, x in enumerate(values) if not _is_distance(x, negative=True))
    raise BadAction(k, listen_problem(values[k]) if name == "listen" else
                    f"{name}={show(values[k])}; expected a distance >= 0, units")


def _real_type(t: type) -> bool:
    return issubclass(t, numbers.Real) and not issubclass(t, (bool, np.bool_))


def _is_distance(value: Any, negative: bool = False) -> bool:
    """None, or a real number that is not NaN and (unless ``negative``) not negative."""
    if value is None:
        return True
    if not _real_type(type(value)):
        return False
    try:
        number = float(value)
    except (OverflowError, ValueError):
        return False
    return not math.isnan(number) and (negative or number >= 0)


def _is_integer(value: Any) -> bool:
    return isinstance(value, numbers.Integral) and not isinstance(value, (bool, np.bool_))


def _message_type_problem(message: Any) -> str:
    return (f"the broadcast {show(message)}; expected a tuple in the order of the run's "
            "message fields or a dict by field name (None: repeat the last)")


# ----------------------------------------------------------------------------- ChunkActions
_DENSE = (("sleep", "b"), ("wake_range", "iuf"), ("wake_on_motion", "b"), ("wake_tick", "iu"))
"""The dense form's sleep columns, and the dtype kinds each may have."""


def check_columns(actions: ChunkActions, robots: int, dtype: np.dtype) -> None:
    """Check the form of a chunk's ChunkActions (``robots`` rows; broadcasts in the run's
    message ``dtype``): every column an array of one row per robot, of a fitting dtype.
    Their values are checked where they are written. Raises BadAction."""
    if actions.broadcast is not None and _dense_fits(actions, robots, dtype):
        return  # the usual case, in a few attribute reads
    _column_form(actions.velocities, "velocities", (robots, 2), "iuf")
    _column_form(actions.listen, "listen", (robots,), "iuf")
    if actions.broadcast is not None:
        _column_form(actions.broadcast, "broadcast", (robots,), "V")
        if actions.broadcast.dtype.names != dtype.names:
            raise BadAction(None, f"broadcast rows with the fields {actions.broadcast.dtype.names}"
                                  f"; expected the run's message fields {dtype.names}")
        for name, kinds in _DENSE:
            _column_form(getattr(actions, name), name, (robots,), kinds)
        return
    for name in ("messages", "sleepers"):
        rows = getattr(actions, name)
        if rows and not all(_is_integer(k) and 0 <= k < robots for k in rows):
            bad = next(k for k in rows if not (_is_integer(k) and 0 <= k < robots))
            raise BadAction(None, f"{name} for the row {show(bad)} of a chunk of {robots} "
                                  "robots (rows 0 to R - 1)")
    for k, action in actions.sleepers.items():
        problem = action_problem(action)
        if problem:
            raise BadAction(k, problem)


def _dense_fits(a: ChunkActions, robots: int, dtype: np.dtype) -> bool:
    """Whether the dense form's columns have their shapes and dtypes (check_columns, fast)."""
    try:
        v, one = a.velocities, (robots,)
        kinds = (v.dtype.kind + a.listen.dtype.kind + a.wake_range.dtype.kind
                 + a.sleep.dtype.kind + a.wake_on_motion.dtype.kind + a.wake_tick.dtype.kind)
        return (v.shape == (robots, 2) and kinds in _DENSE_KINDS
                and one == a.listen.shape == a.broadcast.shape == a.sleep.shape
                == a.wake_range.shape == a.wake_on_motion.shape == a.wake_tick.shape
                and a.broadcast.dtype.names == dtype.names and isinstance(v, np.ndarray))
    except (AttributeError, TypeError):  # not arrays: check_columns names the column
        return False


_DENSE_KINDS = frozenset(v + listen + wake + "bb" + tick for v in "iuf" for listen in "iuf"
                         for wake in "iuf" for tick in "iu")
"""The dtype kinds of the dense columns velocities, listen, wake_range, sleep, wake_on_motion
and wake_tick that check_columns accepts (_DENSE), as one string."""


def _column_form(column: Any, name: str, shape: tuple[int, ...], kinds: str) -> None:
    if not isinstance(column, np.ndarray):
        raise BadAction(None, f"{name} {show(column)}; expected a numpy array of shape {shape}")
    if column.shape != shape or column.dtype.kind not in kinds:
        raise BadAction(None, f"{name} of shape {column.shape} and dtype {column.dtype}; "
                              f"expected shape {shape}, one row per robot of the chunk, and "
                              f"dtype kind {' or '.join(kinds)}")


# ----------------------------------------------------------------------------- broadcasts
@dataclass(frozen=True)
class Broadcasts:
    """A run's broadcasts as controllers give them: tuples in the order of the run's message
    ``dtype``, dicts by field name (missing fields zero), or rows of that dtype.

    ``id`` is the engine's: whatever a broadcast holds there is replaced by the sender's
    own id when it is written (swarmsim.tickrows.sign_rows), so no robot can speak as another.
    Every other value must fit its field as given: a bool field takes True or False (or 0, 1),
    an integer field whole numbers in its range, a float field numbers its precision can hold
    (NaN and inf are the controller's business); ``status`` must be an index into STATUSES.

    Attributes:
        dtype: the run's message dtype.
        statuses: the controller's STATUSES.
    """

    dtype: np.dtype
    statuses: tuple[str, ...]

    @property
    def width(self) -> int:
        return len(self.dtype.names)

    def array(self, rows: Sequence[Any]) -> np.ndarray:
        """(len(rows),) rows of the run's dtype from broadcasts (``id`` zero: the engine writes
        it). Raises BadAction naming the index into ``rows`` of the first that does not fit."""
        if not rows:
            return np.zeros(0, dtype=self.dtype)
        columns = self._columns(rows) if set(map(type, rows)) == {tuple} else None
        if columns is None:  # not all plain tuples of the run's width
            columns = self._columns([self._positional(k, row) for k, row in enumerate(rows)])
        out = np.zeros(len(rows), dtype=self.dtype)
        for name, column in zip(self.dtype.names, columns, strict=True):
            if name == "id":
                continue
            values = _field_values(self.dtype[name], column)
            if values is None:
                values = self._diagnosed(name, column)
            out[name] = values
        return out

    def _columns(self, rows: Sequence[tuple]) -> list[tuple] | None:
        """The columns of tuples all of the run's width, else None."""
        try:
            columns = list(zip(*rows, strict=True))
        except ValueError:  # tuples of different lengths
            return None
        return columns if len(columns) == self.width else None

    def status_problem(self, status: Any) -> str:
        """The problem of a broadcast whose status code is ``status``."""
        return f"a broadcast whose status is {show(status)}; expected {self._status_expected()}"

    def _status_expected(self) -> str:
        return (f"a status code: an integer in 0..{len(self.statuses) - 1}, the index of one "
                f"of STATUSES {self.statuses}")

    def _positional(self, k: int, row: Any) -> tuple:
        """A broadcast as a tuple in the dtype's order (BadAction for row ``k``)."""
        names, width = self.dtype.names, self.width
        if isinstance(row, tuple):
            if len(row) == width:
                return row
            if len(row) == width + len(LEGACY_FIELDS):
                return (*row[:2], *row[5:])  # the old base fields: gradient, group, leader
            raise BadAction(k, f"a broadcast tuple of {len(row)} values; expected {width}: "
                               f"({', '.join(names)})")
        if isinstance(row, Mapping):
            unknown = [name for name in row if name not in names]
            if unknown:
                raise BadAction(k, f"a broadcast naming the unknown fields {show(unknown)}; "
                                   f"the run's fields are {list(names)}")
            return tuple(row[name] if name in row else np.zeros((), self.dtype[name])[()]
                         for name in names)
        if isinstance(row, np.void) and row.dtype.names == names:
            return tuple(row[name] for name in names)
        raise BadAction(k, _message_type_problem(row))

    def _diagnosed(self, name: str, column: Sequence[Any]) -> np.ndarray:
        """The values of field ``name`` checked one by one: BadAction for the first that does
        not fit (else, a column that fits only row by row, its values)."""
        field = self.dtype[name]
        for k, value in enumerate(column):
            if _field_values(field, [value]) is None:
                expected = self._status_expected() if name == "status" else _expected(field)
                raise BadAction(k, f"a broadcast whose {name} is {show(value)}; expected "
                                   f"{expected}")
        return np.concatenate([_field_values(field, [value]) for value in column])


_PLAIN = {"b": frozenset({bool}), "i": frozenset({int, bool}), "u": frozenset({int, bool}),
          "f": frozenset({float, int, bool, np.float64, np.float32})}
"""Per kind of field, the types of values that numpy converts to it exactly or refuses
(OverflowError), but for a float too large for a narrower float field (checked)."""


def _field_values(field: np.dtype, column: Sequence[Any]) -> np.ndarray | None:
    """A field's values as a numpy array of shape (len(column), *field.shape), or None
    when one does not fit the field as given (see Broadcasts)."""
    plain = None if field.shape else _PLAIN.get(field.kind)
    if plain is not None and set(map(type, column)) <= plain:  # the usual case, fast
        try:
            if field.kind == "f":
                with np.errstate(over="ignore"):  # a float too large: inf, refused below
                    values = np.fromiter(column, dtype=field, count=len(column))
            else:
                values = np.fromiter(column, dtype=field, count=len(column))
        except OverflowError:
            return None
        if field.kind != "f" or np.isfinite(values).all():
            return values
    try:
        values = np.asarray(column)
    except (ValueError, TypeError, OverflowError):
        return None
    if values.shape != (len(column), *field.shape) or not _fits(field.base, values):
        return None
    return values


def _fits(base: np.dtype, values: np.ndarray) -> bool:
    """Whether every one of ``values`` is a value of a field of dtype ``base`` as given:
    nothing rounded, wrapped or parsed from text."""
    have, want = values.dtype.kind, base.kind
    if want == "b":
        return have == "b" or (have in "iu" and bool(((values == 0) | (values == 1)).all()))
    if want in "iu":
        if have == "b":
            return True
        if have == "f":
            if not (np.isfinite(values).all() and (values == np.trunc(values)).all()):
                return False
        elif have not in "iu":
            return False
        low, high = _int_range(base)
        return values.size == 0 or bool(values.min() >= low and values.max() <= high)
    if want == "f":
        if have in "biu" or (have == "f" and values.dtype.itemsize <= base.itemsize):
            return True
        if have != "f":
            return False
        try:  # a finite value too large for the field would become inf
            with np.errstate(over="raise"):
                values.astype(base)
        except FloatingPointError:
            return False
        return True
    try:
        values.astype(base, casting="same_kind")
    except (TypeError, ValueError):
        return False
    return True


@functools.cache
def _int_range(base: np.dtype) -> tuple[int, int]:
    """The least and the greatest value of an integer dtype."""
    info = np.iinfo(base)
    return int(info.min), int(info.max)


def _expected(field: np.dtype) -> str:
    base = field.base
    if base.kind == "b":
        kind = "True or False"
    elif base.kind in "iu":
        info = np.iinfo(base)
        kind = f"an integer in {info.min}..{info.max} ({base})"
    elif base.kind == "f":
        kind = f"a number within {base}'s range (magnitude <= {np.finfo(base).max:.4g})"
    else:
        kind = f"a value of dtype {base}"
    return f"{field.shape} values, each {kind}" if field.shape else kind


__all__ = ["BOOLS", "LEGACY_FIELDS", "BadAction", "Broadcasts", "action_problem", "blame",
           "check_columns", "columns_of", "move_problem", "show", "sleep_problem"]
