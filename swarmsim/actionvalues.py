"""What the values of one robot's Action may be, checked (the controller API's contract:
the docstring of swarmsim.controller.Action; docs/input-checks.md, "A controller's mistakes").

The engine checks a chunk's Actions a column at a time (:func:`action_columns`), one Action
(:func:`action_problem`) only to name the robot once a column is found wrong, or when a batch
controller puts one (ChunkActions.put). A problem is a :class:`BadAction` naming the row of
the chunk. This module does not import the controller API (which uses it).
"""

from __future__ import annotations

import math
import numbers
import reprlib
from collections.abc import Mapping, Sequence
from typing import Any

import numpy as np

BOOLS = frozenset({bool, np.bool_})
"""The types a flag (``wake_on_motion``, a broadcast's bool field) may have; ``sleep`` may
also be 1 or 0."""

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


FINITE_VELOCITY = ("expected finite numbers (vx, vy), or (left, right) wheel speeds from a "
                   "wheel controller, units per tick")
"""What a non-finite velocity was refused for (step's and decide's refusals say it alike)."""


def show(value: Any) -> str:
    """A short one-line repr of ``value`` (with its type where the repr hides it)."""
    text = " ".join(_short.repr(value).split())
    if isinstance(value, (str, bytes, tuple, list, dict, np.ndarray)) or value is None:
        return text
    if isinstance(value, (bool, int, float)):
        return text
    return f"{text} (a {type(value).__name__})"


def action_columns(actions: Sequence[Any], robots: int, action_class: type
                   ) -> tuple[np.ndarray, np.ndarray, dict[int, Any], dict[int, Any]]:
    """The checked columns of a chunk's ``robots`` Actions (``action_class``: the Action class):
    ChunkActions' velocities, listen, messages and sleepers. Velocities are checked here for
    their shape and type; that they are finite, and that ``listen`` is not negative, by the
    compiled pass that writes them (:func:`move_problem`); broadcasts when they are converted
    (swarmsim.engine.actioncheck.Broadcasts). Raises BadAction."""
    if len(actions) != robots:
        raise BadAction(None, f"{len(actions)} actions for a chunk of {robots} robots")
    if robots and set(map(type, actions)) != {action_class}:
        for k, given in enumerate(actions):
            if not isinstance(given, action_class):
                raise BadAction(k, f"{show(given)}; expected an Action")
    velocities = _velocities([a.velocity for a in actions])
    listen = _distances([a.listen for a in actions], "listen")
    sleeps = [a.sleep for a in actions]
    if sleeps.count(True) + sleeps.count(False) != robots:  # bools (or 1, 0) only
        k = next(k for k, s in enumerate(sleeps) if not (s is True or s is False or s in (0, 1)))
        raise BadAction(k, f"sleep={show(sleeps[k])}; expected True or False")
    sleepers = {k: actions[k] for k, s in enumerate(sleeps) if s}
    if sleepers and not _sleepers_fit(list(sleepers.values())):
        for k, action in sleepers.items():
            problem = sleep_problem(action)
            if problem:
                raise BadAction(k, problem)
    messages = {k: a.message for k, a in enumerate(actions) if a.message is not None}
    return velocities, listen, messages, sleepers


def action_problem(action: Any) -> str | None:
    """What is wrong with the values of one robot's Action (None: nothing; that it is an
    Action is the caller's to check); its broadcast's values are checked when it is written
    (swarmsim.engine.actioncheck.Broadcasts)."""
    velocity = _velocity_problem(action.velocity)
    if velocity:
        return velocity
    if not _is_distance(action.listen):
        return listen_problem(action.listen)
    if type(action.sleep) not in BOOLS:
        return f"sleep={show(action.sleep)}; expected True or False"
    if action.message is not None and not isinstance(action.message, (tuple, Mapping,
                                                                         np.void)):
        return message_type_problem(action.message)
    return sleep_problem(action) if action.sleep else None


def sleep_problem(action: Any) -> str | None:
    """What is wrong with a sleeping robot's promises (None: nothing)."""
    if not _is_distance(action.wake_range):
        return (f"wake_range={show(action.wake_range)}; expected a distance >= 0, units "
                "(None: the sensing range)")
    if type(action.wake_on_motion) not in BOOLS:
        return f"wake_on_motion={show(action.wake_on_motion)}; expected True or False"
    tick = action.wake_tick
    if tick is not None and not (is_integer(tick) and tick >= 0):
        return f"wake_tick={show(tick)}; expected a tick: an integer >= 0 (None: no timeout)"
    return None


def _sleepers_fit(sleepers: list[Any]) -> bool:
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
        vx, vy = float(velocity[0]), float(velocity[1])
        return f"the velocity ({vx!r}, {vy!r}); {FINITE_VELOCITY}"
    return listen_problem(float(listen))


def listen_problem(value: Any) -> str:
    """The problem of a robot's ``listen``."""
    return f"listen={show(value)}; expected a distance >= 0, units (None: the sensing range)"


def wake_range_problem(value: float) -> str:
    """The problem of a dense wake_range column's value."""
    return (f"wake_range={float(value)!r}; expected a distance >= 0, units (NaN: the sensing "
            "range)")


def _velocities(values: list) -> np.ndarray:
    """(R, 2) float velocities from R Actions' (BadAction naming the first that is not two
    numbers; finiteness is checked where they are written)."""
    try:  # numpy finds the type: text is not a number
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
        return f"the velocity {show(value)}; {FINITE_VELOCITY}"
    return None


def _distances(values: list, name: str) -> np.ndarray:
    """(R,) float distances, NaN for None, from R Actions' ``name`` (BadAction naming the first
    that is neither None nor a number, or is NaN; a negative one is refused where it is
    written)."""
    nones = values.count(None)
    if nones == len(values):
        return np.full(len(values), np.nan)
    if not nones:  # the usual case: numpy finds the type (text is not a number)
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


def is_integer(value: Any) -> bool:
    return isinstance(value, numbers.Integral) and not isinstance(value, (bool, np.bool_))


def message_type_problem(message: Any) -> str:
    return (f"the broadcast {show(message)}; expected a tuple in the order of the run's "
            "message fields or a dict by field name (None: repeat the last)")


__all__ = ["BOOLS", "BadAction", "action_columns", "action_problem", "is_integer",
           "listen_problem", "message_type_problem", "move_problem", "show", "sleep_problem",
           "wake_range_problem"]
