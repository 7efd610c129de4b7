"""Cost objectives: what a planner minimises, and the costs of the pieces it assembles.

A planner builds a path from straight segments and turns at waypoints.  It asks the
objective for

* :meth:`~CostObjective.segment_cost` -- the cost of a straight segment (None: infeasible);
* :meth:`~CostObjective.turn_cost` -- the cost of a turn (None: no feasible execution);
* :meth:`~CostObjective.turn_value` -- the cost of turns whose cheapest feasible execution
  has a given net energy, vectorised (planners cost many turns at once with
  :func:`~ecoplan.energy.turns.turn_candidates` and convert with it);
* :meth:`~CostObjective.value` -- the scalar to minimise from a full evaluation.

Every objective prunes the same infeasible pieces; :class:`EnergyCost` values them in
joules, :class:`LengthCost` in metres (a feasible turn costs 0: the shortest-path
baseline).  A new objective subclasses :class:`CostObjective` and overrides
``segment_cost``, ``turn_value`` and ``value``.
"""

from __future__ import annotations

import math

import numpy as np

from ecoplan._typing import ArrayLike, FloatArray
from ecoplan.energy.path import path_cost
from ecoplan.energy.primitives import (
    TurnMode,
    Vehicle,
    VehicleParams,
    WorldLike,
    check_vehicle_world,
    params_on,
    positive_speed,
    wrap_pi,
)
from ecoplan.energy.result import PathCost
from ecoplan.energy.turns import choose_turn, fillet_collides
from ecoplan.errors import InputError
from ecoplan.models.inertial import Elevation, climb_energy_along_j
from ecoplan.models.limits import check_tracks
from ecoplan.models.tracked import TrackedParams

__all__ = ["CostObjective", "EnergyCost", "LengthCost"]


class CostObjective:
    """Interface of a pluggable path cost (module docstring), the one planners talk to.

    ``segment_cost`` and ``turn_cost`` return ``None`` for impassable / infeasible
    (pruned by planners); ``turn_cost`` is ``turn_value`` of the cheapest feasible turn's
    net energy, so a subclass changes how turns are valued by overriding ``turn_value``
    alone.  ``path`` evaluates a whole path with :func:`~ecoplan.energy.path.path_cost`.
    Subclasses: :class:`EnergyCost`, :class:`LengthCost`.

    Parameters
    ----------
    vehicle : TerrainVehicle or TrackedParams or WheeledParams
        The vehicle (e.g. ``vehicle(name)``; plain parameters only without terrain
        regions).
    speed_mps : float
        Cruise speed [m/s] (see :mod:`ecoplan.planning.speed` to choose it).
    world : WorldLike, optional
        For terrain regions and fillet collision checks.
    turn : {"auto", "spot", "arc"}
        Allowed turn executions.
    ramps : bool
        Passed to :func:`~ecoplan.energy.path.path_cost` by :meth:`path`.
    elevation : callable, optional
        Ground elevation ``z(x, y)`` [m]: straight segments also cost their climbs
        (:func:`ecoplan.models.inertial.climb_energy_along_j`, the vehicle's mass).
    """

    name = "cost"

    def __init__(
        self,
        vehicle: Vehicle,
        speed_mps: float,
        *,
        world: WorldLike | None = None,
        turn: TurnMode = "auto",
        ramps: bool = False,
        elevation: Elevation | None = None,
    ) -> None:
        check_vehicle_world(vehicle, world)
        self.elevation = elevation
        self.vehicle = vehicle
        self.speed_mps = float(positive_speed("speed_mps", speed_mps))
        self.world = world
        self.turn = turn
        self.ramps = ramps
        self._per_m: dict[str | None, float | None] = {}
        if turn not in ("auto", "spot", "arc"):
            raise InputError(f"turn must be 'auto', 'spot' or 'arc', got {turn!r}")

    def params(self, terrain: str | None = None) -> VehicleParams:
        """Vehicle parameters on a terrain."""
        return params_on(self.vehicle, terrain)

    def terrain_at(self, point: ArrayLike) -> str | None:
        """Terrain at a point (``None`` without a world)."""
        return None if self.world is None else self.world.terrain_at(point)[0]

    def segment_energy(self, p0: ArrayLike, p1: ArrayLike) -> float | None:
        """Energy of driving straight ``p0 -> p1`` across terrains [J]; None if infeasible."""
        a = np.asarray(p0, dtype=np.float64)
        b = np.asarray(p1, dtype=np.float64)
        pieces: list[tuple[float, str | None]] = [(float(np.hypot(*(b - a))), None)]
        if self.world is not None:
            pieces = [(pc.length_m, pc.terrain) for pc in self.world.split_by_terrain(a, b)]
        energy = 0.0
        for length, terr in pieces:
            per_m = self.straight_energy_per_m(terr)
            if per_m is None:
                return None
            energy += per_m * length
        if self.elevation is not None:
            p = self.params(pieces[0][1])
            eta = p.eta if isinstance(p, TrackedParams) else 1.0
            energy += climb_energy_along_j(self.elevation, a, b, p.mass_kg, eta)
        return energy

    def straight_energy_per_m(self, terrain: str | None = None) -> float | None:
        """Energy per metre of straight driving at the cost's speed [J/m]; None if infeasible."""
        if terrain not in self._per_m:
            params = self.params(terrain)
            v = self.speed_mps
            ok = bool(check_tracks(params, v, v).ok.all())
            self._per_m[terrain] = float(params.power(v, v).total_w) / v if ok else None
        return self._per_m[terrain]

    def turn_energy(
        self, p_prev: ArrayLike, p: ArrayLike, p_next: ArrayLike, room_m: float = math.inf
    ) -> tuple[float, float] | None:
        """Net energy [J] and radius [m] of the cheapest feasible turn at ``p``; None if none.

        The fillet of an arc turn is checked against the world's free space.
        """
        a, b, c = (np.asarray(q, dtype=np.float64) for q in (p_prev, p, p_next))
        h0 = math.atan2(b[1] - a[1], b[0] - a[0])
        h1 = math.atan2(c[1] - b[1], c[0] - b[0])
        dpsi = float(wrap_pi(h1 - h0))
        collides = None if self.world is None else fillet_collides(self.world, np.stack([a, b, c]))
        params = self.params(self.terrain_at(b))
        return choose_turn(params, dpsi, self.speed_mps, room_m, self.turn, collides)

    def segment_cost(self, p0: ArrayLike, p1: ArrayLike) -> float | None:
        """Cost of the straight segment ``p0 -> p1`` (None: infeasible)."""
        raise NotImplementedError

    def per_metre(self, energy_per_m_jpm: float) -> float:
        """Cost per metre of a feasible steady motion that takes this energy per metre.

        Parameters
        ----------
        energy_per_m_jpm : float
            Energy per metre driven [J/m].

        Returns
        -------
        float
            The objective's cost per metre.
        """
        raise NotImplementedError

    def turn_value(self, net_energy_j: ArrayLike) -> FloatArray:
        """Cost of turns whose cheapest feasible execution has this net energy (vectorised).

        Parameters
        ----------
        net_energy_j : array_like
            Net energy of each turn's cheapest feasible execution [J]
            (:func:`~ecoplan.energy.turns.turn_costs`); NaN or inf = no feasible execution.

        Returns
        -------
        ndarray
            The objective's cost of each turn; NaN where infeasible.
        """
        raise NotImplementedError

    def turn_cost(
        self, p_prev: ArrayLike, p: ArrayLike, p_next: ArrayLike, room_m: float = math.inf
    ) -> float | None:
        """Cost of turning at ``p`` from ``p_prev -> p`` to ``p -> p_next`` (None: infeasible).

        ``turn_value`` of the net energy of :meth:`turn_energy`.
        """
        out = self.turn_energy(p_prev, p, p_next, room_m)
        if out is None:
            return None
        value = float(self.turn_value(out[0]))
        return None if math.isnan(value) else value

    def path(self, path: ArrayLike, initial_heading_rad: float | None = None) -> PathCost:
        """Full evaluation of a waypoint path (:func:`path_cost`)."""
        return path_cost(
            path,
            self.vehicle,
            self.speed_mps,
            world=self.world,
            initial_heading_rad=initial_heading_rad,
            turn=self.turn,
            ramps=self.ramps,
            elevation=self.elevation,
        )

    def value(self, pc: PathCost) -> float:
        """The scalar this objective minimises, from a full evaluation."""
        raise NotImplementedError


