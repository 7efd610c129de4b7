"""The track the heading controller drives around corners, and the terrain under it.

References written here, independent of :mod:`ecoplan.energy.swept`:

* a **unicycle integration** of the heading controller's law (tracked paper §IV, eq. 23,
  with the slow-down for a goal abeam of :mod:`ecoplan.dynamics.controller`), explicit
  Euler at 1 ms;
* the **simulator** (:func:`ecoplan.sim.simulate.simulate_waypoints`: drive law, lag and
  all), its power recomputed per sample on the terrain under the robot.
"""

from __future__ import annotations

import itertools
import math

import numpy as np
import pytest
from hypothesis import given, settings
from hypothesis import strategies as st
from scipy.spatial import cKDTree

from ecoplan.dynamics.controller import HeadingController, power_limited_radius
from ecoplan.energy.path import path_cost
from ecoplan.energy.swept import steady_per_m, sweep_corner, swept_track, terrain_shift_j
from ecoplan.geometry.maps import GridMap
from ecoplan.presets import vehicle
from ecoplan.sim.simulate import simulate_waypoints
from test_lattice_driven import _simulated_j  # the simulator, power on the terrain under it

HUSKY = vehicle("husky-a200")
V = 0.5
CTRL = HeadingController(speed_mps=V)  # G = 0.18 1/s, d_th = 1 m, slow-down beyond 45 deg


def _unicycle(wps: np.ndarray, yaw0: float, dt: float = 1e-3) -> tuple[np.ndarray, np.ndarray]:
    """Times and positions of eq. (23) on a unicycle: w = G phi, v = v_sp min(1, cos phi / cos 45).

    The Husky's yaw rate (at most G pi = 0.57 rad/s) stays far below its top yaw rate
    (1 m/s / 0.52 m = 1.9 rad/s) and its forward speed below eq. (5)'s limit, so neither
    saturates here.
    """
    x, y, yaw, k, t = float(wps[0, 0]), float(wps[0, 1]), yaw0, 1, 0.0
    ts, xy = [0.0], [(x, y)]
    while True:
        gx, gy = wps[k]
        if math.hypot(gx - x, gy - y) < CTRL.switch_radius_m:
            if k == len(wps) - 1:
                return np.array(ts), np.array(xy)
            k += 1
            continue
        phi = math.remainder(math.atan2(gy - y, gx - x) - yaw, 2.0 * math.pi)
        v = V * min(max(math.cos(phi) / math.cos(math.pi / 4.0), 0.0), 1.0)
        x, y, yaw, t = (
            x + v * math.cos(yaw) * dt,
            y + v * math.sin(yaw) * dt,
            yaw + 0.18 * phi * dt,
            t + dt,
        )
        ts.append(t)
        xy.append((x, y))


@pytest.mark.parametrize("deg", [45.0, 90.0, -135.0])
def test_swept_track_follows_the_controller_law_around_a_corner(deg: float) -> None:
    a = math.radians(deg)
    wps = np.array([[0.0, 0.0], [15.0, 0.0], [15.0 + 20.0 * math.cos(a), 20.0 * math.sin(a)]])
    track = swept_track(wps, HUSKY.on("asphalt"), CTRL)
    t_ref, xy_ref = _unicycle(wps, 0.0)
    # same positions at the same times, within half a cell of the 0.1 m terrain grids the
    # track is read on (the reference's 1 ms Euler against 1.1 s Heun steps and the
    # straight line once the heading error is below 0.01 rad; measured 1.5-4 cm)
    q = np.linspace(0.0, min(t_ref[-1], track.t_s[-1]), 400)
    ref = np.column_stack([np.interp(q, t_ref, xy_ref[:, 0]), np.interp(q, t_ref, xy_ref[:, 1])])
    assert np.max(np.hypot(*(track.at(q) - ref).T)) < 0.05
    # it swings out on the side of its incoming heading: the reference's farthest point
    # along +x lies past the switch point (x = 14 m), and the track's matches it
    assert np.max(xy_ref[:, 0]) > 14.2
    assert np.max(track.xy_m[:, 0]) == pytest.approx(np.max(xy_ref[:, 0]), abs=0.05)
    assert track.t_s[-1] == pytest.approx(t_ref[-1], rel=0.01)
    assert track.completed


