"""Running a scenario's cases: plan, simulate with the heading controller, account energy.

One case (:class:`~ecoplan.app.scenario.build.Case`) is planned by the graph or an OMPL
planner (or takes its fixed waypoints), optionally at the energy-optimal speed, then
simulated with the heading controller of tracked paper eq. (23); the power is
re-evaluated on the terrain under the vehicle, the vehicle's limits and the map's
clearance are checked, and the energy is compared with the battery budget.
"""

from __future__ import annotations

import dataclasses
from collections.abc import Sequence
from dataclasses import dataclass
from pathlib import Path
from typing import Any

import numpy as np

from ecoplan._typing import BoolArray, FloatArray
from ecoplan.app.scenario.build import Case, Scenario, build_scenario
from ecoplan.app.scenario.elevation import climb_power_w
from ecoplan.app.scenario.schema import BatterySection, PlannerSection
from ecoplan.dynamics.controller import HeadingController
from ecoplan.energy.controlled import corner_pairs
from ecoplan.energy.objective import EnergyCost, LengthCost
from ecoplan.energy.path import path_cost
from ecoplan.energy.primitives import params_on
from ecoplan.errors import InputError, PlanningError
from ecoplan.geometry.maps import GridMap
from ecoplan.models.limits import check_tracks
from ecoplan.models.tracked import TrackedParams
from ecoplan.presets import vehicle as named_vehicle
from ecoplan.sim.simulate import SimConfig, SimResult, simulate_waypoints

__all__ = [
    "BatteryVerdict",
    "CaseResult",
    "PlanOutcome",
    "battery_verdict",
    "candidate_routes",
    "cheapest",
    "plan_case",
    "run_case",
    "simulate_case",
]


@dataclass(frozen=True, eq=False)
class PlanOutcome:
    """The route of one case: planned, or the fixed waypoints.

    Attributes
    ----------
    planner : str
        ``"fixed"``, ``"graph"`` or ``"ompl:<name>"``, with ``"/length"`` for the
        shortest-path baseline.
    waypoints : ndarray
        ``(n, 2)`` polyline [m]: the start, then the goals in order.
    speed_mps : float
        Speed set point of the heading controller ``v_sp`` [m/s].
    planning_time_s : float
        Wall-clock time of planning [s] (0 for fixed waypoints).
    estimate_energy_j : float or None
        Analytic energy of the route driven by the case's heading controller
        (:func:`ecoplan.energy.path.path_cost` with ``turn=HeadingController(...)``) [J].
    feasible : bool or None
        Whether every command of the analytic execution respects the vehicle's limits.
    violations : tuple of str
        The violated constraints, naming the segment or turn.
    alternatives : tuple of ndarray
        Further distinct waypoint sets the planner returned (``planner.k > 1``).
    speed_policy : str
        ``"fixed"`` or ``"optimal"`` (:func:`ecoplan.planning.speed.best_speed` on the
        route, after planning at the nominal ``speed.v_mps``).
    """

    planner: str
    waypoints: FloatArray
    speed_mps: float
    planning_time_s: float = 0.0
    estimate_energy_j: float | None = None
    feasible: bool | None = None
    violations: tuple[str, ...] = ()
    alternatives: tuple[FloatArray, ...] = ()
    speed_policy: str = "fixed"

    @property
    def length_m(self) -> float:
        """Length of the waypoint polyline [m]."""
        return float(np.sum(np.hypot(*np.diff(self.waypoints, axis=0).T)))


@dataclass(frozen=True)
class BatteryVerdict:
    """Whether a run fits its battery budget, and where the battery would run out.

    Attributes
    ----------
    capacity_wh : float
        Battery capacity [Wh].
    usable_j : float
        Energy available after the reserve [J].
    used_j : float
        Energy the simulated run used [J].
    completes : bool
        True when the run reached its goal within the usable energy.
    margin_j : float
        ``usable_j - used_j`` [J] (negative when the battery runs out).
    empty_at : tuple of float or None
        ``(t_s, x_m, y_m, distance_m)`` where the usable energy is exhausted, if it is.
    """

    capacity_wh: float
    usable_j: float
    used_j: float
    completes: bool
    margin_j: float
    empty_at: tuple[float, float, float, float] | None

    @property
    def margin_fraction(self) -> float:
        """Margin as a fraction of the usable energy."""
        return self.margin_j / self.usable_j

    def sentence(self) -> str:
        """One sentence for reports."""
        wh = self.used_j / 3600.0
        if self.completes:
            return (
                f"The plan completes on the battery: it uses {wh:.2f} Wh of "
                f"{self.usable_j / 3600.0:.2f} Wh usable, a margin of "
                f"{self.margin_j / 3600.0:.2f} Wh ({100 * self.margin_fraction:.0f} %)."
            )
        if self.empty_at is None:
            return (
                f"The run did not reach its goal (time limit); it used {wh:.2f} Wh of "
                f"{self.usable_j / 3600.0:.2f} Wh usable."
            )
        t, x, y, d = self.empty_at
        return (
            f"The plan does NOT complete: the {self.usable_j / 3600.0:.2f} Wh usable run out "
            f"after {t:.0f} s and {d:.1f} m, at ({x:.1f}, {y:.1f}) m; the whole run needs "
            f"{wh:.2f} Wh ({-self.margin_j / 3600.0:.2f} Wh more)."
        )


