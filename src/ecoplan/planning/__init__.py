"""Planners: waypoint graph, dense lattice reference, speed choice (and OMPL in its module).

This package re-exports the shared result types, the cost objects, the graph planner,
the waypoint refinement, the lattice reference and the speed choice.  The OMPL planner is
imported from ``ecoplan.planning.ompl`` explicitly, so that importing this package does
not load OMPL.
"""

from ecoplan.planning.base import (
    CostObjective,
    Deadline,
    EnergyCost,
    LengthCost,
    Plan,
    PlanResult,
    check_endpoints,
)
from ecoplan.planning.graph import GraphPlanner, GraphPlannerOptions, plan_graph
from ecoplan.planning.reference import LatticeOptions, plan_reference
from ecoplan.planning.refine import RefineOptions, refine_waypoints
from ecoplan.planning.speed import SpeedChoice, best_speed, energy_vs_speed

__all__ = [
    "CostObjective",
    "Deadline",
    "EnergyCost",
    "GraphPlanner",
    "GraphPlannerOptions",
    "LatticeOptions",
    "LengthCost",
    "Plan",
    "PlanResult",
    "RefineOptions",
    "SpeedChoice",
    "best_speed",
    "check_endpoints",
    "energy_vs_speed",
    "plan_graph",
    "plan_reference",
    "refine_waypoints",
]
