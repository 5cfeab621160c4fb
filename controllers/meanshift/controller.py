"""Mean-shift exploration shape assembly (Sun, Zhou, Ma, Li, Gross, Chen & Zhao, Nat. Commun.
14:3476, 2023), scaled to the GGC paper's units; a modern assignment-free anchor.

Each robot sums three velocity commands (from the released MATLAB code's structure, see
/work/shared/research/algorithms.md section 5a), then low-pass filters and caps the sum:

* Entering: off the target, head for the nearest sensed target point (the beacon when none is
  sensed): ``kappa_enter`` times a unit vector.
* Exploring (mean shift): with the raised-cosine kernel W(d) = (1 + cos(pi d / R)) / 2 over the
  sensed target points within R = ``r_sense``, ``m_fill`` is the W-weighted mean of all of them
  and ``m_expl`` the W-weighted mean of those not occupied by a neighbour (within
  ``r_occupied`` of one); the command is ``kappa_fill (m_fill - p) + kappa_expl (m_expl - p)``:
  a robot surrounded by neighbours and free target floor gives up its place for the densest
  free floor nearby.
* Interaction: repulsion ``kappa_avoid (d_cover - d) / d`` along the unit vector away from
  each neighbour closer than ``d_cover`` (the paper's r_avoid), and velocity consensus
  ``-kappa_cons * mean_j (v_i - v_j)`` over neighbours within r_sense (neighbours broadcast
  their velocity).
* ``v <- (1 - inertia) * cmd + inertia * v``, capped at v_max (the code's 0.1 / 0.9 filter).

Scaling from the paper's units (r_avoid 1.5, r_sense 2.5, v_max 5 per second, dt 0.01 s) to
ours (d_cover 6 = r_avoid, so lengths x4; v 0.1 per tick, so speeds x0.02): gains on lengths
(kappa_fill 5, kappa_expl 15) become /200, gains on unit vectors or ratios (kappa_enter 10,
kappa_avoid 25) become x0.02, kappa_cons stays 1, r_sense = 2.5 / 1.5 * d_cover = 10.
The paper's gray "halo" around the shape (which guides robots in from afar) is replaced by the
beacon's bearing, and its shape-pose negotiation is not needed (the target is fixed).

Sensing: relative positions (bearing and distance) of every neighbour within r_sense, their
broadcast velocities, a local map of the target floor within r_sense (``min_probe_range`` 10:
the engine must let the floor probe reach that far; GGC's robots sense only the floor under
them and 2 units ahead), odometry and the beacon's bearing. Far more than GGC's hop counts and
distances.
"""

from __future__ import annotations

import math
from collections.abc import Sequence
from dataclasses import dataclass

import numpy as np

from controllers.common.localmap import MIN_MAP_CELL, LocalMap, clamp, sq_norms
from controllers.common.mapkernel import warm_up as _warm_up_map
from swarmsim.controller import (
    NO_SENDER,
    Action,
    Perception,
    RobotSetup,
    make_action,
    require_non_negative,
    require_positive,
)

from .chunk import EXPLORING, RESTING, SEEKING
from .kernel import explore, interact
from .kernel import warm_up as _warm_up_kernels
from .swarm import MeanShiftSwarm
from .swarm import warm_up as _warm_up_chunk

STATUSES = ("Seeking", "Exploring", "Resting")
MESSAGE_FIELDS = [("vx", "f4"), ("vy", "f4")]
MIN_PROBE_RANGE = 10.0


@dataclass(frozen=True)
class MeanShiftParams:
    """Parameters of the mean-shift controller (lengths in units, speeds in units per tick).

    Attributes:
        d_cover: avoidance distance (the paper's r_avoid): neighbours closer repel; sets the
            spacing, like GGC's d_cover (default 6).
        r_sense: kernel radius R and sensing radius for neighbours and floor (paper:
            2.5 / 1.5 r_avoid = 10; at most the class's min_probe_range, 10).
        r_occupied: a sensed target point within this distance of a neighbour is occupied
            (paper: max(r_avoid / 2, 2 r_body) = 3).
        map_cell: spacing of the lattice of floor points a robot senses (at least 0.1).
        v: top speed (paper Table 2: 0.1).
        kappa_enter: entering speed toward the nearest target point (paper 10 -> 0.2).
        kappa_fill: gain toward the kernel mean of all target points (paper 5 -> 0.025).
        kappa_expl: gain toward the kernel mean of unoccupied target points (15 -> 0.075).
        kappa_avoid: avoidance gain (paper 25 -> 0.5).
        kappa_cons: velocity-consensus gain (paper 1).
        inertia: weight of the previous velocity in the low-pass filter (paper 0.9).
        deadband: a robot whose command and velocity are both below this rests (and sleeps).
    """

    d_cover: float = 6.0
    r_sense: float = 10.0
    r_occupied: float = 3.0
    map_cell: float = 1.0
    v: float = 0.1
    kappa_enter: float = 0.2
    kappa_fill: float = 0.025
    kappa_expl: float = 0.075
    kappa_avoid: float = 0.5
    kappa_cons: float = 1.0
    inertia: float = 0.9
    deadband: float = 0.004

    def __post_init__(self) -> None:
        require_positive(self, "d_cover", "r_sense", "r_occupied", "map_cell", "v", "kappa_enter")
        require_non_negative(self, "kappa_fill", "kappa_expl", "kappa_avoid", "kappa_cons",
                             "deadband")
        if not 0 <= self.inertia < 1:
            raise ValueError(f"inertia must be in [0, 1), got {self.inertia!r}")
        if self.r_sense > MIN_PROBE_RANGE:
            raise ValueError(f"r_sense ({self.r_sense}) must not exceed the probe range the "
                             f"controller requests ({MIN_PROBE_RANGE})")
        if not MIN_MAP_CELL <= self.map_cell <= self.r_sense / 4:
            raise ValueError(f"map_cell ({self.map_cell}) must be at least {MIN_MAP_CELL} (the "
                             "floor points a robot senses) and at most r_sense / 4")