@dataclass(frozen=True, eq=False)
class CaseResult:
    """Plan, simulation and energy accounting of one case.

    The power is the simulator's, re-evaluated per step on the terrain under the
    vehicle when the map has terrain regions (the kinematics stay those of the default
    terrain).

    Attributes
    ----------
    name : str
        Case name.
    plan : PlanOutcome
        The route.
    sim : SimResult or None
        The heading-controller run (None for ``plan`` only).
    p_total_w : ndarray
        Electrical power per step [W] (terrain-aware).
    p_left_w, p_right_w : ndarray
        Mechanical power per side per step [W] (terrain-aware).
    components_w : dict of str to ndarray
        Power breakdown per step [W].
    terrain : tuple of str
        Terrain under the vehicle per step.
    energy_j : float
        Energy of locomotion [J].
    breakdown_j : dict of str to float
        Energy per component [J]; sums to ``energy_j``.
    battery : BatteryVerdict or None
        Battery check, when the scenario has a budget.
    violation_s : dict of str to float
        Time the simulated commands spent violating each of the vehicle's limits
        (:func:`ecoplan.models.limits.check_tracks`: top speed, power limits) [s].
    clearance_violation_s : float
        Time the vehicle's centre spent outside the free space (closer to an obstacle
        or to the map edge than ``map.inflation_m``) [s].
    over_limit : ndarray of bool
        Per step, True where the commands violate a limit of the vehicle.
    error : str or None
        Why the case has no route (the planner failed on valid input), else None.
    """

    name: str
    plan: PlanOutcome
    sim: SimResult | None
    p_total_w: FloatArray
    p_left_w: FloatArray
    p_right_w: FloatArray
    components_w: dict[str, FloatArray]
    terrain: tuple[str, ...]
    energy_j: float
    breakdown_j: dict[str, float]
    battery: BatteryVerdict | None
    violation_s: dict[str, float]
    clearance_violation_s: float
    over_limit: BoolArray
    error: str | None = None

    @classmethod
    def unsimulated(cls, name: str, plan: PlanOutcome, error: str | None = None) -> CaseResult:
        """A result holding only a route (``ecoplan plan``) or a planner failure."""
        empty = np.zeros(0)
        no_steps = np.zeros(0, dtype=np.bool_)
        return cls(
            name, plan, None, empty, empty, empty, {}, (), 0.0, {}, None, {}, 0.0, no_steps,
            error=error,
        )  # fmt: skip

    @property
    def cumulative_energy_j(self) -> FloatArray:
        """Energy used up to the start of each step [J]."""
        if self.sim is None:
            return np.zeros(0)
        dt = self.sim.dt_s
        return np.concatenate([[0.0], np.cumsum(self.p_total_w[:-1]) * dt])

    @property
    def peak_power_w(self) -> float:
        """Largest power of an integrated step [W]."""
        if self.sim is None or self.sim.n_steps == 0:
            return 0.0
        return float(np.max(self.p_total_w[:-1]))

    def summary(self) -> dict[str, Any]:
        """JSON-ready numbers of the case (SI units)."""
        out: dict[str, Any] = {
            "name": self.name,
            "planner": self.plan.planner,
            "waypoints": self.plan.waypoints.tolist(),
            "speed_mps": self.plan.speed_mps,
            "speed_policy": self.plan.speed_policy,
            "planning_time_s": round(self.plan.planning_time_s, 4),
            "planned_length_m": round(self.plan.length_m, 4),
            "estimate_energy_j": self.plan.estimate_energy_j,
            "plan_feasible": self.plan.feasible,
            "plan_violations": list(self.plan.violations),
            "error": self.error,
        }
        if self.sim is not None:
            out.update(
                energy_j=self.energy_j,
                time_s=self.sim.time_s,
                length_m=self.sim.length_m,
                psi_rad=self.sim.psi_rad,
                peak_power_w=self.peak_power_w,
                mean_power_w=self.energy_j / self.sim.time_s if self.sim.time_s else 0.0,
                completed=self.sim.completed,
                breakdown_j=dict(self.breakdown_j),
                limit_violation_s=dict(self.violation_s),
                clearance_violation_s=self.clearance_violation_s,
            )
        if self.battery is not None:
            b = self.battery
            out["battery"] = {
                "capacity_wh": b.capacity_wh,
                "usable_j": b.usable_j,
                "used_j": b.used_j,
                "completes": b.completes,
                "margin_j": b.margin_j,
                "margin_fraction": b.margin_fraction,
                "empty_at": (
                    None
                    if b.empty_at is None
                    else dict(zip(("t_s", "x_m", "y_m", "distance_m"), b.empty_at, strict=True))
                ),
            }
        return out


