"""Finishing a lattice route: smoothing, refinement, and the pick as driven.

After the search, a lattice route is smoothed (string pulling) and refined
(:mod:`ecoplan.planning.refine`); with a heading controller every stage is ranked by the
energy as the controller drives it (:func:`~ecoplan.energy.path.path_cost` with
``turn=controller``), and the final pick among the candidate routes is by the
controller's roll-out (the simulator's physics, power on the terrain under the robot).
:class:`RouteFinisher` holds what these steps share; the
:class:`~ecoplan.planning.lattice.LatticePlanner` owns one.
"""

from __future__ import annotations

import math
from collections.abc import Callable

import numpy as np

from ecoplan._typing import FloatArray
from ecoplan.dynamics.controller import HeadingController, WaypointFollower, power_limited_radius
from ecoplan.dynamics.drive import IcrArrays
from ecoplan.dynamics.rollout import ROLLOUT_STATE, rollout
from ecoplan.energy.controlled import controlled_turns
from ecoplan.energy.driven_path import DrivenPathCost
from ecoplan.energy.objective import CostObjective
from ecoplan.energy.path import path_cost
from ecoplan.energy.primitives import VehicleParams
from ecoplan.energy.result import PathCost
from ecoplan.energy.trajectory import TrackTrajectory, trajectory_cost
from ecoplan.geometry.maps import GridMap
from ecoplan.planning.base import Deadline
from ecoplan.planning.lattice.primitives import PenaltyWeights
from ecoplan.planning.lattice.smooth import Smoother
from ecoplan.planning.refine import RefineOptions, RefineResult, refine_waypoints

__all__ = ["Candidate", "RouteFinisher", "drive_paths"]

# a route refined for a controller must be estimated cheaper by more than the controlled
# model's error (as the graph planner's refinement)
_DRIVEN_GAIN = 0.01
# step of the controller roll-outs that pick among routes [s] (G = 0.18 /s: G dt = 0.036).
# At 0.1 s the Husky's 60 m sites of benchmarks/sites.py were within 0.01 % of the
# simulator at 0.01 s; on the candidates of the 18 200 m sites of lattice_scale.py (24 Nov)
# 0.2 s is within 0.13 % of 0.1 s and picks the same route on 17, on the 18th (a 0.01 %
# tie at 0.1 s) the route that 0.04 s steps and the corner tables both find cheaper
_ROLLOUT_DT_S = 0.2
_MAX_PIECES = 100_000  # pieces of driven evaluations kept across queries (a few MB)

Candidate = tuple[FloatArray, PathCost]
"""A candidate route: waypoints ``(N, 2)`` [m] and their full evaluation."""


