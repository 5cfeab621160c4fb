"""Controllers built from mixins: no mixin's method silently replaces another's.

GGCRobot's surplus ``give_up`` once shadowed the aggregation mixin's ``give_up`` of the same
name: robots not formed in time stopped for good as Surplus instead of covering on their own.
"""

import importlib
from collections import defaultdict

from swarmsim.controller import available_controllers, get_controller

DELIBERATE_OVERRIDES = {("fcdfs", "formation_gradient")}
"""(controller, method) pairs where a class overrides its mixin's method on purpose."""


def shadowed_methods(cls: type) -> dict[str, list[str]]:
    """Methods (and properties) defined by more than one class of ``cls``'s MRO."""
    owners = defaultdict(list)
    for klass in cls.__mro__[:-1]:  # not object
        for name, value in vars(klass).items():
            if name.startswith("__"):
                continue
            if callable(value) or isinstance(value, (property, staticmethod, classmethod)):
                owners[name].append(klass.__name__)
    return {name: classes for name, classes in owners.items() if len(classes) > 1}


REFERENCES = {"kilobot": "KilobotRobot", "fcdfs": "FCDFSRobot"}
"""Batch controllers whose per-robot reference (in the same package) is built from mixins."""


def test_no_controller_method_is_shadowed_by_accident():
    found = {}
    for name in available_controllers():
        cls = get_controller(name)
        reference = REFERENCES.get(name)
        classes = [cls] if reference is None else [
            cls, getattr(importlib.import_module(cls.__module__.rpartition(".")[0]), reference)]
        for klass in classes:
            for method, owners in shadowed_methods(klass).items():
                if (name, method) not in DELIBERATE_OVERRIDES:
                    found[(name, method)] = owners
    assert found == {}


def test_the_check_sees_a_shadowed_method():
    class First:
        def give_up(self):
            return "surplus"

    class Second:
        def give_up(self):
            return "cover alone"

    class Robot(First, Second):
        pass

    assert shadowed_methods(Robot) == {"give_up": ["First", "Second"]}
