"""``swarmsim study realism``: drives x noise x message models against the baseline."""

from __future__ import annotations

import csv
import dataclasses

import pytest

from swarmsim import Simulation
from swarmsim.cli import REALISM_DRIVES, REALISM_MESSAGES, main
from swarmsim.errors import ConfigError
from swarmsim.experiments.realism import (
    DRIVES,
    MESSAGES,
    RealismSetup,
    check_setup,
    conditions,
    message_range50,
    study_realism,
)
from swarmsim.world import world as world_module

SETUP = RealismSetup(world="tiny", drives=("holonomic",), noise=(0.0, 0.05), max_ticks=300)


def rows_of(path):
    with open(path, newline="") as f:
        return list(csv.DictReader(f))


@pytest.fixture(scope="module")
def study(tmp_path_factory):
    out = tmp_path_factory.mktemp("realism") / "out"
    result = study_realism(SETUP, out, reps=1, workers=1, progress=False)
    return out, result


def test_the_grid_is_the_baseline_then_every_combination():
    conds = conditions(SETUP, reps=2)
    assert [c.label for c in conds] == [
        "baseline: holonomic, ghost, noise 0, uniform", "holonomic, rigid, noise 0, uniform",
        "holonomic, rigid, noise 0, logistic", "holonomic, rigid, noise 0.05, uniform",
        "holonomic, rigid, noise 0.05, logistic"]
    assert all(len(c.runs) == 2 for c in conds)
    base, noisy_logistic = conds[0].runs[0].settings, conds[-1].runs[0].settings
    assert "drive" not in base and base["mode"] == "ghost"  # holonomic is the default drive
    assert not {"speed_noise", "message_model", "floor_edge_misread"} & set(base)
    reach = message_range50(SETUP)
    sensing = Simulation("tiny", controller="ggc", max_ticks=1).sensing_range
    assert reach == pytest.approx(0.8 * sensing)
    assert noisy_logistic == {**noisy_logistic, "mode": "rigid", "speed_noise": 0.05,
                              "bearing_noise": 0.05, "floor_edge_band": 1.0,
                              "floor_edge_misread": 0.1, "message_model": "logistic",
                              "message_range50": reach, "message_falloff": 1.5}


def test_a_drive_other_than_holonomic_is_a_run_setting():
    setup = RealismSetup(world="tiny", drives=("diff",), noise=(0.0,), messages=("uniform",))
    diff = conditions(setup, reps=1)[1]
    assert diff.label == "diff, rigid, noise 0, uniform"
    assert diff.runs[0].settings["drive"] == "diff"


def test_study_writes_its_files_with_the_baseline_first(study):
    out, result = study
    assert result.failed == 0
    assert len(rows_of(out / "results.csv")) == 5
    conds = rows_of(out / "conditions.csv")
    assert conds[0]["condition"] == "baseline: holonomic, ghost, noise 0, uniform"
    assert float(conds[0]["ticks_vs_baseline"] or 1) == 1.0
    assert {"stuck_robots_mean", "stuck_robot_ticks_mean", "distance_vs_baseline",
            "collisions_robot_wall_mean"} <= set(conds[0])
    report = (out / "REPORT.md").read_text()
    assert "| baseline: holonomic, ghost, noise 0, uniform | " in report
    assert "| holonomic, rigid, noise 0.05, logistic | " in report
    assert "stuck robots (against wall / against robots)" in report
    assert (out / "realism.png").stat().st_size > 10_000
    for run in (out / "runs").iterdir():
        assert (run / "summary.json").is_file()


def test_the_steering_drives_run_as_conditions_of_their_own(tmp_path):
    setup = RealismSetup(world="tiny", drives=("diff", "kilobot"), noise=(0.0,),
                         messages=("uniform",), max_ticks=200)
    result = study_realism(setup, tmp_path / "out", reps=1, workers=1, progress=False)
    assert result.failed == 0
    conds = {c["condition"]: c for c in rows_of(tmp_path / "out" / "conditions.csv")}
    assert set(conds) == {"baseline: holonomic, ghost, noise 0, uniform",
                          "diff, rigid, noise 0, uniform", "kilobot, rigid, noise 0, uniform"}
    distances = {name: float(c["total_distance_mean"]) for name, c in conds.items()}
    assert len(set(distances.values())) == 3  # each drive moved the robots its own way


def test_a_second_study_runs_nothing(study):
    out, _ = study
    again = study_realism(SETUP, out, reps=1, workers=1, progress=False)
    assert "0 run now, 5 already there" in again.sweep_line


def test_the_cli_knows_the_studys_axes():
    assert (REALISM_DRIVES, REALISM_MESSAGES) == (DRIVES, MESSAGES)


HOLONOMIC = ["--drives", "holonomic"]  # one drive: the refusals come before any run


@pytest.mark.parametrize("argv,key", [
    (["realism", *HOLONOMIC, "--noise", "0.6"], "--noise"),
    (["realism", *HOLONOMIC, "--noise", "-0.1"], "--noise"),
    (["realism", *HOLONOMIC, "--set", "message_model=logistic"], "message_model"),
    (["realism", *HOLONOMIC, "--set", "drive=diff"], "drive"),
    (["realism", "--drives", "hovercraft"], "drive"),
    (["realism", *HOLONOMIC, "--reps", "0"], "--reps"),
    (["realism", *HOLONOMIC, "--world", "nowhere"], "nowhere"),
    (["collisions", "--drives", "diff"], "--drives"),
    (["collisions", "--messages", "logistic"], "--messages"),
])
def test_bad_study_input_is_one_line_naming_it(argv, key, tmp_path, capsys):
    world = [] if "--world" in argv else ["--world", "tiny"]
    code = main(["study", *argv, *world, "--out", str(tmp_path / "o"), "--quiet"])
    err = capsys.readouterr().err.strip()
    assert code == 2 and key in err and len(err.splitlines()) == 1, err
    assert not (tmp_path / "o").exists()



def test_a_world_whose_defaults_set_what_the_study_varies_is_refused(monkeypatch):
    """A drive or model in a world's [defaults] would silently change the conditions that
    leave the key out (the baseline among them)."""
    tiny = world_module.load_world("tiny")
    monkeypatch.setattr(world_module, "load_world", lambda name: dataclasses.replace(
        tiny, defaults={"message_model": "logistic"}))
    with pytest.raises(ConfigError, match=r"defaults\.message_model.*--messages"):
        check_setup(RealismSetup(world="tiny", drives=("holonomic",)))
