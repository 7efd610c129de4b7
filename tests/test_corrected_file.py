"""The corrected-model file is checked by a schema: every error is one line naming the field."""

from __future__ import annotations

import copy
import json
import re
import typing
from pathlib import Path
from typing import Any

import pytest

from ecoplan.cli import main
from ecoplan.diagnose.corrected import load_corrected_model, save_corrected_model
from ecoplan.diagnose.corrected_file import FORMAT, CorrectedModelFile
from ecoplan.errors import InputError

GOOD: dict[str, Any] = {
    "format": FORMAT,
    "vehicle": "auriga-beta-wide",
    "terrain": "asphalt",
    "kind": "tracked",
    "params": {"k_resistance_n": 342.0, "p_powerup_w": 58.0},
    "effect": {"name": "speed_dependent_resistance", "params": {"c_n_s_per_m": 100.0}},
}


def _write(tmp_path: Path, obj: Any, name: str = "m.json") -> Path:
    p = tmp_path / name
    p.write_text(json.dumps(obj, indent=2))
    return p


def _line_of(path: Path, needle: str) -> int:
    """1-based line of the first line holding ``needle`` (found in the text, by hand)."""
    return next(i for i, ln in enumerate(path.read_text().splitlines(), 1) if needle in ln)


def test_the_schema_tag_is_the_format_constant() -> None:
    assert typing.get_args(CorrectedModelFile.model_fields["format"].annotation) == (FORMAT,)


def test_a_good_file_loads_with_its_effect(tmp_path: Path) -> None:
    m = load_corrected_model(_write(tmp_path, GOOD))
    assert (m.vehicle, m.terrain, m.effect) == (
        "auriga-beta-wide",
        "asphalt",
        GOOD["effect"]["name"],
    )
    assert m.params.k_resistance_n == 342.0 and dict(m.effect_params) == {"c_n_s_per_m": 100.0}
    # a null effect parameter is an infinite one (a saturation without cap)
    sat = copy.deepcopy(GOOD)
    sat["effect"] = {"name": "power_saturation", "params": {"p_max_w": None}}
    assert load_corrected_model(_write(tmp_path, sat)).effect_params["p_max_w"] == float("inf")
    sat["effect"]["params"]["p_max_w"] = -1.0  # but not a negative one
    with pytest.raises(
        InputError, match=r"p_max_w = -1\.0 \[W\] .*accepted: \[0, inf\] \(null: no"
    ):
        load_corrected_model(_write(tmp_path, sat, "sat.json"))
    # a null elsewhere is refused (below); an inertia with infinite mass simulated to nan
    heavy = {
        **GOOD,
        "effect": {"name": "inertia", "params": {"mass_kg": None, "yaw_inertia_kgm2": 90.0}},
    }
    with pytest.raises(InputError, match=r"effect.params.mass_kg|mass_kg = null"):
        load_corrected_model(_write(tmp_path, heavy, "heavy.json"))


def _set(path: list[str], value: Any) -> dict[str, Any]:
    obj = copy.deepcopy(GOOD)
    node = obj
    for k in path[:-1]:
        node = node[k]
    if value is KeyError:
        del node[path[-1]]
    else:
        node[path[-1]] = value
    return obj


