"""Chipmunk's body functions, callable from compiled code (numba), so that a loop over many
bodies runs without a Python call per body.

pymunk reaches Chipmunk through cffi, one Python call per body and function. Here each
function is passed to compiled code as its address, a plain integer, and called through an
LLVM call of the function's C type (the intrinsics below): a C call per body, and the compiled
code stays cacheable (the address is an argument, not a constant). Plain integers also keep
numba's dispatch cheap (a ctypes function pointer as an argument is converted on every call).

``cpBodySetVelocity`` takes a ``cpVect`` (two doubles) by value, and ``cpBodyGetPosition``
returns one. On the platforms listed in ``_SAME_ABI`` such a struct travels exactly as two
doubles do, both ways (the SysV x86-64 ABI: two SSE registers; AArch64: a homogeneous float
aggregate, two vector registers). So the setter is called as taking two doubles, and the
getters through an LLVM call returning ``{double, double}``, which LLVM lowers to those
registers. Elsewhere (Windows x64 passes and returns it through memory) :func:`body_calls`
returns None and callers use pymunk's own calls. :func:`body_calls` also checks every
function once, on bodies of its own, before anyone relies on it.
"""

from __future__ import annotations

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

_KINEMATIC, _STATIC = int(pymunk.Body.KINEMATIC), int(pymunk.Body.STATIC)

_SAME_ABI = {"x86_64", "amd64", "aarch64", "arm64"}


@dataclass(frozen=True)
class BodyCalls:
    """The addresses of Chipmunk's body functions, to pass to compiled code (each called
    through the intrinsic named).

    Attributes:
        set_velocity: ``cpBodySetVelocity(body, vx, vy)`` (:func:`call_body_xy`), velocity in
            units per second of pymunk time.
        activate: ``cpBodyActivate(body)`` (:func:`call_body`): wakes a sleeping body and its
            component.
        set_type: ``cpBodySetType(body, type)`` (:func:`call_body_int`), a pymunk body type
            (DYNAMIC, KINEMATIC, STATIC).
        is_sleeping: ``cpBodyIsSleeping(body) -> 0 or 1`` (:func:`call_body_flag`).
        get_position: ``cpBodyGetPosition`` (:func:`read_vects`).
        get_velocity: ``cpBodyGetVelocity`` (:func:`read_vects`).
    """

    set_velocity: int
    activate: int
    set_type: int
    is_sleeping: int
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


def _is_address(*values: Any) -> bool:
    """Are these numba types integers (addresses are passed as plain integers)?"""
    return all(isinstance(v, types.Integer) for v in values)


def _callee(builder: ir.IRBuilder, address: Any, result: Any, *params: Any) -> Any:
    """The C function at ``address`` (an integer value), of LLVM type ``result(*params)``."""
    return builder.inttoptr(address, ir.FunctionType(result, params).as_pointer())


_BYTE_PTR = ir.IntType(8).as_pointer()


@intrinsic
def call_body(typingctx, function, body):
    """Call ``void function(cpBody *body)``, both given as addresses."""
    if not _is_address(function, body):
        return None

    def codegen(context, builder, signature, args):
        callee = _callee(builder, args[0], ir.VoidType(), _BYTE_PTR)
        builder.call(callee, [builder.inttoptr(args[1], _BYTE_PTR)])
        return context.get_dummy_value()

    return types.none(function, body), codegen


@intrinsic
def call_body_int(typingctx, function, body, value):
    """Call ``void function(cpBody *body, int value)`` (an enum such as cpBodyType)."""
    if not (_is_address(function, body) and isinstance(value, types.Integer)):
        return None

    def codegen(context, builder, signature, args):
        callee = _callee(builder, args[0], ir.VoidType(), _BYTE_PTR, ir.IntType(32))
        value = context.cast(builder, args[2], signature.args[2], types.int32)
        builder.call(callee, [builder.inttoptr(args[1], _BYTE_PTR), value])
        return context.get_dummy_value()

    return types.none(function, body, value), codegen


