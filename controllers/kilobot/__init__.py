"""The Kilobot controller: its declarations (params.py), the batch controller (controller.py),
its swarm (swarm.py) and compiled chunk kernels (chunk.py), and the per-robot reference
(robot.py)."""

from pathlib import Path

from swarmsim.controller import stamp_kernels_by_code

# chunk.py's kernels read params.py's constants: the package's kernels are stamped by the code
# of all its files, before any of them is decorated
stamp_kernels_by_code(Path(__file__).parent, whole=True)

from .controller import Kilobot
from .params import (
           INSIDE,
           JOINED,
           MESSAGE_FIELDS,
           MOVING,
           OUTSIDE,
           STATUSES,
           TRAVEL,
           WAIT,
           KilobotParams,
)
from .robot import KilobotRobot

__all__ = ["INSIDE", "JOINED", "MESSAGE_FIELDS", "MOVING", "OUTSIDE", "STATUSES", "TRAVEL",
           "WAIT", "Kilobot", "KilobotParams", "KilobotRobot"]
