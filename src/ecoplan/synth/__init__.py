"""Blind-check generator: realistic synthetic logs with one withheld effect (issue 6, item 3).

A *case* is a session of several runs of one vehicle preset, generated from the preset's
model plus one effect that the diagnosis must find without being told.  The answer is kept
in :attr:`~ecoplan.synth.cases.SynthCase.truth`, apart from the logs.  The generator moves
the robot with the same physics as the simulator (:mod:`ecoplan.dynamics`) and applies
each effect as the diagnosis defines it (:mod:`ecoplan.diagnose.effects`).

Pipeline, one module a step
---------------------------
1. **Commands** -- :mod:`ecoplan.synth.manoeuvres`: realistic manoeuvres give side-speed
   command profiles ``cmd_left(t), cmd_right(t)`` [m/s]: the identification grid of the
   tracked paper §III-C (:func:`~ecoplan.synth.manoeuvres.stationary_grid_commands`), the
   spirals of its Fig. 12 (:func:`~ecoplan.synth.manoeuvres.spiral_commands`) and A->B runs
   under the heading controller of §IV, eq. (23), closed loop on the true pose
   (:func:`~ecoplan.synth.manoeuvres.waypoint_runs`: the controller of
   :mod:`ecoplan.dynamics.controller` stepped by :func:`ecoplan.dynamics.rollout.rollout`).
2. **Drive and kinematics** -- :mod:`ecoplan.synth.trajectory`: actual side speeds by the
   one drive law (:func:`ecoplan.dynamics.drive.follow_commands`: acceleration limit and,
   for ``actuator_lag`` only, a first-order lag), the pose by the one integrator
   (:func:`ecoplan.dynamics.integrate.integrate_tracks`), giving a
   :class:`~ecoplan.synth.trajectory.Trajectory` of true values.
3. **Power** -- :mod:`ecoplan.synth.withheld`: the effect, its magnitude and parameters;
   :func:`~ecoplan.synth.withheld.inject` gives the true electrical power ``P_T`` [W] on a
   trajectory.  Deterministic: any randomness is drawn by the generator into the
   parameters (e.g. a spike train's seed).
4. **Sensors** -- :mod:`ecoplan.synth.sensors`: the log, measured speeds, power, yaw rate
   and pose with white Gaussian noise (:class:`~ecoplan.synth.sensors.SensorNoise`);
   commands logged exactly.
5. **Cases** -- :mod:`ecoplan.synth.cases`: a session of runs, the withheld truth, the case
   directories (:func:`~ecoplan.synth.cases.generate_case`,
   :func:`~ecoplan.synth.cases.write_cases`).

Times are *session* times: the runs of a case follow each other on one clock (with
pauses), so a drift or a step shows across runs.
"""
