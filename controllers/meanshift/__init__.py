"""The MeanShift controller (controller.py) and its compiled kernel (kernel.py)."""

from .controller import MeanShift, MeanShiftParams

__all__ = ["MeanShift", "MeanShiftParams"]
