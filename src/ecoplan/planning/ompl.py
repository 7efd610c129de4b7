"""OMPL sampling-based planners with ecoplan's energy objective (issue 3, deliverable 4).

The OMPL glue is one :class:`ompl.base.OptimizationObjective` subclass and one state
validity function; everything about the vehicle lives in :mod:`ecoplan.energy` and
everything about the map in :class:`ecoplan.geometry.world.World`.

State spaces and what a motion costs
------------------------------------
``"se2"``
    A motion ``(x1, y1, yaw1) -> (x2, y2, yaw2)`` is executed as a turn from ``yaw1`` to
    the segment direction ``theta``, the straight segment, and a turn from ``theta`` to
    ``yaw2``.  Its cost is ``h(theta - yaw1) + c L + h(yaw2 - theta)`` where ``c L`` is
    the straight segment's cost and ``h`` the net cost of a turn by the cost module
    (:func:`ecoplan.energy.turns.turn_costs`, on the spot or a fillet arc, with room for a fillet
    of half the segment).  Splitting the turn at a waypoint in two costs the same as the
    whole turn whenever the waypoint's yaw lies between the incoming and outgoing
    directions (on-the-spot energy is proportional to the angle, tracked paper eq. 11),
    so the optimum aligns the yaws.  The turn out of the start (when no initial heading
    is given) and the turn into the goal are free: the cost module does the same
    (a path starts aligned with its first segment and has no goal heading).  The
    returned path is evaluated by :func:`ecoplan.energy.path.path_cost` on its waypoints.
``"dubins"`` / ``"reeds_shepp"``
    For vehicles with a minimum turning radius at the cruise speed (the Pioneer 3-AT:
    on-the-spot turns exceed its side power limit, wheeled paper Fig. 10).  The radius
    defaults to ``1.02 * min_radius_for_speed(params, v)`` so that every arc is a
    feasible ``cmd(v, r)`` (wheeled paper §III-C).  A motion is a sequence of arcs of
    radius ``r`` and straights (Reeds-Shepp: forward or reverse); its cost is the sum of
    per-metre costs of each piece, the pieces found by sampling the curve with OMPL's
    own interpolation.  The returned path is turned into a timed track-speed trajectory
    and evaluated by :func:`ecoplan.energy.trajectory.trajectory_cost`.

Files
-----
This module runs the search (:class:`OmplPlanner`); the OMPL objective and validity
checks are :mod:`ecoplan.planning.ompl_glue`, the motion costs
:mod:`ecoplan.planning.ompl_motions`, and OMPL's benchmark log format (for Planner
Arena) :mod:`ecoplan.planning.benchlog`.

Decisions where the issue is silent
-----------------------------------
* Reproducibility: OMPL planners are anytime, so a time budget alone stops them after a
  machine-dependent number of iterations.  With ``max_iterations`` set, a fixed ``seed``
  gives the same plan on every run as long as the iteration cap, not the time budget,
  ends the search (``stats["stopped_by_time"]`` says which did).  OMPL's global seed
  (``ompl.util.RNG.setSeed``) is set before anything random is created.
* Planners: ``RRTstar``, ``InformedRRTstar``, ``SORRTstar`` (r-disc neighbourhoods: the
  k-nearest variant evaluated ~7x more motion costs per iteration), ``BITstar`` (the
  default: few motion-cost calls, good in every space) and ``RRTConnect`` (feasibility
  only; not in Dubins space, which is not reversible).  ``PRMstar`` is refused: OMPL's
  PRM grows its roadmap in a second thread that calls the Python objective and
  deadlocks on the interpreter lock.  ``FMT`` is refused: it found no exact solution
  with this objective in our tests.
* Speed: every motion cost is a Python call (~2-20 us for SE2 with the precomputed turn
  table, more in Dubins / Reeds-Shepp spaces, whose curves are sampled); budgets of
  1-2 s give a few thousand iterations.
* Simplification never increases the objective: OMPL's ``PathSimplifier`` (with this
  objective), then greedy waypoint removal for SE2 paths; every candidate is evaluated
  by the cost module and the cheapest feasible one is kept.
* Terminal hygiene: OMPL's console output is switched off while planning and every
  OMPL object is released before :meth:`OmplPlanner.plan` returns, so nanobind has no
  leaked instances to report at interpreter exit.
"""