def _case_scenario(case: Case) -> Scenario:
    return build_scenario(case.spec, case.source)


def plan_case(case: Case, *, time_budget_s: float | None = None) -> PlanOutcome:
    """Plan the route of a case (or take its fixed waypoints).

    Parameters
    ----------
    case : Case
        The case.
    time_budget_s : float, optional
        Replaces the scenario's ``planner.time_s`` (``--time-budget``: lower or raise it).

    Returns
    -------
    PlanOutcome
        The route and how it was found.

    Raises
    ------
    PlanningError
        The planner found no route within its budget.
    """
    sc = _case_scenario(case)
    spec = case.spec
    planner = case.planner
    speed = float(spec.speed.v_mps)  # the fixed speed, or the nominal one to plan at
    start = np.asarray([spec.start.xy], dtype=np.float64)
    if planner.type == "none":
        assert spec.waypoints is not None
        wps = np.vstack([start, np.asarray(spec.waypoints, dtype=np.float64)])
        plan = PlanOutcome("fixed", wps, speed)
    else:
        plan = _plan_with(sc, planner, speed, time_budget_s)
    if spec.speed.policy == "optimal":
        from ecoplan.planning.speed import best_speed

        top = sc.params.top_track_speed_mps
        choice = best_speed(
            plan.waypoints,
            sc.vehicle,
            world=sc.world,
            initial_heading_rad=spec.start.yaw_rad,
            v_min_mps=spec.speed.v_min_mps,
            v_max_mps=min(spec.speed.v_max_mps or top, top),
        )
        speed = float(choice.speed_mps)
    if plan.estimate_energy_j is None or speed != plan.speed_mps:
        pc = path_cost(
            plan.waypoints,
            sc.vehicle,
            speed,
            world=sc.world,
            initial_heading_rad=spec.start.yaw_rad,
            elevation=sc.elevation,
        )
        plan = dataclasses.replace(
            plan,
            speed_mps=speed,
            feasible=pc.feasible,
            violations=tuple(v.message() for v in pc.violations),
        )
    # the energy estimate: the route as the heading controller drives it (issue 11, item 6)
    ctrl = HeadingController(
        spec.controller.gain, speed, spec.controller.d_th_m,
        slowdown_heading_rad=spec.controller.slowdown_heading_rad,
    )  # fmt: skip
    estimate = path_cost(
        plan.waypoints, sc.vehicle, speed, world=sc.world,
        initial_heading_rad=spec.start.yaw_rad, turn=ctrl, elevation=sc.elevation,
    )  # fmt: skip
    plan = dataclasses.replace(plan, estimate_energy_j=estimate.energy_j)
    return dataclasses.replace(plan, speed_policy=spec.speed.policy)


