"""Screen GGC rule sets cheaply: worlds x group counts x paired seeds, short horizons, an abort
rule, one table per world and group count (the protocol of issue 70's research notes, sec. 5).

Each run is ``Simulation(world, groups=G, seed=S, max_ticks=T, settings={"ruleset": NAME,
...})`` in its own process (the public API; ``--code DIR`` puts another checkout first on the
child's import path, so two versions can be screened alike). A run stops at completion, at the
horizon, or when aborted: its robots on the target rose by fewer than --abort-rise in the
last --abort-window ticks while its coverage is below --abort-below (checked every RECORD
ticks; --abort-rise 0 turns it off; near completion robots on target hardly rise while
coverage still does, so the tail is spared). Each run's result (its
summary.json fields and a trace of robots on target and coverage every RECORD ticks) is kept
in --out, one JSON file per run written atomically, so an interrupted screen resumes where it
stopped. Per rule set the table gives:

- done: runs complete / runs; aborted: runs the abort rule stopped; coverage: the median
  final coverage (at the horizon or the abort);
- ticks: the completion tick's median [min-max] over the runs that completed;
- x floor: the median completion tick / the world's travel floor (swarmsim/world/floor.py);
- arrive/1k: robots on target gained per 1,000 ticks over the delivery phase (from the first
  record with at least 10 % of the run's final robots on target, to the run's end), median;
- dist/placed: the summary's distance per placed robot, median;
- vs FIRST: paired differences against the first rule set: of completion ticks over the
  seeds both completed (median [min..max], the median in %, how many were faster), and of
  final coverage over every seed (median [min..max]).

    python bench/screen_rules.py --rulesets yield-holes paper --worlds K --seeds 0-4
    python bench/screen_rules.py --rulesets yield-holes NEW --worlds K house --groups 3 \\
        --workers 2 --out /tmp/screen
    python bench/screen_rules.py --rulesets yield-holes --code /tmp/old --out /tmp/screen-old
"""

from __future__ import annotations

import argparse
import concurrent.futures
import hashlib
import json
import os
import statistics
import subprocess
import sys
from pathlib import Path

HERE = Path(__file__).resolve().parents[1]  # this checkout (swarmsim/, controllers/)
RECORD = 250
"""Ticks between two records of a run's trace (and two checks of the abort rule)."""
K_GROUPS = (1, 3, 6, 10)
"""K's group counts when --groups is not given (other worlds: their default groups)."""
DELIVERY_START = 0.1
"""The delivery phase starts at the first record with this share of the final robots on target."""

WORKER = r"""
import json, sys
from swarmsim import ConfigError, Simulation
from swarmsim.engine.hooks import Hook
job = json.loads(sys.argv[1])

class Watch(Hook):
    def __init__(self):
        self.trace = []  # [tick, robots on target, coverage]
    def post_step(self, run):
        if run.tick % job["record"] == 0:
            self.trace.append([run.tick, int(run.on_target.sum()), float(run.metrics.coverage)])
    def is_finished(self, run):
        rise, window = job["abort_rise"], job["abort_window"]
        if (rise <= 0 or run.tick < window or run.tick % job["record"] or not self.trace
                or self.trace[-1][2] >= job["abort_below"]):
            return None
        back = [n for t, n, _ in self.trace if t == run.tick - window]
        return "aborted" if back and self.trace[-1][1] - back[0] < rise else None

try:
    sim = Simulation(job["world"], controller="ggc", groups=job["groups"], seed=job["seed"],
                     max_ticks=job["max_ticks"], settings={"ruleset": job["ruleset"],
                                                           **job["settings"]})
except ConfigError as exc:
    sys.exit(f"swarmsim: error: {exc}")
watch = Watch()
sim.hooks.append(watch)
watch.trace.append([sim.tick, int(sim.on_target.sum()), float(sim.metrics.coverage)])
summary = sim.run().summary
if watch.trace[-1][0] != sim.tick:
    watch.trace.append([sim.tick, int(sim.on_target.sum()), float(sim.metrics.coverage)])
print(json.dumps({"summary": summary, "trace": watch.trace}))
"""


def seed_list(text: str) -> list[int]:
    """``"0-4"`` -> [0, 1, 2, 3, 4]; ``"0,3,7"`` -> [0, 3, 7] (ranges and lists combine)."""
    seeds: list[int] = []
    try:
        for part in text.split(","):
            low, _, high = part.partition("-")
            seeds.extend(range(int(low), int(high or low) + 1))
    except ValueError:
        raise argparse.ArgumentTypeError(f"expected seeds like 0-4 or 0,2,5, got {text!r}"
                                         ) from None
    if not seeds:
        raise argparse.ArgumentTypeError(f"no seeds in {text!r}")
    return seeds


