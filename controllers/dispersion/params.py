"""Dispersion's declarations: its parameters (:class:`DispersionParams`), statuses and what the
engine reads of the class (:class:`DispersionDeclarations`), shared by the batch controller
(controller.py's Dispersion) and the per-robot one (robot.py's DispersionRobot)."""

from __future__ import annotations

from dataclasses import dataclass
from typing import ClassVar

from swarmsim.controller import require_positive

IDLE, SEEKING, SPREADING = 0, 1, 2
STATUSES = ("Idle", "Seeking", "Spreading")


@dataclass(frozen=True)
class DispersionParams:
    """Parameters (units; speeds in units per tick).

    Attributes:
        d_cover: neighbours closer than this repel (the desired spacing).
        v: top speed (paper: 0.1).
        gain: repulsion gain (speed per unit of missing distance).
        deadband: speeds below this are treated as zero (the robot rests).
        probe_distance: how far ahead the floor probe looks before a step.
    """

    d_cover: float = 6.0
    v: float = 0.1
    gain: float = 0.05
    deadband: float = 0.005
    probe_distance: float = 1.0

    def __post_init__(self) -> None:
        require_positive(self, "d_cover", "v", "gain", "probe_distance")
        if self.deadband < 0:
            raise ValueError(f"deadband must be >= 0, got {self.deadband!r}")


class DispersionDeclarations:
    """What the engine reads of a dispersion controller class
    (swarmsim.controller.ControllerClass)."""

    name = "dispersion"
    Params = DispersionParams
    STATUSES = STATUSES
    MESSAGE_FIELDS: ClassVar[list] = []

    @classmethod
    def sensing_range(cls, params: DispersionParams) -> float:
        """Neighbours within d_cover repel."""
        return params.d_cover
