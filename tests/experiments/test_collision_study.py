"""``swarmsim study collisions``: ghost against rigid robots, resumable, with a report."""

from __future__ import annotations

import csv

import pytest

from swarmsim.cli import main
from swarmsim.experiments.collisions import StudySetup, study_collisions

CROWDED = """
name = "crowded"
[target]
outline = [[0, 0], [12, 0], [12, 12], [0, 12]]
[[spawn]]
outline = [[0, -30], [20, -30], [20, -10], [0, -10]]
[beacon]
position = [6, 6]
[arena]
margin = 10
"""


@pytest.fixture(scope="module")
def study(tmp_path_factory):
    base = tmp_path_factory.mktemp("study")
    world = base / "crowded.toml"
    world.write_text(CROWDED)
    setup = StudySetup(world=str(world), robots=60, groups=2, max_ticks=600, noise=(0.0, 0.05))
    result = study_collisions(setup, base / "out", reps=1, workers=1, progress=False)
    return setup, base / "out", result


def rows_of(path):
    with open(path, newline="") as f:
        return list(csv.DictReader(f))


@pytest.mark.slow
def test_study_runs_both_modes_and_counts_contacts_only_when_rigid(study):
    _, out, result = study
    assert result.failed == 0
    runs = rows_of(out / "results.csv")
    assert sorted(r["mode"] for r in runs) == ["ghost", "ghost", "rigid", "rigid"]
    for r in runs:
        contacts = int(r["collisions_robot_robot"])
        assert (contacts > 0) == (r["mode"] == "rigid"), r["mode"]
    conds = {r["condition"]: r for r in rows_of(out / "conditions.csv")}
    assert set(conds) == {"ghost", "rigid", "ghost, noise 0.05", "rigid, noise 0.05"}
    assert float(conds["ghost"]["contact_robot_ticks_mean"]) == 0
    assert float(conds["rigid"]["contact_robot_ticks_mean"]) > 0
    for run_dir in (out / "runs").iterdir():
        assert len(rows_of(run_dir / "robots.csv")) == 60


@pytest.mark.slow
def test_study_writes_report_and_plot_and_resumes(study):
    setup, out, _ = study
    report = (out / "REPORT.md").read_text()
    assert "| ghost | 1/1 |" in report and "| rigid, noise 0.05 | 1/1 |" in report
    assert "## Rigid against ghost" in report and "50 % coverage" in report
    assert "## Noise against ideal robots" in report and "[rigid, noise 0.05]" in report
    assert (out / "collisions.png").stat().st_size > 10_000
    again = study_collisions(setup, out, reps=1, workers=1, progress=False)
    assert "0 run now, 4 already there" in again.sweep_line


@pytest.mark.parametrize("argv,key", [
    (["--noise", "-0.1"], "--noise"),
    (["--set", "wobble=1"], "wobble"),
    (["--reps", "0"], "--reps"),
    (["--world", "nowhere"], "nowhere"),
])
def test_bad_study_input_is_one_line_naming_it(argv, key, tmp_path, capsys):
    code = main(["study", "collisions", "--out", str(tmp_path / "o"), "--quiet", *argv])
    err = capsys.readouterr().err.strip()
    assert code == 2 and key in err and len(err.splitlines()) == 1
    assert not (tmp_path / "o" / "runs").exists()
