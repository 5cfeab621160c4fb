"""A controller's mistakes: one line naming the controller, the robot and the tick.

Every way a controller can break the controller API (tests/bad_controllers.py: raising in
any of its hooks, returning what is not an Action, a velocity or a broadcast that does not
fit, sleep promises out of range) stops the run with ``swarmsim: error: controller 'NAME',
robot R, tick T: PROBLEM`` and exit status 2; an exception of the controller's own code keeps
its traceback below that line, without the engine's frames. The id of a broadcast is always
the sender's own.
"""

from __future__ import annotations

import dataclasses
import re
from pathlib import Path

import numpy as np
import pytest

import tests.bad_controllers as bad
from swarmsim import Simulation
from swarmsim.cli import main
from swarmsim.controller import Action, ChunkActions, available_controllers, get_controller
from swarmsim.engine.config import engine_settings
from swarmsim.errors import ConfigError, ControllerError
from swarmsim.experiments import run_sweep
from swarmsim.experiments.spec import RunSpec
from tests.errlines import error_lines

MODULE = "tests.bad_controllers"
AT = f"robot {bad.BAD_ROBOT}, tick {bad.BAD_TICK}"
"""Where each bad controller misbehaves (its robot and tick)."""
RUN = ["--robots", "6", "--max-ticks", "8", "--quiet"]

# (class, where, problem): what each one returns or raises, and the line that names it
RETURNS = [
    ("ReturnsNone", AT, "step() returned None; expected an Action"),
    ("ReturnsTuple", AT, r"step() returned (0.05, 0.0); expected an Action"),
    ("NanVelocity", AT, "step() returned the velocity (nan, 0.0); expected finite numbers"),
    ("InfVelocity", AT, "step() returned the velocity (0.0, -inf); expected finite numbers"),
    ("StringVelocity", AT, "step() returned the velocity ('fast', 0.0); expected two numbers"),
    ("NumericStringVelocity", AT, "step() returned the velocity ('1', '0'); expected two"),
    ("ThreeVelocity", AT, "step() returned a velocity of shape (3,); expected (vx, vy)"),
    ("ScalarVelocity", AT, "step() returned a velocity of shape (); expected (vx, vy)"),
    ("StringStatus", AT, ("step() returned a broadcast whose status is 'Walking'; expected a "
                         "status code: an integer in 0..1")),
    ("StatusOutOfRange", AT, ("step() returned a broadcast whose status is 2; expected a "
                             "status code: an integer in 0..1")),
    ("NegativeStatus", AT, "step() returned a broadcast whose status is -1; expected"),
    ("ShortTuple", AT, ("step() returned a broadcast tuple of 3 values; expected 5: "
                       "(id, status, moving, x, hops)")),
    ("LongTuple", AT, "step() returned a broadcast tuple of 6 values; expected 5"),
    ("UnknownField", AT, "step() returned a broadcast naming the unknown fields ['speed']"),
    ("TooBigForField", AT, ("step() returned a broadcast whose hops is 70000; expected an "
                           "integer in -32768..32767 (int16)")),
    ("FractionInIntField", AT, ("step() returned a broadcast whose hops is 2.5; expected an "
                               "integer")),
    ("StringInFloatField", AT, ("step() returned a broadcast whose x is 'left'; expected a "
                               "number")),
    ("MessageIsString", AT, "step() returned the broadcast 'hello'; expected a tuple"),
    ("NegativeListen", AT, "step() returned listen=-1.0; expected a distance >= 0"),
    ("NanListen", AT, "step() returned listen=nan; expected a distance >= 0"),
    ("StringListen", AT, "step() returned listen='far'; expected a distance >= 0"),
    ("StringSleep", AT, "step() returned sleep='no'; expected True or False"),
    ("NegativeWakeRange", AT, "step() returned wake_range=-2.0; expected a distance >= 0"),
    ("NanWakeRange", AT, "step() returned wake_range=nan; expected a distance >= 0"),
    ("NegativeWakeTick", AT, "step() returned wake_tick=-5; expected a tick: an integer >= 0"),
    ("FloatWakeTick", AT, "step() returned wake_tick=5.5; expected a tick: an integer >= 0"),
    ("StringWakeOnMotion", AT, ("step() returned wake_on_motion='never'; expected True or "
                               "False")),
    ("SummarizeReturnsList", "tick 8", "summarize() returned [1, 2]; expected a dict"),
    ("CreateSwarmReturnsNone", None, "create_swarm() returned None; expected a Swarm"),
    ("Batch_nan", AT, "decide() returned the velocity (0.05, nan); expected finite numbers"),
    ("Batch_status", AT, ("decide() returned a broadcast whose status is 9; expected a status "
                         "code: an integer in 0..0")),
    ("Batch_listen", AT, "decide() returned listen=-3.0; expected a distance >= 0"),
    ("Batch_wake_range", AT, "decide() returned wake_range=-1.0; expected a distance >= 0"),
    ("Batch_shape", f"tick {bad.BAD_TICK}", ("decide() returned velocities of shape (6, 1) "
                                            "and dtype float64; expected shape (6, 2)")),
    ("Batch_flat", f"tick {bad.BAD_TICK}", ("decide() returned velocities of shape (6,) "
                                           "and dtype float64; expected shape (6, 2)")),
    ("Batch_short", f"tick {bad.BAD_TICK}", ("decide() returned sleep of shape (5,) and dtype "
                                            "bool; expected shape (6,)")),
]

