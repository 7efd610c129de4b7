"""The generic YAML reader: line numbers, duplicate keys, one-line schema errors for any model."""

from __future__ import annotations

import pytest
from pydantic import BaseModel, ConfigDict, Field, ValidationError

from ecoplan.errors import InputError, ScenarioError
from ecoplan.io.yaml import format_validation, read_yaml

DOC = """\
# a comment on line 1
name: husky
geometry:
  track_width_m: 0.55
  wheels: [0.1, 0.2, 0.3]
"""


class _Geometry(BaseModel):
    model_config = ConfigDict(extra="forbid", strict=True)
    track_width_m: float = Field(gt=0.0)
    wheels: list[float]


class _Doc(BaseModel):
    model_config = ConfigDict(extra="forbid", strict=True)
    name: str
    geometry: _Geometry


def test_every_node_keeps_its_line() -> None:
    data, lines = read_yaml(DOC, "v.yaml")
    assert data["geometry"]["wheels"] == [0.1, 0.2, 0.3]
    # counted by hand in DOC above
    assert lines.line(("name",)) == 2
    assert lines.line(("geometry", "track_width_m")) == 4
    assert lines.line(("geometry", "wheels", 2)) == 5
    assert lines.line(("geometry", "absent")) == 3  # falls back to the parent's line


def test_duplicate_keys_are_errors_of_the_callers_class() -> None:
    with pytest.raises(ScenarioError, match=r"v\.yaml:3: duplicate key 'a'"):
        read_yaml("a: 1\nb: 2\na: 3\n", "v.yaml", ScenarioError)
    with pytest.raises(InputError, match="empty vehicle file"):
        read_yaml("", "v.yaml", kind="vehicle file")


@pytest.mark.parametrize(
    ("text", "expected"),
    [
        (DOC.replace("0.55", "-0.55"), "v.yaml:4: geometry.track_width_m: expected a number > 0"),
        (DOC.replace("track_width_m", "track_with_m"), "v.yaml:4: unknown key 'track_with_m'"),
        (DOC.replace("name: husky\n", ""), "(top level): missing required key 'name'"),
    ],
)
def test_schema_errors_name_file_line_and_field_for_any_model(text: str, expected: str) -> None:
    data, lines = read_yaml(text, "v.yaml")
    with pytest.raises(ValidationError) as info:
        _Doc.model_validate(data)
    message = format_validation(info.value, "v.yaml", lines, _Doc)
    assert expected in message and "\n" not in message