def _plan_with(
    sc: Scenario, planner: PlannerSection, speed_mps: float, time_budget_s: float | None
) -> PlanOutcome:
    cost: EnergyCost | LengthCost
    if planner.objective == "energy":  # climbs cost M g dz / eta (terrain.elevation)
        cost = EnergyCost(sc.vehicle, speed_mps, world=sc.world, elevation=sc.elevation)
    else:
        cost = LengthCost(sc.vehicle, speed_mps, world=sc.world)
    budget = planner.time_s if time_budget_s is None else time_budget_s  # the flag overrides
    start, goal, heading = sc.spec.start.xy, sc.goal_xy, sc.spec.start.yaw_rad
    if isinstance(sc.world, GridMap) or planner.type == "lattice":
        from ecoplan.planning.lattice import LatticePlanner, LatticePlannerOptions

        if not isinstance(sc.world, GridMap):
            raise InputError(
                f"{sc.source}: planner type lattice plans on grid maps: give map: {{ros: FILE}}"
            )
        if planner.type not in ("lattice", "graph"):
            raise InputError(
                f"{sc.source}: planner type {planner.type} needs a polygon map; "
                "use planner: {type: lattice} with map: {ros: ...}"
            )
        c = sc.spec.controller  # corners costed as this controller drives them
        ctrl = HeadingController(
            c.gain, speed_mps, c.d_th_m, slowdown_heading_rad=c.slowdown_heading_rad
        )
        lopts = LatticePlannerOptions(time_budget_s=budget, controller=ctrl)
        res = LatticePlanner(sc.world, cost, lopts).plan(start, goal, initial_heading_rad=heading)
    elif planner.type == "graph":
        from ecoplan.planning.graph import GraphPlanner, GraphPlannerOptions

        c = sc.spec.controller  # the route is refined as this controller drives it
        ctrl = HeadingController(
            c.gain, speed_mps, c.d_th_m, slowdown_heading_rad=c.slowdown_heading_rad
        )
        # its corner and corner-pair tables (seconds; cached, and the estimate needs them
        # too) are built before the planner's clock starts
        params0 = params_on(sc.vehicle, sc.world.terrain_at(np.asarray([start]))[0])
        corner_pairs(params0, dataclasses.replace(ctrl, speed_mps=speed_mps))
        options = GraphPlannerOptions(k_paths=planner.k, time_budget_s=budget, controller=ctrl)
        res = GraphPlanner(sc.world, cost, options).plan(start, goal, initial_heading_rad=heading)
    else:
        from ecoplan.planning.ompl import OmplOptions, OmplPlanner

        assert planner.name is not None
        opts = OmplOptions(
            planner.name,
            time_budget_s=budget,
            seed=planner.seed,
            max_iterations=planner.max_iterations,
        )
        res = OmplPlanner(sc.world, cost, opts).plan(start, goal, initial_heading_rad=heading)
    best = res.best
    name = res.planner
    if planner.objective == "length" and "length" not in name:
        name += "/length"
    return PlanOutcome(
        name,
        np.asarray(best.waypoints, dtype=np.float64),
        speed_mps,
        planning_time_s=res.planning_time_s,
        estimate_energy_j=best.cost.energy_j,
        feasible=best.cost.feasible,
        violations=tuple(v.message() for v in best.cost.violations),
        alternatives=tuple(np.asarray(p.waypoints) for p in res.alternatives[1:]),
    )


def simulate_case(
    case: Case, plan: PlanOutcome | None = None, *, time_budget_s: float | None = None
) -> CaseResult:
    """Plan (unless ``plan`` is given) and simulate one case with the heading controller.

    Parameters
    ----------
    case : Case
        The case.
    plan : PlanOutcome, optional
        A route to simulate instead of planning one.
    time_budget_s : float, optional
        Replaces the scenario's ``planner.time_s``.

    Returns
    -------
    CaseResult
        The simulated run with its energy accounting and battery verdict.
    """
    sc = _case_scenario(case)
    if plan is None:
        plan = plan_case(case, time_budget_s=time_budget_s)
    spec = case.spec
    ctrl = HeadingController(
        gain=spec.controller.gain,
        speed_mps=plan.speed_mps,
        switch_radius_m=spec.controller.d_th_m,
        slowdown_heading_rad=spec.controller.slowdown_heading_rad,
    )
    sim = simulate_waypoints(
        sc.params,
        plan.waypoints,
        ctrl,
        start_yaw_rad=spec.start.yaw_rad,
        config=SimConfig(
            dt_s=spec.simulation.dt_s,
            t_max_s=spec.simulation.t_max_s,
            inertial=spec.simulation.inertial,
        ),
    )
    return _account(sc, case.name, plan, sim)


