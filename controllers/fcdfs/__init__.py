"""The FCDFS controller: its declarations (params.py), the batch controller (controller.py),
its swarm (swarm.py) and compiled chunk kernel (chunk.py), and the per-robot reference
(robot.py)."""

from pathlib import Path

from swarmsim.controller import stamp_kernels_by_code

# chunk.py's kernel reads params.py's constants: the package's kernels are stamped by the code
# of all its files, before any of them is decorated
stamp_kernels_by_code(Path(__file__).parent, whole=True)

from .controller import FCDFS
from .params import FCDFSParams
from .robot import FCDFSRobot

__all__ = ["FCDFS", "FCDFSParams", "FCDFSRobot"]