@pytest.mark.parametrize(
    ("name", "speed", "limited"),
    [("husky-a200", 0.5, False), ("auriga-beta-narrow", 0.5, False), ("pioneer-3at", 0.4, True)],
)
def test_swept_track_matches_the_simulator_within_the_braking_distance(
    name: str, speed: float, limited: bool
) -> None:
    # The simulator adds the drive law: the forward speed follows the slow-down for a sharp
    # corner at most at the acceleration limit, so the robot runs on by up to the braking
    # distance v^2 / (2 a_max) (Husky 0.13 m, Auriga-beta 0.36 m, Pioneer 0.22 m), which
    # the kinematic track leaves out.  Every simulated position before the final stop (it
    # brakes inside the switching radius of the goal) lies within that (+ 5 cm) of the
    # track; the Pioneer is power-limited (wheeled paper §III), turning no tighter than
    # r_min and switching within 1.5 r_min.
    params = vehicle(name, "asphalt")
    ctrl = HeadingController(speed_mps=speed, power_limited=limited)
    wps = np.array([[0.0, 0.0], [15.0, 0.0], [15.0, 20.0], [40.0, 25.0], [30.0, 5.0]])
    track = swept_track(wps, params, ctrl)
    sim = simulate_waypoints(params, wps, ctrl)
    xy = np.column_stack([sim.x, sim.y])
    d_switch = max(ctrl.switch_radius_m, 1.5 * power_limited_radius(params, speed))
    before_stop = np.hypot(*(xy - wps[-1]).T) > d_switch
    gap, _ = cKDTree(_dense(track.xy_m)).query(xy[before_stop])
    assert np.max(gap) < speed**2 / (2.0 * params.accel_max_mps2) + 0.05


def _dense(xy: np.ndarray, step_m: float = 0.005) -> np.ndarray:
    """Points every ``step_m`` or less along the polyline ``xy``."""
    parts = [
        np.linspace(a, b, max(math.ceil(math.hypot(*(b - a)) / step_m), 1), endpoint=False)
        for a, b in itertools.pairwise(xy)
    ]
    return np.vstack([*parts, xy[-1:]])


def _road(width_m: float) -> GridMap:
    """Snow with an asphalt road from y = 10 m to y = 10 + width_m, 60 m x 40 m."""
    labels = np.ones((400, 600), dtype=np.uint8)
    labels[100 : 100 + round(width_m / 0.1), :] = 0
    return GridMap(
        np.zeros((400, 600), dtype=np.int8), 0.1, terrain=labels,
        terrain_names=("asphalt", "snow"),
    )  # fmt: skip


def test_a_corner_beside_costly_terrain_costs_more_as_the_simulator_finds() -> None:
    # The route climbs onto a 4 m road at 45 degrees and turns along its far edge (0.2 m
    # inside): the controller swings out onto the snow beyond and heads for the next way
    # point, 30 m on, from there, so much of that leg is driven on snow.  The same corner
    # on a 10 m road stays on asphalt.  Every polyline point has the same terrain on both
    # maps; only the track differs.  The estimate must see the difference the simulator
    # sees (the Husky's snow costs 2.3 times asphalt per metre).
    wps = np.array([[3.0, 3.0], [13.8, 13.8], [45.0, 13.8], [57.0, 13.8]])
    narrow, wide = _road(4.0), _road(10.0)
    assert narrow.terrain_at(wps) == wide.terrain_at(wps)
    est_n = path_cost(wps, HUSKY, V, world=narrow, turn=CTRL).energy_j
    est_w = path_cost(wps, HUSKY, V, world=wide, turn=CTRL).energy_j
    sim_n, sim_w = _simulated_j(narrow, wps), _simulated_j(wide, wps)
    assert sim_n > 1.1 * sim_w  # premise: the swing-out costs in reality
    assert est_n > est_w
    assert est_n - est_w == pytest.approx(sim_n - sim_w, rel=0.15)
    assert est_n == pytest.approx(sim_n, rel=0.03)