def run_case(case: Case, time_budget_s: float | None = None) -> CaseResult:
    """Plan and simulate one case of a sweep; a planner failure becomes a failed result.

    The picklable task of ``ecoplan compare`` and ``bench``: one case that finds no route
    (:class:`~ecoplan.errors.PlanningError`) must not sink the others, so it comes back
    as a :class:`CaseResult` without simulation whose ``error`` says why.  Bad input
    still raises.

    Parameters
    ----------
    case : Case
        The case.
    time_budget_s : float, optional
        Replaces the scenario's ``planner.time_s``.

    Returns
    -------
    CaseResult
        The simulated case, or a failed one (``sim is None``, ``error`` set).
    """
    try:
        return simulate_case(case, time_budget_s=time_budget_s)
    except PlanningError as exc:
        spec = case.spec
        planner = case.planner
        name = planner.type if planner.name is None else f"{planner.type}:{planner.name}"
        plan = PlanOutcome(name, np.asarray([spec.start.xy]), spec.speed.v_mps)
        return CaseResult.unsimulated(case.name, plan, error=str(exc))


def _account(sc: Scenario, name: str, plan: PlanOutcome, sim: SimResult) -> CaseResult:
    dt = sim.dt_s
    n = sim.n_steps
    if sc.regions or sc.world.has_regions:
        pts = np.column_stack([sim.x, sim.y])
        terrain = tuple(t or sc.default_terrain for t in sc.world.terrain_at(pts))
        p_total = np.array(sim.p_total, dtype=np.float64, copy=True)
        p_left = np.array(sim.p_left, dtype=np.float64, copy=True)
        p_right = np.array(sim.p_right, dtype=np.float64, copy=True)
        comps = {k: np.array(v, dtype=np.float64, copy=True) for k, v in sim.components_w.items()}
        for terr in sorted(set(terrain)):
            idx = np.flatnonzero(np.asarray(terrain) == terr)
            pw = sc.vehicle.on(terr).power(sim.v_left[idx], sim.v_right[idx])
            p_total[idx] = pw.total_w
            if "inertial_w" in comps:  # mass terms: the same on every terrain
                p_total[idx] += comps["inertial_w"][idx]
            p_left[idx] = pw.left_w
            p_right[idx] = pw.right_w
            for k, v in pw.components().items():
                comps[k][idx] = v
    else:
        terrain = (sc.default_terrain,) * len(sim.t)
        p_total = np.asarray(sim.p_total, dtype=np.float64)
        p_left = np.asarray(sim.p_left, dtype=np.float64)
        p_right = np.asarray(sim.p_right, dtype=np.float64)
        comps = {k: np.asarray(v, dtype=np.float64) for k, v in sim.components_w.items()}
    if sc.model is not None and sc.model.effect != "none":
        p_total, comps = _with_effect(sc.model, sim, p_total, comps)
    if sc.elevation is not None:  # G(q): the climbs along the simulated path
        p = sc.params
        eta = p.eta if isinstance(p, TrackedParams) else 1.0  # as energy.path charges them
        comps["grade_w"] = climb_power_w(sc.elevation, sim.x, sim.y, dt, p.mass_kg, eta)
        p_total = p_total + comps["grade_w"]
    violated = np.full(len(sim.t), "", dtype=object)
    for terr in sorted(set(terrain)):
        idx = np.flatnonzero(np.asarray(terrain) == terr)
        check = check_tracks(sc.vehicle.on(terr), sim.v_left[idx], sim.v_right[idx])
        violated[idx] = check.violated
    names, counts = np.unique(violated[:n].astype(str), return_counts=True)
    violation_s = {str(k): float(c) * dt for k, c in zip(names, counts, strict=True) if k}
    outside = ~sc.world.is_free(sim.x[:n], sim.y[:n])
    clearance_s = float(np.count_nonzero(outside)) * dt
    energy = float(np.sum(p_total[:n]) * dt)
    breakdown = {k: float(np.sum(v[:n]) * dt) for k, v in comps.items()}
    battery = None
    if sc.spec.battery is not None:
        battery = battery_verdict(sc.spec.battery, sim, p_total, energy)
    return CaseResult(
        name,
        plan,
        sim,
        p_total,
        p_left,
        p_right,
        comps,
        terrain,
        energy,
        breakdown,
        battery,
        violation_s,
        clearance_s,
        np.asarray(violated != "", dtype=np.bool_),
    )


def _with_effect(
    model: Any, sim: SimResult, p_total: FloatArray, comps: dict[str, FloatArray]
) -> tuple[FloatArray, dict[str, FloatArray]]:
    """Add a corrected model's fitted effect along the simulated trajectory.

    :meth:`CorrectedModel.trajectory_power` gives the total power with the effect (from the
    commanded speeds for ``actuator_lag``); the difference to the base model's power is
    booked under traction resistance, as the corrected model's steady-state power does.
    """
    lag = model.effect == "actuator_lag"
    vl = sim.v_left_cmd if lag else sim.v_left
    vr = sim.v_right_cmd if lag else sim.v_right
    total = np.asarray(
        model.trajectory_power(sim.t, vl, vr, x=sim.x, y=sim.y, yaw=sim.yaw), dtype=np.float64
    )
    comps = dict(comps)
    comps["resistance_w"] = comps["resistance_w"] + (total - p_total)
    return total, comps


