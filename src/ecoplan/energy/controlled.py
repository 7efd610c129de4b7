"""Corners as the heading controller drives them: energy tabulated with the simulator's physics.

The static primitives (:mod:`ecoplan.energy.primitives`) cost a turn as a steady motion
reached instantly.  The heading controller of the tracked paper (§IV, eq. 23) does
something else at a corner: it switches to the next way point ``d_th`` early, turns at
``w = G phi_e`` (saturated, eqs. 5-6) while the forward speed drops, and converges on the
new leg over several time constants ``1 / G``; it starts from rest and stops ``d_th``
before the last way point, under the drive law's acceleration limit.

This module measures those effects once per (vehicle, controller, speed, step) with the
same time-domain physics as the simulator (:func:`ecoplan.dynamics.rollout.rollout`, the
heading controller and the drive law of :mod:`ecoplan.dynamics`), on canonical runs, all
in one batch:

* a **corner** run: a leg of ``L``, a heading change ``dpsi``, a leg of ``l`` (the
  controller aims at its end, so short legs are steered at more sharply), then ``L`` more
  in the same direction; against an aligned straight run of the same length ``2 L + l``:
  the *corner excess* of ``(dpsi, l)`` (net of the corner the controller cuts);
* a **last corner** run: the same without the ``L`` after ``l``, where the robot stops
  (``d_th`` before the goal) while still converging; against a straight ``L + l``;
* a run that **starts misaligned** by ``dpsi`` with a first leg of ``l``, then ``L`` on
  (or stops at ``l``: a one-segment path); against the straight run minus ``L`` of
  steady driving;
* the straight run of ``3 L`` from rest to rest against ``3 L`` of steady driving: the
  *ends* (start ramp, early stop).

``L = max(10 m, 8 v / G) + d_th`` (the heading error decays as ``exp(-G t)``: 8 time
constants of driving); ``l`` on 7 geometric steps from ``max(1.5 d_th, v / G)`` to ``L``
(``d_th`` as widened for power-limited turning).  Below the turning radius ``v / G``,
eq. (23) at a constant set point can orbit a goal; the default slow-down reaches it (see
:mod:`ecoplan.dynamics.controller`), but tables started at ``1.5 d_th`` measured worse
than rolling such paths out (48.8 % against 78.8 % of short-legged Auriga-beta paths
within 3 %), so paths with a leg after the first below ``v / G`` are rolled out
(:func:`drive_path`).  ``dpsi`` every 11.25 degrees (only ``|dpsi|`` for left-right
symmetric vehicles).  Excesses are interpolated bilinearly in ``(dpsi, log l)``, clamped
at the table's edges.

Corners closer than ``L`` overlap: the controller meets the second corner still turning
out of the first (a residual heading error, a lower speed), and two same-way corners are
cut as one.  :func:`corner_pairs` tabulates that interaction once: a **pair** run (a
lead-in, ``dpsi_in``, a leg ``l < L``, ``dpsi_out``, then ``L``) minus its aligned
straight run and its two isolated corner excesses, every 22.5 degrees in both angles and
on the same legs (zero at ``L``), interpolated trilinearly.

A path's energy is then its straight driving plus its corners', pairs' and ends'
excesses (:func:`ecoplan.energy.path.path_cost` with ``turn=controller``).  This is a
model, not a rollout of the path: about 1400 canonical runs once per (vehicle, terrain,
controller), 5-10 s, the pairs only when a path has corners closer than ``L``; then
table look-ups, about a millisecond per path.  Where it errs:

* three or more corners within ``L`` of each other (only neighbouring pairs are
  corrected; the third corner's effect on the first is missed): on random paths whose
  legs are all 1.6-8 m, 85 % of the Auriga-beta paths costed from the tables are within
  3 % (worst -10.7 %), 71 % of the Pioneer's (most of its paths are rolled out there;
  ``benchmarks/analytic_vs_sim.py --legs 1.6 8``);
* interpolation between the grid angles and legs;
* a pair whose second corner is the path's last (its correction assumes driving on);
* terrain changes inside a corner: the excess is a blend of the tables of the terrains
  the controller turns on, and :func:`ecoplan.energy.path.path_cost` charges straight
  driving on the terrains of the track it drives (:mod:`ecoplan.energy.swept`).

Measured against the simulator on 200 random polylines per vehicle
(``benchmarks/analytic_vs_sim.py``; README) and on the shipped scenarios
(``tests/test_scenarios_shipped.py``).
"""