def setting(text: str) -> tuple[str, object]:
    """``KEY=VALUE``, the value read as JSON (a number, true/false) or else as text."""
    key, sep, value = text.partition("=")
    if not sep or not key:
        raise argparse.ArgumentTypeError(f"expected KEY=VALUE, got {text!r}")
    try:
        return key, json.loads(value)
    except json.JSONDecodeError:
        return key, value


def run_once(job: dict, code: Path, out: Path) -> dict:
    """The run ``job`` describes: read from ``out`` if it ran before, else run in a child
    process (``code`` first on its import path) and kept there (written atomically)."""
    tag = hashlib.sha256(json.dumps(job, sort_keys=True).encode()).hexdigest()[:10]
    path = out / (f"{Path(job['world']).stem}-g{job['groups']}-{job['ruleset']}"
                  f"-s{job['seed']}-{tag}.json")
    if path.is_file():
        return json.loads(path.read_text())
    env = dict(os.environ, PYTHONPATH=os.pathsep.join(
        [str(code), *filter(None, [os.environ.get("PYTHONPATH")])]))
    done = subprocess.run([sys.executable, "-c", WORKER, json.dumps(job)], env=env,
                          capture_output=True, text=True, check=False)
    if done.returncode:
        lines = done.stderr.strip().splitlines() or [f"exit status {done.returncode}"]
        raise RuntimeError(f"{job['world']}, {job['groups']} group(s), ruleset "
                           f"{job['ruleset']}, seed {job['seed']}: "
                           f"{lines[-1].removeprefix('swarmsim: error: ')}")
    result = {"job": job, **json.loads(done.stdout.strip().splitlines()[-1])}
    summary = result["summary"]
    print(f"ran {path.stem}: {summary['stop_reason']} at tick {summary['ticks']:,}, coverage "
          f"{summary['coverage']:.4f}", file=sys.stderr, flush=True)
    tmp = path.with_suffix(".tmp")
    tmp.write_text(json.dumps(result))
    os.replace(tmp, path)
    return result


def delivery_rate(trace: list[list[float]]) -> float | None:
    """Robots on target gained per 1,000 ticks over the delivery phase (see the module)."""
    final = trace[-1][1]
    start = next(row for row in trace if row[1] >= DELIVERY_START * final)
    ticks = trace[-1][0] - start[0]
    return 1000 * (final - start[1]) / ticks if ticks > 0 else None


def median(values: list) -> float | None:
    values = [v for v in values if v is not None]
    return statistics.median(values) if values else None


def number(value: float | None, digits: int = 0) -> str:
    return "-" if value is None else f"{value:,.{digits}f}"


def rows_for(results: dict[str, dict[int, dict]], floor: float) -> list[str]:
    """The table's lines for one world and group count: ``results[ruleset][seed]``."""
    first = next(iter(results))
    lines = [(f"  {'ruleset':<22} {'done':>5} {'aborted':>7} {'coverage':>8} "
              f"{'ticks median [min-max]':>26} "
              f"{'x floor':>7} {'arrive/1k':>9} {'dist/placed':>11}  vs {first}")]
    for name, runs in results.items():
        summaries = [r["summary"] for r in runs.values()]
        ticks = [s["completion_tick"] for s in summaries if s["completion_tick"] is not None]
        spread = (f"{number(median(ticks))} [{number(min(ticks))}-{number(max(ticks))}]"
                  if ticks else "-")
        ratio = median(ticks) / floor if ticks and floor > 0 else None
        rate = median([delivery_rate(r["trace"]) for r in runs.values()])
        per_placed = median([s["distance_per_placed_robot"] for s in summaries])
        versus = paired(results[first], runs) if name != first else "-"
        aborted = sum(s["stop_reason"] == "aborted" for s in summaries)
        lines.append(f"  {name:<22} {len(ticks):>2}/{len(summaries):<2} {aborted:>7} "
                     f"{median([s['coverage'] for s in summaries]):>8.4f} {spread:>26} "
                     f"{number(ratio, 2):>7} {number(rate, 1):>9} {number(per_placed, 1):>11}  "
                     f"{versus}")
    return lines


def paired(base: dict[int, dict], other: dict[int, dict]) -> str:
    """Paired differences other - base: completion ticks over the seeds both completed, and
    final coverage over every seed both ran."""
    seeds = [s for s in base if s in other]
    ticks = [(other[s]["summary"]["completion_tick"], base[s]["summary"]["completion_tick"])
             for s in seeds]
    ticks = [(a, b) for a, b in ticks if a is not None and b is not None]
    cover = [other[s]["summary"]["coverage"] - base[s]["summary"]["coverage"] for s in seeds]
    text = (f"coverage {median(cover):+.4f} [{min(cover):+.4f}..{max(cover):+.4f}]"
            if cover else "no seed in common")
    if not ticks:
        return text
    diffs = [a - b for a, b in ticks]
    share = median([100 * (a - b) / b for a, b in ticks])
    return (f"ticks {median(diffs):+,.0f} [{min(diffs):+,}..{max(diffs):+,}] ({share:+.1f} %), "
            f"faster on {sum(d < 0 for d in diffs)}/{len(ticks)}; {text}")