RAISES = [
    ("RaisesInStep", AT, "step() raised ZeroDivisionError: float division by zero",
     "user_helper"),
    ("RaisesInInit", f"robot {bad.BAD_ROBOT}", "__init__() raised RuntimeError: no battery",
     "__init__"),
    ("RaisesInCreateSwarm", None, "create_swarm() raised KeyError: 'layout'", "create_swarm"),
    ("RaisesInSummarize", "tick 8", ("summarize() raised ZeroDivisionError: float division "
     "by zero"), "summarize"),
    ("RaisesInSensingRange", None, "sensing_range() raised NotImplementedError: which range?",
     "sensing_range"),
    ("Batch_raise", f"tick {bad.BAD_TICK}", ("decide() raised ZeroDivisionError: batch "
                                             "division"), "decide"),
]

SETUP_FAILURES = ("RaisesInInit", "RaisesInCreateSwarm", "RaisesInSensingRange",
                  "CreateSwarmReturnsNone")
"""Controllers that fail before the run's first tick."""


def first_line(name: str, where: str | None) -> str:
    """The start of the line that names controller ``name`` misbehaving ``where``."""
    return f"swarmsim: error: controller '{MODULE}:{name}'" + (f", {where}: " if where else ": ")


def run_cli(name: str, capsys, *extra: str) -> tuple[int, list[str]]:
    code = main(["run", "tiny", "--controller", f"{MODULE}:{name}", *RUN, *extra])
    return code, error_lines(capsys.readouterr().err)


@pytest.mark.parametrize("name, where, problem", RETURNS, ids=[r[0] for r in RETURNS])
def test_what_the_engine_refuses_is_one_line_naming_controller_robot_and_tick(
        name, where, problem, capsys):
    code, err = run_cli(name, capsys)
    assert code == 2
    assert len(err) == 1, err  # no traceback: the controller raised nothing
    assert err[0].startswith(first_line(name, where) + problem), err[0]


def frames(lines: list[str]) -> list[str]:
    """The files of a printed traceback's frames."""
    return [m.group(1) for line in lines if (m := re.match(r'\s*File "([^"]+)"', line))]


@pytest.mark.parametrize("name, where, problem, function", RAISES, ids=[r[0] for r in RAISES])
def test_a_controllers_exception_is_the_line_then_its_own_frames(name, where, problem,
                                                                 function, capsys):
    code, err = run_cli(name, capsys)
    assert code == 2
    assert err[0] == first_line(name, where) + problem, err[0]
    assert err[1] == "Traceback (most recent call last):"
    files = frames(err)
    assert files and all(Path(f).name == "bad_controllers.py" for f in files), files
    assert any(line.strip().endswith(f"in {function}") for line in err), err
    engine = Path(__import__("swarmsim").__file__).parent
    assert not any(str(engine) in line or "numpy" in line for line in err[1:]), err