@intrinsic
def call_body_xy(typingctx, function, body, x, y):
    """Call ``void function(cpBody *body, cpVect (x, y))``, the vector passed as two doubles
    (the ABIs of ``_SAME_ABI``)."""
    if not (_is_address(function, body) and x == types.float64 and y == types.float64):
        return None

    def codegen(context, builder, signature, args):
        double = ir.DoubleType()
        callee = _callee(builder, args[0], ir.VoidType(), _BYTE_PTR, double, double)
        builder.call(callee, [builder.inttoptr(args[1], _BYTE_PTR), args[2], args[3]])
        return context.get_dummy_value()

    return types.none(function, body, x, y), codegen


@intrinsic
def call_body_double(typingctx, function, body, value):
    """Call ``void function(cpBody *body, cpFloat value)`` (cpFloat: a double)."""
    if not (_is_address(function, body) and value == types.float64):
        return None

    def codegen(context, builder, signature, args):
        callee = _callee(builder, args[0], ir.VoidType(), _BYTE_PTR, ir.DoubleType())
        builder.call(callee, [builder.inttoptr(args[1], _BYTE_PTR), args[2]])
        return context.get_dummy_value()

    return types.none(function, body, value), codegen


@intrinsic
def call_body_flag(typingctx, function, body):
    """Call ``cpBool function(const cpBody *body)``: 0 or 1 (cpBool is an unsigned char)."""
    if not _is_address(function, body):
        return None

    def codegen(context, builder, signature, args):
        callee = _callee(builder, args[0], ir.IntType(8), _BYTE_PTR)
        return builder.call(callee, [builder.inttoptr(args[1], _BYTE_PTR)])

    return types.uint8(function, body), codegen


@intrinsic
def _vect_of(typingctx, function, body):
    """Call ``cpVect function(const cpBody *body)``, both given as addresses: (x, y)."""
    if not _is_address(function, body):
        return None

    def codegen(context, builder, signature, args):
        double = ir.DoubleType()
        callee = _callee(builder, args[0], ir.LiteralStructType([double, double]), _BYTE_PTR)
        vect = builder.call(callee, [builder.inttoptr(args[1], _BYTE_PTR)])
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
        out[k] = call_body_flag(is_sleeping, bodies[k]) != 0


def command(calls: BodyCalls, robot_at: np.ndarray, control_at: np.ndarray,
            to_unpark: np.ndarray, to_park: np.ndarray, write: np.ndarray, v: np.ndarray
            ) -> None:
    """Parking's Chipmunk calls in one compiled pass, in its order: unpark robots
    ``to_unpark`` (wake the robot's body ``robot_at[i]`` first, then make its control body
    ``control_at[i]`` KINEMATIC), park ``to_park`` (control body STATIC), then set the control
    bodies' velocities ``v[i]`` of ``write`` (units per second of pymunk time)."""
    _command(calls.activate, calls.set_type, calls.set_velocity, robot_at, control_at,
             to_unpark, to_park, write, v)


@njit(cache=True)
def _command(activate, set_type, set_velocity, robot_at, control_at, to_unpark, to_park,
             write, v):  # pragma: no cover - compiled
    _unpark_and_park(activate, set_type, robot_at, control_at, to_unpark, to_park)
    for i in write:
        call_body_xy(set_velocity, control_at[i], v[i, 0], v[i, 1])


@njit(cache=True)
def _unpark_and_park(activate, set_type, robot_at, control_at, to_unpark,
                     to_park):  # pragma: no cover - compiled
    """Wake each robot of ``to_unpark`` and make its control body kinematic again, then make
    the control bodies of ``to_park`` static (Parking's order)."""
    for i in to_unpark:
        call_body(activate, robot_at[i])
        call_body_int(set_type, control_at[i], _KINEMATIC)
    for i in to_park:
        call_body_int(set_type, control_at[i], _STATIC)


