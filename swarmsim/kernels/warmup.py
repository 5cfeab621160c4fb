"""The engine's compiled kernels, warmed up before a run's clock starts.

Each kernel module registers its own warm-up when it is imported, by decorating it::

    @kernel_warm_up("tick rows")
    def warm_up() -> None:
        ...  # call each kernel once on tiny inputs: compiled (first time) or loaded (cache)

:class:`swarmsim.Simulation` warms every registered kernel, in the order the modules were
imported, then its controller's (see ``Simulation._setup``). A kernel module that a run
imports is warmed; one it does not import costs nothing. The name is what the build notice
(swarmsim.kernels.kernelbuild) shows while the step compiles.
"""

from __future__ import annotations

from collections.abc import Callable

WarmUp = Callable[[], None]

_REGISTERED: dict[str, WarmUp] = {}
"""Step name -> warm-up, in registration (import) order."""


def kernel_warm_up(name: str) -> Callable[[WarmUp], WarmUp]:
    """Register the decorated function as the warm-up step ``name``; returns it unchanged.

    A second registration under the same name (a module imported again) replaces the first
    and keeps its place.
    """

    def register(warm_up: WarmUp) -> WarmUp:
        _REGISTERED[name] = warm_up
        return warm_up

    return register


def registered_warm_ups() -> tuple[tuple[str, WarmUp], ...]:
    """Every registered warm-up step as (name, function), in registration order."""
    return tuple(_REGISTERED.items())