@pytest.mark.parametrize("name", SETUP_FAILURES)
def test_a_controller_failing_at_setup_leaves_no_output_folder(name, tmp_path, capsys):
    out = tmp_path / "out"
    code, err = run_cli(name, capsys, "--out", str(out))
    assert code == 2 and err[0].startswith(first_line(name, None)[:-2])
    assert not out.exists()


def test_the_python_api_raises_a_controller_error_caused_by_the_controllers_exception():
    sim = Simulation("tiny", controller=bad.RaisesInStep, robots=6, max_ticks=8)
    with pytest.raises(ControllerError) as caught:
        sim.run()
    error = caught.value
    assert (error.controller, error.robot, error.tick) == (
        "tests.bad_controllers:RaisesInStep", bad.BAD_ROBOT, bad.BAD_TICK)
    assert isinstance(error.__cause__, ZeroDivisionError)
    assert "in user_helper" in error.user_traceback()


def test_an_interrupt_in_a_controller_is_an_interrupt_not_its_error():
    class Interrupted(bad.Walker):
        def bad(self, perception):
            raise KeyboardInterrupt

    sim = Simulation("tiny", controller=Interrupted, robots=6, max_ticks=8)
    with pytest.raises(KeyboardInterrupt):
        sim.run()


def test_a_batch_that_puts_a_bad_action_names_the_robot():
    def nan_for_the_bad_robot(robot, tick, action):
        bad_one = robot.id == bad.BAD_ROBOT and tick == bad.BAD_TICK
        return Action((0.0, float("nan"))) if bad_one else action

    class PutsNan(bad.Walker):
        @classmethod
        def create_swarm(cls, setups, params, rngs):
            return bad.PutSwarm.of(bad.Walker, setups, params, rngs, edit=nan_for_the_bad_robot)

    sim = Simulation("tiny", controller=PutsNan, robots=6, max_ticks=8)
    with pytest.raises(ControllerError, match=re.escape(
            f"{AT}: decide() returned the velocity (0.0, nan); expected finite")):
        sim.run()


@pytest.mark.slow
def test_a_sweep_records_a_failing_controller_with_its_line(tmp_path):
    runs = [RunSpec("tiny", f"{MODULE}:RaisesInStep", {"robots": 6, "max_ticks": 8}, 0),
            RunSpec("tiny", f"{MODULE}:Walker", {"robots": 6, "max_ticks": 8}, 0)]
    report = run_sweep(runs, tmp_path / "sweep", workers=1, progress=False)
    assert report.failed == 1
    error = (tmp_path / "sweep" / "runs" / runs[0].run_id / "error.txt").read_text()
    line, _, details = error.partition("\n\n")
    assert line == (f"controller '{MODULE}:RaisesInStep', {AT}: step() raised "
                    "ZeroDivisionError: float division by zero")
    assert "in user_helper" in details and "swarmsim/engine/sim.py" not in details


def test_no_robot_can_broadcast_another_robots_id():
    """Spoofer's robots all claim id 0, by tuple and by dict, Batch_spoof's by dense rows."""
    for controller in (bad.Spoofer, bad.Batch_spoof):
        sim = Simulation("tiny", controller=controller, robots=6, max_ticks=8)
        for _ in range(3):
            sim.step()
            assert sim.messages["id"].tolist() == list(range(6))
    sim = Simulation("tiny", controller=bad.Spoofer, robots=6, max_ticks=8)
    sim.step()
    odd = sim.messages[1::2]
    assert (odd["status"] == 1).all() and (odd["x"] == 1.5).all() and (odd["hops"] == 0).all()


class OldBaseFields(bad.Walker):
    """Broadcasts with the base fields of earlier versions (id, status, gradient, group,
    leader, moving, ...): no longer read as the run's fields, refused."""

    def good(self, perception):
        return Action((self.v, 0.0), (self.id, 1, 4, 2, False, True, 2.5, 3))


@pytest.mark.parametrize("controller", [bad.Walker, bad.Batch_none],
                         ids=["per-robot", "batch"])
def test_good_controllers_run_as_before(controller):
    sim = Simulation("tiny", controller=controller, robots=6, max_ticks=8)
    result = sim.run()
    assert result.summary["ticks"] == 8
    assert sim.messages["id"].tolist() == list(range(6))