from __future__ import annotations

import functools
import math
from dataclasses import dataclass

import numpy as np
from numpy.typing import NDArray

from ecoplan._typing import FloatArray, IntArray
from ecoplan.dynamics.controller import HeadingController, WaypointFollower, power_limited_radius
from ecoplan.dynamics.drive import IcrArrays
from ecoplan.dynamics.rollout import ROLLOUT_STATE, rollout
from ecoplan.energy.primitives import VehicleParams
from ecoplan.models.kinematics import tracks_to_twist
from ecoplan.models.limits import check_tracks
from ecoplan.models.power import COMPONENTS

__all__ = [
    "ORBIT",
    "ControlledTurns",
    "CornerPairs",
    "Excess",
    "blend_excess",
    "controlled_turns",
    "corner_pairs",
    "drive_path",
]

#: Constraint name of a corner or start the heading controller never completes: the next
#: way point lies inside its turning circle and it circles it (tracked paper eq. 23).
ORBIT = "controller_orbits_goal"

_N_ANGLES = 17  # per sign, 0..pi (11.25 degrees apart)
_CHUNK = 128  # runs per rollout batch
_N_LEGS = 7  # leg lengths, geometric from the shortest to the settled one
_DT_S = 0.04


@dataclass(frozen=True, slots=True)
class Excess:
    """What a canonical run costs beyond the steady straight driving it replaces.

    Attributes
    ----------
    energy_j : float
        Energy excess [J] (negative when the controller saves driving).
    breakdown_j : dict
        Energy excess per power component [J].
    duration_s : float
        Time excess [s].
    length_m : float
        Driven-distance excess [m] (negative where a corner is cut).
    psi_rad : float
        Steered angle ``integral |w| dt`` of the run [rad] (tracked eq. 11).
    peak_power_w : float
        Largest total power in the run [W].
    violated : str
        First vehicle limit a sample of the run breaks; ``""`` if none.
    """

    energy_j: float
    breakdown_j: dict[str, float]
    duration_s: float
    length_m: float
    psi_rad: float
    peak_power_w: float
    violated: str


@dataclass(frozen=True, eq=False)
class ControlledTurns:
    """Excess tables of one vehicle under one controller (see the module docstring).

    Attributes
    ----------
    angles_rad : ndarray
        Heading changes of the table [rad], increasing (``0 .. pi`` when the vehicle is
        left-right symmetric and tables are mirrored, else ``-pi .. pi``).
    legs_m : ndarray
        Lengths of the leg after the corner (or of the first leg) [m], increasing; the
        last is the settled length ``L``.
    corner, last, initial, initial_last : ndarray, shape (n_angles, n_legs, 5 + n_components)
        Per angle and leg: energy [J], duration [s], length [m], psi [rad], peak power [W],
        then the energy per component [J], for a corner, for the last corner of a path
        (its leg ends at the goal), for a misaligned start, and for a misaligned start
        on a one-segment path.
    corner_violated, last_violated, initial_violated, initial_last_violated : ndarray
        Per angle and leg, the first limit broken ("" if none; :data:`ORBIT`).
        The first limit broken ("" if none).
    ends : Excess
        Start from rest and stop ``d_th`` early, on a straight.
    symmetric : bool
        True when the tables hold ``|dpsi|`` only.
    """

    angles_rad: FloatArray
    legs_m: FloatArray
    corner: FloatArray
    last: FloatArray
    initial: FloatArray
    initial_last: FloatArray
    corner_violated: NDArray[np.object_]
    last_violated: NDArray[np.object_]
    initial_violated: NDArray[np.object_]
    initial_last_violated: NDArray[np.object_]
    ends: Excess
    symmetric: bool

    def _lookup(
        self, table: FloatArray, names: NDArray[np.object_], dpsi: float, leg_m: float
    ) -> Excess:
        i, wa = _cell(self.angles_rad, abs(dpsi) if self.symmetric else dpsi)
        j, wl = _cell(np.log(self.legs_m), math.log(max(leg_m, 1e-9)))
        row = (1.0 - wa) * ((1.0 - wl) * table[i, j] + wl * table[i, j + 1]) + wa * (
            (1.0 - wl) * table[i + 1, j] + wl * table[i + 1, j + 1]
        )
        near = (i if wa < 0.5 else i + 1, j if wl < 0.5 else j + 1)
        violated = str(names[near])
        return Excess(
            energy_j=float(row[0]),
            breakdown_j={c: float(row[5 + k]) for k, c in enumerate(COMPONENTS)},
            duration_s=float(row[1]),
            length_m=float(row[2]),
            psi_rad=float(row[3]),
            peak_power_w=float(table[near][4]),
            violated=violated,
        )

    def corner_excess(
        self, dpsi_rad: float, leg_out_m: float = math.inf, *, last: bool = False
    ) -> Excess:
        """Excess of a corner with heading change ``dpsi`` (left positive) [J, s, m].

        ``leg_out_m``: length of the leg after the corner (the controller aims at its end);
        ``last``: that leg ends at the goal, where the robot stops.
        """
        if last:
            return self._lookup(self.last, self.last_violated, dpsi_rad, leg_out_m)
        return self._lookup(self.corner, self.corner_violated, dpsi_rad, leg_out_m)

    def initial_excess(
        self, dpsi_rad: float, leg_m: float = math.inf, *, last: bool = False
    ) -> Excess:
        """Excess of a start misaligned by ``dpsi`` with a first leg of ``leg_m``.

        ``last``: that leg ends at the goal (a one-segment path).
        """
        if last:
            return self._lookup(self.initial_last, self.initial_last_violated, dpsi_rad, leg_m)
        return self._lookup(self.initial, self.initial_violated, dpsi_rad, leg_m)


