"""How much of a run's tick is compiled code, and how much is Python between compiled calls.

One whole run per seed. Every numba kernel the simulator and the controllers hold as a
module attribute is wrapped with a timer (a kernel called from inside another is part of its
caller's time, not counted twice), and so is pymunk's ``Space.step`` (Chipmunk's C step).
Prints per seed the whole tick, Chipmunk's step, the kernels (and their calls a tick) and the
rest: the Python between them (the engine's and the controller's glue, numpy's small calls).
The timers add well under a microsecond a call.

    python bench/bench_glue.py                       # K, seeds 0-2
    python bench/bench_glue.py --world house --seeds 0 --controller ggc

Wall time; these machines are noisy (+-30 %): compare the shares, measured with nothing else
running.
"""

from __future__ import annotations

import argparse
import sys
import time
from collections.abc import Callable, Iterator
from contextlib import contextmanager
from typing import Any

import pymunk
from numba.core.registry import CPUDispatcher

from swarmsim import Simulation
from swarmsim.errors import ConfigError

OWN_PACKAGES = ("swarmsim", "controllers")


class Clock:
    """Seconds and calls spent inside wrapped callables, by kind."""

    def __init__(self) -> None:
        self.seconds = {"chipmunk": 0.0, "kernels": 0.0}
        self.calls = {"chipmunk": 0, "kernels": 0}

    def timed(self, kind: str, f: Callable) -> Callable:
        """``f`` with its time added to ``kind``."""
        def wrapper(*args: Any, **kwargs: Any) -> Any:
            start = time.perf_counter()
            try:
                return f(*args, **kwargs)
            finally:
                self.seconds[kind] += time.perf_counter() - start
                self.calls[kind] += 1
        return wrapper


@contextmanager
def timers(clock: Clock) -> Iterator[int]:
    """Wrap every kernel held by a loaded module of OWN_PACKAGES, and Space.step, for the
    block; yields how many module attributes were wrapped; restores them after."""
    swapped = []
    for name, module in list(sys.modules.items()):
        if module is None or not name.startswith(OWN_PACKAGES):
            continue
        for attr, value in list(vars(module).items()):
            if isinstance(value, CPUDispatcher):
                swapped.append((module, attr, value))
                setattr(module, attr, clock.timed("kernels", value))
    step = pymunk.Space.step
    pymunk.Space.step = clock.timed("chipmunk", step)
    try:
        yield len(swapped)
    finally:
        pymunk.Space.step = step
        for module, attr, value in swapped:
            setattr(module, attr, value)


def measure(world: str, controller: str, seed: int, max_ticks: int | None) -> dict:
    """One whole run: ms a tick in all, in Chipmunk's step, in kernels, and the rest."""
    sim = Simulation(world, controller=controller, seed=seed, max_ticks=max_ticks)
    sim.step()  # every module the run uses is imported and its kernels loaded
    clock = Clock()
    with timers(clock) as wrapped:
        start, first = time.perf_counter(), sim.tick
        while sim.finished() is None:
            sim.step()
        whole = time.perf_counter() - start
    ticks = sim.tick - first
    per_tick = {k: v / ticks * 1e3 for k, v in clock.seconds.items()}
    return {"ticks": ticks, "wrapped": wrapped, "tick": whole / ticks * 1e3, **per_tick,
            "python": (whole - sum(clock.seconds.values())) / ticks * 1e3,
            "kernel_calls": clock.calls["kernels"] / ticks}


def main(argv: list[str] | None = None) -> None:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--world", default="K")
    parser.add_argument("--controller", default="ggc")
    parser.add_argument("--seeds", type=int, nargs="+", default=[0, 1, 2])
    parser.add_argument("--max-ticks", type=int, dest="max_ticks")
    args = parser.parse_args(argv)
    print(f"{args.world}, {args.controller}: ms a tick (share of the tick)")
    print(f"{'seed':>4}{'ticks':>8}{'tick':>8}{'chipmunk':>16}{'kernels':>16}{'calls':>7}"
          f"{'python':>16}")
    for seed in args.seeds:
        try:
            r = measure(args.world, args.controller, seed, args.max_ticks)
        except ConfigError as bad:  # a world, controller, seed or limit the run refuses
            parser.error(str(bad))
        cells = "".join(f"{r[k]:>8.3f} ({r[k] / r['tick']:4.0%})"
                        for k in ("chipmunk", "kernels"))
        print(f"{seed:>4}{r['ticks']:>8}{r['tick']:>8.3f}{cells}{r['kernel_calls']:>7.1f}"
              f"{r['python']:>8.3f} ({r['python'] / r['tick']:4.0%})", flush=True)


if __name__ == "__main__":
    main()
