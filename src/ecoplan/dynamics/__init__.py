"""Time-domain physics, written once: drive law, pose integration, heading controller.

* :mod:`ecoplan.dynamics.drive` -- how actual track speeds follow commands: saturation
  (tracked eqs. 4-6), acceleration limit, first-order lag; the rest-to-rest profile;
* :mod:`ecoplan.dynamics.integrate` -- the ICR kinematics (tracked eqs. 1-3) integrated
  in time by exact arcs;
* :mod:`ecoplan.dynamics.controller` -- the heading controller with way points (tracked
  paper §IV, eq. 23) for both vehicles, with power-limited turning for wheeled ones.

The simulator (:mod:`ecoplan.sim.simulate`) and the energy module call these; so should
everything else that moves a robot in time.
"""
