"""Simulation: heading controller (tracked paper eq. 23) and integrator.

* :mod:`ecoplan.sim.controller` -- heading controller with way points (§IV, eq. 23);
* :mod:`ecoplan.sim.simulate` -- fixed-step ICR-kinematics integrator with power and
  energy from the vehicle's model, vectorised over runs, CSV in the diagnosis log format.

The A->B replay of §IV-A is :mod:`ecoplan.experiments.ab_replay`.
"""

from ecoplan.sim.controller import HeadingController, WaypointFollower
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
    "HeadingController",
    "SimConfig",
    "SimResult",
    "TrackSchedule",
    "WaypointFollower",
    "WaypointRun",
    "simulate_batch",
    "simulate_policy",
    "simulate_tracks",
    "simulate_waypoints",
]
