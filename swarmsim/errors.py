"""Errors that swarmsim reports to users.

Every problem with user input (world files, parameters, sweep specs) is raised as a
:class:`ConfigError` whose message names the file (when there is one), the key and the
offending value, so that the command line can print one clear line instead of a traceback.
A controller that raises or breaks the controller contract is a :class:`ControllerError`
naming the controller, the robot and the tick.
"""

from __future__ import annotations

import contextlib
import difflib
import functools
import os
import traceback
from collections.abc import Iterable, Iterator
from pathlib import Path

MAX_LISTED = 12
"""An unknown name's message lists the known names when there are at most this many."""


class ConfigError(ValueError):
    """Bad user input: a world file, a parameter or a spec that cannot be used."""

    def __init__(self, message: str, *, source: str | None = None, key: str | None = None):
        self.source = source
        self.key = key
        where = ""
        if source:
            where += f"{source}: "
        if key:
            where += f"key '{key}': "
        super().__init__(f"{where}{message}")


class ControllerError(RuntimeError):
    """A controller raised, or handed the engine something the controller API does not allow.

    ``str(error)`` is one line: ``controller 'NAME', robot R, tick T: PROBLEM`` (robot and tick
    left out where they are not known, e.g. a whole chunk's ``decide`` or a robot's
    ``__init__``). When the controller's own code raised, that exception is the
    ``__cause__``, and :meth:`user_traceback` gives its traceback without swarmsim's frames.

    Attributes:
        problem: what went wrong, e.g. "step() returned a velocity of shape (3,); expected
            (vx, vy)".
        controller: the controller as the run names it (e.g. "mybots.walk:RandomWalk"), or None
            until the engine fills it in (:meth:`where`).
        robot: the robot's id, or None.
        tick: the tick, or None.
    """

    def __init__(self, problem: str, *, controller: str | None = None, robot: int | None = None,
                 tick: int | None = None):
        self.problem, self.controller, self.robot, self.tick = problem, controller, robot, tick
        super().__init__(problem)

    def __str__(self) -> str:
        where = [f"controller {self.controller!r}" if self.controller else "controller"]
        if self.robot is not None:
            where.append(f"robot {self.robot}")
        if self.tick is not None:
            where.append(f"tick {self.tick}")
        return f"{', '.join(where)}: {self.problem}"

    def where(self, controller: str, tick: int | None = None) -> ControllerError:
        """This error with the controller's name and, unless it has one, the tick."""
        return ControllerError(self.problem, controller=controller, robot=self.robot,
                               tick=self.tick if self.tick is not None else tick)

    def user_traceback(self) -> str:
        """The traceback of the controller's own exception (the ``__cause__``), with the frames
        of swarmsim, numpy, numba and pymunk left out; "" when the controller raised
        nothing (it returned something the engine refuses)."""
        cause = self.__cause__
        if cause is None or isinstance(cause, ControllerError):
            return ""
        trace = traceback.TracebackException.from_exception(cause)
        for part in _chain(trace):
            part.stack = traceback.StackSummary.from_list(
                [frame for frame in part.stack if not _engine_file(frame.filename)])
        return "".join(trace.format())


def raised(call: str, exc: BaseException) -> str:
    """"step() raised ValueError: the message" (the message on one line)."""
    text = " ".join(str(exc).split())
    return f"{call} raised {type(exc).__name__}" + (f": {text}" if text else "")


def _chain(trace: traceback.TracebackException) -> Iterator[traceback.TracebackException]:
    """A traceback and those of the exceptions it was raised from or while handling."""
    seen: set[int] = set()
    part: traceback.TracebackException | None = trace
    while part is not None and id(part) not in seen:
        seen.add(id(part))
        yield part
        part = part.__cause__ or part.__context__


@functools.cache
def _package_folders() -> tuple[str, ...]:
    """The folders of the engine's own code and the libraries it calls controllers through."""
    import importlib.util

    folders = [str(Path(__file__).resolve().parent)]
    for name in ("numpy", "numba", "pymunk", "importlib"):
        spec = importlib.util.find_spec(name)
        if spec is not None and spec.submodule_search_locations:
            folders.extend(str(Path(p).resolve()) for p in spec.submodule_search_locations)
    return tuple(folder + os.sep for folder in folders)


def _engine_file(filename: str) -> bool:
    """Whether a traceback frame's file belongs to swarmsim, numpy, numba, pymunk or the
    import machinery (a controller module that fails as it is imported)."""
    if filename.startswith("<frozen importlib"):
        return True
    try:
        resolved = str(Path(filename).resolve())
    except (OSError, ValueError):
        return False
    return resolved.startswith(_package_folders())


def interrupt_within(exc: BaseException | None) -> bool:
    """Whether ``exc`` is a KeyboardInterrupt or was raised from one.

    Ctrl-C (or SIGTERM, which the command line treats alike) that arrives while compiled code
    calls back into Python, as numba does when it loads a cached kernel, leaves that code as a
    ``SystemError`` whose cause is the KeyboardInterrupt.
    """
    seen: set[int] = set()
    while exc is not None and id(exc) not in seen:
        if isinstance(exc, KeyboardInterrupt):
            return True
        seen.add(id(exc))
        exc = exc.__cause__ or exc.__context__
    return False


@contextlib.contextmanager
def interrupts_unwrapped() -> Iterator[None]:
    """Re-raise an error that an interrupt caused (see :func:`interrupt_within`) as the
    KeyboardInterrupt it is, so that it ends a run or a sweep as Ctrl-C does."""
    try:
        yield
    except Exception as exc:
        if interrupt_within(exc):
            raise KeyboardInterrupt from exc
        raise


def did_you_mean(name: str, known: Iterable[str], n: int = 3) -> str:
    """``"; did you mean 'a', 'b' or 'c'?"`` with the (up to ``n``) known names closest to
    ``name`` (difflib), or ``""`` when none is close."""
    close = difflib.get_close_matches(str(name), sorted(set(known)), n=n, cutoff=0.6)
    if not close:
        return ""
    quoted = [repr(c) for c in close]
    listed = quoted[0] if len(quoted) == 1 else ", ".join(quoted[:-1]) + " or " + quoted[-1]
    return f"; did you mean {listed}?"


def unknown_name(what: str, name: str, known: Iterable[str], listing: str = "") -> str:
    """The message for an unknown name: ``unknown parameter 'robot'; did you mean 'robots'?``
    (the three closest known names). With none close: the known names when they are few (at
    most MAX_LISTED), else ``listing`` (where to find them, e.g. "see 'swarmsim params'")."""
    known = sorted(set(known))
    hint = did_you_mean(name, known)
    if hint:
        return f"unknown {what} {name!r}{hint}"
    if len(known) <= MAX_LISTED or not listing:
        return f"unknown {what} {name!r}; known: {', '.join(known) or 'none'}"
    return f"unknown {what} {name!r}; {listing}"
