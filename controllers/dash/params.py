"""DASH's declarations: its parameters (:class:`DashParams`), statuses, message fields and
what the engine reads of the class (:class:`DashDeclarations`), shared by the batch controller
(controller.py's Dash) and the per-robot one (robot.py's DashRobot)."""

from __future__ import annotations

from dataclasses import dataclass

from swarmsim.controller import require_positive

SEEKING, SPREADING, RESTING = 0, 1, 2
STATUSES = ("Seeking", "Spreading", "Resting")
MESSAGE_FIELDS = [("spacing", "f4")]


@dataclass(frozen=True)
class DashParams:
    """Parameters of the DASH-like controller (lengths in units, speeds in units per tick).

    Attributes:
        d_safe: smallest distance kept from any neighbour (paper Table 2: 1).
        d_cover: largest spacing a robot adapts to (GGC's coverage distance; default 6).
        s_start: spacing a robot starts from when it reaches the target.
        adapt_rate: change of the spacing per tick, units.
        consensus_band: a robot's spacing steps toward the mean spacing of its on-target
            neighbours within 1.5 * d_cover while it differs from it by more than this, units.
        tolerance: a neighbour closer than s * (1 - tolerance) counts as too close.
        crowd: with this many neighbours too close, the spacing shrinks.
        v: top speed (paper: 0.1).
        gain: repulsion gain (speed per unit of missing distance, per neighbour).
        deadband: speeds below this are treated as zero (the robot rests).
        probe_distance: how far ahead the floor probe looks before a step (<= 2, the
            engine's probe range).
    """

    d_safe: float = 1.0
    d_cover: float = 6.0
    s_start: float = 2.0
    adapt_rate: float = 0.004
    consensus_band: float = 0.2
    tolerance: float = 0.1
    crowd: int = 3
    v: float = 0.1
    gain: float = 0.05
    deadband: float = 0.005
    probe_distance: float = 1.0

    def __post_init__(self) -> None:
        require_positive(self, "d_safe", "d_cover", "s_start", "adapt_rate", "v", "gain",
                         "probe_distance", "crowd")
        if not self.d_safe <= self.s_start <= self.d_cover:
            raise ValueError(f"need d_safe <= s_start <= d_cover, got {self.d_safe}, "
                             f"{self.s_start}, {self.d_cover}")
        if not 0 <= self.tolerance < 1:
            raise ValueError(f"tolerance must be in [0, 1), got {self.tolerance!r}")
        if self.deadband < 0 or self.consensus_band < 0:
            raise ValueError("deadband and consensus_band must be >= 0")
        if self.probe_distance > 2.0:
            raise ValueError(f"probe_distance ({self.probe_distance}) must be <= 2 (the "
                             "engine's default probe range)")


class DashDeclarations:
    """What the engine reads of a DASH controller class (swarmsim.controller.ControllerClass)."""

    name = "dash"
    Params = DashParams
    STATUSES = STATUSES
    SETTLED_STATUSES = ("Resting",)  # done, standing still (collision instruments)
    MESSAGE_FIELDS = MESSAGE_FIELDS
    requires_beacon = True

    @classmethod
    def sensing_range(cls, params: DashParams) -> float:
        """Neighbours within 1.5 * d_cover tell their spacing."""
        return 1.5 * params.d_cover
