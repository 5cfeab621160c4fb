"""Ctrl-C (and SIGTERM, which the command line treats alike) stop a run however busy its
physics is.

Python runs a signal handler at the next bytecode of the main thread. While pymunk steps its
space, the only Python code that runs is pymunk's collision callbacks, called from C through
cffi, and cffi prints and swallows any exception raised in them ("Exception ignored from cffi
callback ext_cpCollisionBeginFunc ... KeyboardInterrupt"): an interrupt that lands there is
lost and the run goes on. So:

- :func:`handled` (``Simulation.run`` wraps its tick loop in it) replaces, for the run, the
  handlers of SIGINT and SIGTERM that raise KeyboardInterrupt (Python's default for SIGINT,
  the command line's for SIGTERM) with one of its own;
- code in which a KeyboardInterrupt would be lost (pymunk's step: ``Physics.step``) runs
  inside :data:`shield`; a signal that arrives there is only noted, and
  :func:`raise_pending` raises it as KeyboardInterrupt at the next safe point: the end of the
  tick (``Simulation.step``), or the end of :func:`handled`;
- anywhere else the handler raises KeyboardInterrupt at once, as Python's own does (an
  interrupt while numba loads a kernel still ends the run: see
  swarmsim.errors.interrupts_unwrapped). A second signal inside the shield is noted too
  (raised there it would only be swallowed, noisily): the run stops at the tick's end.

Outside :func:`handled` (a loop of ``sim.step()`` of your own, a thread other than the main
one) signals are left to Python's handlers; wrap such a loop in ``handled()`` to get the same
guarantee.
"""

from __future__ import annotations

import contextlib
import signal
import threading
from collections.abc import Iterator
from types import FrameType

_SIGNALS = (signal.SIGINT, signal.SIGTERM)

_MAIN_THREAD = threading.main_thread().ident
"""Signal handlers run in the main thread: only its shielded blocks count."""


class _Shield:
    """A re-entrant block in which an interrupt is only noted (module docstring). ``depth``
    counts the shielded blocks the main thread is in; ``pending`` is the signal noted, 0 for
    none. Other threads (a Dask worker's runs) pass through."""

    def __init__(self) -> None:
        self.depth = 0
        self.pending = 0

    def __enter__(self) -> None:
        if threading.get_ident() == _MAIN_THREAD:
            self.depth += 1

    def __exit__(self, exc_type, exc, tb) -> None:
        if threading.get_ident() == _MAIN_THREAD:
            self.depth -= 1


shield = _Shield()
"""``with shield:`` around code in which a KeyboardInterrupt would be swallowed (pymunk's
step): a signal received inside is raised by the next :func:`raise_pending`."""


def raise_pending() -> None:
    """Raise KeyboardInterrupt if a signal was noted inside :data:`shield` (a safe point:
    call it where the state is whole, e.g. between two ticks), in the main thread only."""
    if shield.pending and threading.get_ident() == _MAIN_THREAD:
        shield.pending = 0
        raise KeyboardInterrupt


def _on_signal(signum: int, frame: FrameType | None) -> None:
    """SIGINT / SIGTERM while :func:`handled`: noted inside :data:`shield`, raised as
    KeyboardInterrupt anywhere else."""
    if shield.depth:
        shield.pending = signum
        return
    raise KeyboardInterrupt


@contextlib.contextmanager
def handled() -> Iterator[None]:
    """While the block runs (in the main thread), SIGINT and SIGTERM whose handler raises
    KeyboardInterrupt are handled by this module (see the module docstring); other handlers
    (SIG_IGN, a handler of your own, SIGTERM's default) are left alone. Re-entrant; restores
    the handlers at the end, and raises a signal still pending then (none is lost)."""
    if threading.current_thread() is not threading.main_thread():
        yield
        return
    replaced = {}
    for sig in _SIGNALS:
        if signal.getsignal(sig) is signal.default_int_handler:
            replaced[sig] = signal.signal(sig, _on_signal)
    try:
        yield
    except BaseException:
        shield.pending = 0  # the block ends anyway
        raise
    finally:
        for sig, previous in replaced.items():
            signal.signal(sig, previous)
    if replaced:
        raise_pending()
