"""Energy lattice planner on occupancy grids (state lattice, hybrid-A* family).

States are ``(node, heading)``: nodes every ``cell_m`` on the map (at the centres of
fine grid cells), headings the 8 or 16 directions of the lattice (16: the directions to
the nodes ``(1, 0), (2, 1), (1, 1), (1, 2), ...`` — every straight step ends exactly on
a node).  Motion primitives from ``(n, h)``:

* **straight**: to ``(n + d_h, h)``; energy ``P_T(v, v) / v`` per metre of each terrain
  it crosses (tracked eq. 9 with ``w = 0``; wheeled eqs. 13-14), the terrain sampled at
  five points along the step;
* **turn left / right** to heading ``h ± 1``: the cheapest feasible execution of the
  heading change ``Δψ`` on the node's terrain at cruise speed ``v`` —
  :func:`ecoplan.energy.turns.turn_costs`: on the spot where the vehicle can (tracked eq. 20),
  else an arc of radius ``r`` feasible in ``(v, r)`` (power limits, wheeled §III-C and
  tracked eq. 5) — followed by ``m`` straight steps on the new heading, with ``m`` the
  smallest number whose length is at least twice the largest fillet tangent
  ``r tan(Δψ/2)`` of the terrain; every segment of the resulting polyline therefore has
  room for the arcs at both of its ends (spot turns: ``m = 0``).

Every primitive's cost is computed for all nodes at once with numpy when the planner is
built (:mod:`~ecoplan.planning.lattice.primitives`), collision-checked against the
**inflated fine grid** (:attr:`ecoplan.geometry.maps.GridMap.blocked`) through
precomputed fine-cell offsets sampled every quarter of a fine cell, read as strided
views of the grid (one per offset, no index arrays). A query runs A* from the start: the
heuristic is a 2-D Dijkstra from the goal over the straight steps alone (every
transition is a turn of cost >= 0 and straight steps, so it is an admissible and
consistent lower bound: terrain and obstacles included, turns left out), and the search
is scipy's Dijkstra (in C) on the transitions reweighted by the heuristic, limited to a
growing bound -- the states it settles are those A* expands, and the result is optimal
on the lattice (``tests/test_lattice.py`` checks it against plain Dijkstra). Any-angle
smoothing passes (:mod:`~ecoplan.planning.lattice.smooth`: string pulling on the grid)
follow while the time budget lasts; every stage is evaluated in full and the best one is
kept. The budget is checked between phases: the build is not part of a query's budget; a
query raises when the budget is spent before its search starts, and a search that ends
after the budget returns its path unsmoothed. The returned
:class:`~ecoplan.planning.base.Plan` carries the waypoints (heading changes of the
lattice path) and their full evaluation by :func:`ecoplan.energy.path.path_cost` on the
grid, like every planner.

**As driven.**  With ``LatticePlannerOptions(controller=HeadingController(...))`` the
corners are costed the way the tracked paper's heading controller (§IV, eq. 23) drives
them, not as steady primitives: a corner's first heading step costs the controller's
corner excess of that angle and each further step at the same node a slope through the
tables at a right angle
(:func:`~ecoplan.planning.lattice.primitives.driven_turn_costs`, from the tables of
:mod:`ecoplan.energy.controlled`).  A turn on the spot then leads into a second layer of
states (a corner under way at the node) whose further turns cost that slope, and
straight steps lead back; the heuristic is unchanged and stays a lower bound, every
turn costing >= 0.  The refinement is ranked by the energy as driven (its pieces --
start, corners, corner pairs, segments -- cached per planner,
:class:`~ecoplan.energy.driven_path.DrivenPathCost`, so a candidate that moves one way
point re-costs only its neighbourhood); every smoothing stage, the refined route and the
static lattice's routes (and those refined as driven) are candidates, and the pick is
the candidate whose controller roll-out (the simulator's physics, power on the terrain
under the robot; all candidates in one batch) is cheapest
(:mod:`~ecoplan.planning.lattice.driven`).

The search costs come from the cost objective's ``per_metre`` and ``turn_value``
(:class:`~ecoplan.energy.objective.EnergyCost`: joules;
:class:`~ecoplan.energy.objective.LengthCost`: metres, turns free but only feasible
ones), or from
:class:`PenaltyWeights` — length plus unitless turn and terrain penalties, the way Nav2's
Smac planners cost paths — for baselines.
"""

from ecoplan.planning.lattice.planner import LatticePlanner, LatticePlannerOptions, plan_lattice
from ecoplan.planning.lattice.primitives import PenaltyWeights, lattice_directions

__all__ = [
    "LatticePlanner",
    "LatticePlannerOptions",
    "PenaltyWeights",
    "lattice_directions",
    "plan_lattice",
]
