"""The contacts part: collisions, overlap and contact impulse (collision realism)."""

from __future__ import annotations

from collections.abc import Mapping
from typing import Any

import numpy as np

from swarmsim.metrics.part import MetricPart, Observation, Reporter, RobotReporter


class ContactsPart(MetricPart):
    """Contacts read from the physics each tick: who touches, overlap, impulse; and the
    physics' own counts of contacts begun (swarmsim.physics.physics.ContactStats).

    Args:
        physics: the run's Physics (its ``contact_state()`` and ``contacts`` are read).
    """

    name = "contacts"

    def __init__(self, physics: Any):
        self.physics = physics
        self.max_overlap = 0.0  # deepest penetration seen, units
        self.total_impulse = 0.0
        self.peak_impulse = 0.0
        self.overlap_sum = 0.0
        self.overlap_contacts = 0
        self.contact_ticks = np.zeros(physics.n, dtype=np.int64)  # ticks each robot touched
        self.contact_robot_ticks = 0
        self._in_contact = 0  # robots touching at the end of the last tick
        self._impulse = 0.0  # contact impulse of the last tick's last substep
        self.state: Any = None
        """The ContactState at the end of the last observed tick (None before the first);
        parts after this one read it."""

    def observe(self, now: Observation) -> None:
        c = self.state = self.physics.contact_state()
        self.max_overlap = max(self.max_overlap, c.max_overlap)
        self.total_impulse += c.impulse
        self.peak_impulse = max(self.peak_impulse, c.peak_impulse)
        self.overlap_sum += c.overlap_sum
        self.overlap_contacts += c.robot_pairs
        self.contact_ticks += c.in_contact
        touching = int(np.count_nonzero(c.in_contact))
        self.contact_robot_ticks += touching
        self._in_contact, self._impulse = touching, c.impulse

    def columns(self) -> Mapping[str, Reporter]:
        return {"in_contact": lambda: self._in_contact,
                "contacts_robot_robot": lambda: self.physics.contacts.robot_robot,
                "contacts_robot_wall": lambda: self.physics.contacts.robot_wall,
                "max_overlap": lambda: round(self.max_overlap, 6),
                "contact_impulse": lambda: round(self._impulse, 6)}

    def robot_columns(self) -> Mapping[str, RobotReporter]:
        return {"contacts_robot": lambda: self.physics.contacts.per_robot.tolist(),
                "contacts_wall": lambda: self.physics.contacts.per_robot_wall.tolist(),
                "contact_ticks": lambda: self.contact_ticks.tolist()}

    def summary_fields(self) -> Mapping[str, Reporter]:
        return {"collisions_robot_robot": lambda: self.physics.contacts.robot_robot,
                "collisions_robot_wall": lambda: self.physics.contacts.robot_wall,
                "max_overlap": lambda: round(self.max_overlap, 6),
                "total_contact_impulse": lambda: round(self.total_impulse, 3),
                "contact_robot_ticks": lambda: self.contact_robot_ticks,
                "mean_overlap": lambda: round(self.overlap_sum / self.overlap_contacts, 6)
                if self.overlap_contacts else 0.0,
                "peak_contact_impulse": lambda: round(self.peak_impulse, 6),
                "robots_touched": lambda: int((self._per_robot() > 0).sum()),
                "contacts_per_robot_mean": lambda: round(float(self._per_robot().mean()), 3)
                if self._per_robot().size else 0.0,
                "contacts_per_robot_max": lambda: int(self._per_robot().max())
                if self._per_robot().size else 0}

    def _per_robot(self) -> np.ndarray:
        """(N,) robot-robot contacts each robot took part in."""
        return self.physics.contacts.per_robot


__all__ = ["ContactsPart"]
