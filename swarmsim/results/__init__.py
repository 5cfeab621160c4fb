"""What a run hands out: the summary's collector, snapshots for observers, the output files, run
folders, trajectories, plots, the code's version."""
