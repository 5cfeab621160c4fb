"""Where controllers are found: by registered name or as ``module:Class``.

A controller joins the registry one way: an entry point in the ``swarmsim.controllers``
group (``name = "package.module:Class"`` in the installing project's ``pyproject.toml``),
found without importing anything else and loaded when first asked for. swarmsim's own
controllers are registered so; the engine lists no controller itself. A class of one's own
runs without registering: name it as ``module:Class`` or pass the class.
"""

from __future__ import annotations

import dataclasses
import importlib
import os
import sys
from importlib.metadata import EntryPoint, entry_points
from typing import Any

from swarmsim.errors import ConfigError, ControllerError, did_you_mean, raised, unknown_name

ENTRY_POINT_GROUP = "swarmsim.controllers"
_LOADED: dict[str, type[Any]] = {}
"""Registered classes already loaded, by name."""


def _entry_points() -> dict[str, EntryPoint]:
    return {ep.name: ep for ep in entry_points(group=ENTRY_POINT_GROUP)}


def available_controllers() -> list[str]:
    """Names of the registered controllers (the entry points of ``swarmsim.controllers``)."""
    return sorted(_entry_points())


def get_controller(name: str | type[Any]) -> type[Any]:
    """A controller class by registered name, ``module:Class``, or the class itself."""
    if isinstance(name, type):
        _check_controller_class(name, getattr(name, "__name__", repr(name)))
        return name
    if ":" in name:
        return _from_module(name)
    if name in _LOADED:
        return _LOADED[name]
    point = _entry_points().get(name)
    if point is None:
        raise ConfigError(f"{unknown_name('controller', name, available_controllers())} "
                          "(or give module:Class)", key="controller")
    cls = _check_controller_class(point.load(), name)
    _LOADED[name] = cls
    return cls


def resolve_controller(controller: str | type[Any]) -> tuple[type[Any], str]:
    """A run's controller class and the name its summary reports, from a registered name, a
    ``"module:Class"`` string or a class. A class is reported by its registered name if it is
    the class registered under its ``name``, else as ``"module:Class"``."""
    if isinstance(controller, str):
        return get_controller(controller), controller
    if not isinstance(controller, type):
        raise ConfigError(f"expected a controller name, 'module:Class' or a controller class, "
                          f"got {controller!r}", key="controller")
    declared = getattr(controller, "name", None)
    if (isinstance(declared, str) and declared in available_controllers()
            and get_controller(declared) is controller):
        name = declared
    else:
        name = f"{controller.__module__}:{controller.__qualname__}"
    _check_controller_class(controller, name)
    return controller, name


def _from_module(name: str) -> type[Any]:
    mod_name, _, cls_name = name.partition(":")
    importable_from_here()
    try:
        mod = importlib.import_module(mod_name)
    except ImportError as exc:
        raise ConfigError(f"cannot import module {mod_name!r}: {exc}", key="controller") from None
    except Exception as exc:  # the module's own code failed (a SyntaxError, a raise)
        raise ControllerError(raised(f"importing module {mod_name!r}", exc),
                              controller=name) from exc
    cls = getattr(mod, cls_name, None)
    if cls is None:
        classes = [k for k, v in vars(mod).items() if isinstance(v, type)]
        raise ConfigError(f"module {mod_name!r} has no {cls_name!r}"
                          f"{did_you_mean(cls_name, classes)}", key="controller")
    return _check_controller_class(cls, name)


def importable_from_here() -> None:
    """Let ``module:Class`` name a module in the current folder, as ``python -m swarmsim``
    does (the installed ``swarmsim`` command does not put the current folder on sys.path).
    Appended, so that it never shadows an installed module."""
    here = os.getcwd()
    if here not in sys.path and "" not in sys.path:
        sys.path.append(here)


def _check_controller_class(cls: Any, name: str) -> type[Any]:
    """``cls``, once checked to be a controller class (ConfigError naming ``name`` if not)."""
    if not isinstance(cls, type):
        raise ConfigError(f"{name!r} is not a class", key="controller")
    checked: type[Any] = cls
    missing = [a for a in ("name", "Params", "STATUSES", "sensing_range") if not hasattr(cls, a)]
    if not (hasattr(cls, "step") or hasattr(cls, "create_swarm")):
        missing.append("step or create_swarm")
    if missing:
        raise ConfigError(f"{name!r} is not a controller class (missing {missing})",
                          key="controller")
    _check_params_class(checked.Params, name)
    return checked


def _check_params_class(params: Any, name: str) -> None:
    """A controller's ``Params``: a dataclass whose every field has a default (a run sets
    the ones it names)."""
    if not (isinstance(params, type) and dataclasses.is_dataclass(params)):
        raise ConfigError(f"{name!r}: Params must be a dataclass whose fields all have "
                          f"defaults, got {params!r}", key="controller")
    bare = [f.name for f in dataclasses.fields(params)
            if f.default is dataclasses.MISSING and f.default_factory is dataclasses.MISSING]
    if bare:
        raise ConfigError(f"{name!r}: Params field(s) {bare} have no default; every "
                          "parameter needs one", key="controller")


__all__ = ["ENTRY_POINT_GROUP", "available_controllers", "get_controller", "resolve_controller"]
