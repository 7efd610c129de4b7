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
        """:func:`refine_waypoints` of the route, as the controller drives it if ``driven``.

        As driven, legs (after the first) shorter than the corner tables reach are merged
        first (:meth:`drop_short_legs`).  When only the last leg stays short (the goal
        close behind a building's corner: it cannot be dropped), the route up to its last
        corner is refined and the last leg appended unchanged; the refinement does not
        see how the last corner's angle changes, so the result is a candidate for
        :meth:`pick` to judge by roll-out.  A route that keeps another short leg is
        returned unrefined (changed if merging changed it, for :meth:`pick` to judge):
        the refinement tries no candidate with such a leg, so it could only move that
        leg's ends, against a start value that needs a roll-out of its own (0.04 s steps,
        about 0.35 s on a 200 m site); on the 18 sites of ``benchmarks/lattice_scale.py``
        it kept none of those moves.
        """
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
        changed = merged.shape != wps.shape or not np.array_equal(merged, wps)
        legs = np.hypot(*np.diff(merged, axis=0).T)
        body = merged  # the part refined: all of it, or up to a short last leg
        if len(merged) > 3 and legs[-1] < min_leg <= float(legs[1:-1].min()):
            body = merged[:-1]
        if float(np.hypot(*np.diff(body[1:], axis=0).T).min(initial=math.inf)) < min_leg:
            return RefineResult(merged, self.evaluate(merged, heading), 0, changed)
        many = None
        if self._drive is not None:
            drive = self._drive

            def many(ws: list[FloatArray]) -> list[PathCost]:
                return drive.many(ws, heading)

        res = refine_waypoints(
            body, self.cost, self.grid, initial_heading_rad=heading,
            options=self.refine_options, deadline=deadline, driven=as_driven,
            driven_many=many, min_leg_m=min_leg, min_gain=_DRIVEN_GAIN,
        )  # fmt: skip
        if body is not merged:  # the short last leg, appended again
            out = np.vstack([res.waypoints, merged[-1:]]) if res.improved else merged
            return RefineResult(
                out, self.evaluate(out, heading), res.evaluations, res.improved or changed
            )
        if res.improved or not changed:
            return res
        return RefineResult(merged, res.cost, res.evaluations, True)  # judged by pick

    def drop_short_legs(self, wps: FloatArray, min_leg_m: float) -> FloatArray:
        """Merge or lengthen legs (after the first) shorter than ``min_leg_m`` where free.

        The controller switches to the next way point ``d_th`` early and cannot follow
        such legs; the driven refinement tries no candidate with one
        (:func:`~ecoplan.planning.refine.refine_waypoints` ``min_leg_m``), so a route
        that keeps one is not refined as driven.  Shortest leg first, its end (or else
        its start) is dropped when the segment that replaces it is free on the grid;
        where neither is, its two corners merge into one where their outer legs meet
        (:meth:`merge_corners`), or else one of its ends slides along its other leg
        until the short leg is ``min_leg_m`` long (:meth:`slide_short_leg`).  Each step
        removes a way point or a short leg, so the loop ends.
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
                fixed = self.merge_corners(w, int(k), min_leg_m)
                if fixed is None:
                    fixed = self.slide_short_leg(w, int(k), min_leg_m)
                if fixed is not None:
                    w = fixed
                    break
            else:
                return w
        return w

    def merge_corners(self, wps: FloatArray, k: int, reach_m: float) -> FloatArray | None:
        """Replace the two corners of leg ``k`` by one where legs ``k - 1`` and ``k + 1`` meet.

        With way points ``a, b, c, d`` at ``k - 1 .. k + 2``, the point ``x = a + t (b - a)
        = c + s (d - c)`` with ``t >= 1`` and ``s <= 0`` lies beyond ``b`` on the incoming
        leg and before ``c`` on the outgoing one: the two corners of a route hugging a
        convex obstacle corner (which the lattice turns in heading steps), blunted into
        one on their outer side.  Only the extensions ``b -> x`` and ``x -> c`` are new
        ground; they must be free and each at most ``reach_m`` long.  The legs to ``x``
        are longer than those they replace, so no leg becomes short.  ``None``: the legs
        do not meet there (parallel, or an S-bend), or the extensions are blocked.
        """
        if not 1 <= k < len(wps) - 2:
            return None
        a, b, c, d = wps[k - 1 : k + 3]
        u, v, r = b - a, d - c, c - a
        den = float(u[0] * v[1] - u[1] * v[0])
        if abs(den) < 1e-12:
            return None
        t = float(r[0] * v[1] - r[1] * v[0]) / den
        s = float(r[0] * u[1] - r[1] * u[0]) / den
        x = a + t * u
        if t < 1.0 or s > 0.0 or max(np.hypot(*(x - b)), np.hypot(*(x - c))) > reach_m:
            return None
        if not (self.grid.segment_free(b, x) and self.grid.segment_free(x, c)):
            return None
        return np.vstack([wps[:k], x, wps[k + 2 :]])

    def slide_short_leg(self, wps: FloatArray, k: int, min_leg_m: float) -> FloatArray | None:
        """Lengthen leg ``k`` (way points ``k -> k + 1``) to ``min_leg_m`` by sliding one end.

        Way point ``k`` moves back along leg ``k - 1``, or way point ``k + 1`` on along
        leg ``k + 1`` (never the start or the goal), by the smallest multiple of the grid
        resolution that makes leg ``k`` at least ``min_leg_m`` long on a free segment
        while the leg it shortens keeps ``min_leg_m`` (the first leg: one resolution).
        The moved point stays on its leg, so only the new leg ``k`` needs the collision
        check; no leg becomes short, so :meth:`drop_short_legs` ends.  At a building's
        corner, where the lattice leaves a short leg and neither of its ends can be
        dropped, this blunts the two corners into a driveable pair.  ``None``: no slide
        fits.
        """
        res, n = self.grid.resolution_m, len(wps)
        best: tuple[float, FloatArray] | None = None
        for moved, anchor, toward in ((k, k + 1, k - 1), (k + 1, k, k + 2)):
            if not (0 < moved < n - 1 and 0 <= toward < n):
                continue
            p, q = wps[moved], wps[toward]
            length = float(np.hypot(*(q - p)))
            keep = res if min(moved, toward) == 0 else min_leg_m  # the leg it shortens
            s = res * np.arange(1, math.floor((length - keep) / res) + 1)
            if s.size == 0:
                continue
            pts = p + s[:, None] * ((q - p) / length)
            ok = np.hypot(*(pts - wps[anchor]).T) >= min_leg_m
            for j in np.flatnonzero(ok):
                if best is not None and s[j] >= best[0]:
                    break
                if self.grid.segment_free(pts[j], wps[anchor]):
                    w = wps.copy()
                    w[moved] = pts[j]
                    best = (float(s[j]), w)
                    break
        return None if best is None else best[1]

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
