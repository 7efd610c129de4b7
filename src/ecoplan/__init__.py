"""ecoplan: energy-aware path planning for skid-steer mobile robots.

The package is layered; a layer imports only the layers before it (``.importlinter``, checked
by ``lint-imports`` in ``make test``; the README's "What is in the box" says what each holds)::

    errors, _typing -> models/ -> presets -> dynamics/ -> geometry/ -> energy/ | sim/
      -> planning/ -> io/ -> diagnose/ -> synth/ | experiments/ -> app/ -> cli

Frames follow ROS REP-103 (x forward, y left, yaw counter-clockwise).  The
tracked paper (Morales et al. 2009) uses a local frame with Y forward and X to
the right; :mod:`ecoplan.models.kinematics` converts at the model boundary.
"""

from ecoplan.errors import EcoplanError, InfeasibleError, InputError, PlanningError

__all__ = ["EcoplanError", "InfeasibleError", "InputError", "PlanningError", "__version__"]
__version__ = "0.1.0"
