"""The examples run (a user's first contact with the API)."""

import subprocess
import sys
from pathlib import Path

import pytest

from swarmsim import Simulation

ROOT = Path(__file__).resolve().parents[2]


def test_custom_controller_by_module_and_class():
    sim = Simulation("tiny", controller="examples.my_controller:GoToLight", robots=10, seed=1,
                     max_ticks=600)
    res = sim.run()
    assert res.summary["robots_on_target"] == 10


@pytest.mark.slow
def test_run_ggc_example(tmp_path):
    out = subprocess.run([sys.executable, str(ROOT / "examples" / "run_ggc.py")], cwd=tmp_path,
                         capture_output=True, text=True, timeout=600, check=False)
    assert out.returncode == 0, out.stderr[-2000:]
    assert "coverage" in out.stdout
    assert (tmp_path / "tiny-last.png").stat().st_size > 1000


@pytest.mark.slow
def test_where_distance_goes_ledger_adds_up_to_the_runs_distance():
    from examples.where_distance_goes import Ledger

    sim = Simulation("tiny", seed=2, max_ticks=1500)
    ledger = Ledger(sim, late_from=300)
    result = sim.run(on_tick=ledger)
    total = result.summary["total_distance"]
    assert total > 100
    assert abs(ledger.distance.sum() - total) < 1e-6 * total
    settled = ledger.settled_at >= 0
    assert settled.sum() == result.summary["status_counts"]["Arrive"] > 0
    assert len(ledger.late) == int((ledger.settled_at > 300).sum()) > 0
    split = ledger.driven + ledger.pushed
    assert abs(split.sum() - total) < 1e-6 * total
    coverage = sim.statuses.index("Coverage")
    assert ledger.driven[coverage] > 0.5 * total  # robots walk to their places in Coverage
    assert ledger.driven[sim.statuses.index("Arrive")] == 0  # arrived robots are never driven


@pytest.mark.slow
def test_the_swarmsim_command_finds_a_controller_module_in_the_current_folder():
    """The command in examples/my_controller.py's docstring, run as a user would from the
    repository (the installed script does not put the current folder on sys.path)."""
    command = Path(sys.executable).parent / "swarmsim"
    out = subprocess.run([str(command), "run", "tiny", "--controller",
                          "examples.my_controller:GoToLight", "--max-ticks", "50", "--quiet"],
                         cwd=ROOT, capture_output=True, text=True, timeout=300, check=False)
    assert out.returncode == 0, out.stderr[-2000:]
    assert "tiny examples.my_controller:GoToLight" in out.stdout
