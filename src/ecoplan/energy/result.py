"""What an evaluation returns: energy, duration, turned angle and feasibility of a path."""

from __future__ import annotations

from dataclasses import dataclass, field

from ecoplan.energy.turns import TurnPlan
from ecoplan.errors import InfeasibleError

__all__ = ["PathCost", "Violation"]


@dataclass(frozen=True, slots=True)
class Violation:
    """One constraint a path breaks.

    Attributes
    ----------
    element : str
        ``"segment"``, ``"turn"`` (at a waypoint) or ``"sample"`` (of a trajectory).
    index : int
        Segment index (from 0), waypoint index of the turn, or sample index.
    constraint : str
        Violated constraint: a vehicle parameter (``top_track_speed_mps``,
        ``p_side_max_w``, ``p_total_max_w``, ``p_motor_max_w``), ``turn_room`` (no
        feasible fillet fits between the segments) or ``collision`` (leaves free space).
    speed_mps : float
        Linear speed of the command [m/s].
    radius_m : float
        Turning radius of the command [m] (``inf`` straight, 0 on the spot).
    """

    element: str
    index: int
    constraint: str
    speed_mps: float
    radius_m: float

    def message(self) -> str:
        """A sentence naming the element, the command and the constraint."""
        where = {"turn": "turn at waypoint", "sample": "trajectory sample"}.get(
            self.element, self.element
        )
        return (
            f"{where} {self.index}: cmd(v={self.speed_mps:.3g} m/s, r={self.radius_m:.3g} m) "
            f"violates {self.constraint}"
        )


@dataclass(frozen=True, slots=True)
class PathCost:
    """Length, duration, turned angle, energy and feasibility of an executed path.

    Attributes
    ----------
    length_m : float
        Distance driven [m].
    duration_s : float
        Time taken [s].
    psi_rad : float
        Total turned angle ``psi = integral |w| dt`` [rad] (tracked eq. 11).
    energy_j : float
        Electrical energy of locomotion [J].
    breakdown_j : dict
        Energy per component of :data:`~ecoplan.models.power.COMPONENTS` [J]; sums to
        ``energy_j``.
    peak_power_w : float
        Largest total power drawn [W].
    feasible : bool
        True when no constraint is violated.
    violations : tuple of Violation
        Every violated constraint, in path order.
    turns : tuple of TurnPlan
        Turn executions at the waypoints (the initial turn first when there is one).
    """

    length_m: float
    duration_s: float
    psi_rad: float
    energy_j: float
    breakdown_j: dict[str, float]
    peak_power_w: float
    feasible: bool
    violations: tuple[Violation, ...] = ()
    turns: tuple[TurnPlan, ...] = field(default=(), repr=False)

    def raise_if_infeasible(self) -> PathCost:
        """Return ``self`` if feasible, else raise naming the first offending element.

        Raises
        ------
        InfeasibleError
            Message: ``"segment 2: cmd(v=0.9 m/s, r=inf m) violates p_side_max_w"``
            (plus the number of further violations).
        """
        if self.feasible:
            return self
        first = self.violations[0]
        more = len(self.violations) - 1
        extra = f" (and {more} more violation{'s' if more > 1 else ''})" if more else ""
        raise InfeasibleError(f"infeasible path: {first.message()}{extra}")

    @property
    def mean_power_w(self) -> float:
        """Mean power ``energy / duration`` [W]."""
        return self.energy_j / self.duration_s if self.duration_s > 0 else 0.0

    def to_dict(self) -> dict[str, object]:
        """Plain-data view (for JSON reports)."""
        return {
            "length_m": self.length_m,
            "duration_s": self.duration_s,
            "psi_rad": self.psi_rad,
            "energy_j": self.energy_j,
            "breakdown_j": dict(self.breakdown_j),
            "peak_power_w": self.peak_power_w,
            "feasible": self.feasible,
            "violations": [v.message() for v in self.violations],
        }
