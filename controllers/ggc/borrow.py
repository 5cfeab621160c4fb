"""Borrowed array views for compiled code: the same array, not reference-counted.

numba counts a reference to every array it passes to a compiled function up and down on each
call (atomic operations). A GGC rule is given the robot's view, one array slice per field of
schema.VIEW_FIELDS, and a decision makes dozens of rule calls (the view is one struct passed
by pointer, rules/common.py, whose fields are these slices). The driver's arrays are its arguments, which the caller holds
for the whole call, so it hands the rules borrowed views of them: the same data, shape and
strides, and no reference count (a null meminfo, which numba's counting skips).

Borrow only a compiled function's ARGUMENTS. numba frees a local array after its last use,
even while a borrowed view of it is still read: heap corruption.
"""

from __future__ import annotations

from numba import types
from numba.core import cgutils
from numba.extending import intrinsic


@intrinsic
def borrowed(typingctx, arr):  # pragma: no cover - compiled
    """``arr`` as a view that holds no reference: valid only while ``arr`` itself lives (an
    argument of the calling compiled function, held by its caller)."""
    if not isinstance(arr, types.Array):
        return None

    def codegen(context, builder, signature, args):
        source = context.make_array(arr)(context, builder, value=args[0])
        view = context.make_array(arr)(context, builder)
        for name in ("parent", "nitems", "itemsize", "data", "shape", "strides"):
            setattr(view, name, getattr(source, name))
        view.meminfo = cgutils.get_null_value(view.meminfo.type)
        return view._getvalue()

    return arr(arr), codegen
