"""The diagnosis JSON has exactly the stable shape of issue 6 (plus documented extra keys)."""

from __future__ import annotations

import copy
import json
from functools import cache
from typing import Any

import pytest

from ecoplan.diagnose.pipeline import diagnose
from ecoplan.diagnose.report import JSON_KEYS, to_json_dict, validate_json, write_json
from ecoplan.errors import InputError
from ecoplan.synth.cases import generate_case

EXTRA_KEYS = {
    "calibration",
    "how_far",
    "channels",
    "distinguishability",
    "where_time",
    "where_time_terrain",
    "naming",
    "tied",
    "log",
}


@cache
def _json(effect: str) -> str:
    case = generate_case(7, effect, "large", n_waypoint_runs=1, rate_hz=20.0)
    return json.dumps(to_json_dict(diagnose(list(case.logs), case.vehicle, case.terrain)))


@pytest.mark.parametrize("effect", ["inertia", "none", "power_saturation"])
def test_json_has_exactly_the_stable_shape(effect: str) -> None:
    obj = json.loads(_json(effect))  # round-trips through text: only JSON types inside
    validate_json(obj)
    assert list(obj)[:4] == list(JSON_KEYS)
    assert set(obj) - set(JSON_KEYS) <= EXTRA_KEYS
    assert set(obj["gap"]) == {"metric", "before", "after"} and obj["gap"]["metric"] == "mae_w"
    assert all(set(w) == {"regime", "error_share", "time_share"} for w in obj["where"])
    assert all(set(e) == {"name", "before", "after", "params"} for e in obj["effects"])
    assert set(obj["verdict"]) == {"effect", "confidence"}
    # ranked best first: the verdict's effect (when one) leads the list
    if obj["verdict"]["effect"] not in ("none", "unexplained", "ambiguous"):
        assert obj["effects"][0]["name"] == obj["verdict"]["effect"]
    for w in obj["where"]:
        assert 0.0 <= w["error_share"] <= 1.0 and 0.0 <= w["time_share"] <= 1.0
    # the evidence of the naming rule: both alternatives, each with its held-out MAE
    assert [a["name"] for a in obj["naming"]["alternatives"]] == ["structural", "time_step"]
    assert all(isinstance(a["halves_note"], str) for a in obj["naming"]["alternatives"])
    assert all(isinstance(a["after"], float) for a in obj["naming"]["alternatives"])
    assert isinstance(obj["naming"]["reason"], str)


def test_saturation_cap_is_a_number_and_inf_would_be_null() -> None:
    obj = json.loads(_json("power_saturation"))
    sat = next(e for e in obj["effects"] if e["name"] == "power_saturation")
    assert isinstance(sat["params"]["p_max_w"], float)


def _broken(path: list[Any], value: Any) -> dict[str, Any]:
    obj: dict[str, Any] = copy.deepcopy(json.loads(_json("inertia")))
    node: Any = obj
    for k in path[:-1]:
        node = node[k]
    if value is KeyError:
        del node[path[-1]]
    else:
        node[path[-1]] = value
    return obj


@pytest.mark.parametrize(
    ("path", "value", "message"),
    [
        (["gap"], KeyError, "missing required key 'gap'"),
        (["gap", "metric"], "rmse_w", "gap.metric: expected one of 'mae_w'"),
        (["gap", "before"], None, "gap.before: expected a number"),
        (["gap", "after"], True, "gap.after: expected a number"),
        (["gap", "after"], float("nan"), "gap.after: expected a finite number"),
        (["where", 0, "regime"], 3, r"where\[0\].regime: expected a string"),
        (["effects", 0, "extra"], 1.0, r"unknown key 'extra' in effects\[0\]"),
        (["verdict", "confidence"], 1.5, "verdict.confidence: expected a number <= 1"),
        (["verdict", "confidence"], -0.1, "verdict.confidence: expected a number >= 0"),
        (["where_time"], [{"run": "r1"}], r"where_time\[0\]: missing required key"),
        (["where_time"], None, "where_time: expected a list"),
    ],
)
def test_validator_names_the_broken_field(path: list[Any], value: Any, message: str) -> None:
    with pytest.raises(InputError, match=message) as err:  # one hierarchy (issue 10 item 6)
        validate_json(_broken(path, value))
    assert str(err.value).startswith("diagnosis JSON: ") and "\n" not in str(err.value)


def test_validator_takes_documented_extra_keys_and_refuses_a_non_object() -> None:
    obj = _broken(["ranking"], {"routes": [], "changed": False})  # `--scenario`'s extra key
    validate_json(obj)
    with pytest.raises(InputError, match=r"\(top level\): expected a mapping"):
        validate_json([obj])


def test_write_json_writes_a_valid_file(tmp_path) -> None:  # type: ignore[no-untyped-def]
    case = generate_case(8, "none", "large", n_waypoint_runs=1, rate_hz=20.0)
    d = diagnose(list(case.logs), case.vehicle, case.terrain)
    p = write_json(d, tmp_path / "sub" / "d.json")
    obj = json.loads(p.read_text())
    validate_json(obj)
    assert list(obj)[:4] == ["gap", "where", "effects", "verdict"]  # the contract keys first