from __future__ import annotations

import itertools
import math
from collections.abc import Callable
from dataclasses import dataclass
from typing import Any, Literal

import numpy as np
from ompl import base as ob
from ompl import geometric as og
from ompl import util as ou

from ecoplan._typing import ArrayLike, FloatArray
from ecoplan.energy.objective import CostObjective
from ecoplan.energy.result import PathCost, Violation
from ecoplan.energy.trajectory import TrackTrajectory, trajectory_cost
from ecoplan.energy.turns import turn_costs
from ecoplan.errors import InputError, PlanningError
from ecoplan.geometry.world import World
from ecoplan.models.kinematics import setpoint_to_tracks
from ecoplan.models.limits import min_radius_for_speed
from ecoplan.planning.base import Deadline, Plan, PlanResult, check_budget, check_endpoints
from ecoplan.planning.ompl_glue import (
    OmplObjective,
    SegmentValidator,
    quiet_ompl,
    state_validity,
    termination,
)
from ecoplan.planning.ompl_motions import CurveMotions, StraightMotions, objective_kind, wrap_angle

__all__ = [
    "PLANNERS",
    "STATE_SPACES",
    "OmplOptions",
    "OmplPlanner",
    "plan_ompl",
]

StateSpaceName = Literal["auto", "se2", "dubins", "reeds_shepp"]


def _rdisc(cls: Callable[[Any], Any]) -> Callable[[Any], Any]:
    """RRT* variant with the r-disc neighbourhood, bounded informed sampling, no pruning.

    With OMPL 2.0.1's k-nearest neighbourhood RRT* evaluated ~150 motion costs per
    iteration on our maps against ~20 with the r-disc one; each is a Python call here.
    """

    def make(si: Any) -> Any:
        planner = cls(si)
        planner.setKNearest(False)
        # the budget is checked between iterations only: informed rejection sampling
        # (100 attempts by default) and tree pruning (a Python heuristic per vertex, in
        # one step) ran 0.25 s and 0.7 s past a 2 s budget in Dubins spaces
        planner.setNumSamplingAttempts(10)
        planner.setTreePruning(False)
        return planner

    return make


#: Planners by name (OMPL class names); aliases such as ``"RRT*"`` are accepted.
PLANNERS: dict[str, Callable[[Any], Any]] = {
    "RRTstar": _rdisc(og.RRTstar),
    "InformedRRTstar": _rdisc(og.InformedRRTstar),
    "SORRTstar": _rdisc(og.SORRTstar),
    "BITstar": og.BITstar,
    "RRTConnect": og.RRTConnect,
}
#: State space names accepted by :class:`OmplOptions`.
STATE_SPACES = ("auto", "se2", "dubins", "reeds_shepp")

_REFUSED = {
    "fmt": "OMPL's FMT* found no exact solution with the Python objective in our tests",
    "prmstar": "OMPL's PRM grows its roadmap in a second thread that deadlocks on the "
    "Python objective",
    "prm": "OMPL's PRM grows its roadmap in a second thread that deadlocks on the Python objective",
}
_RADIUS_MARGIN = 1.02  # default Dubins radius = margin * min feasible radius
_SOLVE_SHARE = 0.75  # share of the time budget given to the search
_SIMPLIFY_SHARE = 0.85  # OMPL's simplifier runs until this share of the budget
_PRUNE_SHARE = 0.95  # greedy waypoint removal stops at this share
_SIMPLIFY_STEPS = 200  # cap on OMPL simplifier termination checks (determinism)
_EPS_T = 1e-9