def _leg_m(controller: HeadingController, speed_mps: float) -> float:
    return max(10.0, 8.0 * speed_mps / controller.gain) + controller.switch_radius_m


@functools.lru_cache(maxsize=64)
def controlled_turns(
    params: VehicleParams, controller: HeadingController, dt_s: float = _DT_S
) -> ControlledTurns:
    """Tabulate a controller's corner, start and stop excesses for one vehicle (cached).

    Parameters
    ----------
    params : TrackedParams or WheeledParams
        Vehicle on one terrain.
    controller : HeadingController
        Gain, set point (its ``speed_mps``) and switching radius.
    dt_s : float
        Step of the rollouts [s] (default 0.04: against the simulator at 0.01 s the
        corner excesses agree within 0.3 % of the run's energy).

    Returns
    -------
    ControlledTurns
        The tables.
    """
    v = controller.speed_mps
    leg = _leg_m(controller, v)
    icr0 = params.icr
    symmetric = icr0.x_m == 0.0 and abs(icr0.y_left_m + icr0.y_right_m) < 1e-12
    half = np.linspace(0.0, math.pi, _N_ANGLES)
    angles = half if symmetric else np.concatenate([-half[:0:-1], half])
    # shortest leg: a goal closer than the turning radius v / (G phi) can be orbited forever
    r_min = power_limited_radius(params, v) if controller.power_limited else 0.0
    d_switch = max(controller.switch_radius_m, 1.5 * r_min)  # as the follower widens it
    leg = leg + d_switch - controller.switch_radius_m
    leg_min = min(max(1.5 * d_switch, v / controller.gain), 0.5 * leg)
    legs = np.geomspace(leg_min, leg, _N_LEGS)
    na, nl = angles.size, legs.size
    aa, ll = (g.ravel() for g in np.meshgrid(angles, legs, indexing="ij"))
    m = aa.size
    goals: list[FloatArray] = []
    starts = np.zeros((4 * m + 2 * nl, 3))
    for a, lo in zip(aa, ll, strict=True):  # corners: leg in, lo at angle a, then leg on
        u = np.array([math.cos(a), math.sin(a)])
        goals.append(np.array([[leg, 0.0], [leg, 0.0] + lo * u, [leg, 0.0] + (lo + leg) * u]))
    for a, lo in zip(aa, ll, strict=True):  # last corners: leg in, lo at angle a, stop
        u = np.array([math.cos(a), math.sin(a)])
        goals.append(np.array([[leg, 0.0], [leg, 0.0] + lo * u]))
    for k, (a, lo) in enumerate(zip(aa, ll, strict=True)):  # misaligned starts, then on
        goals.append(np.array([[lo, 0.0], [lo + leg, 0.0]]))
        starts[2 * m + k, 2] = -a
    for k, (a, lo) in enumerate(zip(aa, ll, strict=True)):  # misaligned starts, stop at lo
        goals.append(np.array([[lo, 0.0]]))
        starts[3 * m + k, 2] = -a
    for lo in legs:  # straight references: leg + lo + leg, aligned
        goals.append(np.array([[leg + lo + leg, 0.0]]))
    for lo in legs:  # and leg + lo
        goals.append(np.array([[leg + lo, 0.0]]))
    t_max = 2.5 * 3.0 * leg / v + 30.0
    stats, violated, finished = _run_batch(params, controller, goals, starts, dt_s, t_max)
    long_ref = np.tile(stats[4 * m : 4 * m + nl], (na, 1))  # leg + lo + leg per (angle, lo)
    short_ref = np.tile(stats[4 * m + nl :], (na, 1))  # leg + lo
    per_m = float(params.power(v, v).total_w) / v
    comps = params.power(v, v).components()
    steady = np.array([per_m, 1.0 / v, 1.0, 0.0, 0.0, *(float(comps[c]) / v for c in COMPONENTS)])
    parts = (slice(0, m), slice(m, 2 * m), slice(2 * m, 3 * m), slice(3 * m, 4 * m))
    # the misaligned start of lo (+ leg) against the aligned leg + lo (+ leg) minus a leg
    refs = (long_ref, short_ref, long_ref - leg * steady, short_ref - leg * steady)
    tables = []
    for part, ref in zip(parts, refs, strict=True):
        tab = stats[part] - ref
        tab[:, 3:5] = stats[part][:, 3:5]  # psi and peak are the run's own, not excesses
        t3 = tab.reshape(na, nl, -1)
        ok2 = finished[part].reshape(na, nl).copy()
        n2 = violated[part].reshape(na, nl).copy()
        # a run that never reached its goal (it orbits it: the goal lies inside its turning
        # circle) is flagged and takes the next longer leg's values
        n2[~ok2] = ORBIT
        for j in range(nl - 2, -1, -1):
            t3[~ok2[:, j], j] = t3[~ok2[:, j], j + 1]
            ok2[:, j] |= ok2[:, j + 1]
        tables.append((t3, n2))
    straight = stats[4 * m + nl - 1]  # leg + leg + leg aligned
    ends_row = straight - 3.0 * leg * steady
    ends = Excess(
        energy_j=float(ends_row[0]),
        breakdown_j={c: float(ends_row[5 + k]) for k, c in enumerate(COMPONENTS)},
        duration_s=float(ends_row[1]),
        length_m=float(ends_row[2]),
        psi_rad=float(straight[3]),
        peak_power_w=float(straight[4]),
        violated=str(violated[4 * m + nl - 1]),
    )
    return ControlledTurns(
        angles,
        legs,
        tables[0][0],
        tables[1][0],
        tables[2][0],
        tables[3][0],
        tables[0][1],
        tables[1][1],
        tables[2][1],
        tables[3][1],
        ends,
        symmetric,
    )


