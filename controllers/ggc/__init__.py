"""GGC: gradient-and-grouping self-organising coverage (the paper's controller).

``--controller ggc``. The class here only declares: its parameters (params.py), statuses
(statuses.py), broadcast fields (schema.py: one row per datum of a robot's state and
broadcast). The run's robots are one :class:`GGCSwarm` (swarm.py): their state rows
(state.py) and the compiled driver (decide.py) that decides each robot by the rules in
rules/, one module per rule family:

=============================  =============================================================
rule                           where
=============================  =============================================================
travel (Initial)               rules/travel.py
gradient (Algorithm 1, 2:8)    rules/gradient.py
detection (Algorithm 7)        rules/detection.py
coverage (Algorithm 2)         rules/coverage.py (edge following, boundary fill, giving way)
arrival (Algorithm 2's stops)  rules/arrival.py
inter-group (Section 4.3)      rules/intergroup.py (the rule sets, GGCParams.ruleset)
deadlock (Algorithms 5-6)      rules/deadlock.py
surplus                        rules/surplus.py
aggregation (Algorithms 3-4)   rules/aggregation.py (the scattered start)
holes in the structure         rules/holes.py (rule sets with HOLES)
islands off the target         rules/island.py (d_cover <= yield_release)
confined movers give up        rules/confined.py (SURPLUS, d_cover <= yield_release)
crossing the structure         rules/cross.py (rule sets with CROSS)
=============================  =============================================================

rules/rulesets.py names the rule sets and their flags; rules/common.py holds what every rule
shares (the View and Probe structs, actions, small geometry).
"""

from __future__ import annotations

from collections.abc import Sequence
from pathlib import Path
from typing import Any

import numpy as np

from controllers.common.gradient import COLOURINGS
from swarmsim.controller import MAX_GROUPS, RobotSetup, stamp_kernels_by_code

# the driver (decide.py) is compiled with rules from every file here: its kernels are
# stamped by the code of the whole package, before any of them is decorated
stamp_kernels_by_code(Path(__file__).parent, whole=True)

from .params import GGCParams
from .schema import SILENT
from .state import message_fields
from .statuses import SETTLED, STATUSES
from .swarm import FAILURE_MODES, GGCSwarm, same_run_ruleset


class GGC:
    """Gradient-and-grouping coverage (the paper's): a gradient, groups, edge-following fill.

    Robots leave their formations for the beacon, spread a hop-count gradient over the
    target, and fill it group by group along its edges, d_cover apart (paper Sections 3-4).
    This class declares the controller (parameters, statuses, broadcasts); the robots are
    one :class:`GGCSwarm`, their rules in rules/.
    """

    name = "ggc"
    Params = GGCParams
    STATUSES = STATUSES
    SETTLED_STATUSES = SETTLED
    MESSAGE_FIELDS = message_fields(1, scattered=True)  # a run's: message_fields_for
    SILENT = SILENT
    COLOURINGS = COLOURINGS
    LEADER_FIELD = "leader"
    GROUP_FIELD = "group"
    INITIAL_STATUSES = ("Initial",)
    COVERING_STATUSES = ("Coverage",)
    FAILURE_MODES = FAILURE_MODES
    default_start = "formation"
    max_groups = MAX_GROUPS
    """Every run's bound (swarmsim/limits.py): GGC's per-group values are sized by the run."""
    requires_beacon = True
    probe_params = ("probe_distance", "boundary_probe")
    """Parameters that are floor-probe lengths (checked against the probe range)."""

    @classmethod
    def message_fields_for(cls, groups: int, scattered: bool) -> list[tuple]:
        """GGC's broadcast fields for a run with ``groups`` groups, its robots started
        ``scattered`` or not (state.message_fields)."""
        return message_fields(groups, scattered)

    @classmethod
    def sensing_range(cls, params: GGCParams) -> float:
        """Robots hear broadcasts within R_c (and at least far enough to edge-follow)."""
        return max(params.R_c, params.gradient_reach * params.d_cover, params.d_cover + 2)

    @classmethod
    def same_run_settings(cls, params: GGCParams, config: Any) -> dict[str, Any]:
        """{"ruleset": name} when another rule set, ``name``, makes this run by construction
        and names it canonically (swarm.same_run_ruleset: "paper" where equivalent), else {}
        (``config``: the run's SimConfig; its groups count)."""
        name = same_run_ruleset(params, int(config.groups))
        return {} if name == params.ruleset else {"ruleset": name}

    @classmethod
    def create_swarm(cls, setups: Sequence[RobotSetup], params: GGCParams,
                     rngs: Sequence[np.random.Generator]) -> GGCSwarm:
        """The run's robots (row i: robot i)."""
        return GGCSwarm(setups, params, rngs)


__all__ = ["GGC", "GGCParams", "GGCSwarm"]
