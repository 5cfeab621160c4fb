"""Checkpoints: a run's whole state in a file, to continue it later, in this or another process.

A checkpoint holds the Simulation's state as it is between two ticks: the physics (what
varies in the pymunk Space: every body's motion and the Space's cached contacts, with their
impulses; swarmsim/physics/spacestate.py), every controller's state, every random stream, the
metrics, the time series so far, the engine's wake and sleep state, which robots are parked
and which pymunk has put to sleep; plus, optionally, the caller's own ``extra`` (the command
line keeps its options and trajectory samples there).

Saving is an event in the run. Loading makes the Space again, as the run's constructor
builds it, and gives it the saved state; what Chipmunk keeps besides is not saved: body
sleep state and idle time, sleeping groups, the joints' accumulated impulses, the spatial
index's structure. A loaded Space steps close to, not bit for bit like, the one that was
saved. So :func:`save` re-seats the live run on the very bytes it wrote: the run that saved
continues from the state loaded back from the file, by the same procedure :func:`load`
follows in any other process (swarmsim/physics/physics.py Physics.__setstate__). Both
continue from identical state and end identically. The price: a run that saves differs
(slightly, as chaotic runs do) from the same run that never saves; docs/checkpoints.md
measures it.

File layout: one line of magic (:data:`MAGIC`), one line of JSON header (format, code
version, tick, world, controller, the body's length and sha256), then the body: a
cloudpickle (a user's controller class defined in a script travels by value) of the run's
state, in which the Simulation itself is a reference (closures of the run point to whichever
Simulation loads it). A file without the magic, of another format, written by other code
(another :func:`code_version`: the classes pickled may differ), or whose body is truncated or
damaged (length or digest) is refused with one line (ConfigError naming the file). Files are
written atomically (a temporary file and a rename).

``sim`` below is a swarmsim.engine.sim.Simulation (not imported here: sim.py imports this).
"""

from __future__ import annotations

import copyreg
import hashlib
import io
import json
import pickle
import types
from pathlib import Path
from typing import Any

import cloudpickle

from swarmsim.errors import ConfigError
from swarmsim.registry import importable_from_here
from swarmsim.results.output import atomic_write_bytes
from swarmsim.results.provenance import code_version

FILE_NAME = "checkpoint.swarmsim"
"""The checkpoint ``swarmsim run --out DIR --checkpoint-every N`` keeps in DIR."""
MAGIC = b"SWARMSIM-CHECKPOINT\n"
"""A checkpoint file's first line."""
FORMAT = 3
"""The checkpoint layout's version (the header's "format"; 3: the physics as arrays,
swarmsim/physics/spacestate.py, not pymunk's pickle of the Space)."""
_RUN = "run"
"""The persistent id of the Simulation in a checkpoint's body."""
UNSAVED = ("_renderer", "_renderer_key")
"""Simulation attributes a checkpoint leaves out: views of the run (remade when asked for);
a run that saves keeps its own."""


def _reduce_mappingproxy(proxy: types.MappingProxyType) -> tuple:
    return types.MappingProxyType, (dict(proxy),)


class _Pickler(cloudpickle.CloudPickler):
    """cloudpickle, plus read-only mappings (world defaults, controller declarations); the
    run itself (``sim``) is written as a reference."""

    dispatch_table = copyreg.dispatch_table.copy()
    dispatch_table.update(cloudpickle.CloudPickler.dispatch_table)
    dispatch_table[types.MappingProxyType] = _reduce_mappingproxy

    def __init__(self, file: io.BytesIO, sim: Any):
        super().__init__(file, protocol=pickle.HIGHEST_PROTOCOL)
        self._sim = sim

    def persistent_id(self, obj: Any) -> str | None:
        return _RUN if obj is self._sim else None


class _Unpickler(pickle.Unpickler):
    """Loads a body, the run's reference resolved to ``target``."""

    def __init__(self, file: io.BytesIO, target: Any):
        super().__init__(file)
        self._target = target

    def persistent_load(self, pid: Any) -> Any:
        if pid != _RUN:
            raise pickle.UnpicklingError(f"unknown reference {pid!r}")
        return self._target


def _pickled(sim: Any, obj: Any) -> bytes:
    buf = io.BytesIO()
    _Pickler(buf, sim).dump(obj)
    return buf.getvalue()


def run_state(sim: Any) -> dict[str, Any]:
    """What a checkpoint saves of ``sim``: its attributes, less :data:`UNSAVED`."""
    return {k: v for k, v in vars(sim).items() if k not in UNSAVED}


def _check_savable(sim: Any) -> None:
    """ConfigError if ``sim`` has a part no checkpoint can hold: a user's loop hook (which
    the user holds too: a restored run would call a copy of it)."""
    user_hooks = sim.hooks[sim.engine_hooks:]
    if user_hooks:
        raise ConfigError(f"a run with a user's loop hook ({type(user_hooks[0]).__name__}) "
                          "cannot be checkpointed: a restored run would call a copy of it, "
                          "not yours", key="hooks")


def _culprit(sim: Any, name: str, value: Any, depth: int = 5) -> str:
    """The path of the deepest part of ``value`` (``name``) that does not pickle: its
    attributes, list items and dict values, ``depth`` levels down."""
    if depth == 0:
        return name
    if value is sim or name == "sim":
        parts = [(f"sim.{k}", v) for k, v in (run_state(sim) if value is sim else value).items()]
    elif isinstance(value, dict):
        parts = [(f"{name}[{k!r}]", v) for k, v in value.items()]
    elif isinstance(value, (list, tuple)):
        parts = [(f"{name}[{i}]", v) for i, v in enumerate(value)]
    elif hasattr(value, "__dict__") and not isinstance(value, type):
        parts = [(f"{name}.{k}", v) for k, v in vars(value).items()]
    else:
        return name
    for part, item in parts:
        try:
            _pickled(sim, item)
        except Exception:  # noqa: BLE001 - the part that fails, whatever it raises
            return _culprit(sim, part, item, depth - 1)
    return name


