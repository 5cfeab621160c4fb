"""Chipmunk's body functions, callable from compiled code (numba), so that a loop over many
bodies runs without a Python call per body.

pymunk reaches Chipmunk through cffi, one Python call per body and function. numba calls a C
function through a ctypes function pointer at the cost of a C call, and takes such a pointer as
an argument (a first-class function), so the compiled code stays cacheable.

``cpBodySetVelocity`` takes a ``cpVect`` (two doubles) by value, and ``cpBodyGetPosition``
returns one. On the platforms listed in ``_SAME_ABI`` such a struct travels exactly as two
doubles do, both ways (the SysV x86-64 ABI: two SSE registers; AArch64: a homogeneous float
aggregate, two vector registers). So the setter is declared as taking two doubles, and the
getters are called by :func:`read_vects` through an LLVM call returning ``{double, double}``,
which LLVM lowers to those registers. Elsewhere (Windows x64 passes and returns it through
memory) :func:`body_calls` returns None and callers use pymunk's own calls. :func:`body_calls`
also checks every function once, on bodies of its own, before anyone relies on it.
"""

from __future__ import annotations

import ctypes
import functools
import platform
import sys
import warnings
from collections.abc import Sequence
from dataclasses import dataclass
from typing import Any

import numpy as np
import pymunk
from llvmlite import ir
from numba import njit, types
from numba.core.errors import NumbaError
from numba.extending import intrinsic
from pymunk._chipmunk_cffi import ffi, lib

_SAME_ABI = {"x86_64", "amd64", "aarch64", "arm64"}


@dataclass(frozen=True)
class BodyCalls:
    """Chipmunk body functions as ctypes pointers, to pass to compiled code.

    Attributes:
        set_velocity: ``(body address, vx, vy)``, velocity in units per second of pymunk time.
        activate: ``(body address)``, wakes a sleeping body and its component.
        set_type: ``(body address, type)``, a pymunk body type (DYNAMIC, KINEMATIC, STATIC).
        is_sleeping: ``(body address) -> 0 or 1``, is the body asleep in pymunk.
        get_position: the address of ``cpBodyGetPosition``, for :func:`read_vects`.
        get_velocity: the address of ``cpBodyGetVelocity``, for :func:`read_vects`.
    """

    set_velocity: Any
    activate: Any
    set_type: Any
    is_sleeping: Any
    get_position: int
    get_velocity: int


def address(body: pymunk.Body) -> int:
    """The ``cpBody *`` of a pymunk body, as an integer (valid while the body lives)."""
    return int(ffi.cast("uintptr_t", body._body))


def addresses(bodies: Sequence[pymunk.Body]) -> np.ndarray:
    """(len,) uintp: :func:`address` of each body."""
    return np.array([address(b) for b in bodies], dtype=np.uintp)


def _address_of(name: str) -> int:
    return int(ffi.cast("uintptr_t", ffi.addressof(lib, name)))


def _pointer(name: str, restype: Any, *argtypes: Any) -> Any:
    return ctypes.CFUNCTYPE(restype, *argtypes)(_address_of(name))


@intrinsic
def _vect_of(typingctx, function, body):
    """Call ``cpVect function(const cpBody *body)``, both given as addresses: (x, y)."""
    if not (isinstance(function, types.Integer) and isinstance(body, types.Integer)):
        return None

    def codegen(context, builder, signature, args):
        double, byte_ptr = ir.DoubleType(), ir.IntType(8).as_pointer()
        call_type = ir.FunctionType(ir.LiteralStructType([double, double]), [byte_ptr])
        callee = builder.inttoptr(args[0], call_type.as_pointer())
        vect = builder.call(callee, [builder.inttoptr(args[1], byte_ptr)])
        return context.make_tuple(builder, signature.return_type,
                                  [builder.extract_value(vect, 0), builder.extract_value(vect, 1)])

    return types.UniTuple(types.float64, 2)(function, body), codegen


@njit(cache=True)
def read_vects(getter, bodies, out):  # pragma: no cover - compiled
    """``out[k] = getter(bodies[k])`` for a ``cpVect`` getter (BodyCalls.get_position or
    get_velocity) and body addresses ``bodies`` (K,); ``out`` (K, 2) float64."""
    for k in range(len(bodies)):
        out[k, 0], out[k, 1] = _vect_of(getter, bodies[k])


@njit(cache=True)
def read_flags(is_sleeping, bodies, out):  # pragma: no cover - compiled
    """``out[k] = is_sleeping(bodies[k]) != 0`` for body addresses ``bodies`` (K,)."""
    for k in range(len(bodies)):
        out[k] = is_sleeping(bodies[k]) != 0


@functools.cache
def body_calls() -> BodyCalls | None:
    """The body functions for compiled code, or None where their calling convention is not
    known to match (then call pymunk's ``lib`` functions one by one instead)."""
    if sys.platform == "win32" or platform.machine().lower() not in _SAME_ABI:
        return None
    calls = BodyCalls(
        set_velocity=_pointer("cpBodySetVelocity", None, ctypes.c_void_p, ctypes.c_double,
                              ctypes.c_double),
        activate=_pointer("cpBodyActivate", None, ctypes.c_void_p),
        set_type=_pointer("cpBodySetType", None, ctypes.c_void_p, ctypes.c_int),
        is_sleeping=_pointer("cpBodyIsSleeping", ctypes.c_ubyte, ctypes.c_void_p),
        get_position=_address_of("cpBodyGetPosition"),
        get_velocity=_address_of("cpBodyGetVelocity"))
    try:
        works = _works(calls)
    except (RuntimeError, NumbaError) as error:  # e.g. under a numba setting that breaks them
        warnings.warn(f"compiled Chipmunk calls unavailable ({type(error).__name__}: "
                      f"{str(error).splitlines()[0] if str(error) else ''}); pymunk's own "
                      "calls are used (slower, the same runs)", RuntimeWarning, stacklevel=2)
        return None
    return calls if works else None


def _works(calls: BodyCalls) -> bool:
    """Do the compiled calls do what pymunk's own calls do, on bodies of their own?"""
    space = pymunk.Space()
    space.sleep_time_threshold = 0.01
    body, resting = pymunk.Body(body_type=pymunk.Body.KINEMATIC), pymunk.Body(1.0, 1.0)
    body.position, resting.position = (0.5, -2.25), (40.0, 40.0)
    space.add(body, resting, pymunk.Circle(resting, 1.0))
    calls.set_velocity(address(body), 1.25, -3.5)
    calls.set_type(address(body), pymunk.Body.STATIC)
    stopped = tuple(body.velocity) == (0.0, 0.0)  # Chipmunk zeroes a static body's velocity
    calls.set_type(address(body), pymunk.Body.KINEMATIC)
    calls.set_velocity(address(body), 1.25, -3.5)
    for _ in range(5):
        space.step(0.1)
    both = addresses([body, resting])
    vects, flags = np.zeros((2, 2)), np.zeros(2, dtype=bool)
    read_vects(calls.get_velocity, both, vects)
    same = vects.tolist() == [list(body.velocity), list(resting.velocity)]
    read_vects(calls.get_position, both, vects)
    same = same and vects.tolist() == [list(body.position), list(resting.position)]
    read_flags(calls.is_sleeping, both, flags)
    same = same and flags.tolist() == [False, True] == [body.is_sleeping, resting.is_sleeping]
    return (stopped and same and body.body_type == pymunk.Body.KINEMATIC
            and tuple(body.velocity) == (1.25, -3.5))