def test_a_tuple_with_the_old_base_fields_is_refused():
    sim = Simulation("tiny", controller=OldBaseFields, robots=6, max_ticks=8)
    with pytest.raises(ControllerError, match=re.escape(
            "a broadcast tuple of 8 values; expected 5: (id, status, moving, x, hops)")):
        sim.run()


def test_columns_of_actions_refuse_what_the_engine_would_not_use():
    with pytest.raises(Exception, match=r"a velocity of shape \(3,\)") as caught:
        ChunkActions.of([Action(), Action((1.0, 2.0, 3.0))])
    assert caught.value.row == 1
    with pytest.raises(Exception, match="expected an Action") as caught:
        ChunkActions.of([Action(), None])  # type: ignore[list-item]
    assert caught.value.row == 1
    assert np.isnan(ChunkActions.of([Action(), Action(listen=2)]).listen[0])


MODULE_FAULTS = [  # a controller module that fails as it is imported: (source, problem)
    ("x = = 1\n", "importing module 'faulty_bot' raised SyntaxError: invalid syntax"),
    ("raise RuntimeError('no battery')\n",
     "importing module 'faulty_bot' raised RuntimeError: no battery"),
    ("import math\nmath.sqrt(-1)\n",
     "importing module 'faulty_bot' raised ValueError: math domain error"),
]


@pytest.mark.parametrize("source, problem", MODULE_FAULTS, ids=["syntax", "raise", "domain"])
def test_a_module_that_fails_as_it_is_imported_is_the_line_then_its_own_frames(
        source, problem, tmp_path, monkeypatch, capsys):
    (tmp_path / "faulty_bot.py").write_text(source)
    monkeypatch.chdir(tmp_path)
    monkeypatch.syspath_prepend(str(tmp_path))
    code = main(["run", "tiny", "--controller", "faulty_bot:Bot", "--out", "out", *RUN])
    err = capsys.readouterr().err.splitlines()
    assert code == 2
    assert err[0].startswith(f"swarmsim: error: controller 'faulty_bot:Bot': {problem}"), err
    assert "faulty_bot.py" in "\n".join(err[1:])
    assert not any("importlib" in line or "swarmsim" in line for line in err[1:]), err
    assert not (tmp_path / "out").exists()


def test_a_misspelt_class_gets_the_closest_names(tmp_path, monkeypatch, capsys):
    monkeypatch.chdir(Path(__file__).parents[2])
    code = main(["run", "tiny", "--controller", f"{MODULE}:RaisesInStpe", *RUN])
    err = capsys.readouterr().err.strip()
    assert code == 2 and "did you mean 'RaisesInStep'" in err and "\n" not in err, err


def declaring(**declarations) -> type:
    """bad.Walker with these class attributes (classmethods given as plain functions)."""
    attrs = {k: classmethod(v) if callable(v) and not isinstance(v, type) else v
             for k, v in declarations.items()}
    return type("Declared", (bad.Walker,), attrs)


class PlainParams:
    """Not a dataclass."""

    v = 0.05


@dataclasses.dataclass(frozen=True)
class BareParams:
    """A field without a default."""

    v: float


