"""Sim-to-real gap diagnosis: log input/output, blind-check generator, effects and verdicts.

Modules: :mod:`ecoplan.diagnose.logio` (the log format, CSV/BorealTC/ROS 2 bag loaders),
:mod:`ecoplan.diagnose.synth` (synthetic logs with withheld effects for the blind check).
"""
