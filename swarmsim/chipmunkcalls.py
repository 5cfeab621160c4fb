"""Chipmunk's body functions, callable from compiled code (numba), so that a loop over many
bodies runs without a Python call per body.

pymunk reaches Chipmunk through cffi; each call from Python costs ~0.4 µs. numba calls a C
function through a ctypes function pointer at the cost of a C call, and takes such a pointer as
an argument (a first-class function), so the compiled code stays cacheable.

``cpBodySetVelocity`` takes a ``cpVect`` (two doubles) by value. On the platforms listed in
``_SAME_ABI`` such a struct travels exactly as two double arguments do (the SysV x86-64 ABI:
two SSE registers; AArch64: a homogeneous float aggregate, two vector registers), so the pointer
is declared as taking two doubles. Elsewhere (Windows x64 passes it by reference)
:func:`body_calls` returns None and callers use pymunk's own calls. :func:`body_calls` also
checks the result once, on a body of its own, before anyone relies on it.
"""

from __future__ import annotations

import ctypes
import functools
import platform
import sys
from dataclasses import dataclass
from typing import Any

import pymunk
from pymunk._chipmunk_cffi import ffi, lib

_SAME_ABI = {"x86_64", "amd64", "aarch64", "arm64"}


@dataclass(frozen=True)
class BodyCalls:
    """Chipmunk body functions as ctypes pointers, to pass to compiled code.

    Attributes:
        set_velocity: ``(body address, vx, vy)``, velocity in units per second of pymunk time.
        activate: ``(body address)``, wakes a sleeping body and its component.
        set_type: ``(body address, type)``, a pymunk body type (DYNAMIC, KINEMATIC, STATIC).
    """

    set_velocity: Any
    activate: Any
    set_type: Any


def address(body: pymunk.Body) -> int:
    """The ``cpBody *`` of a pymunk body, as an integer (valid while the body lives)."""
    return int(ffi.cast("uintptr_t", body._body))


def _pointer(name: str, restype: Any, *argtypes: Any) -> Any:
    where = int(ffi.cast("uintptr_t", ffi.addressof(lib, name)))
    return ctypes.CFUNCTYPE(restype, *argtypes)(where)


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
        set_type=_pointer("cpBodySetType", None, ctypes.c_void_p, ctypes.c_int))
    return calls if _works(calls) else None


def _works(calls: BodyCalls) -> bool:
    """Do the pointers do what pymunk's own calls do, on a body of their own?"""
    body = pymunk.Body(body_type=pymunk.Body.KINEMATIC)
    space = pymunk.Space()
    space.add(body)
    calls.set_velocity(address(body), 1.25, -3.5)
    calls.set_type(address(body), pymunk.Body.STATIC)
    moved = tuple(body.velocity) == (0.0, 0.0)  # Chipmunk zeroes a static body's velocity
    calls.set_type(address(body), pymunk.Body.KINEMATIC)
    calls.set_velocity(address(body), 1.25, -3.5)
    return moved and tuple(body.velocity) == (1.25, -3.5) and body.body_type == pymunk.Body.KINEMATIC
