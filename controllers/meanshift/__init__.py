"""The mean-shift controller: its declarations and per-robot reference (controller.py), the
run's robots as arrays (swarm.py) and their compiled kernels (chunk.py, kernel.py)."""

from pathlib import Path

from swarmsim.controller import stamp_kernels_by_code

# chunk.py's kernels are compiled with kernel.py's: stamped by the code of the whole package
stamp_kernels_by_code(Path(__file__).parent, whole=True)

from .controller import MeanShift, MeanShiftParams, MeanShiftRobot

__all__ = ["MeanShift", "MeanShiftParams", "MeanShiftRobot"]
