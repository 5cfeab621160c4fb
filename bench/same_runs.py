"""Are the runs the same runs as before? Whole runs' outputs hashed against a recorded set.

A change that leaves the rules alone (a faster tick, a compiled path, a refactoring) must
leave every run the same to the bit. This script runs whole runs through the CLI, as a user
does (K, house and K from a scattered start, seed 0 by default), and hashes what they wrote:
summary.json without the fields that time the run (wall and CPU seconds, controller ms) or
name the code, timeseries.csv and robots.csv.

    python bench/same_runs.py                       # check against bench/same_runs.json
    python bench/same_runs.py --record              # write the current code's hashes there
    python bench/same_runs.py --cases K house       # some of the cases

Exit status 1 when a hash differs. A whole K run takes about a minute, house two.
"""

from __future__ import annotations

import argparse
import hashlib
import json
import subprocess
import sys
import tempfile
from pathlib import Path
from typing import Any

from swarmsim.engine.sim import TIMING_FIELDS
from swarmsim.results.provenance import code_version

RECORD = Path(__file__).with_name("same_runs.json")
CASES = {
    "K": ["K", "--seed", "0"],
    "house": ["house", "--seed", "0"],
    "K scattered": ["K", "--seed", "0", "--set", "start=random"],
}
"""Each case's `swarmsim run` arguments (same_runs.json also names the code that recorded
them, ``recorded_by``)."""
UNHASHED = {*TIMING_FIELDS, "code_version"}


def _kept(value: Any) -> Any:
    """``value`` without the summary fields that time the run or name the code."""
    if isinstance(value, dict):
        return {k: _kept(v) for k, v in value.items() if k not in UNHASHED}
    if isinstance(value, list):
        return [_kept(v) for v in value]
    return value


def hashes(folder: Path) -> dict[str, str]:
    """sha256 (16 hex digits) of a run folder's summary (untimed), time series and robots."""
    summary = json.loads((folder / "summary.json").read_text())
    out = {"summary.json": json.dumps(_kept(summary), sort_keys=True).encode()}
    out.update({name: (folder / name).read_bytes() for name in ("timeseries.csv", "robots.csv")})
    return {name: hashlib.sha256(data).hexdigest()[:16] for name, data in out.items()}


def run_case(args: list[str], work: Path) -> dict[str, str]:
    """One whole run through the CLI into ``work``; its hashes."""
    subprocess.run([sys.executable, "-m", "swarmsim", "run", *args, "--out", str(work),
                    "--quiet"], check=True)
    return hashes(work)


def main() -> int:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--record", action="store_true", help=f"write {RECORD.name}")
    parser.add_argument("--cases", nargs="+", choices=sorted(CASES), default=list(CASES))
    args = parser.parse_args()
    recorded = json.loads(RECORD.read_text()) if RECORD.exists() else {}
    differ = False
    with tempfile.TemporaryDirectory() as tmp:
        for i, case in enumerate(args.cases):
            now = run_case(CASES[case], Path(tmp) / str(i))
            if args.record:
                recorded[case] = now
                print(f"{case}: recorded {now}")
                continue
            was = recorded.get(case)
            same = now == was
            differ |= not same
            print(f"{case}: {'same' if same else 'DIFFERENT'} "
                  f"{'' if same else f'(now {now}, recorded {was})'}", flush=True)
    if args.record:
        recorded["recorded_by"] = code_version()
        RECORD.write_text(json.dumps(recorded, indent=2, sort_keys=True) + "\n")
    return 1 if differ else 0


if __name__ == "__main__":
    raise SystemExit(main())
