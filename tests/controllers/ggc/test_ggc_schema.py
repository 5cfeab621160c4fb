"""GGC's schema (controllers/ggc/schema.py): one name per datum in state, broadcast and view,
the generated module current, RuleParams made of GGCParams' fields, each flag's scope."""

from __future__ import annotations

import ast
import math
from dataclasses import fields

import numba
import numpy as np

from controllers.ggc import GGC, GGCParams
from controllers.ggc.decide import DERIVED, PARAM_NAMES, RuleParams
from controllers.ggc.heard import Heard
from controllers.ggc.rules.rulesets import ANY_GROUPS, BETWEEN_GROUPS, FLAG_SCOPE, RULESETS
from controllers.ggc.schema import (
    BASE,
    BASE_NAMES,
    BROADCAST_NAMES,
    DATA,
    GENERATED,
    PER_GROUP,
    REGENERATE,
    VIEW_FIELDS,
    PerGroup,
    generated_source,
    message_fields,
)
from controllers.ggc.state import STATE_DTYPE, new_per_group, new_state
from controllers.ggc.swarm import rule_params
from swarmsim.controller import RobotSetup, message_dtype
from tests.ggc_bot import view

RULES = GENERATED.parent / "rules"


def test_the_generated_module_is_current():
    assert GENERATED.read_text() == generated_source(), f"stale: run {REGENERATE}"


def _assignments(function: str) -> list[tuple[str, str]]:
    """(target, value) source texts of the assignments in _generated.py's ``function``."""
    tree = ast.parse(GENERATED.read_text())
    body = next(n for n in tree.body if isinstance(n, ast.FunctionDef) and n.name == function)
    return [(ast.unparse(n.targets[0]), ast.unparse(n.value))
            for n in ast.walk(body) if isinstance(n, ast.Assign)]


def test_state_broadcast_and_view_call_each_datum_by_one_name():
    names = [d.name for d in DATA]
    assert len(set(names)) == len(names)
    assert STATE_DTYPE.names + PerGroup._fields == tuple(
        [d.name for d in DATA if not d.per_group] + [d.name for d in PER_GROUP])
    assert PerGroup._fields == ("ldist", "lepoch")  # the rules' mine.NAME
    broadcast = message_dtype(message_fields(3, scattered=True))
    assert broadcast.names == BROADCAST_NAMES
    own = [d.name for d in DATA if d.broadcast not in (None, BASE)]
    assert [name for name in BROADCAST_NAMES if name not in BASE_NAMES] == own
    assert set(BROADCAST_NAMES) - set(names) == {"moving"}  # computed from the status
    assert tuple(numba.typeof(view([((1.0, 0.0), 0, 1, 0)])).field_dict) == VIEW_FIELDS
    assert VIEW_FIELDS == ("off", "dist", *BROADCAST_NAMES)
    assert Heard._fields == ("starts", *VIEW_FIELDS)
    # the generated code copies each field to the field of the same name
    pointed = _assignments("point_view")
    assert pointed == [(f"view.{n}", f"heard.{n}[a:b]") for n in VIEW_FIELDS]
    copied = {target.split(".")[1].split("[")[0]: value for target, value in
              _assignments("copy_broadcast")}
    assert set(copied) == set(BROADCAST_NAMES) - {"moving"}
    assert all(value.startswith(f"{'mine' if name in PerGroup._fields else 'me'}.{name}")
               for name, value in copied.items())
    assert GGC.SILENT == {"gradient": np.iinfo(np.int32).max}  # a colouring's name too


def test_every_broadcast_field_is_read_by_a_rule():
    """A field broadcast but never heard costs every tick's copy of every heard message."""
    source = "\n".join(f.read_text() for f in RULES.glob("*.py"))
    unread = [name for name in BROADCAST_NAMES if f"view.{name}[" not in source]
    assert unread == []


def test_per_group_fields_have_one_entry_per_group_only_in_a_scattered_start():
    for d in DATA:
        if d.per_group:
            assert message_dtype(message_fields(5, True))[d.name].shape == (5,)
            assert message_dtype(message_fields(5, False))[d.name].shape == (0,)


def test_a_new_row_holds_each_datums_initial_value():
    setups = [RobotSetup(robot_id=i, leader=False, group=1, groups=2, scattered=True)
              for i in range(3)]
    state = new_state(setups, orbit=1, h_max=5, rngs=[np.random.default_rng(i) for i in range(3)])
    per_group = new_per_group(setups)
    by_setup = {"id", "group", "leader", "status", "visited", "gradient", "gradient_low", "sense",
                "h", "rng"}
    for d in DATA:
        if d.name in by_setup:
            continue
        column = getattr(per_group, d.name) if d.per_group else state[d.name]
        assert len(column) == 3 and (not d.per_group or column.shape == (3, 2)), d.name
        values = column.ravel().tolist()
        if isinstance(d.initial, float) and math.isnan(d.initial):
            assert all(math.isnan(v) for v in values), d.name
        else:
            assert values == [d.initial] * len(values), d.name


def test_rule_params_are_ggc_params_fields_and_the_declared_derived_values():
    params = GGCParams(d_cover=4, T_r=50, surplus_spread=False)
    rules = rule_params(params, groups=2, scattered=False)
    numeric = [f.name for f in fields(GGCParams) if f.type in ("float", "int", "bool")]
    assert list(PARAM_NAMES) == numeric
    assert RuleParams._fields == (*numeric, *DERIVED)
    assert not set(DERIVED) & {f.name for f in fields(GGCParams)}  # one name, one meaning
    for name in numeric:
        assert getattr(rules, name) == getattr(params, name)
        assert type(getattr(rules, name)).__name__ == next(
            f.type for f in fields(GGCParams) if f.name == name)
    assert rules.d_cover == 4.0 and isinstance(rules.d_cover, float)
    assert rules.surplus_turn == math.radians(params.surplus_winding)


def test_every_flag_declares_its_scope():
    every = 0
    for flags in RULESETS.values():
        every |= flags
    assert sum(FLAG_SCOPE) == every and len(FLAG_SCOPE) == every.bit_count()
    lengths = {f.name for f in fields(GGCParams) if f.type == "float"}
    for scope in FLAG_SCOPE.values():
        assert scope in (ANY_GROUPS, BETWEEN_GROUPS) or scope in lengths