def command_spin(calls: BodyCalls, set_spin: int, robot_at: np.ndarray, control_at: np.ndarray,
                 to_unpark: np.ndarray, to_park: np.ndarray, write: np.ndarray, v: np.ndarray,
                 w: np.ndarray) -> None:
    """:func:`command` for a steering drive, in Parking.command_spin's order: unpark, park,
    then for each robot of ``write`` its control body's velocity ``v[i]`` and then its spin
    ``w[i]`` (``set_spin``: :func:`spin_setter`'s address)."""
    _command_spin(calls.activate, calls.set_type, calls.set_velocity, set_spin, robot_at,
                  control_at, to_unpark, to_park, write, v, w)


@njit(cache=True)
def _command_spin(activate, set_type, set_velocity, set_spin, robot_at, control_at, to_unpark,
                  to_park, write, v, w):  # pragma: no cover - compiled
    _unpark_and_park(activate, set_type, robot_at, control_at, to_unpark, to_park)
    for i in write:
        call_body_xy(set_velocity, control_at[i], v[i, 0], v[i, 1])
        call_body_double(set_spin, control_at[i], w[i])


@functools.cache
def spin_setter(calls: BodyCalls) -> int | None:
    """The address of ``cpBodySetAngularVelocity`` for :func:`command_spin`, once it has been
    seen to do what pymunk's own call does on a body of its own; None if not (then pymunk's
    calls are used). Asked only by runs with a steering drive (a holonomic run loads no
    kernel of it)."""
    set_spin = _address_of("cpBodySetAngularVelocity")
    space = pymunk.Space()
    body, robot = pymunk.Body(body_type=pymunk.Body.KINEMATIC), pymunk.Body(1.0, 1.0)
    space.add(body, robot)
    one, none = np.zeros(1, np.int64), np.zeros(0, np.int64)
    try:
        command_spin(calls, set_spin, addresses([robot]), addresses([body]), none, none, one,
                     np.array([[1.25, -3.5]]), np.array([0.75]))
    except (RuntimeError, NumbaError) as error:
        warnings.warn(f"compiled Chipmunk spin calls unavailable ({type(error).__name__}); "
                      "pymunk's own calls are used (slower, the same runs)", RuntimeWarning,
                      stacklevel=2)
        return None
    works = tuple(body.velocity) == (1.25, -3.5) and body.angular_velocity == 0.75
    return set_spin if works else None


@functools.cache
def body_calls() -> BodyCalls | None:
    """The body functions for compiled code, or None where their calling convention is not
    known to match (then call pymunk's ``lib`` functions one by one instead)."""
    if sys.platform == "win32" or platform.machine().lower() not in _SAME_ABI:
        return None
    calls = BodyCalls(
        set_velocity=_address_of("cpBodySetVelocity"),
        activate=_address_of("cpBodyActivate"),
        set_type=_address_of("cpBodySetType"),
        is_sleeping=_address_of("cpBodyIsSleeping"),
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
    """Do the compiled calls do what pymunk's own calls do, on bodies of their own? Only the
    kernels a run uses are called (no extra compiled code to load)."""
    space = pymunk.Space()
    space.sleep_time_threshold = 0.01
    body, resting = pymunk.Body(body_type=pymunk.Body.KINEMATIC), pymunk.Body(1.0, 1.0)
    body.position, resting.position = (0.5, -2.25), (40.0, 40.0)
    space.add(body, resting, pymunk.Circle(resting, 1.0))
    robot_at, control_at = addresses([resting]), addresses([body])
    one, none, v = np.zeros(1, np.int64), np.zeros(0, np.int64), np.array([[1.25, -3.5]])
    command(calls, robot_at, control_at, none, none, one, v)  # a velocity
    written = tuple(body.velocity) == (1.25, -3.5)
    command(calls, robot_at, control_at, none, one, none, v)  # parked
    parked = body.body_type == pymunk.Body.STATIC and tuple(body.velocity) == (0.0, 0.0)
    command(calls, robot_at, control_at, one, none, one, v)  # unparked, the velocity again
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
    command(calls, robot_at, control_at, one, none, none, v)  # wakes the resting body
    return (written and parked and same and body.body_type == pymunk.Body.KINEMATIC
            and tuple(body.velocity) == (1.25, -3.5) and not resting.is_sleeping)
