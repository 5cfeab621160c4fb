"""Experiments: sweep specs (params x grid x seeds), resumable runners, executors, tables.

``swarmsim sweep SPEC --out DIR`` runs a TOML spec (see :mod:`.spec`);
``swarmsim reproduce FIG`` runs the paper's Section 6 figures (see :mod:`.reproduce`).

Python API::

    from swarmsim.experiments import load_spec, run_sweep
    report = run_sweep(load_spec("sweep.toml").runs(), "out/", workers=4)
"""

from swarmsim.experiments.runner import RunStore, Sweep, SweepReport, execute_run
from swarmsim.experiments.spec import RunSpec, SweepSpec, load_spec, run_id, spec_from_dict
from swarmsim.experiments.sweep import run_sweep

__all__ = ["RunSpec", "RunStore", "Sweep", "SweepReport", "SweepSpec", "execute_run",
           "load_spec", "run_id", "run_sweep", "spec_from_dict"]
