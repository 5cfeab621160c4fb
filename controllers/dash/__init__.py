"""The Dash controller (controller.py) and its compiled kernel (kernel.py)."""

from .controller import Dash, DashParams

__all__ = ["Dash", "DashParams"]
