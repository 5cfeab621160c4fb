"""``python -m tests.slow_contacts ARGS``: ``swarmsim ARGS`` with slow contact callbacks, so
that the run spends its time inside pymunk's step, in a cffi callback, where a
KeyboardInterrupt raised by a signal handler used to be swallowed.

Each robot-robot and robot-wall contact that begins sleeps ``SLOW_CONTACT_SECONDS``
(environment, default 0.2 s); the first one creates the file ``SLOW_CONTACT_MARKER`` (if set)
once it is inside the callback, so that a test knows when to send its signal.
"""

from __future__ import annotations

import functools
import os
import sys
import time
from pathlib import Path

import pymunk


def _slowed(callback, seconds: float, marker: Path | None):
    @functools.wraps(callback)
    def slow(arbiter, space, data):
        if marker is not None and not marker.exists():
            marker.touch()
        time.sleep(seconds)
        return callback(arbiter, space, data)

    return slow


def install() -> None:
    """Make every ``begin`` callback registered from now on slow (see the module docstring)."""
    seconds = float(os.environ.get("SLOW_CONTACT_SECONDS", "0.2"))
    marker = os.environ.get("SLOW_CONTACT_MARKER")
    marker_path = Path(marker) if marker else None
    on_collision = pymunk.Space.on_collision

    def slow_on_collision(self, *types, begin=None, **kw):
        if begin is not None:
            begin = _slowed(begin, seconds, marker_path)
        return on_collision(self, *types, begin=begin, **kw)

    pymunk.Space.on_collision = slow_on_collision


if __name__ == "__main__":
    install()
    from swarmsim.cli import main

    sys.exit(main(sys.argv[1:]))
