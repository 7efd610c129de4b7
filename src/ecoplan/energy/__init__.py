"""Energy of paths and trajectories, and the cost objectives planners minimise.

* :mod:`ecoplan.energy.primitives` -- energy of one steady motion (straight, on the spot,
  arc); the vehicle and world interfaces the module needs;
* :mod:`ecoplan.energy.turns` -- executions of a heading change and their net energy;
* :mod:`ecoplan.energy.path` -- energy and feasibility of a waypoint path;
* :mod:`ecoplan.energy.trajectory` -- energy of a timed track-speed trajectory;
* :mod:`ecoplan.energy.controlled` -- corners, start and stop as the heading controller
  drives them (tabulated with the simulator's physics): the estimate within 3 % of the
  simulated energy on the shipped scenarios;
* :mod:`ecoplan.energy.result` -- :class:`~ecoplan.energy.result.PathCost`, what both return;
* :mod:`ecoplan.energy.objective` -- cost objectives (energy, length) for planners.

The package imports the models and the dynamics only (the vehicle and the world come in
through small protocols).
"""
