"""Presets: the papers' values by stable name, χ consistent with Table II's text, overrides."""

from __future__ import annotations

import dataclasses
from pathlib import Path

import pytest

from ecoplan.errors import InputError
from ecoplan.io.vehicles import load_vehicle
from ecoplan.models import TrackedParams, WheeledParams
from ecoplan.presets import default_terrain, terrain_names, vehicle, vehicle_names


def _t(name: str, terrain: str) -> TrackedParams:
    p = vehicle(name, terrain)
    assert isinstance(p, TrackedParams)
    return p


def test_names_are_stable() -> None:
    assert vehicle_names() == [
        "auriga-beta-narrow",
        "auriga-beta-wide",
        "husky-a200",
        "pioneer-3at",
    ]
    paper = ["asphalt", "hoisted", "marble"]
    assert terrain_names("auriga-beta-wide") == sorted([*paper, "grass", "gravel", "sand", "snow"])
    assert terrain_names("pioneer-3at") == ["asphalt", "grass", "gravel", "sand", "vinyl"]
    assert default_terrain("pioneer-3at") == "asphalt"


@pytest.mark.parametrize("belt", ["auriga-beta-wide", "auriga-beta-narrow"])
def test_auriga_values_from_the_tracked_paper(belt: str) -> None:
    # §III-A/B: 286 kg, L = 0.42 m, contact length 0.72 m, V_max = 0.86 m/s; §III-C:
    # µ 0.63 marble / 0.81 asphalt, K 342 N wide / 324 N narrow / 282 N hoisted, power-up
    # 58 W, braking 164 W, non-regenerated 162 N (|Vl| + |Vr|), η 0.95.
    m, a, h = _t(belt, "marble"), _t(belt, "asphalt"), _t(belt, "hoisted")
    for p in (m, a, h):
        assert (p.mass_kg, p.track_gauge_m, p.contact_length_m) == (286.0, 0.42, 0.72)
        assert p.top_track_speed_mps == 0.86 and p.n_contact_points == 4
        assert (p.p_powerup_w, p.eta) == (58.0, 0.95)
    for p in (m, a):
        assert (p.p_braking_w, p.k_nonregen_n) == (164.0, 162.0)
    # hoisted: no ground contact, so no track brakes or drags the other (§II-C)
    assert (h.p_braking_w, h.k_nonregen_n) == (0.0, 0.0)
    assert (m.mu, a.mu, h.mu) == (0.63, 0.81, 0.0)
    k = 342.0 if belt.endswith("wide") else 324.0
    assert (m.k_resistance_n, a.k_resistance_n, h.k_resistance_n) == (k, k, 282.0)


def test_chi_consistent_with_table_ii_text() -> None:
    # §II-B: χ < 1; §III-C: the ICR distance grows on asphalt and with the wide belts, so
    # χ(asphalt) < χ(marble) and χ(wide) < χ(narrow).
    chi = {
        (b, t): _t(f"auriga-beta-{b}", t).chi
        for b in ("wide", "narrow")
        for t in ("marble", "asphalt")
    }
    assert all(0.0 < c < 1.0 for c in chi.values())
    for b in ("wide", "narrow"):
        assert chi[(b, "asphalt")] < chi[(b, "marble")]
    for t in ("marble", "asphalt"):
        assert chi[("wide", t)] < chi[("narrow", t)]


def test_pioneer_tables() -> None:
    p = vehicle("pioneer-3at", "asphalt")
    assert isinstance(p, WheeledParams)
    assert p.inner.a_alpha == -170.0 and p.outer.b_beta == 4.818  # Table I
    assert p.top_track_speed_mps == 0.9  # §III-C


def test_every_value_can_be_overridden() -> None:
    p = vehicle("auriga-beta-wide", "marble", {"mu": 0.5, "chi": 0.7, "p_motor_max_w": 900.0})
    assert isinstance(p, TrackedParams)
    assert (p.mu, p.chi, p.p_motor_max_w) == (0.5, 0.7, 900.0)
    w = vehicle("pioneer-3at", overrides={"p_side_max_w": 15, "outer": {"a_inf": 11.0}})
    assert isinstance(w, WheeledParams)
    assert w.p_side_max_w == 15 and w.outer.a_inf == 11.0 and w.outer.a_alpha == 250.0


def test_a_vehicle_follows_the_terrain_with_its_overrides() -> None:
    p = vehicle("auriga-beta-narrow", "marble", {"eta": 0.9})
    assert p.kind == "tracked" and p.terrain == "marble"
    # tracked §III-C: mu 0.63 on marble, 0.81 on asphalt; the override holds on both
    assert (p.mu, p.on("asphalt").mu) == (0.63, 0.81)
    assert p.on("asphalt").eta == 0.9 and p.on("ASPHALT").name == "auriga-beta-narrow/asphalt"
    assert p.on() is p and p.on("marble") is p
    assert p.on("asphalt") is p.on("asphalt")  # cached
    assert p.on("asphalt").on("marble") == p
    # a change made after building would not follow the terrain: refused, with the way out
    changed = dataclasses.replace(p, mu=0.5)
    assert changed.source is None
    with pytest.raises(InputError, match=r"dataclasses\.replace.*overrides="):
        changed.on("asphalt")


def test_a_vehicle_file_is_named_the_same_way() -> None:
    robot = load_vehicle(Path(__file__).resolve().parents[1] / "scenarios/vehicles/robot50.yaml")
    p = vehicle(robot, "grass")
    assert p.terrain == "grass" and p.on("asphalt").terrain == "asphalt"
    # C_rr M g / 2 per side (robot50.yaml: C_rr 0.08 on grass, 0.02 on asphalt, M = 50 kg)
    assert p.k_resistance_n - p.on("asphalt").k_resistance_n == pytest.approx(
        (0.08 - 0.02) * 50.0 * 9.81 / 2.0
    )


@pytest.mark.parametrize(
    ("call", "pattern"),
    [
        (lambda: vehicle("husky"), r"unknown vehicle preset 'husky'; accepted: auriga-beta-narrow"),
        (
            lambda: vehicle("pioneer-3at", "marble"),
            r"unknown terrain preset 'marble'.*asphalt, grass, gravel, sand, vinyl",
        ),
        (
            lambda: vehicle("pioneer-3at", overrides={"wheel": 1}),
            r"unknown parameter 'wheel'.*mass_kg",
        ),
        (
            lambda: vehicle("pioneer-3at", overrides={"inner": {"c": 1}}),
            r"unknown coefficient.*a_alpha",
        ),
        (
            lambda: vehicle("auriga-beta-wide", overrides={"mass_kg": -5.0}),
            r"mass_kg = -5.0.*\(0, inf\]",
        ),
        (lambda: vehicle("auriga-beta-wide", overrides={"chi": 1.0}), r"chi = 1.0.*\(0, 1\)"),
        (lambda: vehicle("auriga-beta-wide", overrides={"mu": "high"}), r"mu = 'high'"),
        (lambda: vehicle("auriga-beta-wide", overrides={"eta": 2.0}), r"eta = 2.0.*\(0, 1\]"),
        (lambda: TrackedParams().on("asphalt"), r"built by hand.*presets\.vehicle"),
    ],
)
def test_bad_presets_and_overrides_name_the_problem(call: object, pattern: str) -> None:
    with pytest.raises(InputError, match=pattern):
        call()  # type: ignore[operator]
