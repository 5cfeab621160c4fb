"""Run metrics, exactly as the paper defines them, as named parts.

Each part (:class:`MetricPart`) observes the run at the end of every tick and declares its
time-series columns, robots.csv columns and summary fields; :class:`RunMetrics` gathers them
(swarmsim/metrics/collector.py). The parts of a run, in the order their outputs are written:

* ``coverage`` (coverage.py): coverage P on the paper's raster (grid.py) and the completion
  tick t_dpl = first tick with 1 - P <= eps0;
* ``progress`` (progress.py): distance walked, robots moving, awake, on the target and
  placed, and when coverage settled;
* ``contacts`` (contacts.py): collisions, overlap and contact impulse;
* ``settled`` (settled.py): settled robots pushed out of place;
* ``spacing`` (spacing.py): nearest-neighbour spacing on the target at the end.

A new metric is one new part, added to :func:`standard_parts`. The stop rules that read the
metrics (complete, plateau, stall) are loop hooks (swarmsim/engine/hooks.py).
"""

from swarmsim.metrics.collector import ObservedRun, RunMetrics, standard_parts
from swarmsim.metrics.contacts import ContactsPart
from swarmsim.metrics.coverage import CoveragePart
from swarmsim.metrics.final import FinalState
from swarmsim.metrics.grid import STENCIL_CAP, CoverageGrid, IncrementalCoverage
from swarmsim.metrics.part import MetricPart, Observation, RunEnd
from swarmsim.metrics.progress import (
    MOVING_FRACTION,
    NOT_YET,
    ProgressPart,
    RobotTracks,
    first_within,
)
from swarmsim.metrics.settled import SettledPart, SettledWatch
from swarmsim.metrics.spacing import SpacingPart, nearest_neighbour_spacing
from swarmsim.metrics.stuck import StuckPart

__all__ = ["MOVING_FRACTION", "NOT_YET", "STENCIL_CAP", "ContactsPart", "CoverageGrid",
           "CoveragePart", "FinalState", "IncrementalCoverage", "MetricPart", "Observation",
           "ObservedRun", "ProgressPart", "RobotTracks", "RunEnd", "RunMetrics", "SettledPart",
           "SettledWatch", "SpacingPart", "StuckPart", "first_within", "nearest_neighbour_spacing",
           "standard_parts"]
