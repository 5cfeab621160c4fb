"""Loop hooks: what runs around each tick besides the robots (ARGoS' loop functions), and the
stop rules that end a run.

A run keeps its hooks in one list, ``Simulation.hooks``, built in this order: the fault
injector (if the run has failures: swarmsim/engine/faults.py), the metrics
(swarmsim.metrics.RunMetrics), then the stop rules of :func:`stop_rules`: complete, stalled,
plateau, max_ticks. A user of the Python API adds one with ``sim.hooks.append(hook)`` (or
inserts it before ``sim.metrics`` to change what a tick's metrics see).
"""

from __future__ import annotations

from typing import Any, Protocol

from swarmsim.metrics import CoveragePart, ProgressPart, RunMetrics


class LoopHook(Protocol):
    """What a loop hook is (subclass :class:`Hook` for do-nothing defaults).

    ``run`` is the Simulation; a hook may read all of it and act on it through its public
    methods (``run.fail(robots)``, say), and ``run.tick`` is the tick's number. The calls, in
    the order of ``Simulation.hooks`` at each point:

    - ``start(run)``: once, when the run is set up (tick 0, before any tick).
    - ``pre_step(run)``: at the start of each tick, before the robots sense (``run.tick`` is
      the tick before).
    - ``post_step(run)``: at the end of each tick, after the physics step (``run.tick``
      counts the tick, ``run.positions`` and ``run.messages`` are its end state). The
      metrics are a hook too: hooks before them change what the tick's metrics see (the
      fault injector fails robots here), hooks after them read the tick's metrics
      (``run.metrics``).
    - ``is_finished(run)``: after each tick (and the ``on_tick`` callback of
      ``Simulation.run``): a reason to stop the run (a short word: it is the summary's
      ``stop_reason``) or None to go on. The first hook that gives a reason ends the run;
      the hooks after it are not asked. It should only answer (state belongs in
      ``post_step``): it may be asked more than once a tick.

    Hooks must be deterministic (a random draw from their own Generator, seeded from the run
    seed) so that one seed still decides the run.
    """

    def start(self, run: Any) -> None: ...

    def pre_step(self, run: Any) -> None: ...

    def post_step(self, run: Any) -> None: ...

    def is_finished(self, run: Any) -> str | None: ...


class Hook:
    """A loop hook that does nothing: override the calls you need (see :class:`LoopHook`)."""

    def start(self, run: Any) -> None:
        """Once, at tick 0."""

    def pre_step(self, run: Any) -> None:
        """Before each tick."""

    def post_step(self, run: Any) -> None:
        """After each tick's physics step."""

    def is_finished(self, run: Any) -> str | None:
        """A reason to stop now, or None."""
        return None


class CompleteRule(Hook):
    """Stop ("complete") at the completion tick (coverage within eps0 of the target)."""

    def __init__(self, coverage: CoveragePart):
        self.coverage = coverage

    def is_finished(self, run: Any) -> str | None:
        return "complete" if self.coverage.completion_tick is not None else None


class StallRule(Hook):
    """Stop ("stalled") when no robot moved more than ``wake_eps`` units in a tick and no
    broadcast changed for ``stall_ticks`` ticks.

    Attributes:
        last_change_tick: the last tick in which a robot moved or a broadcast changed (0 at
            the start).
    """

    def __init__(self, progress: ProgressPart, stall_ticks: int, wake_eps: float):
        self.progress = progress
        self.stall_ticks = stall_ticks
        self.wake_eps = wake_eps
        self.last_change_tick = 0

    def post_step(self, run: Any) -> None:
        if run.broadcasts_changed or self.progress.longest_step > self.wake_eps:
            self.last_change_tick = run.tick

    def is_finished(self, run: Any) -> str | None:
        return "stalled" if run.tick - self.last_change_tick >= self.stall_ticks else None


class PlateauRule(Hook):
    """Stop ("plateau") when coverage has not risen by ``plateau_delta`` for
    ``plateau_ticks`` ticks.

    Attributes:
        plateau_tick: the last tick at which coverage rose by more than plateau_delta above
            the coverage of the previous such tick (0 at the start).
    """

    def __init__(self, coverage: CoveragePart, plateau_ticks: int, plateau_delta: float):
        self.coverage = coverage
        self.plateau_ticks = plateau_ticks
        self.plateau_delta = plateau_delta
        self.plateau_tick = 0
        self._reference = -1.0  # the coverage at plateau_tick (none yet: below any)

    def start(self, run: Any) -> None:
        self.post_step(run)

    def post_step(self, run: Any) -> None:
        if self.coverage.coverage > self._reference + self.plateau_delta:
            self._reference = self.coverage.coverage
            self.plateau_tick = run.tick

    def is_finished(self, run: Any) -> str | None:
        return "plateau" if run.tick - self.plateau_tick >= self.plateau_ticks else None


class MaxTicksRule(Hook):
    """Stop ("max_ticks") at tick ``max_ticks``."""

    def __init__(self, max_ticks: int):
        self.max_ticks = max_ticks

    def is_finished(self, run: Any) -> str | None:
        return "max_ticks" if run.tick >= self.max_ticks else None


def stop_rules(config: Any, metrics: RunMetrics) -> list[Hook]:
    """A run's stop rules, in the order they are asked: complete (if ``stop_on_complete``),
    stalled, plateau, max_ticks (``config``: the run's SimConfig)."""
    coverage = metrics.part(CoveragePart)
    complete = [CompleteRule(coverage)] if config.stop_on_complete else []
    return [*complete,
            StallRule(metrics.part(ProgressPart), config.stall_ticks, config.wake_eps),
            PlateauRule(coverage, config.plateau_ticks, config.plateau_delta),
            MaxTicksRule(config.max_ticks)]


__all__ = ["CompleteRule", "Hook", "LoopHook", "MaxTicksRule", "PlateauRule", "StallRule",
           "stop_rules"]
