"""The CVT controller (controller.py) and its compiled kernel (kernel.py)."""

from .controller import CVT, CVTParams

__all__ = ["CVT", "CVTParams"]