def dumps(sim: Any, extra: Any = None) -> bytes:
    """A checkpoint of ``sim`` (between two ticks) as bytes, with the caller's ``extra``.
    ConfigError if the run holds something that cannot be saved (naming it)."""
    _check_savable(sim)
    payload = {"state": run_state(sim), "extra": extra}
    try:
        body = _pickled(sim, payload)
    except Exception as exc:  # noqa: BLE001 - pickling a user's object may raise anything
        where = _culprit(sim, "sim", payload["state"])
        if where == "sim" and extra is not None:
            where = _culprit(sim, "extra", extra)
        raise ConfigError(f"cannot save {where}: {type(exc).__name__}: {exc}",
                          key="checkpoint") from None
    header = {"format": FORMAT, "code_version": code_version(), "tick": int(sim.tick),
              "world": sim.world.name, "controller": sim.controller_name,
              "body_bytes": len(body), "body_sha256": hashlib.sha256(body).hexdigest()}
    return MAGIC + json.dumps(header, sort_keys=True).encode("utf-8") + b"\n" + body


def save(sim: Any, path: str | Path, extra: Any = None) -> Any:
    """Write a checkpoint of ``sim`` (and ``extra``) to ``path``, atomically, then re-seat
    ``sim`` on it: the run goes on from the state loaded back from those bytes, as a restore
    of the file would (see the module's docstring). Returns the ``extra`` loaded back (the
    caller goes on with it, as a restore would). ConfigError (nothing written) if the run
    holds something that cannot be saved."""
    data = dumps(sim, extra)
    atomic_write_bytes(path, data)
    _, offset = _split(data, Path(path))
    return _load_into(sim, data[offset:])


def _split(data: bytes, path: Path) -> tuple[dict[str, Any], int]:
    """The header of checkpoint bytes ``data`` (read from ``path``) and its body's offset,
    checked (format, code version, body length and digest). ConfigError naming the file."""
    if not data.startswith(MAGIC):
        raise ConfigError("not a swarmsim checkpoint (no checkpoint header)", source=str(path))
    end = data.find(b"\n", len(MAGIC))
    try:
        header = json.loads(data[len(MAGIC):end]) if end >= 0 else None
    except (json.JSONDecodeError, UnicodeDecodeError):
        header = None
    if not isinstance(header, dict):
        raise ConfigError("damaged checkpoint header", source=str(path))
    if header.get("format") != FORMAT:
        raise ConfigError(f"checkpoint format {header.get('format')!r}; this code reads "
                          f"format {FORMAT}", source=str(path))
    ours = code_version()
    if header.get("code_version") != ours:
        raise ConfigError(f"checkpoint written by swarmsim {header.get('code_version')!r}, "
                          f"this is {ours!r}: restore it with the code that wrote it",
                          source=str(path))
    body = memoryview(data)[end + 1:]
    if len(body) != header.get("body_bytes"):
        raise ConfigError(f"truncated or damaged checkpoint ({len(body)} bytes after the "
                          f"header, {header.get('body_bytes')!r} written)", source=str(path))
    if hashlib.sha256(body).hexdigest() != header.get("body_sha256"):
        raise ConfigError("damaged checkpoint (its contents do not match their digest)",
                          source=str(path))
    return header, end + 1


def read_header(path: str | Path) -> dict[str, Any]:
    """The header of the checkpoint at ``path`` (format, code_version, tick, world,
    controller, body_bytes, body_sha256), checked as :func:`load` checks it."""
    return _split(_read(Path(path)), Path(path))[0]


def _read(path: Path) -> bytes:
    try:
        return path.read_bytes()
    except OSError as exc:
        raise ConfigError(f"cannot read checkpoint: {exc.strerror}", source=str(path)) from None


def _load_into(target: Any, body: bytes) -> Any:
    """Give ``target`` (a Simulation, new or the one that saved) the state in checkpoint
    ``body``; returns the body's ``extra``. The run's stop reason is asked again (stop rules
    only answer: swarmsim.engine.hooks), so that a file saved from an ``on_tick`` callback
    continues as the run that saved it does."""
    payload = _Unpickler(io.BytesIO(body), target).load()
    kept = {k: v for k, v in vars(target).items() if k in UNSAVED}
    target.__dict__ = {**payload["state"], **kept}  # one assignment: never half re-seated
    target.stop_reason = target.finished()
    return payload["extra"]


def load(path: str | Path, cls: type) -> tuple[Any, Any]:
    """The run saved at ``path`` (a new ``cls``, the Simulation class) at its saved tick,
    ready to continue, and the ``extra`` saved with it. ConfigError (one line naming the
    file) if it is not a checkpoint this code can read, or is truncated or damaged."""
    path = Path(path)
    data = _read(path)
    _, offset = _split(data, path)
    sim = cls.__new__(cls)
    importable_from_here()  # a user's module:Class, pickled by name, loads as it was found
    try:
        extra = _load_into(sim, data[offset:])
    except ConfigError:
        raise
    except Exception as exc:  # noqa: BLE001 - a body that passed its digest but cannot load
        raise ConfigError(f"cannot load checkpoint ({type(exc).__name__}: {exc})",
                          source=str(path)) from None
    return sim, extra
