"""The OMPL glue: one optimisation objective and the validity checks, adapting ecoplan.

Nothing of ecoplan's vehicle model lives here: the objective calls a motion-cost
function (:mod:`ecoplan.planning.ompl_motions`) and the validity checks ask the
:class:`~ecoplan.geometry.world.World`.  OMPL's Python objectives must implement ``stateCost``
and ``motionCost``; the heuristic is set explicitly (``motionCostHeuristic``).
"""

from __future__ import annotations

import math
from collections.abc import Callable, Iterator
from contextlib import contextmanager
from typing import Any

import shapely
from ompl import base as ob
from ompl import util as ou

from ecoplan.geometry.world import World
from ecoplan.planning.base import Deadline

__all__ = ["OmplObjective", "SegmentValidator", "quiet_ompl", "state_validity", "termination"]


class OmplObjective(ob.OptimizationObjective):  # type: ignore[misc]
    """OMPL objective whose motion cost is ecoplan's cost of the motion (energy or length)."""

    def __init__(self, si: Any, motion: Callable[[Any, Any], float], heuristic_per_m: float):
        super().__init__(si)
        self.motion = motion
        self.h = heuristic_per_m
        self.calls = 0

    def stateCost(self, s: Any) -> Any:
        """States cost nothing: the whole cost is in the motions."""
        return ob.Cost(0.0)

    def motionCost(self, s1: Any, s2: Any) -> Any:
        """Cost of the motion ``s1 -> s2`` by the motion-cost function (counted)."""
        self.calls += 1
        return ob.Cost(self.motion(s1, s2))

    def motionCostHeuristic(self, s1: Any, s2: Any) -> Any:
        """Admissible lower bound: cost per metre times the straight-line distance."""
        return ob.Cost(self.h * math.hypot(s2.getX() - s1.getX(), s2.getY() - s1.getY()))

    def isSymmetric(self) -> bool:
        """Motions are not symmetric (turn costs depend on the direction of travel)."""
        return False


class SegmentValidator(ob.MotionValidator):  # type: ignore[misc]
    """Exact check of SE2 motions: the straight segment lies in the free space (shapely).

    On-the-spot turns at the ends sweep nothing beyond the footprint disc, so the
    segment decides validity.
    """

    def __init__(self, si: Any, world: World):
        super().__init__(si)
        self.world = world

    def checkMotion(self, s1: Any, s2: Any) -> bool:
        """True when the segment ``s1 -> s2`` lies in the free space."""
        return self.world.segment_free((s1.getX(), s1.getY()), (s2.getX(), s2.getY()))


def state_validity(world: World) -> Callable[[Any], bool]:
    """State validity from the world's free space (inflated obstacles and bounds)."""
    free = world.free_space

    def valid(state: Any) -> bool:
        return bool(shapely.intersects_xy(free, state.getX(), state.getY()))

    return valid


@contextmanager
def quiet_ompl() -> Iterator[None]:
    """Silence OMPL's console output (it reports through exceptions and results here)."""
    ou.noOutputHandler()
    try:
        yield
    finally:
        ou.restorePreviousOutputHandler()


def termination(
    deadline: Deadline, until_s: float, max_checks: int | None
) -> tuple[Any, list[int]]:
    """A termination condition at ``until_s`` of the deadline or after ``max_checks`` checks.

    Returns the condition and a one-element list counting the checks (iterations).
    """
    count = [0]

    def done() -> bool:
        count[0] += 1
        if max_checks is not None and count[0] > max_checks:
            return True
        return deadline.elapsed_s >= until_s

    return ob.PlannerTerminationCondition(done), count
