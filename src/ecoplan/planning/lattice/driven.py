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

import numpy as np

from ecoplan._typing import FloatArray
from ecoplan.dynamics.controller import HeadingController
from ecoplan.energy.controlled import controlled_turns, drive_path
from ecoplan.energy.driven_path import DrivenPathCost
from ecoplan.energy.objective import CostObjective
from ecoplan.energy.path import path_cost
from ecoplan.energy.result import PathCost
from ecoplan.energy.trajectory import TrackTrajectory, trajectory_cost
from ecoplan.geometry.maps import GridMap
from ecoplan.planning.base import Deadline
from ecoplan.planning.lattice.primitives import PenaltyWeights
from ecoplan.planning.lattice.smooth import Smoother
from ecoplan.planning.refine import RefineOptions, RefineResult, refine_waypoints

__all__ = ["Candidate", "RouteFinisher"]

# a route refined for a controller must be estimated cheaper by more than the controlled
# model's error (as the graph planner's refinement)
_DRIVEN_GAIN = 0.01
# step of the controller roll-outs that pick among routes [s]: on the Husky's 60 m sites of
# benchmarks/sites.py within 0.01 % of the simulator at 0.01 s
_ROLLOUT_DT_S = 0.1
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
        if controller is not None and cost.elevation is None:
            self._drive = DrivenPathCost(
                cost.vehicle, cost.speed_mps, controller, world=grid, max_pieces=_MAX_PIECES
            )

    def rank(
        self, wps: FloatArray, pc: PathCost, heading: float | None, *, driven: bool
    ) -> tuple[bool, float]:
        """Sort key of an evaluated path: feasible first, then the search objective.

        ``driven``: the objective of the path as the controller drives it (:meth:`driven`).
        """
        if self.weights is not None:  # the penalty baseline ranks by its own costs
            value = pc.length_m + self.weights.turn_per_rad * pc.psi_rad
        elif driven:
            value = self.cost.value(self.driven(wps, heading))
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
        """The full evaluation of a route with the cost object's turn model."""
        return path_cost(
            wps,
            self.cost.vehicle,
            self.cost.speed_mps,
            world=self.grid,
            initial_heading_rad=heading,
            turn=self.cost.turn,
            ramps=self.cost.ramps,
        )

    def refine(
        self, wps: FloatArray, heading: float | None, deadline: Deadline, *, driven: bool
    ) -> RefineResult:
        """:func:`refine_waypoints` of the route, as the controller drives it if ``driven``."""
        if not driven or self.ctrl is None:
            return refine_waypoints(
                wps, self.cost, self.grid, initial_heading_rad=heading,
                options=self.refine_options, deadline=deadline,
            )  # fmt: skip
        start = self.grid.terrain_names[int(self.grid.terrain_id_at(wps[:1])[0])]
        min_leg = float(controlled_turns(self.cost.params(start), self.ctrl).legs_m[0])

        def as_driven(w: FloatArray) -> PathCost:
            return self.driven(w, heading)

        merged = self.drop_short_legs(wps, min_leg)
        res = refine_waypoints(
            merged, self.cost, self.grid, initial_heading_rad=heading,
            options=self.refine_options, deadline=deadline, driven=as_driven,
            min_leg_m=min_leg, min_gain=_DRIVEN_GAIN,
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

        Every smoothing stage is evaluated in full and the best (feasible first, then the
        objective, as driven when ``driven``) is kept, so smoothing never loses.  Returns
        that stage, then the refined route if the refinement improved it (each with its
        evaluation), and the smoothing and evaluation times [s].
        """
        t0 = deadline.elapsed_s
        wps, pc = raw, self.evaluate(raw, heading)
        t_eval, t_smooth = deadline.elapsed_s - t0, 0.0
        best_key = self.rank(raw, pc, heading, driven=driven)
        stage = raw
        for _ in range(self.passes):
            if deadline.expired:
                break
            t0 = deadline.elapsed_s
            stage = self.smoother.shortcut(stage)
            t1 = deadline.elapsed_s
            pc_stage = self.evaluate(stage, heading)
            t_smooth, t_eval = t_smooth + t1 - t0, t_eval + deadline.elapsed_s - t1
            key = self.rank(stage, pc_stage, heading, driven=driven)
            if key < best_key:
                wps, pc, best_key = stage, pc_stage, key
        out = [(wps, pc)]
        if self.refine_options is not None and self.weights is None and not deadline.expired:
            t0 = deadline.elapsed_s
            ref = self.refine(wps, heading, deadline, driven=driven)
            t_smooth += deadline.elapsed_s - t0
            if ref.improved:
                out.append((ref.waypoints, ref.cost))
        return out, t_smooth, t_eval

    def pick(self, cands: list[Candidate], heading: float | None, deadline: Deadline) -> Candidate:
        """The candidate route the controller drives cheapest, by roll-out.

        Feasible first, then the objective of the controller's roll-out
        (:meth:`rollout_value`: the simulator's physics, power on the terrain under the
        robot).  The corner tables cannot see where the controller's cut and overshot
        corners leave the polyline's terrain, and a refinement under them alone can trade
        real energy for model error; the roll-out settles it.  Candidates are rolled out
        in order while the budget lasts (at least the first).
        """
        keys: list[tuple[bool, float]] = []
        for k, (w, pc) in enumerate(cands):
            if k > 0 and deadline.expired:
                break
            keys.append((not pc.feasible, self.rollout_value(w, heading)))
        return cands[min(range(len(keys)), key=keys.__getitem__)]

    def rollout_value(self, wps: FloatArray, heading: float | None) -> float:
        """Objective of the route as the controller drives it, rolled out (inf: never ends)."""
        assert self.ctrl is not None
        yaw0 = heading
        if yaw0 is None:
            yaw0 = math.atan2(float(wps[1, 1] - wps[0, 1]), float(wps[1, 0] - wps[0, 0]))
        params = self.cost.params(self.grid.terrain_at(wps[:1])[0])
        t, vl, vr, done = drive_path(params, wps, self.ctrl, yaw0, _ROLLOUT_DT_S)
        if not done or t.size < 2:
            return math.inf
        pose = (float(wps[0, 0]), float(wps[0, 1]), yaw0)
        traj = TrackTrajectory(t, vl, vr)
        return self.cost.value(
            trajectory_cost(traj, self.cost.vehicle, world=self.grid, start_pose=pose)
        )
