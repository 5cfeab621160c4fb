"""Run GGC on a world from Python, print the summary and save the last frame.

    python examples/run_ggc.py            # the small 'tiny' world, a few seconds
    python examples/run_ggc.py K 3        # the letter K with 3 groups (minutes)
"""

import sys

from swarmsim import Simulation, load_world
from swarmsim.render import save_png

world = load_world(sys.argv[1] if len(sys.argv) > 1 else "tiny")
groups = int(sys.argv[2]) if len(sys.argv) > 2 else 1
sim = Simulation(world, controller="ggc", groups=groups, seed=1, max_ticks=20_000)
result = sim.run(progress=True)
s = result.summary
print(f"coverage {s['coverage']:.3f}, completion tick {s['completion_tick']}, "
      f"stop: {s['stop_reason']}, distance {s['total_distance']:.0f}")
save_png(sim.render(color_by="status"), f"{world.name}-last.png")
