"""The examples run (a user's first contact with the API)."""

import subprocess
import sys
from pathlib import Path

from swarmsim import Simulation

ROOT = Path(__file__).resolve().parent.parent


def test_custom_controller_by_module_and_class():
    sim = Simulation("tiny", controller="examples.my_controller:GoToLight", robots=10, seed=1,
                     max_ticks=600)
    res = sim.run()
    assert res.summary["robots_on_target"] == 10


def test_run_ggc_example(tmp_path):
    out = subprocess.run([sys.executable, str(ROOT / "examples" / "run_ggc.py")], cwd=tmp_path,
                         capture_output=True, text=True, timeout=600, check=False)
    assert out.returncode == 0, out.stderr[-2000:]
    assert "coverage" in out.stdout
    assert (tmp_path / "tiny-last.png").stat().st_size > 1000
