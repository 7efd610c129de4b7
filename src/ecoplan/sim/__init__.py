"""Simulation: batch integrator of the time-domain physics, A->B replay.

* :mod:`ecoplan.sim.simulate` -- fixed-step ICR-kinematics integrator with power and
  energy from the vehicle's model, vectorised over runs, CSV in the diagnosis log format;
* :mod:`ecoplan.sim.replay` -- the A->B obstacle experiment of §IV-A (Table III, Fig. 14).
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
