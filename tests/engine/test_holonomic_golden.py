"""Holonomic runs are the runs of the code before drives existed (issue 69).

The hashes below were recorded at a7f483f, before any drive code: each is the sha256 of a
run's positions at every tick, its broadcasts and floor readings at the end. A drive model,
odometry or heading mark that leaks into a holonomic run (a new random draw, a changed body,
a different command) changes them.
"""

from __future__ import annotations

import pytest

from tests.runhash import run_hash

NOISY = {"speed_noise": 0.05, "heading_noise": 0.05, "distance_noise": 0.05,
         "bearing_noise": 0.05, "message_loss": 0.1}

CASES = {
    "tiny ggc seed 0": ("tiny", "ggc", 0, 400, {}),
    "tiny ggc seed 1": ("tiny", "ggc", 1, 400, {}),
    "tiny ggc seed 1 no sleep": ("tiny", "ggc", 1, 400, {"physics_sleep": False}),
    "tiny ggc seed 0 noisy": ("tiny", "ggc", 0, 400, NOISY),
    "tiny dispersion seed 2": ("tiny", "dispersion", 2, 300, {}),
    "K ggc seed 0": ("K", "ggc", 0, 300, {}),
}


GOLDEN = {
    "K ggc seed 0": "569dac50382a1368",
    "tiny dispersion seed 2": "873890e429a298b5",
    "tiny ggc seed 0": "fee33ae96ffb8f8b",
    "tiny ggc seed 0 noisy": "9712a0a093538eba",
    "tiny ggc seed 1": "a1ba76aa6dcafd01",
    "tiny ggc seed 1 no sleep": "a1ba76aa6dcafd01",
}


@pytest.mark.parametrize("case", sorted(CASES))
def test_holonomic_runs_hash_as_before_drives(case: str) -> None:
    assert run_hash(*CASES[case]) == GOLDEN[case]


if __name__ == "__main__":
    for name in sorted(CASES):
        print(f"    {name!r}: {run_hash(*CASES[name])!r},")
