"""Simulation: batch integrator of the time-domain physics.

* :mod:`ecoplan.sim.simulate` -- fixed-step ICR-kinematics integrator with power and
  energy from the vehicle's model, vectorised over runs; a result converts to the log
  (:meth:`~ecoplan.sim.simulate.SimResult.to_log`).

The A->B replay of §IV-A is :mod:`ecoplan.experiments.ab_replay`.
"""

from ecoplan.sim.simulate import (
    EXTRA_COLUMNS,
    SimConfig,
    SimResult,
    TrackSchedule,
    WaypointRun,
    breakdown_columns,
    simulate_batch,
    simulate_policy,
    simulate_tracks,
    simulate_waypoints,
)

__all__ = [
    "EXTRA_COLUMNS",
    "SimConfig",
    "SimResult",
    "TrackSchedule",
    "WaypointRun",
    "breakdown_columns",
    "simulate_batch",
    "simulate_policy",
    "simulate_tracks",
    "simulate_waypoints",
]