DECLARATIONS = [  # (class attributes, the message's telling part)
    ({"Params": PlainParams}, "Params must be a dataclass whose fields all have defaults"),
    ({"Params": BareParams}, "Params field(s) ['v'] have no default"),
    ({"STATUSES": ()}, "STATUSES must be a tuple of 1 to 127 distinct names"),
    ({"STATUSES": "Walking"}, "STATUSES must be a tuple of 1 to 127 distinct names"),
    ({"STATUSES": ("A", "A")}, "STATUSES must be a tuple of 1 to 127 distinct names"),
    ({"STATUSES": ("A", 1)}, "STATUSES must be a tuple of 1 to 127 distinct names"),
    ({"MESSAGE_FIELDS": [("hops", "bogus")]}, "MESSAGE_FIELDS [('hops', 'bogus')] is not"),
    ({"MESSAGE_FIELDS": [("status", "i4")]}, "field 'status' occurs more than once"),
    ({"MESSAGE_FIELDS": [("x", "f4"), ("x", "i2")]}, "field 'x' occurs more than once"),
    ({"SILENT": {"gradient": 3}}, "SILENT names ['gradient'], which it does not broadcast"),
    ({"COLOURINGS": {"hue": "scale"}}, "COLOURINGS names ['hue'], which it does not"),
    ({"LEADER_FIELD": "boss"}, "LEADER_FIELD names ['boss'], which it does not broadcast"),
    ({"sensing_range": lambda cls, params: float("nan")},
     "sensing_range() returned nan; expected a distance > 0, units"),
    ({"sensing_range": lambda cls, params: -2},
     "sensing_range() returned -2; expected a distance > 0, units"),
    ({"sensing_range": lambda cls, params: "far"},
     "sensing_range() returned 'far'; expected a distance > 0, units"),
    ({"sensing_range": lambda cls, params: None},
     "sensing_range() returned None; expected a distance > 0, units"),
]


@pytest.mark.parametrize("declarations, problem", DECLARATIONS,
                         ids=[f"{next(iter(d))}-{k}" for k, (d, _) in enumerate(DECLARATIONS)])
def test_a_malformed_declaration_is_refused_naming_it(declarations, problem):
    from swarmsim import ConfigError

    with pytest.raises((ConfigError, ControllerError)) as refused:
        Simulation("tiny", controller=declaring(**declarations), robots=4, max_ticks=5).run()
    assert problem in str(refused.value), str(refused.value)
    assert "Declared" in str(refused.value)  # the controller is named


class SleepsPastInt64(bad.Walker):
    """Sleeps with a timeout past int64's range: never, as None."""

    def step(self, perception):
        return Action((0.0, 0.0), None, sleep=True, wake_tick=10**30)


def test_a_timeout_past_int64_is_never():
    sim = Simulation("tiny", controller=SleepsPastInt64, robots=4, max_ticks=20)
    sim.run()
    assert sim.asleep.all() and (sim.wake_tick == np.iinfo(np.int64).max).all()


ENGINE_NAMES = [("radius", "PhysicsConfig"), ("seed", "SimConfig"), ("groups", "SimConfig"),
                ("probe_range", "SimConfig"), ("start", "SimConfig"), ("max_ticks", "SimConfig"),
                ("mode", "PhysicsConfig")]


@pytest.mark.parametrize("field, section", ENGINE_NAMES, ids=[n for n, _ in ENGINE_NAMES])
def test_a_parameter_named_like_an_engine_setting_is_refused(field, section):
    """The engine would take a run's value of that name: the controller never would."""
    params = dataclasses.make_dataclass("Params", [("v", float, 0.05), (field, int, 1)],
                                        frozen=True)
    walker = type("Clash", (bad.Walker,), {"Params": params, "name": "clash"})
    with pytest.raises(ConfigError, match=re.escape(
            f"{walker.__module__}:Clash: Params field {field!r} has the name of the engine setting "
            f"{section}.{field}; a run's {field} would set the engine's, never the "
            "controller's: rename the field")):
        Simulation("tiny", controller=walker, robots=6, max_ticks=8)


def test_the_refusal_of_an_engine_name_is_one_line(capsys):
    code, err = run_cli("ParamNamedRadius", capsys)
    assert code == 2
    line = (f"swarmsim: error: key 'controller': {MODULE}:ParamNamedRadius: Params field "
            "'radius' has the name of the engine setting PhysicsConfig.radius; a run's "
            "radius would set the engine's, never the controller's: rename the field")
    assert err == [line]


def test_no_registered_controller_names_an_engine_setting_and_d_cover_is_the_controllers():
    """d_cover is a controller parameter (GGC's and the baselines'), routed to the
    controller's Params: the engine has no setting of that name."""
    assert "d_cover" not in engine_settings()
    for name in available_controllers():
        cls = get_controller(name)
        assert not {f.name for f in dataclasses.fields(cls.Params)} & set(engine_settings())
    sim = Simulation("tiny", controller="dispersion", robots=6, d_cover=4.5, max_ticks=8)
    assert sim.params.d_cover == 4.5
