"""Fuzzing the scenario loader: whatever the input, a Scenario or a one-line InputError."""

from __future__ import annotations

import copy
from typing import Any

import yaml
from hypothesis import HealthCheck, given, settings
from hypothesis import strategies as st

from ecoplan.app.scenario import Scenario, parse_scenario
from ecoplan.errors import InputError

VALID: dict[str, Any] = {
    "name": "fuzz",
    "vehicle": {"preset": "auriga-beta-wide", "overrides": {"mu": 0.7}},
    "terrain": {
        "default": "marble",
        "regions": [{"terrain": "asphalt", "rectangle": {"min": [8, -3], "max": [12, 3]}}],
    },
    "map": {
        "bounds": {"min": [0, -5], "max": [20, 5]},
        "obstacles": [
            {"circle": {"center": [5, 2], "radius_m": 1.0}},
            {"polygon": [[14, -4], [16, -4], [15, -1]]},
        ],
        "inflation_m": 0.3,
    },
    "start": {"x": 1, "y": 0, "yaw_deg": 0},
    "goal": {"x": 19, "y": 0},
    "planner": {"type": "graph", "time_s": 1.0},
    "speed": {"policy": "fixed", "v_mps": 0.5},
    "controller": {"gain": 0.18, "d_th_m": 1.0},
    "battery": {"capacity_wh": 10},
    "compare": [{"name": "a", "waypoints": [[10, 4], [19, 0]]}],
}

SCALARS = st.one_of(
    st.none(),
    st.booleans(),
    st.integers(min_value=-(10**30), max_value=10**30),
    st.floats(allow_nan=True, allow_infinity=True),
    st.text(max_size=20),
)
VALUES = st.recursive(
    SCALARS,
    lambda inner: st.one_of(
        st.lists(inner, max_size=4), st.dictionaries(st.text(max_size=8), inner, max_size=4)
    ),
    max_leaves=12,
)
TOKENS = st.sampled_from(
    ["name:", "map:", "bounds:", " ", "\n", "  ", "- ", "[", "]", "{", "}", ",", ":", "&a ",
     "*a", "!!str ", "!!python/name:os.system", "1e999", "-1", "0x10", ".nan", "'", '"', "\t",
     "---", "...", "? ", "|", ">", "#", "vehicle: {preset: pioneer-3at}", "<<: *a", "\x00"]
)  # fmt: skip
FUZZ = settings(max_examples=150, deadline=None, suppress_health_check=[HealthCheck.too_slow])


def check_parse(text: str) -> None:
    try:
        sc = parse_scenario(text, source="fuzz.yaml")
    except InputError as exc:
        msg = str(exc)
        assert msg and "\n" not in msg, msg
        assert "Traceback" not in msg
    else:
        assert isinstance(sc, Scenario)


def _paths(node: Any, prefix: tuple[Any, ...] = ()) -> list[tuple[Any, ...]]:
    out = [prefix]
    if isinstance(node, dict):
        for k, v in node.items():
            out += _paths(v, (*prefix, k))
    elif isinstance(node, list):
        for i, v in enumerate(node):
            out += _paths(v, (*prefix, i))
    return out


PATHS = _paths(VALID)[1:]


def test_the_fuzz_base_scenario_is_valid() -> None:
    assert isinstance(parse_scenario(yaml.safe_dump(VALID)), Scenario)


@FUZZ
@given(st.text(max_size=300))
def test_arbitrary_text(text: str) -> None:
    check_parse(text)


@FUZZ
@given(st.lists(TOKENS, max_size=40).map("".join))
def test_yaml_token_soup(text: str) -> None:
    check_parse(text)


@FUZZ
@given(VALUES)
def test_arbitrary_documents(doc: Any) -> None:
    check_parse(yaml.safe_dump(doc))


@FUZZ
@given(st.lists(st.tuples(st.sampled_from(PATHS), VALUES), min_size=1, max_size=3))
def test_mutated_valid_scenario(mutations: list[tuple[tuple[Any, ...], Any]]) -> None:
    doc = copy.deepcopy(VALID)
    for path, value in mutations:
        node = doc
        try:
            for key in path[:-1]:
                node = node[key]
            node[path[-1]] = value
        except (KeyError, IndexError, TypeError):
            continue  # an earlier mutation removed this path
    check_parse(yaml.safe_dump(doc))


@FUZZ
@given(st.sampled_from(PATHS))
def test_deleted_key(path: tuple[Any, ...]) -> None:
    doc = copy.deepcopy(VALID)
    node = doc
    for key in path[:-1]:
        node = node[key]
    del node[path[-1]]
    check_parse(yaml.safe_dump(doc))
