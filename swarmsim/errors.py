"""Errors that swarmsim reports to users.

Every problem with user input (world files, parameters, sweep specs) is raised as a
:class:`ConfigError` whose message names the file (when there is one), the key and the
offending value, so that the command line can print one clear line instead of a traceback.
"""

from __future__ import annotations

import contextlib
import difflib
from collections.abc import Iterable, Iterator

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