class EnergyCost(CostObjective):
    """Energy objective: segment and turn costs in joules (turns net of saved straights).

    Parameters as :class:`CostObjective`.

    Examples
    --------
    >>> from ecoplan.presets import vehicle
    >>> c = EnergyCost(vehicle("auriga-beta-wide"), 0.5)
    >>> round(c.segment_cost((0, 0), (10, 0)))  # P_T(0.5, 0.5) * 10 m / 0.5 m/s
    8421
    """

    name = "energy"

    def segment_cost(self, p0: ArrayLike, p1: ArrayLike) -> float | None:
        """Energy of the straight segment [J] (None: infeasible speed on some terrain)."""
        return self.segment_energy(p0, p1)

    def per_metre(self, energy_per_m_jpm: float) -> float:
        """The energy per metre itself [J/m]."""
        return float(energy_per_m_jpm)

    def turn_value(self, net_energy_j: ArrayLike) -> FloatArray:
        """The net energy itself [J] (NaN where infeasible)."""
        e = np.asarray(net_energy_j, dtype=np.float64)
        return np.where(np.isfinite(e), e, np.nan)

    def value(self, pc: PathCost) -> float:
        """``pc.energy_j``."""
        return pc.energy_j


class LengthCost(CostObjective):
    """Shortest-path baseline with the same feasibility pruning as :class:`EnergyCost`.

    Segment cost is the length [m]; a turn costs 0 when some feasible execution exists
    and is pruned (None) otherwise, so the baseline never issues an infeasible command.
    """

    name = "length"

    def segment_cost(self, p0: ArrayLike, p1: ArrayLike) -> float | None:
        """Length of the segment [m] (None: its speed is infeasible on some terrain)."""
        if self.segment_energy(p0, p1) is None:
            return None
        return float(np.hypot(*(np.asarray(p1, float) - np.asarray(p0, float))))

    def per_metre(self, energy_per_m_jpm: float) -> float:
        """1: the length baseline counts metres."""
        return 1.0

    def turn_value(self, net_energy_j: ArrayLike) -> FloatArray:
        """0 where a feasible turn exists, NaN elsewhere: the length baseline's turns are free."""
        e = np.asarray(net_energy_j, dtype=np.float64)
        return np.where(np.isfinite(e), 0.0, np.nan)

    def value(self, pc: PathCost) -> float:
        """``pc.length_m``."""
        return pc.length_m
