"""Vehicle files: schema, shipped presets as data, terrain resistance, bad values."""

from __future__ import annotations

import copy
from typing import Any

import numpy as np
import pytest
from pydantic import ValidationError

from ecoplan.errors import InputError
from ecoplan.models.tracked import TrackedParams
from ecoplan.models.vehicle_schema import SOURCES
from ecoplan.models.vehicles import (
    shipped_names,
    shipped_vehicle,
    vehicle_from_mapping,
)
from ecoplan.models.wheeled import WheeledParams
from ecoplan.presets import vehicle

G = 9.81

#: A wheeled robot that is not a preset: 50 kg, 0.55 m gauge, contact-friction model.
ROBOT50: dict[str, Any] = {
    "name": "robot50",
    "kind": "wheeled",
    "power_model": "contact-friction",
    "geometry": {"track_gauge_m": 0.55, "wheelbase_m": 0.5, "n_contact_points": 2, "chi": 0.6},
    "inertia": {"mass_kg": 50.0},
    "limits": {"top_speed_mps": 1.0, "accel_max_mps2": 0.5, "p_total_max_w": 600.0},
    "drivers": {"p_powerup_w": 20.0, "eta": 0.9},
    "default_terrain": "asphalt",
    "terrains": {
        "asphalt": {
            "mu": {"value": 0.5, "source": "assumption"},
            "rolling_resistance": {"value": 0.02, "source": "assumption"},
        },
        "sand": {
            "mu": {"value": 0.6, "source": "assumption"},
            "rolling_resistance": {"value": 0.15, "source": "assumption"},
        },
    },
}


def test_shipped_presets_are_the_papers_values() -> None:
    # tracked paper §III-C: mu 0.63 marble / 0.81 asphalt, K 342 N wide / 324 N narrow,
    # 282 N hoisted; power-up 58 W, braking 164 W, non-regenerated 162 N; Table I geometry
    assert {"auriga-beta-wide", "auriga-beta-narrow", "pioneer-3at"} <= set(shipped_names())
    wide = vehicle("auriga-beta-wide", "marble")
    assert isinstance(wide, TrackedParams)
    assert (wide.mu, wide.k_resistance_n, wide.mass_kg) == (0.63, 342.0, 286.0)
    assert (wide.track_gauge_m, wide.contact_length_m, wide.top_track_speed_mps) == (
        0.42,
        0.72,
        0.86,
    )
    assert (wide.p_powerup_w, wide.p_braking_w, wide.k_nonregen_n) == (58.0, 164.0, 162.0)
    assert vehicle("auriga-beta-narrow", "asphalt").k_resistance_n == 324.0
    assert vehicle("auriga-beta-wide", "asphalt").mu == 0.81
    assert vehicle("auriga-beta-wide", "hoisted").k_resistance_n == 282.0
    # wheeled Table I (asphalt) and Table II (vinyl)
    p3 = vehicle("pioneer-3at", "vinyl")
    assert isinstance(p3, WheeledParams)
    np.testing.assert_array_equal(
        p3.outer.as_array(), [9.8043, 300.0, 2.6260, 0.01263, 35.32, 2.9796]
    )
    np.testing.assert_array_equal(
        vehicle("pioneer-3at").inner.as_array(), [7.5313, -170.0, 2.5507, 0.006, 500.0, 7.7136]
    )


@pytest.mark.parametrize(
    "name", ["auriga-beta-wide", "auriga-beta-narrow", "pioneer-3at", "husky-a200"]
)
def test_every_shipped_terrain_value_has_a_source(name: str) -> None:
    v = shipped_vehicle(name)
    for terrain in v.terrains:
        entry = v.terrain(terrain)
        for field in ("mu", "k_resistance_n", "rolling_resistance", "chi", "sides"):
            value = getattr(entry, field)
            if value is not None:
                assert value.source in SOURCES
        v.params(terrain)  # every terrain builds valid parameters


#: Field terrains of the paper robots' files: the assumed rolling resistance beyond the
#: hard ground's (C_rr), as the files state it.
FIELD_CRR = {
    "auriga-beta-wide": {"gravel": 0.03, "grass": 0.06, "sand": 0.15, "snow": 0.10},
    "auriga-beta-narrow": {"gravel": 0.03, "grass": 0.06, "sand": 0.15, "snow": 0.10},
    "pioneer-3at": {"gravel": 0.03, "grass": 0.06, "sand": 0.15},
}


@pytest.mark.parametrize("name", sorted(FIELD_CRR))
def test_field_terrains_add_their_rolling_resistance_to_straight_driving(name: str) -> None:
    # straight at v: the extra force C_rr M g at speed v through eta (tracked eq. 20; the
    # wheeled model has no eta) over the asphalt power; masses: tracked Table I 286 kg,
    # wheeled paper §III 30 kg
    v = shipped_vehicle(name)
    mass, eta = (286.0, 0.95) if name.startswith("auriga") else (30.0, 1.0)
    for terrain, crr in FIELD_CRR[name].items():
        assert v.terrain(terrain).mu is None or v.terrain(terrain).mu.source == "assumption"
        for speed in (0.2, 0.5):
            field = float(v.params(terrain).power(speed, speed).total_w)
            hard = float(v.params("asphalt").power(speed, speed).total_w)
            expected = crr * mass * G * speed / eta
            assert field - hard == pytest.approx(expected, rel=0.01), (terrain, speed)