class MeanShiftDeclarations:
    """What both mean-shift classes declare (controller API): the name, parameters,
    statuses, broadcasts and sensing."""

    name = "meanshift"
    Params = MeanShiftParams
    STATUSES = STATUSES
    SETTLED_STATUSES = ("Resting",)  # done, standing still (collision instruments)
    MESSAGE_FIELDS = MESSAGE_FIELDS
    requires_beacon = True
    min_probe_range = MIN_PROBE_RANGE

    @classmethod
    def sensing_range(cls, params: MeanShiftParams) -> float:
        return max(params.r_sense + params.r_occupied, params.d_cover)

    @classmethod
    def warm_up(cls) -> None:
        """Compile or load the kernels before a run's clock starts."""
        _warm_up_map()
        _warm_up_kernels()
        _warm_up_chunk()


class MeanShift(MeanShiftDeclarations):
    """Sun et al. 2023: enter, explore free target floor by mean shift, avoid, agree.

    The run's robots are one :class:`~controllers.meanshift.swarm.MeanShiftSwarm` (their
    state in arrays, decided in compiled chunks); :class:`MeanShiftRobot` is the same
    controller one robot at a time, the reference its runs are held to, to the bit.
    """

    @classmethod
    def create_swarm(cls, setups: Sequence[RobotSetup], params: MeanShiftParams,
                     rngs: Sequence[np.random.Generator]) -> MeanShiftSwarm:
        """The run's robots (row i: robot i); mean-shift draws no random numbers."""
        return MeanShiftSwarm(setups, params)


class MeanShiftRobot(MeanShiftDeclarations):
    """One mean-shift robot (a per-robot controller): the reference implementation of
    :class:`MeanShift`, whose swarm makes the very same runs."""

    def __init__(self, setup: RobotSetup, params: MeanShiftParams, rng: np.random.Generator):
        self.id = setup.robot_id
        self.params = params
        self.map = LocalMap(params.r_sense, params.map_cell)
        self.velocity = np.zeros(2)
        self.status = SEEKING

    def message(self) -> tuple:
        return (self.id, self.status, self.status != RESTING, float(self.velocity[0]),
                float(self.velocity[1]))

    def entering(self, perception: Perception, points: np.ndarray, target: np.ndarray
                 ) -> np.ndarray:
        if perception.on_target:
            return np.zeros(2)
        if target.any():
            q = points[target]
            goal = q[np.argmin(sq_norms(q))]
            n = math.hypot(float(goal[0]), float(goal[1]))
            if n > 1e-9:
                return self.params.kappa_enter * goal / n
        if perception.beacon is not None:
            return self.params.kappa_enter * perception.beacon
        return np.zeros(2)

    def exploring(self, perception: Perception, points: np.ndarray, target: np.ndarray
                  ) -> np.ndarray:
        """The mean-shift command toward sensed target floor, free floor most (kernel)."""
        params = self.params
        return explore(points, target, perception.offsets, perception.distances, params.r_sense,
                       params.r_occupied, params.kappa_fill, params.kappa_expl)

    def interaction(self, perception: Perception) -> np.ndarray:
        """Repulsion within d_cover and velocity consensus with the neighbours heard."""
        m, params = perception.messages, self.params
        return interact(perception.offsets, perception.distances, m["id"], m["vx"], m["vy"],
                        self.velocity, params.d_cover, params.r_sense, params.kappa_avoid,
                        params.kappa_cons, NO_SENDER)

    def step(self, perception: Perception) -> Action:
        self.map.move(perception.moved)
        points, target = self.map.sense(perception)
        cmd = self.entering(perception, points, target) + self.exploring(perception, points, target)
        cmd = cmd + self.interaction(perception)
        cmd = clamp(cmd, self.params.v)
        inertia = self.params.inertia
        v = clamp((1 - inertia) * cmd + inertia * self.velocity, self.params.v)
        speed = math.hypot(float(v[0]), float(v[1]))
        if speed < self.params.deadband and math.hypot(*cmd) < self.params.deadband:
            self.velocity = np.zeros(2)
            self.status = RESTING if perception.on_target else SEEKING
            return make_action((0.0, 0.0), self.message(), sleep=True)
        self.velocity = v
        self.status = EXPLORING if perception.on_target else SEEKING
        return make_action((float(v[0]), float(v[1])), self.message())


__all__ = ["MeanShift", "MeanShiftParams", "MeanShiftRobot"]