class RouteFinisher:
    """Smoothing, refinement and the final pick of lattice routes (module doc).

    Parameters
    ----------
    grid : GridMap
        Inflated grid with its terrain layer.
    cost : CostObjective
        Vehicle, cruise speed, turn mode and objective.
    smoother : Smoother
        The lattice's string pulling.
    smoothing_passes : int
        Smoothing passes per route.
    refine : RefineOptions or None
        Refinement options; ``None``: no refinement.
    controller : HeadingController or None
        The controller at the cruise speed: rank and pick as driven; ``None``: statically.
    weights : PenaltyWeights, optional
        Nav2-style penalties: rank by them, never refine.
    """

    def __init__(
        self,
        grid: GridMap,
        cost: CostObjective,
        smoother: Smoother,
        smoothing_passes: int,
        refine: RefineOptions | None,
        controller: HeadingController | None,
        weights: PenaltyWeights | None = None,
    ) -> None:
        self.grid, self.cost, self.smoother = grid, cost, smoother
        self.passes, self.refine_options = smoothing_passes, refine
        self.ctrl, self.weights = controller, weights
        self._drive: DrivenPathCost | None = None  # the evaluations as driven, pieces cached
        self._full: dict[tuple[bytes, float | None], PathCost] = {}  # evaluations, per query
        if controller is not None and cost.elevation is None:
            self._drive = DrivenPathCost(
                cost.vehicle, cost.speed_mps, controller, world=grid, max_pieces=_MAX_PIECES
            )

    def rank(self, pc: PathCost) -> tuple[bool, float]:
        """Sort key of an evaluated path: feasible first, then the search objective."""
        if self.weights is not None:  # the penalty baseline ranks by its own costs
            value = pc.length_m + self.weights.turn_per_rad * pc.psi_rad
        else:
            value = self.cost.value(pc)
        return (not pc.feasible, value)

    def driven(self, wps: FloatArray, heading: float | None) -> PathCost:
        """The path as the controller drives it (:mod:`ecoplan.energy.controlled`).

        :func:`~ecoplan.energy.path.path_cost` with ``turn=controller``; its pieces are
        cached across the stages and queries (:class:`~ecoplan.energy.driven_path.DrivenPathCost`),
        except on an elevation map.
        """
        assert self.ctrl is not None
        if self._drive is not None:
            return self._drive(wps, heading)
        return path_cost(
            wps, self.cost.vehicle, self.cost.speed_mps, world=self.grid,
            initial_heading_rad=heading, turn=self.ctrl, elevation=self.cost.elevation,
        )  # fmt: skip

    def evaluate(self, wps: FloatArray, heading: float | None) -> PathCost:
        """The full evaluation of a route with the cost object's turn model (kept).

        The stages, the refinements' inputs and outputs and the candidates of one query
        share routes: each is evaluated once (:meth:`new_query` forgets them).  With an
        elevation map the evaluation is the refinement's own (with the elevation), else
        this one.
        """
        key = (np.ascontiguousarray(wps).tobytes(), heading)
        if key not in self._full:
            self._full[key] = path_cost(
                wps,
                self.cost.vehicle,
                self.cost.speed_mps,
                world=self.grid,
                initial_heading_rad=heading,
                turn=self.cost.turn,
                ramps=self.cost.ramps,
            )
        return self._full[key]

    def new_query(self) -> None:
        """Forget the evaluations of the last query (:meth:`evaluate`)."""
        self._full.clear()

    def _refine_evaluate(self, heading: float | None) -> Callable[[FloatArray], PathCost] | None:
        """The refinement's full evaluation: :meth:`evaluate` unless on an elevation map."""
        if self.cost.elevation is not None:
            return None  # the refinement's own, with the elevation

        def full(w: FloatArray) -> PathCost:
            return self.evaluate(w, heading)

        return full

    def refine(
        self, wps: FloatArray, heading: float | None, deadline: Deadline, *, driven: bool
    ) -> RefineResult:
        """:func:`refine_waypoints` of the route, as the controller drives it if ``driven``.

        As driven, legs (after the first) shorter than the corner tables reach are merged
        first (:meth:`drop_short_legs`).  A route that keeps such a leg is returned
        unrefined (changed if merging changed it, for :meth:`pick` to judge): the
        refinement tries no candidate with such a leg, so it could only move that leg's
        ends, against a start value that needs a roll-out of its own (0.04 s steps,
        about 0.35 s on a 200 m site); on the 18 sites of ``benchmarks/lattice_scale.py``
        it kept none of those moves.
        """
        if not driven or self.ctrl is None:
            return refine_waypoints(
                wps, self.cost, self.grid, initial_heading_rad=heading,
                options=self.refine_options, deadline=deadline,
                evaluate=self._refine_evaluate(heading),
            )  # fmt: skip
        start = self.grid.terrain_names[int(self.grid.terrain_id_at(wps[:1])[0])]
        min_leg = float(controlled_turns(self.cost.params(start), self.ctrl).legs_m[0])

        def as_driven(w: FloatArray) -> PathCost:
            return self.driven(w, heading)

        merged = self.drop_short_legs(wps, min_leg)
        if float(np.hypot(*np.diff(merged[1:], axis=0).T).min(initial=math.inf)) < min_leg:
            full = self._refine_evaluate(heading)
            if full is not None:
                pc = full(merged)
            else:
                pc = path_cost(
                    merged, self.cost.vehicle, self.cost.speed_mps, world=self.grid,
                    initial_heading_rad=heading, turn=self.cost.turn, ramps=self.cost.ramps,
                    elevation=self.cost.elevation,
                )  # fmt: skip
            return RefineResult(merged, pc, 0, merged.shape != wps.shape)
        many = None
        if self._drive is not None:
            drive = self._drive

            def many(ws: list[FloatArray]) -> list[PathCost]:
                return drive.many(ws, heading)

        res = refine_waypoints(
            merged, self.cost, self.grid, initial_heading_rad=heading,
            options=self.refine_options, deadline=deadline, driven=as_driven,
            driven_many=many, min_leg_m=min_leg, min_gain=_DRIVEN_GAIN,
            evaluate=self._refine_evaluate(heading),
        )  # fmt: skip
        if res.improved or merged.shape == wps.shape:
            return res
        return RefineResult(merged, res.cost, res.evaluations, True)  # judged by pick

    def drop_short_legs(self, wps: FloatArray, min_leg_m: float) -> FloatArray:
        """Drop waypoints of legs (after the first) shorter than ``min_leg_m`` where free.

        The controller switches to the next way point ``d_th`` early and cannot follow
        such legs; the driven refinement tries no candidate with one
        (:func:`~ecoplan.planning.refine.refine_waypoints` ``min_leg_m``), so a route
        with two of them could not be refined.  Shortest leg first, its end (or else its
        start) is dropped when the segment that replaces it is free on the grid.
        """
        w = wps
        while len(w) > 2:
            legs = np.hypot(*np.diff(w, axis=0).T)
            short = [k for k in np.argsort(legs[1:]) + 1 if legs[k] < min_leg_m]
            for k in short:
                drops = [i for i in (k + 1, k) if 0 < i < len(w) - 1]
                i = next((i for i in drops if self.grid.segment_free(w[i - 1], w[i + 1])), -1)
                if i > 0:
                    w = np.delete(w, i, axis=0)
                    break
            else:
                return w
        return w

    def polish(
        self, raw: FloatArray, heading: float | None, deadline: Deadline, *, driven: bool
    ) -> tuple[list[Candidate], float, float]:
        """Smoothing passes and refinement while time remains.

        Every smoothing stage is evaluated in full.  Statically, the best stage (feasible
        first, then the objective) is kept, so smoothing never loses, and refined.  As
        driven (``driven``), every stage is returned as a candidate for :meth:`pick`,
        whose roll-outs rank them, and the last one is refined: ranking the lattice's own
        route as driven needs a roll-out of its own (its legs are shorter than the corner
        tables reach), and the pick rolls it out in the same batch as the other routes
        for little more.  Returns the stages kept, then the refined route if the
        refinement improved it (each with its evaluation), and the smoothing and
        evaluation times [s].
        """
        t0 = deadline.elapsed_s
        stages = [(raw, self.evaluate(raw, heading))]
        t_eval, t_smooth = deadline.elapsed_s - t0, 0.0
        for _ in range(self.passes):
            if deadline.expired:
                break
            t0 = deadline.elapsed_s
            stage = self.smoother.shortcut(stages[-1][0])
            t1 = deadline.elapsed_s
            stages.append((stage, self.evaluate(stage, heading)))
            t_smooth, t_eval = t_smooth + t1 - t0, t_eval + deadline.elapsed_s - t1
        out = stages
        if not driven:
            out = [min(stages, key=lambda c: self.rank(c[1]))]  # the first of equals
        if self.refine_options is not None and self.weights is None and not deadline.expired:
            t0 = deadline.elapsed_s
            ref = self.refine(out[-1][0], heading, deadline, driven=driven)
            t_smooth += deadline.elapsed_s - t0
            if ref.improved:
                out.append((ref.waypoints, ref.cost))
        return out, t_smooth, t_eval

    def pick(self, cands: list[Candidate], heading: float | None, deadline: Deadline) -> Candidate:
        """The candidate route the controller drives cheapest, by roll-out.

        Feasible first, then the objective of the controller's roll-out
        (:meth:`rollout_values`: the simulator's physics, power on the terrain under the
        robot).  The corner tables cannot see where the controller's cut and overshot
        corners leave the polyline's terrain, and a refinement under them alone can trade
        real energy for model error; the roll-out settles it.  All candidates are rolled
        out at once (one batch in lockstep).  When the budget is spent before the pick,
        the last feasible candidate (the most refined route) is returned unrolled.
        """
        if len(cands) == 1:
            return cands[0]
        if deadline.expired:
            return next((c for c in reversed(cands) if c[1].feasible), cands[-1])
        values = self.rollout_values([w for w, _ in cands], heading)
        keys = [(not pc.feasible, val) for (_, pc), val in zip(cands, values, strict=True)]
        return cands[min(range(len(keys)), key=keys.__getitem__)]

    def rollout_values(self, routes: list[FloatArray], heading: float | None) -> list[float]:
        """Objective of each route as the controller drives it, rolled out (inf: never ends).

        The routes share their start (and its terrain); they are rolled out in one batch
        (:func:`drive_paths`), each then costed with the power on the terrain under the
        robot (:func:`~ecoplan.energy.trajectory.trajectory_cost`).
        """
        assert self.ctrl is not None
        yaws = [
            heading if heading is not None else math.atan2(w[1, 1] - w[0, 1], w[1, 0] - w[0, 0])
            for w in routes
        ]
        params = self.cost.params(self.grid.terrain_at(routes[0][:1])[0])
        out = []
        for w, yaw0, (t, vl, vr, done) in zip(
            routes, yaws, drive_paths(params, routes, self.ctrl, yaws, _ROLLOUT_DT_S), strict=True
        ):
            if not done or t.size < 2:
                out.append(math.inf)
                continue
            pose = (float(w[0, 0]), float(w[0, 1]), float(yaw0))
            pc = trajectory_cost(
                TrackTrajectory(t, vl, vr), self.cost.vehicle, world=self.grid, start_pose=pose
            )
            out.append(self.cost.value(pc))
        return out


