"""Loading a scenario file: safe YAML, schema validation, one-line errors, then building.

Loading is defensive: the YAML is read by :func:`ecoplan.io.yaml.read_yaml` (safe
loader only, bounded alias expansion, duplicate keys rejected), and every error -- YAML
syntax, schema, geometry -- is a :class:`~ecoplan.errors.ScenarioError` whose one-line
message names the file, the line, the field and what was expected, e.g.::

    scenarios/ab.yaml:14: speed.v_mps: expected a number > 0; got -0.5

>>> sc = parse_scenario('''
... name: tiny
... vehicle: {preset: pioneer-3at}
... terrain: asphalt
... map: {bounds: {min: [0, 0], max: [10, 10]}}
... start: {x: 1, y: 1}
... waypoints: [[9, 9]]
... ''')
>>> sc.spec.vehicle.preset, sc.goal_xy
('pioneer-3at', (9.0, 9.0))
"""

from __future__ import annotations

from collections.abc import Sequence
from pathlib import Path

from pydantic import ValidationError

from ecoplan.app.scenario.build import Scenario, build_scenario
from ecoplan.app.scenario.schema import MAX_FILE_BYTES, ScenarioSpec
from ecoplan.errors import ScenarioError
from ecoplan.io.yaml import LineMap, format_validation, read_text, read_yaml

__all__ = ["load_scenario", "parse_scenario", "with_vehicle", "with_waypoints"]


def load_scenario(path: str | Path) -> Scenario:
    """Load and validate a scenario file.

    Parameters
    ----------
    path : str or Path
        The YAML file.

    Returns
    -------
    Scenario
        The validated scenario with its geometry and vehicle built.

    Raises
    ------
    ScenarioError
        Missing or unreadable file, invalid YAML, schema violation or impossible geometry;
        the one-line message names the file, the line and the field.
    """
    text = read_text(path, MAX_FILE_BYTES, ScenarioError, kind="scenario file")
    return parse_scenario(text, source=str(Path(path)))


def parse_scenario(text: str, source: str = "<string>") -> Scenario:
    """Validate scenario YAML text; see :func:`load_scenario`.

    Parameters
    ----------
    text : str
        YAML document.
    source : str
        Name used in error messages (a file path).

    Returns
    -------
    Scenario
        The validated scenario.
    """
    if len(text) > MAX_FILE_BYTES:
        raise ScenarioError(f"{source}: scenario too large (at most {MAX_FILE_BYTES} characters)")
    if "\x00" in text:
        raise ScenarioError(f"{source}: not a text file (NUL character)")
    data, lines = read_yaml(text, source, ScenarioError, kind="scenario file")
    if not isinstance(data, dict):
        kind = type(data).__name__
        raise ScenarioError(
            f"{source}:{lines.line(()) or 1}: expected a mapping of sections at top level; "
            f"got {kind}"
        )
    try:
        spec = ScenarioSpec.model_validate(data)
    except ValidationError as exc:
        raise ScenarioError(format_validation(exc, source, lines, ScenarioSpec)) from None
    except RecursionError:
        raise ScenarioError(f"{source}: document nested too deeply") from None
    return build_scenario(spec, source, lines)


def with_waypoints(sc: Scenario, points: Sequence[Sequence[float]]) -> Scenario:
    """The scenario with fixed waypoints instead of its planner, goal and variants.

    The patched spec is validated and built again like a file (points outside the map or
    inside an obstacle are errors); messages name the source with ``(--waypoints)``.

    Parameters
    ----------
    sc : Scenario
        A loaded scenario.
    points : sequence of (x, y)
        The waypoints after the start [m].

    Returns
    -------
    Scenario
        The scenario driving through ``points`` (planner ``none``).

    Raises
    ------
    ScenarioError
        The patched scenario is invalid.
    """
    data = sc.spec.model_dump(exclude_none=True)
    data.update(waypoints=[[float(x), float(y)] for x, y in points], compare=[])
    data.pop("planner", None)
    data.pop("goal", None)
    source = f"{sc.source} (--waypoints)"
    lines = LineMap()  # no lines: the patched spec is not a file
    try:
        spec = ScenarioSpec.model_validate(data)
    except ValidationError as exc:
        raise ScenarioError(format_validation(exc, source, lines, ScenarioSpec)) from None
    return build_scenario(spec, source, lines)


def with_vehicle(sc: Scenario, vehicle: str | Path) -> Scenario:
    """The scenario with another vehicle: a vehicle file, a corrected model or a preset.

    The scenario's overrides belong to its own vehicle and are dropped; its terrains
    (default and regions) must exist in the new vehicle's terrain table.  A corrected
    model (``corrected_model.json`` of ``ecoplan diagnose --out``) drives on the terrain
    it was calibrated on, so the scenario must give no other terrain and no regions.

    Parameters
    ----------
    sc : Scenario
        A loaded scenario.
    vehicle : str or Path
        A vehicle file (``husky.yaml``), a corrected model (``*.json``), both relative to
        the working directory, or a preset.

    Returns
    -------
    Scenario

    Raises
    ------
    ScenarioError
        The vehicle cannot be read or lacks a terrain of the scenario.
    """
    text = str(vehicle)
    path = Path(text).expanduser()
    data = sc.spec.model_dump(exclude_none=True)
    if text.lower().endswith(".json"):
        data["vehicle"] = {"model": str(path.resolve())}
    elif path.exists() or text.endswith((".yaml", ".yml")):
        data["vehicle"] = {"file": str(path.resolve())}
    else:
        data["vehicle"] = {"preset": text}
    source = f"{sc.source} (--vehicle)"
    lines = LineMap()
    try:
        spec = ScenarioSpec.model_validate(data)
    except ValidationError as exc:
        raise ScenarioError(format_validation(exc, source, lines, ScenarioSpec)) from None
    return build_scenario(spec, source, lines)