def _canonical_planner(name: str) -> str:
    if not isinstance(name, str):
        raise InputError(f"planner must be a name, got {name!r}")
    key = name.replace("*", "star").replace("-", "").replace("_", "").lower()
    for canon in PLANNERS:
        if canon.lower() == key:
            return canon
    if key in _REFUSED:
        raise InputError(f"planner {name!r} is not supported: {_REFUSED[key]}")
    raise InputError(f"unknown OMPL planner {name!r}; accepted: {', '.join(PLANNERS)}")


@dataclass(frozen=True, slots=True)
class OmplOptions:
    """Options of :class:`OmplPlanner`.

    Attributes
    ----------
    planner : str
        OMPL planner name, one of :data:`PLANNERS` (``"RRT*"`` style aliases accepted).
    time_budget_s : float
        Wall-clock budget of the whole call (search, simplification, evaluation) [s].
    seed : int
        Seed of OMPL's random number generator (>= 0).
    state_space : {"auto", "se2", "dubins", "reeds_shepp"}
        ``"auto"``: SE2 when the vehicle can turn on the spot at the cruise speed's
        costs, Dubins otherwise (see module doc).
    turning_radius_m : float or None
        Radius of Dubins / Reeds-Shepp arcs [m]; ``None``: 1.02 times the smallest
        feasible radius at the cruise speed.
    max_iterations : int or None
        Cap on the planner's iterations (termination checks); makes runs reproducible.
    simplify : bool
        Simplify the solution (never increases the objective).
    resolution_m : float
        Distance between collision checks along a motion [m].
    goal_headings : int
        Number of headings offered at the goal (and at the start without an initial
        heading) in the Dubins / Reeds-Shepp spaces, where states carry a heading.
    """

    planner: str = "BITstar"
    time_budget_s: float = 1.0
    seed: int = 1
    state_space: StateSpaceName = "auto"
    turning_radius_m: float | None = None
    max_iterations: int | None = None
    simplify: bool = True
    resolution_m: float = 0.05
    goal_headings: int = 16

    def __post_init__(self) -> None:
        object.__setattr__(self, "planner", _canonical_planner(self.planner))
        object.__setattr__(self, "time_budget_s", check_budget(self.time_budget_s))
        if not isinstance(self.seed, int | np.integer) or isinstance(self.seed, bool):
            raise InputError(f"seed must be an integer >= 0, got {self.seed!r}")
        if self.seed < 0:
            raise InputError(f"seed must be >= 0, got {self.seed}")
        if self.state_space not in STATE_SPACES:
            raise InputError(
                f"state_space must be one of {', '.join(STATE_SPACES)}, got {self.state_space!r}"
            )
        r = self.turning_radius_m
        if r is not None and not (isinstance(r, int | float) and math.isfinite(r) and r > 0):
            raise InputError(f"turning_radius_m must be finite and > 0 m, got {r!r}")
        it = self.max_iterations
        if it is not None and (not isinstance(it, int) or isinstance(it, bool) or it < 1):
            raise InputError(f"max_iterations must be an integer >= 1, got {it!r}")
        res = self.resolution_m
        if not (isinstance(res, int | float) and math.isfinite(res) and res > 0):
            raise InputError(f"resolution_m must be finite and > 0 m, got {res!r}")
        if not isinstance(self.goal_headings, int) or not 1 <= self.goal_headings <= 360:
            raise InputError(
                f"goal_headings must be an integer in [1, 360], got {self.goal_headings!r}"
            )