@dataclass(frozen=True, eq=False)
class CornerPairs:
    """Interaction of two corners closer than the controller settles (module docstring).

    Attributes
    ----------
    angles_in_rad : ndarray
        Heading changes of the first corner [rad], increasing (``0 .. pi`` when
        ``symmetric``, else ``-pi .. pi``).
    legs_m : ndarray
        Lengths of the leg between the corners [m]; the last is the settled length, where
        the correction is zero.
    angles_out_rad : ndarray
        Heading changes of the second corner [rad], ``-pi .. pi``.
    table : ndarray, shape (n_in, n_legs, n_out, 5 + n_components)
        What the pair costs beyond its two isolated corners: energy [J], duration [s],
        length [m], psi [rad], 0 (no peak), energy per component [J].
    symmetric : bool
        Mirror ``(dpsi_in, dpsi_out) -> (-dpsi_in, -dpsi_out)`` for negative ``dpsi_in``.
    """

    angles_in_rad: FloatArray
    legs_m: FloatArray
    angles_out_rad: FloatArray
    table: FloatArray
    symmetric: bool

    def correction(self, dpsi_in_rad: float, leg_m: float, dpsi_out_rad: float) -> Excess:
        """Excess of a pair beyond its isolated corners, trilinear in (in, log leg, out)."""
        a_in, a_out = dpsi_in_rad, dpsi_out_rad
        if self.symmetric and a_in < 0.0:
            a_in, a_out = -a_in, -a_out
        i, wi = _cell(self.angles_in_rad, a_in)
        j, wj = _cell(np.log(self.legs_m), math.log(max(leg_m, 1e-9)))
        k, wk = _cell(self.angles_out_rad, a_out)
        row = np.zeros(self.table.shape[-1])
        for di, fi in ((0, 1.0 - wi), (1, wi)):
            for dj, fj in ((0, 1.0 - wj), (1, wj)):
                for dk, fk in ((0, 1.0 - wk), (1, wk)):
                    row += fi * fj * fk * self.table[i + di, j + dj, k + dk]
        return Excess(
            energy_j=float(row[0]),
            breakdown_j={c: float(row[5 + n]) for n, c in enumerate(COMPONENTS)},
            duration_s=float(row[1]),
            length_m=float(row[2]),
            psi_rad=float(row[3]),
            peak_power_w=0.0,
            violated="",
        )


