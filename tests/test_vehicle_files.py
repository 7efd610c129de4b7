"""Reading users' vehicle files: one line naming file, line, field and range."""

from __future__ import annotations

import copy
from pathlib import Path
from typing import Any

import pytest
import yaml

from ecoplan.errors import InputError
from ecoplan.io.vehicles import load_vehicle, parse_vehicle
from test_vehicles import ROBOT50


def _write(tmp_path: Path, data: dict[str, Any], name: str = "robot.yaml") -> Path:
    path = tmp_path / name
    path.write_text(yaml.safe_dump(data, sort_keys=False), encoding="utf-8")
    return path


def _with(path: tuple[str, ...], value: object) -> dict[str, Any]:
    data = copy.deepcopy(ROBOT50)
    node = data
    for key in path[:-1]:
        node = node[key]
    node[path[-1]] = value
    return data


def test_a_robot_that_is_not_a_preset_loads_from_its_file(tmp_path: Path) -> None:
    v = load_vehicle(_write(tmp_path, ROBOT50))
    assert v.name == "robot50" and v.terrains == ["asphalt", "sand"]
    assert v.params("sand").mass_kg == 50.0
    assert load_vehicle("husky-a200").name == "husky-a200"  # presets by name


@pytest.mark.parametrize(
    ("path", "value", "expected"),
    [
        # line numbers counted in the dump of ROBOT50 (sort_keys=False)
        (("inertia", "mass_kg"), -5.0, r"robot.yaml:10: inertia.mass_kg: expected a number > 0"),
        (("geometry", "chi"), 1.0, r"robot.yaml:8: geometry.chi: expected a number < 1"),
        (("limits", "p_total_max_w"), 15.0,
         r"robot.yaml:14: limits.p_total_max_w: 15 W is at or below the idle power .*> 20"),
        (("geometry", "colour"), "red", r"robot.yaml:9: unknown key 'colour' in geometry"),
    ],
)  # fmt: skip
def test_impossible_values_are_one_line_with_file_line_and_range(
    tmp_path: Path, path: tuple[str, ...], value: object, expected: str
) -> None:
    with pytest.raises(InputError, match=expected) as info:
        load_vehicle(_write(tmp_path, _with(path, value)))
    assert "\n" not in str(info.value)


def test_missing_files_and_bad_yaml_are_one_line(tmp_path: Path) -> None:
    with pytest.raises(InputError, match="no vehicle file or preset 'clearpath-husky'"):
        load_vehicle("clearpath-husky")
    with pytest.raises(InputError, match="no such vehicle file"):
        load_vehicle(tmp_path / "missing.yaml")
    with pytest.raises(InputError, match=r"v.yaml:2: invalid YAML"):
        parse_vehicle("name: [unclosed\n", "v.yaml")