def test_rolling_resistance_is_a_share_of_the_weight() -> None:
    # K of tracked eq. (18) from C_rr: the two sides share the force C_rr M g
    v = vehicle_from_mapping(ROBOT50)
    p = v.params("sand")
    assert isinstance(p, TrackedParams)
    assert p.k_resistance_n == pytest.approx(0.15 * 50.0 * G / 2.0)
    # straight-line power at 0.5 m/s differs between terrains by the resistance only:
    # (K_sand - K_asphalt) (|V_l| + |V_r|) / eta
    diff = p.power(0.5, 0.5).total_w - v.params("asphalt").power(0.5, 0.5).total_w
    assert float(diff) == pytest.approx((0.15 - 0.02) * 50 * G / 2 * 1.0 / 0.9)


def test_wheeled_rolling_resistance_adds_to_the_straight_slope() -> None:
    data = copy.deepcopy(shipped_vehicle("pioneer-3at").spec.model_dump())
    data["terrains"]["grass"] = copy.deepcopy(data["terrains"]["asphalt"])
    data["terrains"]["grass"]["rolling_resistance"] = {"value": 0.1, "source": "assumption"}
    v = vehicle_from_mapping(data)
    straight = [float(v.params(t).power(0.4, 0.4).total_w) for t in ("asphalt", "grass")]
    # force C_rr M g at the centre speed 0.4 m/s
    assert straight[1] - straight[0] == pytest.approx(0.1 * 30.0 * G * 0.4)


def test_vehicle_takes_a_file_and_overrides() -> None:
    v = vehicle_from_mapping(ROBOT50)
    spec = vehicle(v, "sand", {"eta": 0.8})
    assert spec.name == "robot50/sand" and spec.source is v
    assert spec.on().eta == 0.8 and spec.on("asphalt").eta == 0.8
    assert spec.on("asphalt").mu == 0.5
    with pytest.raises(InputError, match="unknown terrain preset 'snow' for robot50"):
        spec.on("snow")


def _mutate(path: tuple[str, ...], value: object) -> dict[str, Any]:
    data = copy.deepcopy(ROBOT50)
    node = data
    for key in path[:-1]:
        node = node[key]
    node[path[-1]] = value
    return data


@pytest.mark.parametrize(
    ("path", "value", "pattern"),
    [
        (("inertia", "mass_kg"), -5.0, r"greater than 0"),
        (("geometry", "chi"), 1.0, r"less than 1"),
        (("terrains", "sand", "rolling_resistance", "value"), -0.1, r"rolling_resistance.*>= 0"),
        (("terrains", "sand", "mu", "source"), "guess", r"identified.*paper.*assumption"),
        (("default_terrain",), "ice", r"default_terrain 'ice' is not in terrains"),
        (("terrains", "sand", "sides"), {"inner": [1] * 6, "outer": [1] * 6, "source": "paper"},
         r"sides belongs to the radius-fit model"),
    ],
)  # fmt: skip
def test_impossible_values_are_refused(path: tuple[str, ...], value: object, pattern: str) -> None:
    with pytest.raises(ValidationError, match=pattern):
        vehicle_from_mapping(_mutate(path, value))


def test_a_limit_below_the_idle_power_is_refused() -> None:
    with pytest.raises(InputError, match=r"limits.p_total_max_w: 15 W .*idle power.*> 20"):
        vehicle_from_mapping(_mutate(("limits", "p_total_max_w"), 15.0))


def test_unknown_preset_lists_the_shipped_files() -> None:
    with pytest.raises(InputError, match=r"unknown vehicle preset 'clearpath-husky'.*pioneer-3at"):
        shipped_vehicle("clearpath-husky")


def test_husky_is_identified_on_the_five_borealtc_terrains() -> None:
    husky = shipped_vehicle("husky-a200")
    assert husky.terrains == ["asphalt", "flooring", "ice", "sandy_loam", "snow"]
    assert any("24 V" in a for a in husky.spec.assumptions)
    assert (husky.mass_kg, husky.spec.geometry.track_gauge_m) == (70.0, 0.555)
    # the logs measure motor currents (BorealTC ABOUT.md: curL, curR per side)
    assert husky.spec.power_log.signal == "motor_current"
    for terrain in husky.terrains:
        entry = husky.terrain(terrain)
        for name in ("mu", "k_resistance_n", "turn_slip_scale", "no_load_current_a"):
            field = getattr(entry, name)
            assert field is not None and field.source == "identified" and field.interval
        assert entry.heldout_mae_w is not None
    # straight driving in the logs (husky_terrains.py --explain, part 1: per-run means of
    # 24 V x (|I_L| + |I_R|)) is 175-207 W on sandy loam and 193-360 W on snow, 90-195 W on
    # asphalt, 95-116 W on flooring, 99-133 W on ice: the loose terrains cost more
    straight = {t: float(vehicle("husky-a200", t).power(0.5, 0.5).total_w) for t in husky.terrains}
    firm = max(straight["asphalt"], straight["flooring"], straight["ice"])
    assert firm < straight["sandy_loam"] < straight["snow"]
