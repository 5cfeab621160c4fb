"""A chunk's neighbour columns as the compiled driver (decide.py) takes them: :class:`Heard`."""

from __future__ import annotations

from collections import namedtuple

import numba
from numba import types
from numba.extending import typeof_impl

from .schema import HEARD_FIELDS

Heard = namedtuple("Heard", HEARD_FIELDS)
"""A chunk's neighbour columns (schema.HEARD_FIELDS): ``starts`` (robots + 1,), robot j's
neighbours being rows ``starts[j]:starts[j+1]``, then the View's columns (rules/common.py)
over all of them: ``off`` and ``dist``, then each broadcast field's column, a strided view
of the heard messages."""

OWN_COLUMNS = ("starts", "off", "dist")
"""Heard's columns made for the chunk (C-contiguous); the others are views of the messages."""


@typeof_impl.register(Heard)
def _typeof_heard(heard: Heard, context) -> types.NamedTuple:
    """numba's type of a Heard: every broadcast column typed strided ('A').

    numba types an array C-contiguous when numpy flags it so, as it does every array of 0 or
    1 rows: a chunk that heard one message (a lone awake robot) would then need a driver
    compiled anew for its types, mid-run (about a minute). Typed 'A', one compiled driver
    takes every chunk (numba converts a C-contiguous column to 'A' on the call)."""
    return types.NamedTuple(
        [numba.typeof(column) if name in OWN_COLUMNS else numba.typeof(column).copy(layout="A")
         for name, column in heard._asdict().items()], Heard)