def drive_paths(
    params: VehicleParams,
    paths: list[FloatArray],
    controller: HeadingController,
    yaws0_rad: list[float],
    dt_s: float,
) -> list[tuple[FloatArray, FloatArray, FloatArray, bool]]:
    """:func:`~ecoplan.energy.controlled.drive_path` of several paths in one roll-out.

    The runs are stepped in lockstep (one batch of :func:`~ecoplan.dynamics.rollout.rollout`,
    a run frozen once it stops), each with the time limit ``drive_path`` gives it (three
    times its travel time plus 60 s): per path, the same times, track speeds and
    completion as ``drive_path``.

    Parameters
    ----------
    params : TrackedParams or WheeledParams
        Vehicle (its kinematics and limits drive the motion).
    paths : list of ndarray, shape (n_i, 2)
        Each path: start, then the goals [m].
    controller : HeadingController
        Gains and set point.
    yaws0_rad : list of float
        Initial heading of each run [rad].
    dt_s : float
        Step [s].

    Returns
    -------
    list of (t, v_left, v_right, completed)
        Per path, as :func:`~ecoplan.energy.controlled.drive_path`.
    """
    k = len(paths)
    r_min = power_limited_radius(params, controller.speed_mps) if controller.power_limited else 0.0
    icr = IcrArrays.of([params.icr] * k, [params.top_track_speed_mps] * k)
    policy = WaypointFollower(
        [w[1:] for w in paths], [controller] * k, icr, [r_min] * k,
        [params.accel_max_mps2 * dt_s] * k,
    )  # fmt: skip
    starts = np.array([[w[0, 0], w[0, 1], y] for w, y in zip(paths, yaws0_rad, strict=True)])
    t_max = [
        3.0 * float(np.sum(np.hypot(*np.diff(w, axis=0).T))) / controller.speed_mps + 60.0
        for w in paths
    ]
    rows, end, finished = rollout([params] * k, policy, starts, dt_s, max(t_max))
    i_vl, i_vr = ROLLOUT_STATE.index("v_left"), ROLLOUT_STATE.index("v_right")
    out = []
    for i in range(k):
        n_max = max(math.ceil(t_max[i] / dt_s - 1e-9), 1)  # the steps drive_path allows
        done = bool(finished[i]) and int(end[i]) <= n_max
        e = int(end[i]) if done else n_max
        t = np.arange(e + 1, dtype=np.float64) * dt_s
        out.append((t, rows[: e + 1, i_vl, i].copy(), rows[: e + 1, i_vr, i].copy(), done))
    return out