def battery_verdict(
    b: BatterySection, sim: SimResult, p_total: FloatArray, energy: float
) -> BatteryVerdict:
    """Whether a simulated run fits its battery budget, and where the battery runs out.

    Parameters
    ----------
    b : BatterySection
        Capacity and reserve.
    sim : SimResult
        The simulated run.
    p_total : ndarray
        Electrical power per step [W].
    energy : float
        Energy of the run [J].

    Returns
    -------
    BatteryVerdict
        The verdict; ``empty_at`` is the first step at which the cumulative energy
        reaches the usable energy.
    """
    usable = b.usable_j
    n = sim.n_steps
    cum = np.concatenate([[0.0], np.cumsum(p_total[:n]) * sim.dt_s])
    empty_at = None
    if cum[-1] > usable:
        k = int(np.searchsorted(cum, usable))  # first row with cum >= usable
        dist = np.concatenate([[0.0], np.cumsum(np.hypot(np.diff(sim.x), np.diff(sim.y)))])
        empty_at = (float(sim.t[k]), float(sim.x[k]), float(sim.y[k]), float(dist[k]))
    completes = sim.completed and energy <= usable
    return BatteryVerdict(b.capacity_wh, usable, energy, completes, usable - energy, empty_at)


def candidate_routes(
    scenario: str | Path, vehicle: str, terrain: str | None = None
) -> dict[str, Any]:
    """Candidate routes of a scenario as drive trajectories, for ranking by a diagnosis.

    Each case of the scenario (its ``compare`` variants, or the scenario itself) is
    planned (or takes its fixed waypoints), with the planner's alternatives when it
    returns several; every route is driven turn-on-the-spot then straight at the case's
    speed (:func:`ecoplan.diagnose.ranking.polyline_trajectory`) by the diagnosed vehicle.

    Parameters
    ----------
    scenario : str or Path
        The scenario file (``ecoplan diagnose --scenario``).
    vehicle : str
        The diagnosed vehicle (``--vehicle``): the scenario must drive the same one.
    terrain : str, optional
        The diagnosed terrain (default: the vehicle's).

    Returns
    -------
    dict of str to trajectory
        ``(t, v_left, v_right)`` per route name (``"<case> (alt i)"`` for alternatives).

    Raises
    ------
    InputError
        The scenario drives another vehicle, or gives fewer than two routes.
    """
    from ecoplan.app.scenario import load_scenario
    from ecoplan.diagnose.ranking import polyline_trajectory

    sc = load_scenario(scenario)
    if sc.vehicle_name != vehicle:
        raise InputError(
            f"--scenario {scenario}: its vehicle is {sc.vehicle_name!r} but the logs are "
            f"diagnosed against --vehicle {vehicle!r}; rank routes of the same vehicle"
        )
    params = named_vehicle(vehicle, terrain)
    routes: dict[str, Any] = {}
    for case in sc.cases():
        plan = plan_case(case)
        for i, wps in enumerate((plan.waypoints, *plan.alternatives)):
            name = case.name if i == 0 else f"{case.name} (alt {i})"
            routes[name] = polyline_trajectory(wps.tolist(), params, speed_mps=plan.speed_mps)
    if len(routes) < 2:
        raise InputError(
            f"{sc.source}: it gives one route; a ranking needs at least two "
            "(add `compare:` variants or planner.k > 1)"
        )
    return routes


def cheapest(results: Sequence[CaseResult], source: str = "<scenario>") -> CaseResult:
    """The case that used the least energy among those that found a route.

    Parameters
    ----------
    results : sequence of CaseResult
        The cases of a comparison.
    source : str
        The scenario, for the message.

    Returns
    -------
    CaseResult
        The simulated case of least ``energy_j`` (the first of equals).

    Raises
    ------
    PlanningError
        No case found a route.
    """
    done = [r for r in results if r.error is None and r.sim is not None]
    if not done:
        why = results[0].error if results else "no cases"
        raise PlanningError(f"no case of {source} found a route: {why}")
    return min(done, key=lambda r: r.energy_j)