def blend_excess(excesses: list[Excess], weights: list[float]) -> Excess:
    """Weighted mean of the excesses of one corner on several terrains.

    Energies, times, lengths and angles are averaged with ``weights`` (summing to 1); the
    peak power is the largest and the violation that of the heaviest terrain.
    """
    keys = excesses[0].breakdown_j
    heavy = excesses[int(np.argmax(weights))]
    return Excess(
        energy_j=sum(w * e.energy_j for w, e in zip(weights, excesses, strict=True)),
        breakdown_j={
            k: sum(w * e.breakdown_j[k] for w, e in zip(weights, excesses, strict=True))
            for k in keys
        },
        duration_s=sum(w * e.duration_s for w, e in zip(weights, excesses, strict=True)),
        length_m=sum(w * e.length_m for w, e in zip(weights, excesses, strict=True)),
        psi_rad=sum(w * e.psi_rad for w, e in zip(weights, excesses, strict=True)),
        peak_power_w=max(e.peak_power_w for e in excesses),
        violated=heavy.violated,
    )


def _cell(grid: FloatArray, x: float) -> tuple[int, float]:
    """Lower index and weight of ``x`` (clamped) on an increasing grid."""
    x = min(max(x, float(grid[0])), float(grid[-1]))
    i = max(min(int(np.searchsorted(grid, x, side="right")) - 1, grid.size - 2), 0)
    return i, (x - float(grid[i])) / float(grid[i + 1] - grid[i])


