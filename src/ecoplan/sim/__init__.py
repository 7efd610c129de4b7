"""Simulation: batch integrator of the time-domain physics.

* :mod:`ecoplan.sim.simulate` -- fixed-step ICR-kinematics integrator with power and
  energy from the vehicle's model, vectorised over runs, CSV in the diagnosis log format.

The A->B replay of §IV-A is :mod:`ecoplan.experiments.ab_replay`.
"""

from ecoplan.sim.simulate import (
    EXTRA_COLUMNS,
    LOG_COLUMNS,
    SimConfig,
    SimResult,
    TrackSchedule,
    WaypointRun,
    simulate_batch,
    simulate_policy,
    simulate_tracks,
    simulate_waypoints,
)

__all__ = [
    "EXTRA_COLUMNS",
    "LOG_COLUMNS",
    "SimConfig",
    "SimResult",
    "TrackSchedule",
    "WaypointRun",
    "simulate_batch",
    "simulate_policy",
    "simulate_tracks",
    "simulate_waypoints",
]
