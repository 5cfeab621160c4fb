"""The engine's fast makers for Perception and Action make the very objects the classes do."""

import dataclasses
import inspect

import numpy as np
import pytest

from swarmsim.controller import Action, Perception, make_action, make_perception


@pytest.mark.parametrize(("cls", "make"), [(Perception, make_perception), (Action, make_action)])
def test_a_maker_takes_the_fields_of_its_class_in_order_with_their_defaults(cls, make):
    params = inspect.signature(make).parameters
    fields = dataclasses.fields(cls)
    assert list(params) == [f.name for f in fields]
    for f in fields:
        default = params[f.name].default
        assert default == (inspect.Parameter.empty if f.default is dataclasses.MISSING
                           else f.default)


@pytest.mark.parametrize(("cls", "make"), [(Perception, make_perception), (Action, make_action)])
def test_a_made_object_equals_the_constructed_one_and_is_frozen(cls, make):
    values = [object() for _ in dataclasses.fields(cls)]  # distinct: a swapped field shows
    made = make(*values)
    assert type(made) is cls
    assert made == cls(*values)
    assert [getattr(made, f.name) for f in dataclasses.fields(cls)] == values
    with pytest.raises(dataclasses.FrozenInstanceError):
        made.__setattr__(dataclasses.fields(cls)[0].name, 1)


def test_make_action_fills_defaults_like_the_class():
    assert make_action() == Action()
    assert make_action((1.0, 2.0), sleep=True, listen=3.0) == Action((1.0, 2.0), sleep=True,
                                                                     listen=3.0)
    p = make_perception(3, np.zeros((0, 2)), np.zeros(0), None, True, None, None, np.zeros(2))
    assert p.tick == 3 and p.on_target