@pytest.mark.parametrize(
    ("path", "value", "line_of", "message"),
    [
        (["format"], "ecoplan-corrected-model/0", '"format"', "format: expected one of"),
        (["colour"], "red", None, r"unknown key 'colour' in \(top level\)"),
        (["params"], KeyError, None, "missing required key 'params'"),
        (["vehicle"], "rover-9", '"vehicle"', "vehicle: unknown vehicle preset 'rover-9'"),
        (["terrain"], "mud", '"terrain"', "terrain: unknown terrain preset 'mud'"),
        (["kind"], "wheeled", '"kind"', "kind: 'auriga-beta-wide' is tracked, not wheeled"),
        (["kind"], "legged", '"kind"', "kind: expected one of"),
        (["params", "bogus_n"], 1.0, '"params": {', "params: unknown parameter 'bogus_n'"),
        (["params", "k_resistance_n"], -5.0, '"params": {', "params: .*k_resistance_n"),
        (["effect", "name"], "gremlins", '"name"', "effect.name: unknown effect 'gremlins'"),
        (["effect", "params", "c_n_s_per_m"], "big", "big", "c_n_s_per_m: expected a number"),
        (
            ["effect", "params", "c_n_s_per_m"],
            KeyError,
            '"params": {}',
            r"effect.params: effect 'speed_dependent_resistance' needs parameter\(s\) c_n_s_per_m",
        ),
        # the effect's physical range (effects/base.py Parameter): a null reads as infinite,
        # meaningful only for a saturation's cap; an infinite resistance simulated to nan
        (
            ["effect", "params", "c_n_s_per_m"],
            None,
            '"c_n_s_per_m"',
            r"c_n_s_per_m: .*c_n_s_per_m = null \(infinite\) \[N s/m\] is outside its physical "
            r"range; accepted: finite values in \[0, inf\]",
        ),
        (
            ["effect", "params", "c_n_s_per_m"],
            -3.0,
            '"c_n_s_per_m"',
            r"c_n_s_per_m = -3\.0 \[N s/m\] is outside",
        ),
    ],
)
def test_a_bad_field_is_one_line_naming_file_line_and_field(
    tmp_path: Path, path: list[str], value: Any, line_of: str | None, message: str
) -> None:
    p = _write(tmp_path, _set(path, value))
    with pytest.raises(InputError) as err:
        load_corrected_model(p)
    text = str(err.value)
    assert "\n" not in text and text.startswith(str(p))
    assert re.search(message, text), text
    if line_of is not None:
        assert text.startswith(f"{p}:{_line_of(p, line_of)}: "), text


def test_yaml_files_are_read_the_same_way(tmp_path: Path) -> None:
    p = tmp_path / "m.yaml"
    p.write_text(
        "format: ecoplan-corrected-model/1\nvehicle: pioneer-3at\nparams: {}\n"
        "effect: {name: none, params: {}}\nterrain: vinyl\nkind: wheeled\n"
    )
    assert load_corrected_model(p).terrain == "vinyl"
    p.write_text(p.read_text().replace("kind: wheeled", "kind: wheeled\nkind: tracked"))
    with pytest.raises(InputError, match=r":7: .*duplicate"):
        load_corrected_model(p)


def test_what_save_writes_load_reads(tmp_path: Path) -> None:
    m = load_corrected_model(_write(tmp_path, GOOD))
    for suffix in (".json", ".yaml"):
        back = load_corrected_model(save_corrected_model(m, tmp_path / f"again{suffix}"))
        assert back == m


def test_the_cli_exits_2_with_the_field_for_a_scenario_with_a_bad_model(
    tmp_path: Path, capsys: pytest.CaptureFixture[str]
) -> None:
    _write(tmp_path, _set(["effect", "name"], "gremlins"))
    code, err = _plan_with_model(tmp_path, capsys)
    assert code == 2
    assert "\n" not in err and "effect.name: unknown effect 'gremlins'" in err


def _plan_with_model(
    tmp_path: Path, capsys: pytest.CaptureFixture[str], terrain_line: str = ""
) -> tuple[int, str]:
    """``ecoplan plan`` of a small scenario driving ``m.json``: exit code and stderr."""
    scenario = tmp_path / "s.yaml"
    scenario.write_text(
        f"name: c\nvehicle: {{model: m.json}}\n{terrain_line}"
        "map: {bounds: {min: [0, 0], max: [9, 9]}}\nstart: {x: 1, y: 1}\nwaypoints: [[8, 8]]\n"
    )
    code = main(["plan", str(scenario)])
    return code, capsys.readouterr().err.strip()


@pytest.mark.parametrize(
    ("model_terrain", "said"),
    [("asphalt", "calibrated on 'asphalt'"), (None, "which it does not name")],
)
def test_a_scenario_on_another_terrain_than_its_model_says_which(
    tmp_path: Path, capsys: pytest.CaptureFixture[str], model_terrain: str | None, said: str
) -> None:
    # a corrected model holds the parameters of its logs' ground: a scenario on another terrain
    # is refused; a model diagnosed without --terrain names no ground (it said "calibrated on
    # None" before session 24)
    _write(tmp_path, {**GOOD, "terrain": model_terrain})
    code, err = _plan_with_model(tmp_path, capsys, "terrain: marble\n")
    assert code == 2
    assert "\n" not in err and "terrain:" in err and said in err and "None" not in err