def main(argv: list[str] | None = None) -> int:
    parser = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    parser.add_argument("--rulesets", nargs="+", required=True, metavar="NAME",
                        help="GGC rule sets (the first is the one the others are paired with)")
    parser.add_argument("--worlds", nargs="+", default=["K"], metavar="WORLD")
    parser.add_argument("--groups", nargs="+", type=int, metavar="G",
                        help=f"group counts (default: K {' '.join(map(str, K_GROUPS))}, "
                        "other worlds their own)")
    parser.add_argument("--seeds", type=seed_list, default=seed_list("0-4"))
    parser.add_argument("--max-ticks", type=int, default=12000)
    parser.add_argument("--abort-rise", type=int, default=10,
                        help="abort a run whose robots on target rose by fewer than this in "
                        "the last --abort-window ticks (0: never; default 10)")
    parser.add_argument("--abort-window", type=int, default=2000)
    parser.add_argument("--abort-below", type=float, default=0.95,
                        help="abort only runs whose coverage is below this (default 0.95)")
    parser.add_argument("--set", type=setting, action="append", default=[], dest="settings",
                        metavar="KEY=VALUE", help="a run setting for every run (repeatable)")
    parser.add_argument("--workers", type=int, default=1, help="runs at a time (processes)")
    parser.add_argument("--code", type=Path, default=HERE,
                        help="the checkout to run (default: this one)")
    parser.add_argument("--out", type=Path, default=Path("screen-out"),
                        help="where each run's result is kept (resumes from it)")
    args = parser.parse_args(argv)
    if args.workers < 1 or args.max_ticks < 1 or args.abort_window % RECORD:
        parser.error(f"--workers and --max-ticks must be >= 1, --abort-window a multiple of "
                     f"{RECORD}")
    if not (args.code / "swarmsim").is_dir():
        parser.error(f"--code {args.code}: no swarmsim/ in it")
    sys.path.insert(0, str(HERE))
    from swarmsim.engine.config import SimConfig
    from swarmsim.errors import ConfigError
    from swarmsim.world.floor import travel_floor_ticks
    from swarmsim.world.world import load_world

    try:
        worlds = {world: load_world(world) for world in args.worlds}
    except ConfigError as exc:
        print(f"screen_rules: error: {exc}", file=sys.stderr)
        return 2

    args.out.mkdir(parents=True, exist_ok=True)
    settings = dict(args.settings)
    v_max = float(settings.get("v_max", SimConfig().v_max))
    code = args.code.resolve()
    jobs = []
    for world, loaded in worlds.items():
        counts = args.groups or (list(K_GROUPS) if loaded.name == "K" else
                                 [int(loaded.defaults.get("groups", 1))])
        for groups in counts:
            for ruleset in args.rulesets:
                jobs += [{"world": world, "groups": groups, "ruleset": ruleset, "seed": seed,
                          "max_ticks": args.max_ticks, "abort_rise": args.abort_rise,
                          "abort_window": args.abort_window, "record": RECORD,
                          "abort_below": args.abort_below,
                          "settings": settings, "code": str(code)} for seed in args.seeds]
    with concurrent.futures.ThreadPoolExecutor(args.workers) as pool:
        futures = [pool.submit(run_once, job, code, args.out) for job in jobs]
        try:
            results = [f.result() for f in futures]
        except RuntimeError as exc:
            pool.shutdown(cancel_futures=True)
            print(f"screen_rules: error: {exc}", file=sys.stderr)
            return 2
    table: dict[tuple[str, int], dict[str, dict[int, dict]]] = {}
    for job, result in zip(jobs, results, strict=True):
        key = (job["world"], job["groups"])
        table.setdefault(key, {}).setdefault(job["ruleset"], {})[job["seed"]] = result
    for (world, groups), by_ruleset in table.items():
        loaded = worlds[world]
        floor = travel_floor_ticks(loaded, v_max)
        robots = next(iter(next(iter(by_ruleset.values())).values()))["summary"]["robots"]
        print(f"{loaded.name}, {groups} group(s), {robots} robots: travel floor {floor:,.0f} "
              f"ticks (v_max {v_max:g}); seeds {','.join(map(str, args.seeds))}; horizon "
              f"{args.max_ticks:,}; abort below +{args.abort_rise} on target per "
              f"{args.abort_window:,} ticks under coverage {args.abort_below:g}; code {code}")
        print("\n".join(rows_for(by_ruleset, floor)))
        print()
    return 0


if __name__ == "__main__":
    sys.exit(main())
