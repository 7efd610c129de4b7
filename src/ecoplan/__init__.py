"""ecoplan: energy-aware path planning for skid-steer mobile robots.

The package is layered (lower layers never import upper ones)::

    presets, models/  ->  cost  ->  planning/, sim/  ->  diagnose/  ->  scenario, cli

Frames follow ROS REP-103 (x forward, y left, yaw counter-clockwise).  The
tracked paper (Morales et al. 2009) uses a local frame with Y forward and X to
the right; :mod:`ecoplan.models.kinematics` converts at the model boundary.
"""

from ecoplan.errors import EcoplanError, InfeasibleError, InputError, PlanningError

__all__ = ["EcoplanError", "InfeasibleError", "InputError", "PlanningError", "__version__"]
__version__ = "0.1.0"
