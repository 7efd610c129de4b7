"""What a motion between two OMPL states costs: ecoplan's cost module, made fast.

SE2 motions (:class:`StraightMotions`) are a turn, a straight segment and a turn, with
the turns' net costs looked up in a :class:`TurnTable` built once per plan from
:func:`ecoplan.energy.turns.turn_costs`.  Dubins / Reeds-Shepp motions (:class:`CurveMotions`)
are sampled with the state space's own interpolation and costed per metre of arc and
straight.  See :mod:`ecoplan.planning.ompl` for the model behind each; nothing here
imports OMPL (the state space is passed in).
"""

from __future__ import annotations

import math
from typing import Any

import numpy as np

from ecoplan.energy.objective import CostObjective
from ecoplan.energy.turns import turn_costs
from ecoplan.errors import InputError
from ecoplan.geometry.world import World
from ecoplan.models.limits import check_tracks, vr_to_tracks

__all__ = ["CurveMotions", "StraightMotions", "TurnTable", "objective_kind", "wrap_angle"]

_N_TURN_ANGLES = 91
_ROOMS = np.geomspace(0.01, 100.0, 41)


def wrap_angle(a: float) -> float:
    """Angle ``a`` wrapped to ``[-pi, pi)`` [rad]."""
    return (a + math.pi) % (2.0 * math.pi) - math.pi


def objective_kind(cost: CostObjective) -> str:
    """The cost object's name, ``"energy"`` or ``"length"`` (others raise InputError)."""
    if cost.name not in ("energy", "length"):
        raise InputError(
            f"the OMPL planner supports the 'energy' and 'length' cost objects, got {cost.name!r}"
        )
    return str(cost.name)


class TurnTable:
    """Net cost of a turn by ``|dpsi|`` with fillet room ``room`` (bilinear lookup).

    Built once per plan from :func:`ecoplan.energy.turns.turn_costs` so that the objective's
    inner loop stays pure-Python scalar arithmetic.  Infeasible turns cost ``inf``;
    net costs are clamped at 0 so that motion costs stay above the straight-line bound.
    """

    def __init__(self, cost: CostObjective) -> None:
        params = cost.params()
        a = np.linspace(0.0, math.pi, _N_TURN_ANGLES)
        self.da = float(a[1] - a[0])
        self.log_r0 = math.log(float(_ROOMS[0]))
        self.dlog = math.log(float(_ROOMS[1] / _ROOMS[0]))
        tables = []
        aa, rooms = np.broadcast_arrays(a[:, None], _ROOMS[None, :])
        for sign in (1.0, -1.0):
            net, _ = turn_costs(params, sign * aa, cost.speed_mps, rooms, cost.turn)
            net = cost.turn_value(net)
            tables.append(np.where(np.isnan(net), np.inf, np.maximum(net, 0.0)).tolist())
        self.left: list[list[float]] = tables[0]
        self.right: list[list[float]] = tables[1]

    def __call__(self, dpsi: float, room: float) -> float:
        """Net cost of a turn by ``dpsi`` [rad] with fillet room ``room`` [m]."""
        tab = self.left if dpsi >= 0.0 else self.right
        fa = min(abs(dpsi) / self.da, _N_TURN_ANGLES - 1.000001)
        ia = int(fa)
        wa = fa - ia
        fr = (math.log(max(room, 1e-12)) - self.log_r0) / self.dlog
        fr = min(max(fr, 0.0), len(_ROOMS) - 1.000001)
        ir = int(fr)
        wr = fr - ir
        r0, r1 = tab[ia], tab[ia + 1]
        c00, c01, c10, c11 = r0[ir], r0[ir + 1], r1[ir], r1[ir + 1]
        if math.isinf(c00 + c01 + c10 + c11):
            # pessimistic where any neighbour is infeasible
            return math.inf
        return (1 - wa) * ((1 - wr) * c00 + wr * c01) + wa * ((1 - wr) * c10 + wr * c11)


