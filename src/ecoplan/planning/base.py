"""Types shared by every planner: results, the cost objects, input checks and the deadline.

A planner takes a :class:`~ecoplan.geometry.world.World`, a start and a goal, and a cost object
(:class:`~ecoplan.energy.objective.EnergyCost` or
:class:`~ecoplan.energy.objective.LengthCost`: the baseline is one argument) and returns a
:class:`PlanResult`.  Every returned :class:`Plan` carries the full evaluation of its
waypoints by :func:`ecoplan.energy.path.path_cost` (energy, ψ, breakdown,
feasibility), whatever the objective was.
"""

from __future__ import annotations

import math
import time
from dataclasses import dataclass, field

import numpy as np

from ecoplan._typing import ArrayLike, FloatArray
from ecoplan.energy.objective import CostObjective, EnergyCost, LengthCost
from ecoplan.energy.result import PathCost
from ecoplan.errors import InputError, PlanningError
from ecoplan.geometry.world import World

__all__ = [
    "CostObjective",
    "Deadline",
    "EnergyCost",
    "LengthCost",
    "Plan",
    "PlanResult",
    "as_waypoints",
    "check_budget",
    "check_endpoints",
]


@dataclass(frozen=True, slots=True)
class Plan:
    """One planned path with its full evaluation.

    Attributes
    ----------
    waypoints : ndarray, shape (N, 2)
        Waypoints from start to goal [m].
    cost : PathCost
        :func:`ecoplan.energy.path.path_cost` of the waypoints (energy, ψ, feasibility, ...).
    objective : str
        Name of the objective the planner minimised (``"energy"``, ``"length"``).
    objective_value : float
        Value of that objective for this path (J or m).
    speed_mps : float
        Cruise speed the path was planned and evaluated at [m/s].
    """

    waypoints: FloatArray
    cost: PathCost
    objective: str
    objective_value: float
    speed_mps: float

    @property
    def energy_j(self) -> float:
        """Energy of the path [J]."""
        return self.cost.energy_j

    @property
    def n_waypoints(self) -> int:
        """Number of waypoints including start and goal."""
        return len(self.waypoints)


@dataclass(frozen=True, slots=True)
class PlanResult:
    """What a planner returns.

    Attributes
    ----------
    best : Plan
        The best path found.
    alternatives : tuple of Plan
        The k best distinct waypoint sequences found, best first (``best`` included).
    planner : str
        Planner name (e.g. ``"graph"``, ``"ompl:RRTstar"``).
    planning_time_s : float
        Wall-clock planning time [s].
    stats : dict
        Planner-specific counters (nodes, edges, states, ...).
    """

    best: Plan
    alternatives: tuple[Plan, ...]
    planner: str
    planning_time_s: float
    stats: dict[str, float] = field(default_factory=dict)


def check_endpoints(
    world: World, start: ArrayLike, goal: ArrayLike
) -> tuple[tuple[float, float], tuple[float, float]]:
    """Validate start and goal against the world (bounds, obstacles, footprint).

    Raises
    ------
    ecoplan.geometry.world.GeometryError
        ``OutOfBoundsError`` or ``PointInObstacleError`` naming the point; an
        :class:`~ecoplan.errors.InputError` when start and goal coincide.
    """
    s = world.check_point(start, "start")
    g = world.check_point(goal, "goal")
    if math.hypot(g[0] - s[0], g[1] - s[1]) < 1e-9:
        raise InputError(f"start and goal coincide at ({s[0]:g}, {s[1]:g}): nothing to plan")
    return s, g


def check_budget(time_budget_s: float) -> float:
    """Validate a time budget [s] (finite and > 0)."""
    if not (
        isinstance(time_budget_s, int | float)
        and math.isfinite(time_budget_s)
        and time_budget_s > 0.0
    ):
        raise InputError(f"time_budget_s must be finite and > 0 s, got {time_budget_s!r}")
    return float(time_budget_s)


class Deadline:
    """A wall-clock deadline (monotonic clock) for honouring time budgets."""

    def __init__(self, budget_s: float) -> None:
        self.start = time.perf_counter()
        self.budget_s = check_budget(budget_s)

    @property
    def elapsed_s(self) -> float:
        """Seconds since the deadline was created."""
        return time.perf_counter() - self.start

    @property
    def expired(self) -> bool:
        """True once the budget is spent."""
        return self.elapsed_s >= self.budget_s

    def check(self, what: str) -> None:
        """Raise :class:`~ecoplan.errors.PlanningError` if the budget is spent."""
        if self.expired:
            raise PlanningError(
                f"time budget of {self.budget_s:g} s exhausted while {what}; raise it "
                "with planner.time_s in the scenario, --time-budget on the command line "
                "or time_budget_s in the planner options"
            )


def as_waypoints(points: ArrayLike) -> FloatArray:
    """``(N, 2)`` float array of waypoints."""
    return np.asarray(points, dtype=np.float64).reshape(-1, 2)