@functools.lru_cache(maxsize=64)
def corner_pairs(
    params: VehicleParams, controller: HeadingController, dt_s: float = _DT_S
) -> CornerPairs:
    """Tabulate how two close corners differ from their isolated excesses (cached).

    A pair run drives a lead-in (the switching radius, the drive law's ramp to ``v`` and
    2 m), turns by ``dpsi_in``, drives ``l``, turns by ``dpsi_out`` and drives ``L``; its
    correction is its energy (and time, length, psi) minus the aligned straight run of
    the same length and the two isolated corner excesses of
    :func:`controlled_turns` (``(dpsi_in, l)`` and ``(dpsi_out, L)``).  Angles every 22.5
    degrees (grid points of the corner tables), legs those of the corner tables below
    ``L`` (zero at ``L``, where the first corner has settled).  A pair the controller
    never completes (a goal orbited under ``slowdown_heading_rad=None``) is given 0.

    Parameters
    ----------
    params : TrackedParams or WheeledParams
        Vehicle on one terrain.
    controller : HeadingController
        Gain, set point and switching radius.
    dt_s : float
        Step of the rollouts [s].

    Returns
    -------
    CornerPairs
        The correction table.
    """
    # called as path_cost calls it when dt_s is the default: the cache keys on the
    # arguments as given, and a third positional one would tabulate everything again
    if dt_s == _DT_S:
        single = controlled_turns(params, controller)
    else:
        single = controlled_turns(params, controller, dt_s)
    v = controller.speed_mps
    leg = float(single.legs_m[-1])
    a_in = single.angles_rad[::2]
    a_out = np.linspace(-math.pi, math.pi, 2 * (_N_ANGLES // 2) + 1)
    legs = single.legs_m[:-1]
    grid = [(a1, lo, a2) for a1 in a_in for lo in legs for a2 in a_out]
    # lead-in: enough to reach the set point (the drive law's ramp) before the switch
    r_min = power_limited_radius(params, v) if controller.power_limited else 0.0
    d_switch = max(controller.switch_radius_m, 1.5 * r_min)
    lead = d_switch + v * v / (2.0 * params.accel_max_mps2) + 2.0
    goals: list[FloatArray] = []
    for a1, lo, a2 in grid:
        p1 = np.array([lead, 0.0])
        p2 = p1 + lo * np.array([math.cos(a1), math.sin(a1)])
        p3 = p2 + leg * np.array([math.cos(a1 + a2), math.sin(a1 + a2)])
        goals.append(np.array([p1, p2, p3]))
    goals += [np.array([[lead + lo + leg, 0.0]]) for lo in legs]  # straight references
    t_max = 2.5 * 2.0 * leg / v + 60.0
    starts = np.zeros((len(goals), 3))
    stats, _, finished = _run_batch(
        params, controller, goals, starts, dt_s, t_max, 256, check_limits=False
    )
    n = len(grid)
    ref = np.tile(stats[n:], (a_in.size, 1))  # per (a_in, leg), repeated over a_out below
    first = np.array([_table_row(single, single.corner, a1, lo) for a1, lo, _ in grid])
    second = np.array([_table_row(single, single.corner, a2, leg) for *_, a2 in grid])
    out = stats[:n] - np.repeat(ref, a_out.size, axis=0) - first - second
    out[:, 3] = stats[:n, 3] - first[:, 3] - second[:, 3]  # psi: the runs' own
    out[:, 4] = 0.0
    out[~finished[:n]] = 0.0
    table = np.zeros((a_in.size, single.legs_m.size, a_out.size, stats.shape[1]))
    table[:, :-1] = out.reshape(a_in.size, legs.size, a_out.size, -1)
    return CornerPairs(a_in, single.legs_m, a_out, table, single.symmetric)


def _table_row(single: ControlledTurns, table: FloatArray, dpsi: float, leg_m: float) -> FloatArray:
    """The row of a corner table at grid point ``(dpsi, leg_m)`` (mirrored if symmetric)."""
    x = abs(dpsi) if single.symmetric else dpsi
    i = int(np.argmin(np.abs(single.angles_rad - x)))
    j = int(np.argmin(np.abs(single.legs_m - leg_m)))
    row: FloatArray = table[i, j]
    return row


def _run_batch(
    params: VehicleParams,
    controller: HeadingController,
    goals: list[FloatArray],
    starts: FloatArray,
    dt_s: float,
    t_max: float,
    chunk_runs: int = _CHUNK,
    *,
    check_limits: bool = True,
) -> tuple[FloatArray, NDArray[np.object_], NDArray[np.bool_]]:
    """Roll canonical runs out in chunks: per run its stats, first violation, completion.

    ``check_limits=False`` skips the limit check (every violation is then ``""``).
    """
    r_min = power_limited_radius(params, controller.speed_mps) if controller.power_limited else 0.0
    stats_parts, violated_parts, finished_parts = [], [], []
    for c0 in range(0, len(goals), chunk_runs):  # chunks keep the recorded rows in memory
        chunk = goals[c0 : c0 + chunk_runs]
        k = len(chunk)
        runs = [params] * k
        icr = IcrArrays.of([p.icr for p in runs], [p.top_track_speed_mps for p in runs])
        policy = WaypointFollower(
            chunk, [controller] * k, icr, [r_min] * k, [params.accel_max_mps2 * dt_s] * k
        )
        rows, end, done = rollout(runs, policy, starts[c0 : c0 + k], dt_s, t_max)
        stats_parts.append(_chunk_stats(params, rows, end, dt_s))
        if check_limits:
            violated_parts += [_run_violation(params, rows, i, int(end[i])) for i in range(k)]
        else:
            violated_parts += [""] * k
        finished_parts.append(done)
        del rows
    return (
        np.concatenate(stats_parts),
        np.array(violated_parts, dtype=object),
        np.concatenate(finished_parts),
    )


def _chunk_stats(params: VehicleParams, rows: FloatArray, end: IntArray, dt: float) -> FloatArray:
    """Per run: energy, duration, length, psi, peak, then energy per component.

    Run ``i`` counts rows ``0 .. end[i] - 1`` (the batch's later rows are masked).
    """
    col = {name: rows[:, j, :] for j, name in enumerate(ROLLOUT_STATE)}
    vl, vr = col["v_left"], col["v_right"]
    live = np.arange(rows.shape[0])[:, None] < end[None, :]
    pw = params.power(vl, vr)
    tw = tracks_to_twist(vl, vr, params.icr)
    comps = pw.components()
    total = np.where(live, np.asarray(pw.total_w, dtype=np.float64), 0.0)
    peak = np.max(np.where(live, total, -np.inf), axis=0, initial=-np.inf)
    cols = [
        np.sum(total, axis=0) * dt,
        end * dt,
        np.sum(np.where(live, np.hypot(tw.vx, tw.vy), 0.0), axis=0) * dt,
        np.sum(np.where(live, np.abs(col["wz"]), 0.0), axis=0) * dt,
        np.where(np.isfinite(peak), peak, 0.0),
        *(np.sum(np.where(live, comps[c], 0.0), axis=0) * dt for c in COMPONENTS),
    ]
    out: FloatArray = np.column_stack(cols).astype(np.float64)
    return out


def _run_violation(params: VehicleParams, rows: FloatArray, i: int, end: int) -> str:
    vl = rows[:end, ROLLOUT_STATE.index("v_left"), i]
    vr = rows[:end, ROLLOUT_STATE.index("v_right"), i]
    bad = check_tracks(params, vl, vr).violated
    hit = [str(b) for b in np.ravel(bad) if b]
    return hit[0] if hit else ""


def drive_path(
    params: VehicleParams,
    waypoints: FloatArray,
    controller: HeadingController,
    yaw0_rad: float,
    dt_s: float = _DT_S,
) -> tuple[FloatArray, FloatArray, FloatArray, bool]:
    """Roll the heading controller out along one path (for paths the tables do not cover).

    Parameters
    ----------
    params : TrackedParams or WheeledParams
        Vehicle (its kinematics and limits drive the motion).
    waypoints : ndarray, shape (n, 2)
        Start, then the goals [m].
    controller : HeadingController
        Gains and set point.
    yaw0_rad : float
        Initial heading [rad].
    dt_s : float
        Step [s].

    Returns
    -------
    t, v_left, v_right : ndarray
        Sample times [s] and track speeds [m/s] until the robot stops.
    completed : bool
        False when the time limit (three times the path's travel time plus 60 s) was hit.
    """
    wps = np.asarray(waypoints, dtype=np.float64)
    length = float(np.sum(np.hypot(*np.diff(wps, axis=0).T)))
    r_min = power_limited_radius(params, controller.speed_mps) if controller.power_limited else 0.0
    icr = IcrArrays.of([params.icr], [params.top_track_speed_mps])
    policy = WaypointFollower([wps[1:]], [controller], icr, [r_min], [params.accel_max_mps2 * dt_s])
    start = np.array([[wps[0, 0], wps[0, 1], yaw0_rad]])
    t_max = 3.0 * length / controller.speed_mps + 60.0
    rows, end, finished = rollout([params], policy, start, dt_s, t_max)
    k = int(end[0])
    vl = rows[: k + 1, ROLLOUT_STATE.index("v_left"), 0].copy()
    vr = rows[: k + 1, ROLLOUT_STATE.index("v_right"), 0].copy()
    return np.arange(k + 1, dtype=np.float64) * dt_s, vl, vr, bool(finished[0])