# ---------------------------------------------------------------------------- planner
class OmplPlanner:
    """OMPL planner minimising ecoplan's energy (or length) objective.

    Parameters
    ----------
    world : World
        Obstacles, bounds, footprint inflation and terrain regions.
    cost : EnergyCost or LengthCost
        Objective; the length cost is the shortest-path baseline.
    options : OmplOptions, optional
        Planner name, time budget, seed, state space, ...

    Examples
    --------
    >>> from ecoplan.geometry.world import World, rectangle
    >>> from ecoplan.energy.objective import EnergyCost
    >>> from ecoplan.presets import vehicle
    >>> w = World(rectangle(0, 0, 10, 10), [rectangle(4, 3, 6, 7)], inflation_m=0.3)
    >>> c = EnergyCost(vehicle("auriga-beta-narrow"), 0.5, world=w)
    >>> opts = OmplOptions("RRTstar", time_budget_s=1.0, max_iterations=400, seed=3)
    >>> res = OmplPlanner(w, c, opts).plan((1, 5), (9, 5))
    >>> res.best.cost.feasible, res.planner
    (True, 'ompl:RRTstar/se2')
    """

    def __init__(self, world: World, cost: CostObjective, options: OmplOptions | None = None):
        if not isinstance(world, World):
            raise InputError(
                f"world must be an ecoplan.geometry.world.World, got {type(world).__name__}"
            )
        if not isinstance(cost, CostObjective):
            raise InputError(f"cost must be an EnergyCost or LengthCost, got {type(cost).__name__}")
        if cost.world is not None and cost.world is not world:
            raise InputError("the cost object was built for a different world")
        self.world = world
        self.cost = cost
        self.options = options or OmplOptions()
        self.kind = objective_kind(cost)

    # -- configuration ----------------------------------------------------------------
    def state_space(self) -> tuple[str, float]:
        """Resolved state space name and arc radius [m] (0 for SE2)."""
        opts = self.options
        params = self.cost.params()
        name = opts.state_space
        if name == "auto":
            name = "se2" if self._spot_turns_ok() else "dubins"
        if name == "se2":
            return name, 0.0
        if name == "dubins" and opts.planner == "RRTConnect":
            raise InputError(
                "RRTConnect grows a tree backwards from the goal and needs reversible "
                "motions: use it with state_space 'se2' or 'reeds_shepp', not 'dubins'"
            )
        r_min = float(min_radius_for_speed(params, self.cost.speed_mps))
        if not math.isfinite(r_min):
            raise InputError(f"no turn is feasible at {self.cost.speed_mps:g} m/s for this vehicle")
        r = opts.turning_radius_m if opts.turning_radius_m is not None else _RADIUS_MARGIN * r_min
        if r < r_min:
            raise InputError(
                f"turning_radius_m = {r:g} m is below the smallest feasible radius "
                f"{r_min:.3g} m at {self.cost.speed_mps:g} m/s (power/speed limits)"
            )
        return name, float(r)

    def _spot_turns_ok(self) -> bool:
        net, _ = turn_costs(
            self.cost.params(), np.array([math.pi / 2]), self.cost.speed_mps, 0.0, "spot"
        )
        return bool(np.isfinite(net).all())

    # -- planning ---------------------------------------------------------------------
    def plan(
        self, start: ArrayLike, goal: ArrayLike, *, initial_heading_rad: float | None = None
    ) -> PlanResult:
        """Plan from ``start`` to ``goal`` (positions [m]).

        Parameters
        ----------
        start, goal : array_like, shape (2,)
            Positions [m]; the goal has no heading.
        initial_heading_rad : float, optional
            Heading at the start [rad]; ``None``: free (the path starts aligned).

        Returns
        -------
        PlanResult
            ``best`` is the plan (``alternatives`` holds it alone); ``planner`` is
            ``"ompl:<name>/<space>"``; ``stats`` has ``iterations``, ``solve_time_s``,
            ``raw_objective`` (before simplification), ``turning_radius_m``,
            ``motion_cost_calls``, ``stopped_by_time``, ``seed``.

        Raises
        ------
        InputError
            Start or goal out of bounds or in an obstacle, equal start and goal,
            non-finite heading, infeasible speed or radius.
        PlanningError
            No exact solution within the budget (e.g. the goal is unreachable), or no
            feasible execution of the path found.
        """
        deadline = Deadline(self.options.time_budget_s)
        s, g = check_endpoints(self.world, start, goal)
        if initial_heading_rad is not None and not (
            isinstance(initial_heading_rad, int | float) and math.isfinite(initial_heading_rad)
        ):
            raise InputError(f"initial_heading_rad must be finite, got {initial_heading_rad!r}")
        space_name, radius = self.state_space()
        if self.cost.segment_cost((0.0, 0.0), (1.0, 0.0)) is None:  # before any OMPL object
            raise InputError(
                f"straight driving at {self.cost.speed_mps:g} m/s is infeasible for this vehicle"
            )
        with quiet_ompl():
            raw, simplified, stats = self._search(
                s, g, initial_heading_rad, space_name, radius, deadline
            )
        if raw is None:
            raise PlanningError(
                f"{self.options.planner} found no path from ({s[0]:g}, {s[1]:g}) to "
                f"({g[0]:g}, {g[1]:g}) within {self.options.time_budget_s:g} s "
                "(the goal may be unreachable)"
            )
        best, raw_value = self._choose(raw, simplified, space_name, initial_heading_rad, deadline)
        stats.update(
            turning_radius_m=radius, seed=float(self.options.seed), raw_objective=raw_value
        )
        return PlanResult(
            best=best,
            alternatives=(best,),
            planner=f"ompl:{self.options.planner}/{space_name}",
            planning_time_s=deadline.elapsed_s,
            stats=stats,
        )

    def _search(
        self,
        s: tuple[float, float],
        g: tuple[float, float],
        heading: float | None,
        space_name: str,
        radius: float,
        deadline: Deadline,
    ) -> tuple[FloatArray | None, list[FloatArray], dict[str, float]]:
        """Run OMPL; return the raw poses, simplified candidates (N, 3) and stats.

        The raw poses are None when no exact solution was found.
        """
        opts = self.options
        ou.RNG.setSeed(int(opts.seed) % 2_147_483_646 + 1)  # OMPL ignores seed 0
        if space_name == "se2":
            space = ob.SE2StateSpace()
        elif space_name == "dubins":
            space = ob.DubinsStateSpace(radius)
        else:
            space = ob.ReedsSheppStateSpace(radius)
        xmin, ymin, xmax, ymax = (float(v) for v in self.world.extent())
        bounds = ob.RealVectorBounds(2)
        bounds.setLow(0, xmin)
        bounds.setLow(1, ymin)
        bounds.setHigh(0, xmax)
        bounds.setHigh(1, ymax)
        space.setBounds(bounds)
        ss = og.SimpleSetup(space)
        si = ss.getSpaceInformation()
        ss.setStateValidityChecker(state_validity(self.world))
        si.setStateValidityCheckingResolution(
            min(1.0, opts.resolution_m / space.getMaximumExtent())
        )
        direct = math.atan2(g[1] - s[1], g[0] - s[0])
        if space_name == "se2":
            validator = SegmentValidator(si, self.world)
            si.setMotionValidator(validator)
            motion: Any = StraightMotions(self.cost, s, g, heading is None)
            ss.setStartState(_state(space, s, direct if heading is None else heading))
            ss.setGoalState(_state(space, g, direct), 1e-9)
        else:
            motion = CurveMotions(self.cost, space, radius, max(radius / 4.0, 0.05))
            k = opts.goal_headings
            yaws = [direct + 2.0 * math.pi * i / k for i in range(k)]
            for yaw in [heading] if heading is not None else yaws:
                ss.addStartState(_state(space, s, yaw))
            goals = ob.GoalStates(si)
            for yaw in yaws:
                goals.addState(_state(space, g, yaw))
            ss.setGoal(goals)
        objective = OmplObjective(si, motion, motion.heuristic_per_m())
        ss.setOptimizationObjective(objective)
        ss.setPlanner(PLANNERS[opts.planner](si))
        ss.setup()
        ptc, count = termination(deadline, _SOLVE_SHARE * opts.time_budget_s, opts.max_iterations)
        ss.solve(ptc)
        solve_time = deadline.elapsed_s
        stats = {
            "iterations": float(count[0]),
            "solve_time_s": solve_time,
            "motion_cost_calls": float(objective.calls),
            "stopped_by_time": float(
                opts.max_iterations is None or count[0] <= opts.max_iterations
            ),
        }
        if not ss.haveExactSolutionPath():
            # raised by the caller, so that no traceback keeps OMPL objects alive
            return None, [], stats
        path = og.PathGeometric(ss.getSolutionPath())
        raw = _poses(path)
        candidates: list[FloatArray] = []
        if opts.simplify:
            simplifier = og.PathSimplifier(si, ss.getGoal(), objective)
            ptc2, _ = termination(deadline, _SIMPLIFY_SHARE * opts.time_budget_s, _SIMPLIFY_STEPS)
            simplifier.simplify(path, ptc2)
            candidates.append(_poses(path))
        if space_name != "se2":
            raw = self._densify(motion, raw)
            candidates = [self._densify(motion, c) for c in candidates]
        return raw, candidates, stats

    def _densify(self, motion: CurveMotions, poses: FloatArray) -> FloatArray:
        """Pieces of a curve path as rows ``(x, y, yaw, ds, dyaw, direction)``.

        The last row is the end pose with ``ds = 0``.
        """
        space = motion.space
        rows: list[tuple[float, ...]] = []
        a, b = space.allocState(), space.allocState()
        for p, q in itertools.pairwise(poses):
            _set(a, p)
            _set(b, q)
            rows.extend(motion.pieces(a, b, min(0.02, motion.radius / 20.0)))
        rows.append((*poses[-1], 0.0, 0.0, 1.0))
        return np.asarray(rows, dtype=np.float64).reshape(-1, 6)

    # -- evaluation -------------------------------------------------------------------
    def _choose(
        self,
        raw: FloatArray,
        candidates: list[FloatArray],
        space_name: str,
        heading: float | None,
        deadline: Deadline,
    ) -> tuple[Plan, float]:
        """Evaluate the raw and simplified paths with the cost module; keep the cheapest.

        Returns the plan and the objective value of the raw (unsimplified) path
        (``inf`` when that path has no feasible execution).
        """
        evaluated: list[tuple[float, FloatArray, PathCost]] = []
        for poses in [raw, *candidates]:
            if space_name == "se2":
                wps = _dedupe(poses[:, :2])
                pc = self.cost.path(wps, initial_heading_rad=heading)
                evaluated.append((self._value(pc), wps, pc))
                if not pc.feasible or not self.options.simplify:
                    continue
                wps, pc = self._prune_waypoints(wps, pc, heading, deadline)
            else:
                wps, pc = self._curve_cost(poses)
            evaluated.append((self._value(pc), wps, pc))
        value, wps, pc = min(evaluated, key=lambda e: e[0])
        if not math.isfinite(value):
            raise PlanningError(
                f"{self.options.planner} found a path but no feasible execution of it: "
                f"{pc.violations[0].message() if pc.violations else 'unknown violation'}"
            )
        return Plan(wps, pc, self.kind, value, self.cost.speed_mps), evaluated[0][0]

    def _value(self, pc: PathCost) -> float:
        return self.cost.value(pc) if pc.feasible else math.inf

    def _prune_waypoints(
        self, wps: FloatArray, pc: PathCost, heading: float | None, deadline: Deadline
    ) -> tuple[FloatArray, PathCost]:
        """Greedily drop waypoints while the path stays free and the objective decreases."""
        best_val = self.cost.value(pc)
        improved = True
        until = _PRUNE_SHARE * deadline.budget_s
        while improved and len(wps) > 2:
            improved = False
            for i in range(1, len(wps) - 1):
                if deadline.elapsed_s >= until:
                    return wps, pc
                if not self.world.segment_free(wps[i - 1], wps[i + 1]):
                    continue
                cand = np.delete(wps, i, axis=0)
                cpc = self.cost.path(cand, initial_heading_rad=heading)
                val = self.cost.value(cpc)
                if cpc.feasible and val < best_val - 1e-9:
                    wps, pc, best_val, improved = cand, cpc, val, True
                    break
        return wps, pc

    def _curve_cost(self, rows: FloatArray) -> tuple[FloatArray, PathCost]:
        """Timed track speeds of a sampled curve and their cost (:func:`trajectory_cost`)."""
        v = self.cost.speed_mps
        params = self.cost.params()
        moving = rows[:-1, 3] > 1e-12
        ds, dyaw, direction = rows[:-1, 3][moving], rows[:-1, 4][moving], rows[:-1, 5][moving]
        dt = ds / v
        wz = np.where(dt > 0, dyaw / np.where(dt > 0, dt, 1.0), 0.0)
        vl, vr = setpoint_to_tracks(direction * v, wz, params.icr)
        t_end = np.cumsum(dt)
        t_start = t_end - dt
        t = np.column_stack([t_start, np.maximum(t_end - _EPS_T, t_start + _EPS_T / 2)]).ravel()
        traj = TrackTrajectory(t, np.repeat(vl, 2), np.repeat(vr, 2))
        pts = rows[:, :2]
        start_pose = (float(rows[0, 0]), float(rows[0, 1]), float(rows[0, 2]))
        pc = trajectory_cost(traj, self.cost.vehicle, world=self.cost.world, start_pose=start_pose)
        if not self.world.polyline_free(pts):
            bad = Violation("segment", 0, "collision", v, math.inf)
            pc = PathCost(
                pc.length_m, pc.duration_s, pc.psi_rad, pc.energy_j, pc.breakdown_j,
                pc.peak_power_w, False, (bad, *pc.violations), pc.turns,
            )  # fmt: skip
        return pts, pc


