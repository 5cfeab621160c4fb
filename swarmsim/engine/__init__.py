"""The tick loop and what it runs: Simulation, the per-robot Swarm, a controller's declarations
read once, action checks, settings, stop and fault hooks."""
