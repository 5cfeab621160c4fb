"""Two versions of the code on the same run, taking turns: which is faster, and by how much.

Each version (a folder holding a checkout: swarmsim/ and controllers/, e.g. made with
``git archive REV | tar -x -C /tmp/old``) runs the same world and seed in its own process.
They take turns, --block ticks each, so that both meet the same machine: these machines'
speed drifts by 10-30 % within minutes, which swamps a comparison of runs made one after the
other (or side by side on two cores, which share a cache). Prints each version's seconds per
phase, the ratio of their times block by block (median and quartiles) and whole, and checks
that both runs ended the same: the same ticks, positions and broadcasts (a speed-up must not
change results; a broadcast field that only one version has, or sizes differently, is named
and left out).

    git archive HEAD~3 | tar -x -C /tmp/old
    python bench/bench_versions.py /tmp/old .                  # K seed 0, to completion
    python bench/bench_versions.py /tmp/old . --world house --ticks 5000
    python bench/bench_versions.py /tmp/old . --controller meanshift --block 200
"""

from __future__ import annotations

import argparse
import json
import os
import statistics
import subprocess
import sys
from pathlib import Path

WORKER = r"""
import hashlib, json, sys, time
from swarmsim import Simulation  # the public API: the same in every version
world, seed, ticks, controller = sys.argv[1], int(sys.argv[2]), int(sys.argv[3]), sys.argv[4]
groups = int(sys.argv[5]) or None
sim = Simulation(world, controller=controller or None, seed=seed, max_ticks=ticks or None,
                 groups=groups)
print(json.dumps({"ready": True}), flush=True)
for line in sys.stdin:
    block, began = int(line), time.perf_counter()
    for _ in range(block):
        if sim.stop_reason is not None:
            break
        if hasattr(sim, "advance"):  # a tick and the stop rules (loop hooks)
            sim.advance()
        else:  # code before Simulation.advance
            sim.step()
            sim.stop_reason = sim._should_stop()
    state = {"positions": hashlib.sha256(sim.positions.tobytes()).hexdigest()[:16]}
    for name in sim.dtype.names:  # each broadcast field, with its shape per row
        column = sim.messages[name]
        state[name] = [list(column.shape[1:]), hashlib.sha256(column.tobytes()).hexdigest()[:16]]
    print(json.dumps({"seconds": time.perf_counter() - began, "tick": sim.tick,
                      "done": sim.stop_reason is not None, "state": state,
                      "phases": sim.phase_seconds}), flush=True)
"""


def start(code: Path, args: argparse.Namespace) -> subprocess.Popen:
    """A worker process running the code in ``code`` (first on its import path)."""
    env = dict(os.environ, PYTHONPATH=str(code.resolve()))
    proc = subprocess.Popen([sys.executable, "-c", WORKER, args.world, str(args.seed),
                             str(args.ticks), args.controller, str(args.groups)], cwd=code, env=env, text=True,
                            stdin=subprocess.PIPE, stdout=subprocess.PIPE)
    json.loads(proc.stdout.readline())  # set up (kernels compiled or loaded): ready
    return proc


def turn(proc: subprocess.Popen, block: int) -> dict:
    proc.stdin.write(f"{block}\n")
    proc.stdin.flush()
    return json.loads(proc.stdout.readline())


def main() -> None:
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("old", type=Path, help="folder of the version to compare against")
    ap.add_argument("new", type=Path, help="folder of the version under test")
    ap.add_argument("--world", default="K", help="world name or TOML path (default K)")
    ap.add_argument("--seed", type=int, default=0)
    ap.add_argument("--controller", default="", help="controller (default: the world's)")
    ap.add_argument("--groups", type=int, default=0, help="groups K (default: the world's)")
    ap.add_argument("--ticks", type=int, default=0, help="stop here (default: run to the end)")
    ap.add_argument("--block", type=int, default=250, help="ticks per turn (250)")
    args = ap.parse_args()
    for code in (args.old, args.new):
        if not (code / "swarmsim" / "__init__.py").is_file():
            ap.error(f"{code} holds no swarmsim/ package")
    if args.block <= 0 or args.ticks < 0:
        ap.error("--block must be > 0 and --ticks >= 0")
    procs = {"old": start(args.old, args), "new": start(args.new, args)}
    ratios, totals, last = [], {"old": 0.0, "new": 0.0}, {}
    while not all(r.get("done") for r in last.values()) or not last:
        for name, proc in procs.items():
            last[name] = turn(proc, args.block)
            totals[name] += last[name]["seconds"]
        if last["old"]["seconds"] > 0 and last["new"]["seconds"] > 0:
            ratios.append(last["old"]["seconds"] / last["new"]["seconds"])
        if last["old"]["tick"] != last["new"]["tick"]:
            break  # one ended first: the results differ
    for proc in procs.values():
        proc.stdin.close()
        proc.wait()
    report(args, totals, ratios, last)


def report(args: argparse.Namespace, totals: dict, ratios: list[float], last: dict) -> None:
    run = " ".join([args.world, args.controller, f"{args.groups} groups" if args.groups else ""])
    print(f"{run.strip()} seed {args.seed}: {last['new']['tick']} ticks, blocks of {args.block}")
    for name in ("old", "new"):
        phases = ", ".join(f"{k} {v:.1f}" for k, v in last[name]["phases"].items())
        print(f"  {name}: {totals[name]:.1f} s ({phases})")
    q = statistics.quantiles(ratios, n=4) if len(ratios) > 1 else ratios * 3
    print(f"  old / new: {totals['old'] / totals['new']:.3f} whole; block by block median "
          f"{statistics.median(ratios):.3f} (quartiles {q[0]:.3f}-{q[2]:.3f}, "
          f"{len(ratios)} blocks)")
    same, note = same_end_state(last["old"], last["new"])
    print("  the same end state: " + ("yes" + note if same else
                                      f"NO{note} (old {last['old']}, new {last['new']})"))
    if not same:
        sys.exit(1)


def same_end_state(old: dict, new: dict) -> tuple[bool, str]:
    """Whether both runs ended at the same tick with the same positions and the same values in
    every broadcast field both versions have with one shape per row; and a note naming the
    fields left out (a version may add a field, or size one differently)."""
    a, b = old["state"], new["state"]
    fa = {k: v for k, v in a.items() if k != "positions"}  # field: [shape per row, hash]
    fb = {k: v for k, v in b.items() if k != "positions"}
    shared = [k for k in fa if k in fb and fa[k][0] == fb[k][0]]
    left_out = sorted(set(fa) ^ set(fb) | {k for k in fa if k in fb and fa[k][0] != fb[k][0]})
    same = (old["tick"] == new["tick"] and a["positions"] == b["positions"]
            and all(fa[k] == fb[k] for k in shared))
    note = f" (not compared: {', '.join(left_out)})" if left_out else ""
    return same, note


if __name__ == "__main__":
    main()
