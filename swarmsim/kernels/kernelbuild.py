"""Telling the user that kernels are being compiled (the first run after an install or a code
change), instead of a silent minute.

:func:`build_notice` watches numba's compiler while a run is set up (its warm-up steps,
:func:`step`): if nothing is compiled (the kernels load from the cache) it prints nothing;
otherwise it says so on ``stream`` when the first kernel starts compiling, then

* ``detail=True``: which warm-up step (k of n) and which kernel is compiling (a line redrawn
  in place on a terminal; elsewhere a line per step that compiled), and the time it took;
* ``detail=False`` (``swarmsim run --quiet``): one line, "compiling kernels (first run only)
  ... done in 31.2 s".

The library prints nothing unless asked: the command line asks; in Python, wrap the
:class:`swarmsim.Simulation` construction (which compiles) in ``with build_notice():``.
"""

from __future__ import annotations

import sys
import time
from collections.abc import Iterator
from contextlib import contextmanager
from typing import TextIO

PREFIX = "swarmsim: compiling kernels (first run only)"


class _Notice:
    """The progress of one setup's compiles on ``stream``."""

    def __init__(self, stream: TextIO, detail: bool):
        self.stream, self.detail = stream, detail
        self.live = detail and stream.isatty()
        self.step_name, self.k, self.n = "", 0, 0
        self.started: float | None = None  # perf_counter of the first compile
        self.cpu_start = 0.0
        self.depth = 0
        self.kernels = 0  # kernels (signatures) compiled in all
        self.step_kernels = 0

    def write(self, text: str) -> None:
        self.stream.write(text)
        self.stream.flush()

    def compile_started(self, kernel: str) -> None:
        if self.started is None:
            self.started, self.cpu_start = time.perf_counter(), time.process_time()
            if not self.live:
                self.write(f"{PREFIX} ..." + ("\n" if self.detail else ""))
        self.depth += 1
        self.kernels += 1
        self.step_kernels += 1
        if self.live:
            self.write(f"\r\033[K{PREFIX}: {self.k}/{self.n} {self.step_name}: {kernel}")

    def compile_ended(self) -> None:
        self.depth -= 1

    def step_ended(self, seconds: float) -> None:
        if self.step_kernels and self.detail and not self.live:
            self.write(f"  {self.k}/{self.n} {self.step_name}: {_kernels(self.step_kernels)}, "
                       f"{seconds:.1f} s\n")

    def finish(self) -> None:
        if self.started is None:
            return
        wall = time.perf_counter() - self.started
        cpu = time.process_time() - self.cpu_start
        done = (f"compiled {_kernels(self.kernels)} in {wall:.1f} s ({cpu:.1f} s CPU); later "
                f"runs load them from numba's cache")
        if self.live:
            self.write(f"\r\033[K{PREFIX}: {done}\n")
        elif self.detail:
            self.write(f"swarmsim: {done}\n")
        else:
            self.write(f" done in {wall:.1f} s\n")


def _kernels(count: int) -> str:
    return f"{count} kernel" + ("" if count == 1 else "s")


_ACTIVE: list[_Notice] = []


@contextmanager
def build_notice(stream: TextIO | None = None, detail: bool = True) -> Iterator[None]:
    """Report the kernels compiled inside the block on ``stream`` (default: stderr); silent
    when none is (see the module)."""
    from numba.core import event

    notice = _Notice(sys.stderr if stream is None else stream, detail)

    class Listener(event.Listener):
        def on_start(self, ev: event.Event) -> None:
            disp = ev.data["dispatcher"]
            notice.compile_started(getattr(disp.py_func, "__qualname__", "?"))

        def on_end(self, ev: event.Event) -> None:
            notice.compile_ended()

    listener = Listener()
    event.register("numba:compile", listener)
    _ACTIVE.append(notice)
    try:
        yield
    finally:
        _ACTIVE.remove(notice)
        event.unregister("numba:compile", listener)
        notice.finish()


@contextmanager
def step(name: str, k: int, n: int) -> Iterator[None]:
    """Warm-up step ``k`` of ``n`` (``name``: what it compiles or loads), for the active
    :func:`build_notice` if any."""
    if not _ACTIVE:
        yield
        return
    notice = _ACTIVE[-1]
    notice.step_name, notice.k, notice.n, notice.step_kernels = name, k, n, 0
    start = time.perf_counter()
    try:
        yield
    finally:
        notice.step_ended(time.perf_counter() - start)