def plan_ompl(
    world: World,
    start: ArrayLike,
    goal: ArrayLike,
    cost: CostObjective,
    *,
    options: OmplOptions | None = None,
    initial_heading_rad: float | None = None,
) -> PlanResult:
    """Plan with an OMPL planner: the functional form of :meth:`OmplPlanner.plan`.

    The argument order is that of every planner function
    (:func:`ecoplan.planning.graph.plan_graph`, :func:`ecoplan.planning.reference.plan_reference`).

    Parameters
    ----------
    world : World
        The map.
    start, goal : array_like
        ``(x, y)`` [m].
    cost : CostObjective
        The objective (energy or length).
    options : OmplOptions, optional
        Planner, budget, seed, state space.
    initial_heading_rad : float, optional
        Heading at the start [rad]; free when None.

    Returns
    -------
    PlanResult
        The plan and its statistics.
    """
    return OmplPlanner(world, cost, options).plan(
        start, goal, initial_heading_rad=initial_heading_rad
    )


# ---------------------------------------------------------------------------- helpers
def _state(space: Any, xy: tuple[float, float], yaw: float) -> Any:
    st = space.allocState()
    st.setX(float(xy[0]))
    st.setY(float(xy[1]))
    st.setYaw(float(wrap_angle(yaw)))
    return st


def _set(st: Any, pose: FloatArray) -> None:
    st.setX(float(pose[0]))
    st.setY(float(pose[1]))
    st.setYaw(float(pose[2]))


def _poses(path: Any) -> FloatArray:
    return np.asarray(
        [(st.getX(), st.getY(), st.getYaw()) for st in path.getStates()], dtype=np.float64
    ).reshape(-1, 3)


def _dedupe(points: FloatArray) -> FloatArray:
    keep = np.concatenate([[True], np.hypot(*np.diff(points, axis=0).T) > 1e-9])
    out: FloatArray = points[keep]
    return out
