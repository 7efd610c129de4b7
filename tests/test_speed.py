"""Speed choice: slow is not cheap (tracked §IV, Table III) and limits are respected."""

from __future__ import annotations

import math

import numpy as np
import pytest

from ecoplan.errors import InputError, PlanningError
from ecoplan.planning.speed import best_speed, energy_vs_speed
from ecoplan.presets import vehicle

# A ~52 m A->B path around an obstacle with one and with two intermediate waypoints, like
# the paper's navigation experiment on asphalt (Fig. 14, Table III).
ONE_WAYPOINT = [(0.0, 0.0), (26.0, 8.0), (52.0, 0.0)]
TWO_WAYPOINTS = [(0.0, 0.0), (18.0, 8.0), (34.0, 8.0), (52.0, 0.0)]
NARROW = vehicle("auriga-beta-narrow", "asphalt")


@pytest.mark.parametrize("path", [ONE_WAYPOINT, TWO_WAYPOINTS])
@pytest.mark.parametrize("turn", ["spot", "auto"])
def test_paper_finding_03_costs_more_than_05(path: list[tuple[float, float]], turn: str) -> None:
    e03, e05 = energy_vs_speed(path, NARROW, [0.3, 0.5], turn=turn)  # type: ignore[arg-type]
    assert e03 > e05
    choice = best_speed(path, NARROW, turn=turn, n_scan=21)  # type: ignore[arg-type]
    assert choice.speed_mps >= 0.5
    assert choice.cost.feasible
    assert choice.energy_j <= e05


def test_two_waypoints_cost_more_than_one() -> None:
    # Table III: four way points always cost more than three (more turned angle psi)
    one = best_speed(ONE_WAYPOINT, NARROW, turn="spot")
    two = best_speed(TWO_WAYPOINTS, NARROW, turn="spot")
    assert two.cost.psi_rad > one.cost.psi_rad
    assert two.energy_j > one.energy_j


def test_power_limit_caps_the_speed_by_hand() -> None:
    # Straight path, P_T(v, v) = (2 K v + P_pu) / eta <= 400 W  ->  v <= (400 eta - P_pu) / 2K
    spec = vehicle("auriga-beta-narrow", "asphalt", overrides={"p_total_max_w": 400.0})
    v_cap = (400.0 * 0.95 - 58.0) / (2 * 324.0)
    choice = best_speed([(0, 0), (30, 0)], spec)
    assert choice.speed_mps == pytest.approx(v_cap, abs=2e-3)
    assert choice.speed_mps <= v_cap + 1e-9
    assert choice.cost.feasible
    assert np.isnan(choice.scan_energy_j[choice.scan_speeds_mps > v_cap + 1e-9]).all()


def test_pioneer_respects_its_side_power_limit_on_turns() -> None:
    path = [(0.0, 0.0), (30.0, 0.0), (30.0, 30.0)]
    choice = best_speed(path, vehicle("pioneer-3at"))
    assert choice.cost.feasible
    assert all(t.mode == "arc" for t in choice.cost.turns)
    assert choice.speed_mps < 0.9  # the top speed allows no turn at all (eq. 5)


def test_per_segment_never_worse() -> None:
    path = [(0.0, 0.0), (20.0, 0.0), (35.0, 6.0), (50.0, 6.0)]
    spec = vehicle("pioneer-3at")
    single = best_speed(path, spec)
    multi = best_speed(path, spec, per_segment=True, n_scan=15, sweeps=1)
    assert multi.energy_j <= single.energy_j + 1e-9
    assert multi.segment_speeds_mps.shape == (3,)


def test_bad_ranges_and_infeasible_paths() -> None:
    with pytest.raises(InputError, match="v_min_mps < v_max_mps"):
        best_speed(ONE_WAYPOINT, NARROW, v_min_mps=0.5, v_max_mps=0.4)
    with pytest.raises(InputError, match="v_min_mps"):
        best_speed(ONE_WAYPOINT, NARROW, v_min_mps=0.0)
    # a hairpin between 1 m segments: no Pioneer speed turns that sharply
    with pytest.raises(PlanningError, match="no speed"):
        best_speed([(0, 0), (1, 0), (0, 0.1)], vehicle("pioneer-3at"), n_scan=5)
    assert math.isnan(energy_vs_speed([(0, 0), (1, 0)], vehicle("pioneer-3at"), [0.95])[0])
