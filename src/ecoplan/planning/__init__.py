"""Planners: waypoint graph, dense lattice reference, speed choice (and OMPL in its module).

Import the planners from their modules (``ecoplan.planning.graph``, ...); this package
re-exports the shared result types and cost objects only, so that importing it stays
cheap and does not load OMPL.
"""

from ecoplan.planning.base import (
    Deadline,
    EnergyCost,
    LengthCost,
    PathCostModel,
    Plan,
    PlanResult,
    check_endpoints,
)

__all__ = [
    "Deadline",
    "EnergyCost",
    "LengthCost",
    "PathCostModel",
    "Plan",
    "PlanResult",
    "check_endpoints",
]