def test_a_misaligned_start_beside_costly_terrain_is_costed_on_the_terrain_it_swings_onto() -> None:
    # Start on the road 0.5 m from its edge, facing the snow (90 degrees off the first
    # leg): the controller turns while driving on (the slow-down lets it move from 45
    # degrees of heading error on), swings 2.6 m onto the snow and heads for the goal,
    # 45 m along the road, from there.  On the narrow road that is 39 m of snow (turning
    # on snow is also cheaper than on asphalt); on the wide one all asphalt.
    wps = np.array([[5.0, 13.5], [50.0, 13.5]])
    yaw0 = math.pi / 2.0
    est, sim = {}, {}
    for width in (4.0, 10.0):
        grid = _road(width)
        est[width] = path_cost(
            wps, HUSKY, V, world=grid, turn=CTRL, initial_heading_rad=yaw0
        ).energy_j
        sim[width] = _simulated_j(grid, wps, yaw0)
    assert sim[4.0] > 1.5 * sim[10.0]  # premise: the swing onto the snow costs
    assert est[4.0] == pytest.approx(sim[4.0], rel=0.03)
    assert est[4.0] - est[10.0] == pytest.approx(sim[4.0] - sim[10.0], rel=0.1)


@settings(max_examples=25, deadline=None)
@given(
    legs=st.lists(st.floats(3.0, 15.0), min_size=1, max_size=4),
    turns=st.lists(st.floats(-2.5, 2.5), min_size=3, max_size=3),
)
def test_terrain_shift_is_zero_on_one_terrain(legs: list[float], turns: list[float]) -> None:
    # on one terrain the track's terrain is the polyline's everywhere: no shift, whatever
    # the track's length (cut corners are the corner tables' business)
    heading = np.cumsum([0.0, *turns[: len(legs) - 1]])
    steps = np.column_stack([np.cos(heading), np.sin(heading)]) * np.array(legs)[:, None]
    start = np.array([30.0, 20.0])
    wps = np.vstack([start, start + np.cumsum(steps, axis=0)])
    grid = GridMap(np.zeros((400, 600), dtype=np.int8), 0.1, terrain=np.zeros((400, 600), np.uint8),
                   terrain_names=("snow",))  # fmt: skip
    track = swept_track(wps, HUSKY.on("snow"), CTRL)
    shift = terrain_shift_j(track.xy_m, wps, grid, steady_per_m(HUSKY, V))
    assert all(val == 0.0 for val in shift.values())
    for i in range(1, len(wps) - 1):
        sw = sweep_corner(wps[i - 1 : i + 2], HUSKY.on("snow"), CTRL)
        shift = terrain_shift_j(sw.track.xy_m, sw.planned_m, grid, steady_per_m(HUSKY, V))
        assert all(val == 0.0 for val in shift.values())


def test_a_corner_sweep_starts_at_the_switch_and_is_sampled_on_its_track() -> None:
    tri = np.array([[0.0, 0.0], [15.0, 0.0], [15.0, 20.0]])
    sw = sweep_corner(tri, HUSKY.on("asphalt"), CTRL)
    # from the switch point d_th = 1 m before the corner into the next switching circle
    # (by less than one step of at most 0.5 m)
    assert sw.track.xy_m[0] == pytest.approx([14.0, 0.0])
    assert 0.5 <= math.hypot(*(sw.track.xy_m[-1] - tri[2])) < 1.0
    assert sw.planned_m == pytest.approx(np.array([[14.0, 0.0], [15.0, 0.0], [15.0, 19.0]]))
    # eight samples on the track, the first within the half-sample of driving (at most
    # 0.5 m/s for 4 / G / 16 = 1.4 s) of the switch point, spread over 4 / G = 22 s
    assert sw.samples_m.shape == (8, 2)
    assert math.hypot(*(sw.samples_m[0] - [14.0, 0.0])) < 0.5 * 1.4 + 1e-9
    gap, _ = cKDTree(_dense(sw.track.xy_m)).query(sw.samples_m)
    assert np.max(gap) < 0.01
    # the same corner inside a whole path's track: the samples agree with it
    whole = swept_track(np.array([[-20.0, 0.0], *tri[1:]]), HUSKY.on("asphalt"), CTRL)
    gap, _ = cKDTree(_dense(whole.xy_m)).query(sw.samples_m)
    assert np.max(gap) < 0.05
