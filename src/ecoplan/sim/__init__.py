"""Simulation: heading controller (tracked paper eq. 23), integrator, A->B replay.

* :mod:`ecoplan.sim.controller` -- heading controller with way points (§IV, eq. 23);
* :mod:`ecoplan.sim.simulate` -- fixed-step ICR-kinematics integrator with power and
  energy from the vehicle's model, vectorised over runs, CSV in the diagnosis log format;
* :mod:`ecoplan.sim.replay` -- the A->B obstacle experiment of §IV-A (Table III, Fig. 14).
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