class StraightMotions:
    """SE2 motions: turn, straight segment, turn (module doc)."""

    def __init__(
        self,
        cost: CostObjective,
        start: tuple[float, float],
        goal: tuple[float, float],
        free_start_turn: bool,
    ) -> None:
        self.cost = cost
        self.start = start if free_start_turn else None
        self.goal = goal
        self.fast = cost.world is None or not (
            cost.world.has_regions or cost.world.default_terrain is not None
        )
        per_m = cost.segment_cost((0.0, 0.0), (1.0, 0.0))
        if per_m is None:
            raise InputError(
                f"straight driving at {cost.speed_mps:g} m/s is infeasible for this vehicle"
            )
        self.per_m = float(per_m)
        self.table = TurnTable(cost) if self.fast else None

    def heuristic_per_m(self) -> float:
        """Admissible cost per metre of straight-line distance (0 with terrain regions)."""
        return self.per_m if self.fast else 0.0

    def _turn(self, p: tuple[float, float], yaw_in: float, yaw_out: float, room: float) -> float:
        dpsi = wrap_angle(yaw_out - yaw_in)
        if abs(dpsi) < 1e-12:
            return 0.0
        if self.table is not None:
            return self.table(dpsi, room)
        u_in = (math.cos(yaw_in), math.sin(yaw_in))
        u_out = (math.cos(yaw_out), math.sin(yaw_out))
        prev = (p[0] - room * u_in[0], p[1] - room * u_in[1])
        nxt = (p[0] + room * u_out[0], p[1] + room * u_out[1])
        c = self.cost.turn_cost(prev, p, nxt, room)
        return math.inf if c is None else max(float(c), 0.0)

    def __call__(self, s1: Any, s2: Any) -> float:
        """Cost of the motion ``s1 -> s2``: turn, straight, turn (``inf`` if infeasible)."""
        x1, y1, yaw1 = s1.getX(), s1.getY(), s1.getYaw()
        x2, y2, yaw2 = s2.getX(), s2.getY(), s2.getYaw()
        dx, dy = x2 - x1, y2 - y1
        length = math.hypot(dx, dy)
        if length < 1e-9:
            return self._turn((x1, y1), yaw1, yaw2, 0.0)
        theta = math.atan2(dy, dx)
        if self.fast:
            c = self.per_m * length
        else:
            seg = self.cost.segment_cost((x1, y1), (x2, y2))
            if seg is None:
                return math.inf
            c = float(seg)
        room = 0.5 * length
        if self.start is None or (x1, y1) != self.start:
            c += self._turn((x1, y1), yaw1, theta, room)
        if (x2, y2) != self.goal:
            c += self._turn((x2, y2), theta, yaw2, room)
        return c


class CurveMotions:
    """Dubins / Reeds-Shepp motions: per-metre costs of arcs and straights (module doc)."""

    def __init__(self, cost: CostObjective, space: Any, radius_m: float, step_m: float) -> None:
        self.space = space
        self.radius = radius_m
        self.step = step_m
        self.scratch = space.allocState()
        self.world = cost.world
        self.regions = cost.world is not None and (
            cost.world.has_regions or cost.world.default_terrain is not None
        )
        terrains: list[str | None] = [None]
        if self.regions and isinstance(cost.world, World):
            terrains = list(
                dict.fromkeys(
                    [cost.world.default_terrain] + [r.terrain for r in cost.world.regions]
                )
            )
        self.coef = {t: self._coefficients(cost, t) for t in terrains}
        self.default = terrains[0]

    def _coefficients(
        self, cost: CostObjective, terrain: str | None
    ) -> dict[tuple[int, int], float]:
        """Cost per metre of ``(direction, turn)``: direction +-1, turn = sign of the yaw rate."""
        params = cost.params(terrain)
        v = cost.speed_mps
        out: dict[tuple[int, int], float] = {}
        for d in (1, -1):
            for k in (-1, 0, 1):
                if k == 0:
                    vl, vr = np.asarray(d * v), np.asarray(d * v)
                else:
                    # yaw rate w = (d v) / (d k r) has the sign of k, forwards or backwards
                    vl, vr = vr_to_tracks(params, d * v, d * k * self.radius)
                if not check_tracks(params, vl, vr).ok.all():
                    out[(d, k)] = math.inf
                else:
                    out[(d, k)] = cost.per_metre(float(params.power(vl, vr).total_w) / v)
        return out

    def heuristic_per_m(self) -> float:
        """Admissible cost per metre: the cheapest piece on any terrain."""
        return min(min(c.values()) for c in self.coef.values())

    def pieces(self, s1: Any, s2: Any, step_m: float) -> list[tuple[float, ...]]:
        """Pieces ``(x, y, yaw, ds, dyaw, direction)`` of the curve ``s1 -> s2`` (starts)."""
        length = float(self.space.distance(s1, s2))
        n = max(2, math.ceil(length / step_m))
        ds = length / n
        x0, y0, yaw0 = s1.getX(), s1.getY(), s1.getYaw()
        out: list[tuple[float, ...]] = []
        st = self.scratch
        for i in range(1, n + 1):
            self.space.interpolate(s1, s2, i / n, st)
            x, y, yaw = st.getX(), st.getY(), st.getYaw()
            fwd = (x - x0) * math.cos(yaw0) + (y - y0) * math.sin(yaw0)
            out.append((x0, y0, yaw0, ds, wrap_angle(yaw - yaw0), 1.0 if fwd >= -1e-12 else -1.0))
            x0, y0, yaw0 = x, y, yaw
        return out

    def __call__(self, s1: Any, s2: Any) -> float:
        """Cost of the curve ``s1 -> s2``: per-metre costs of its arcs and straights."""
        pieces = self.pieces(s1, s2, self.step)
        if self.regions and self.world is not None:
            names = self.world.terrain_at([(p[0], p[1]) for p in pieces])
        else:
            names = [self.default] * len(pieces)
        total = 0.0
        for (_, _, _, ds, dyaw, d), terr in zip(pieces, names, strict=True):
            coef = self.coef.get(terr, self.coef[self.default])
            arc = min(self.radius * abs(dyaw), ds)
            if arc > 0.0:
                total += coef[(int(d), 1 if dyaw > 0 else -1)] * arc
            total += coef[(int(d), 0)] * (ds - arc)
        return total
