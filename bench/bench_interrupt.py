"""How fast ``swarmsim run`` stops on SIGTERM / SIGINT while its physics is busy.

Builds a world with ``swarmsim make-world`` (default: the issue's K with 10,000 robots in 16
groups, 640 units high), then, per try, starts ``swarmsim run WORLD --out OUT``, waits until
it ticks (its progress bar shows coverage), waits a random 5-15 s more, sends the signal and
prints the seconds until the process exits, its exit status, whether cffi swallowed an
exception ("Exception ignored"), its last line and whether OUT is left behind.

    python bench/bench_interrupt.py                       # 3 tries: SIGTERM, SIGINT, SIGTERM
    python bench/bench_interrupt.py --robots 2000 --tries 4
"""

from __future__ import annotations

import argparse
import os
import random
import shutil
import signal
import subprocess
import sys
import tempfile
import time
from pathlib import Path


def swarmsim() -> list[str]:
    return [sys.executable, "-m", "swarmsim"]


def one_try(world: Path, out: Path, sig: signal.Signals, rng: random.Random,
            timeout: float) -> str:
    shutil.rmtree(out, ignore_errors=True)
    env = {**os.environ, "SDL_VIDEODRIVER": "dummy", "SDL_AUDIODRIVER": "dummy"}
    proc = subprocess.Popen([*swarmsim(), "run", str(world), "--out", str(out),
                             "--max-ticks", "1000000"], env=env, stderr=subprocess.PIPE,
                            text=True)
    started = time.monotonic()
    seen = ""
    while "coverage" not in seen:
        char = proc.stderr.read(1)
        if not char:
            return f"{sig.name}: the run ended before ticking: {seen[-200:]!r}"
        seen += char
    ticking = time.monotonic() - started
    wait = rng.uniform(5, 15)
    time.sleep(wait)
    proc.send_signal(sig)
    sent = time.monotonic()
    try:
        _, err = proc.communicate(timeout=timeout)
    except subprocess.TimeoutExpired:
        proc.kill()
        proc.communicate()
        return f"{sig.name}: NOT STOPPED within {timeout:.0f} s (killed)"
    last = err.strip().splitlines()[-1] if err.strip() else ""
    return (f"{sig.name}: ticking after {ticking:.1f} s, signal {wait:.1f} s later: exit "
            f"{proc.returncode} in {time.monotonic() - sent:.2f} s; swallowed: "
            f"{'Exception ignored' in err}; last line {last[-40:]!r}; OUT left: {out.exists()}")


def main() -> None:
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--robots", type=int, default=10000)
    ap.add_argument("--groups", type=int, default=16)
    ap.add_argument("--size", type=float, default=640)
    ap.add_argument("--tries", type=int, default=3)
    ap.add_argument("--timeout", type=float, default=120, help="s to wait for an exit")
    ap.add_argument("--seed", type=int, default=0, help="of the random waits")
    args = ap.parse_args()
    rng = random.Random(args.seed)
    with tempfile.TemporaryDirectory() as tmp:
        world = Path(tmp) / "K.toml"
        subprocess.run([*swarmsim(), "make-world", "--text", "K", "--size", str(args.size),
                        "--robots", str(args.robots), "--groups", str(args.groups),
                        "--out", str(world)], check=True, stdout=subprocess.DEVNULL)
        signals = (signal.SIGTERM, signal.SIGINT)
        for k in range(args.tries):
            print(one_try(world, Path(tmp) / "out", signals[k % 2], rng, args.timeout),
                  flush=True)


if __name__ == "__main__":
    main()
