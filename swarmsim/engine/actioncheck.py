"""The engine's checks of what a controller hands it: Actions, ChunkActions and broadcasts.

Everything a controller returns is checked where the engine receives it, before the run uses
it (the contract: docs/input-checks.md, "A controller's mistakes"). A problem raises
:class:`~swarmsim.actionvalues.BadAction` naming the row of the chunk; :func:`blame` turns it,
or an exception the controller raised, into a :class:`~swarmsim.errors.ControllerError`
naming the controller, the robot and the tick. One Action's values are checked by
swarmsim.actionvalues (which the controller API's ChunkActions uses too).

What it costs: a batch controller's dense columns (GGC's) are checked by their shapes and
dtypes (a few attribute reads a chunk), their values inside the compiled passes that write
them (swarmsim.engine.tickrows: finite velocities, listening and wake ranges not negative, status
codes in range, each sender's own id); a list of Actions and their broadcasts a column at a
time, robot by robot only to name the robot once a column is found wrong.
"""

from __future__ import annotations

import functools
from collections.abc import Mapping, Sequence
from dataclasses import dataclass
from typing import Any

import numpy as np

from swarmsim.actionvalues import (
    BOOLS,
    BadAction,
    action_columns,
    action_problem,
    is_integer,
    message_type_problem,
    show,
)
from swarmsim.controller import Action, ChunkActions
from swarmsim.errors import ControllerError, raised


def columns_of(actions: Sequence[Any], robots: int) -> ChunkActions:
    """The checked columns (sparse form) of a chunk's ``robots`` Actions
    (swarmsim.actionvalues.action_columns). Raises BadAction."""
    return ChunkActions(*action_columns(actions, robots, Action))


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
# ----------------------------------------------------------------------------- ChunkActions
_DENSE = ("sleep", "wake_range", "wake_on_motion", "wake_tick")
"""The dense form's sleep columns: numbers, as numpy converts them to bool, float, bool and
int64."""


def check_columns(actions: ChunkActions, robots: int, dtype: np.dtype) -> None:
    """Check the form of a chunk's ChunkActions (``robots`` rows; broadcasts in the run's
    message ``dtype``) before any of it is written. The dense form: its broadcast rows here
    (a few attribute reads); its other columns, one row per robot, where the compiled passes
    write them (swarmsim.engine.tickrows: -2), numbers as numpy converts them (else it raises), and
    :func:`column_problems` names the column. The sparse form: every column, and the rows its
    messages and sleepers name. Raises BadAction."""
    b = actions.broadcast
    if b is not None:
        if not (isinstance(b, np.ndarray) and b.shape == (robots,)
                and b.dtype.names == dtype.names):
            _column_form(b, "broadcast", (robots,), "V")
            raise BadAction(None, f"broadcast rows with the fields {b.dtype.names}; expected "
                                  f"the run's message fields {dtype.names}")
        return
    column_problems(actions, robots)
    for name in ("messages", "sleepers"):
        rows = getattr(actions, name)
        if rows and not all(is_integer(k) and 0 <= k < robots for k in rows):
            bad = next(k for k in rows if not (is_integer(k) and 0 <= k < robots))
            raise BadAction(None, f"{name} for the row {show(bad)} of a chunk of {robots} "
                                  "robots (rows 0 to R - 1)")
    for k, action in actions.sleepers.items():
        problem = (action_problem(action) if isinstance(action, Action) else
                   f"{show(action)}; expected an Action")
        if problem:
            raise BadAction(k, problem)


def column_problems(actions: ChunkActions, robots: int) -> None:
    """BadAction naming the first column of ``actions`` that is not a numpy array of one row
    per robot (``robots`` rows) of a fitting dtype kind; nothing if none."""
    _column_form(actions.velocities, "velocities", (robots, 2), "biuf")
    _column_form(actions.listen, "listen", (robots,), "biuf")
    if actions.broadcast is not None:
        for name in _DENSE:
            _column_form(getattr(actions, name), name, (robots,), "biuf")


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
    own id when it is written (swarmsim.engine.tickrows.sign_rows), so no robot can speak as another.
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
        raise BadAction(k, message_type_problem(row))

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


def _field_values(field: np.dtype, column: Sequence[Any]) -> np.ndarray | None:
    """A field's values as a numpy array of shape (len(column), *field.shape), or None
    when one does not fit the field as given (see Broadcasts)."""
    if not field.shape and field.kind in "ib":  # the usual fields, in one pass or two
        values = _plain_values(field, column)
        if values is not None:
            return values
    try:
        values = np.asarray(column)
    except (ValueError, TypeError, OverflowError):
        return None
    if values.shape != (len(column), *field.shape) or not _fits(field.base, values):
        return None
    return values


def _plain_values(field: np.dtype, column: Sequence[Any]) -> np.ndarray | None:
    """A bool field's Python bools, or a signed integer field's whole numbers in its range,
    converted; None for anything else (which _field_values then looks at)."""
    n = len(column)
    if field.kind == "b":
        return np.fromiter(column, dtype=field, count=n) if set(map(type, column)) <= BOOLS \
            else None
    try:
        wide = np.fromiter(column, dtype=np.int64, count=n)
    except (ValueError, TypeError, OverflowError):
        return None
    if wide.tolist() != list(column):  # a fraction truncated, text parsed
        return None
    low, high = _int_range(field)
    return wide if n == 0 or (wide.min() >= low and wide.max() <= high) else None


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


__all__ = ["Broadcasts", "blame", "check_columns", "column_problems", "columns_of"]
