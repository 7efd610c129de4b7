"""Scenario files: a YAML schema for an ecoplan run, loaded safely and validated.

A scenario names a vehicle preset (with overrides), the terrain (or terrain regions),
a map (bounds and obstacles), start and goal poses or a fixed waypoint list, the
planner, the speed policy, the heading-controller gains (tracked paper eq. 23), the
simulation step, an optional battery budget, the outputs, and optional ``compare``
variants.  The schema is documented in ``scenarios/README.md``.

Loading is defensive: the YAML is read with PyYAML's safe loader only, aliases are
expanded in a bounded way (alias bombs and recursive aliases are rejected before any
Python object is built), and every error -- YAML syntax, schema, geometry -- is a
:class:`~ecoplan.errors.ScenarioError` whose one-line message names the file, the
line, the field and what was expected, e.g.::

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

import dataclasses
import math
import re
import types
import typing
from collections.abc import Mapping, Sequence
from dataclasses import dataclass
from pathlib import Path
from typing import Annotated, Any, Literal, Union

import numpy as np
import yaml
from pydantic import BaseModel, ConfigDict, Field, ValidationError, model_validator
from shapely import Point as ShapelyPoint
from shapely import Polygon, box
from shapely.validation import explain_validity

from ecoplan._typing import BoolArray, FloatArray
from ecoplan.cost import EnergyCost, LengthCost, path_cost
from ecoplan.errors import InputError, PlanningError, ScenarioError
from ecoplan.geometry.world import GeometryError, World, circle
from ecoplan.models.limits import check_tracks
from ecoplan.presets import VehicleParams, VehicleSpec
from ecoplan.sim.controller import HeadingController
from ecoplan.sim.simulate import SimConfig, SimResult, simulate_waypoints

__all__ = [
    "MAX_FILE_BYTES",
    "MAX_YAML_NODES",
    "BatterySection",
    "BatteryVerdict",
    "Case",
    "CaseResult",
    "ControllerSection",
    "MapSection",
    "OutputsSection",
    "PlanOutcome",
    "PlannerSection",
    "Pose",
    "Region",
    "Scenario",
    "ScenarioSpec",
    "Shape",
    "SimulationSection",
    "SpeedSection",
    "TerrainSection",
    "Variant",
    "VehicleSection",
    "load_scenario",
    "parse_scenario",
    "plan_case",
    "run_case",
    "simulate_case",
]

#: Largest scenario file accepted [bytes].
MAX_FILE_BYTES = 1_000_000
#: Largest number of YAML nodes after alias expansion (defence against alias bombs).
MAX_YAML_NODES = 200_000
#: Largest nesting depth of the YAML document.
MAX_YAML_DEPTH = 64
#: Bound on every coordinate and length [m]; larger numbers are rejected as typos.
MAX_COORD_M = 1e5

# --------------------------------------------------------------------------- schema

Coord = Annotated[float, Field(ge=-MAX_COORD_M, le=MAX_COORD_M, allow_inf_nan=False)]
PositiveLength = Annotated[float, Field(gt=0.0, le=MAX_COORD_M, allow_inf_nan=False)]
XY = Annotated[list[Coord], Field(min_length=2, max_length=2)]
Name = Annotated[str, Field(min_length=1, max_length=200)]


class _Section(BaseModel):
    """Base of every schema section: unknown keys and type coercions are errors."""

    model_config = ConfigDict(extra="forbid", strict=True, frozen=True)


class Rectangle(_Section):
    """Axis-aligned rectangle from its lower-left ``min`` to its upper-right ``max`` [m]."""

    min: XY
    max: XY

    @model_validator(mode="after")
    def _ordered(self) -> Rectangle:
        if not (self.min[0] < self.max[0] and self.min[1] < self.max[1]):
            raise ValueError("max must be greater than min in both x and y")
        return self

    def geometry(self) -> Polygon:
        """The rectangle as a shapely polygon."""
        return box(self.min[0], self.min[1], self.max[0], self.max[1])  # validated above


class Circle(_Section):
    """Circle of centre ``center`` [m] and radius ``radius_m`` [m]."""

    center: XY
    radius_m: PositiveLength

    def geometry(self) -> Polygon:
        """The circle as a 32-gon that contains the disc (:func:`ecoplan.geometry.world.circle`)."""
        return circle(self.center[0], self.center[1], self.radius_m, n_vertices=32)


class Shape(_Section):
    """One of ``polygon`` (list of ``[x, y]`` vertices), ``rectangle`` or ``circle``."""

    name: Name | None = None
    polygon: Annotated[list[XY], Field(min_length=3, max_length=10_000)] | None = None
    rectangle: Rectangle | None = None
    circle: Circle | None = None

    @model_validator(mode="after")
    def _exactly_one(self) -> Shape:
        given = [k for k in ("polygon", "rectangle", "circle") if getattr(self, k) is not None]
        if len(given) != 1:
            raise ValueError(
                "give exactly one of polygon, rectangle, circle"
                + (f" (got {', '.join(given)})" if given else "")
            )
        return self

    def geometry(self) -> Polygon:
        """The shape as a shapely polygon (not validated; see :func:`parse_scenario`)."""
        if self.rectangle is not None:
            return self.rectangle.geometry()
        if self.circle is not None:
            return self.circle.geometry()
        assert self.polygon is not None
        return Polygon(self.polygon)


class Region(Shape):
    """A terrain region: a shape with the terrain preset that applies inside it."""

    terrain: Name


class VehicleSection(_Section):
    """Vehicle preset (``ecoplan.presets``) or corrected model, and parameter overrides.

    ``model`` is a file written by ``ecoplan diagnose --out`` (``corrected_model.json``:
    the preset, its re-identified parameters and the fitted unmodelled effect), relative
    to the scenario file.
    """

    preset: Name | None = None
    model: Annotated[str, Field(min_length=1, max_length=4096)] | None = None
    overrides: dict[str, Any] = Field(default_factory=dict)

    @model_validator(mode="after")
    def _one_source(self) -> VehicleSection:
        if (self.preset is None) == (self.model is None):
            raise ValueError("give exactly one of preset (a vehicle preset) or model (a file)")
        return self


class TerrainSection(_Section):
    """Default terrain preset and optional regions of other terrains.

    A plain string ``terrain: marble`` is shorthand for ``{default: marble}``.
    """

    default: Name | None = None
    regions: Annotated[list[Region], Field(max_length=1000)] = Field(default_factory=list)

    @model_validator(mode="before")
    @classmethod
    def _shorthand(cls, data: Any) -> Any:
        return {"default": data} if isinstance(data, str) else data


class MapSection(_Section):
    """Map bounds, obstacles and footprint inflation [m]."""

    bounds: Rectangle
    obstacles: Annotated[list[Shape], Field(max_length=10_000)] = Field(default_factory=list)
    inflation_m: Annotated[float, Field(ge=0.0, le=100.0, allow_inf_nan=False)] = 0.4


class Pose(_Section):
    """A planar pose: position [m] and heading ``yaw_deg`` [deg, counter-clockwise]."""

    x: Coord
    y: Coord
    yaw_deg: Annotated[float, Field(ge=-360.0, le=360.0, allow_inf_nan=False)] = 0.0

    @property
    def xy(self) -> tuple[float, float]:
        """Position as a tuple [m]."""
        return (self.x, self.y)

    @property
    def yaw_rad(self) -> float:
        """Heading [rad]."""
        return math.radians(self.yaw_deg)


class PlannerSection(_Section):
    """Planner choice: ``graph`` (waypoint graph), ``ompl`` (by ``name``) or ``none``."""

    type: Literal["graph", "ompl", "none"] = "graph"
    name: Name | None = None
    time_s: Annotated[float, Field(gt=0.0, le=3600.0, allow_inf_nan=False)] = 1.0
    seed: Annotated[int, Field(ge=0, le=2**32 - 1)] = 0
    objective: Literal["energy", "length"] = "energy"
    k: Annotated[int, Field(ge=1, le=20)] = 1
    max_iterations: Annotated[int, Field(ge=1, le=10_000_000)] | None = None

    @model_validator(mode="after")
    def _name_for_ompl(self) -> PlannerSection:
        if self.type == "ompl" and self.name is None:
            raise ValueError("planner type ompl needs a name (e.g. RRTstar, BITstar, PRMstar)")
        return self


class SpeedSection(_Section):
    """Speed policy: one ``fixed`` speed ``v_mps`` or the energy-``optimal`` speed.

    With ``optimal`` the route is planned at ``v_mps`` and its speed is then chosen in
    ``[v_min_mps, v_max_mps]`` (default: up to the top track speed).
    """

    policy: Literal["fixed", "optimal"] = "fixed"
    v_mps: Annotated[float, Field(gt=0.0, le=10.0, allow_inf_nan=False)] = 0.5
    v_min_mps: Annotated[float, Field(gt=0.0, le=10.0, allow_inf_nan=False)] = 0.05
    v_max_mps: Annotated[float, Field(gt=0.0, le=10.0, allow_inf_nan=False)] | None = None

    @model_validator(mode="after")
    def _range(self) -> SpeedSection:
        if self.v_max_mps is not None and self.v_max_mps <= self.v_min_mps:
            raise ValueError("v_max_mps must be greater than v_min_mps")
        return self


class ControllerSection(_Section):
    """Heading controller of tracked eq. (23): ``w_sp = gain * phi_e``, switch at ``d_th_m``."""

    gain: Annotated[float, Field(gt=0.0, le=100.0, allow_inf_nan=False)] = 0.18
    d_th_m: Annotated[float, Field(gt=0.0, le=100.0, allow_inf_nan=False)] = 1.0


class SimulationSection(_Section):
    """Simulator settings: integration step ``dt_s`` and time limit ``t_max_s`` [s]."""

    dt_s: Annotated[float, Field(gt=0.0, le=1.0, allow_inf_nan=False)] = 0.01
    t_max_s: Annotated[float, Field(gt=0.0, le=86_400.0, allow_inf_nan=False)] = 1200.0


class BatterySection(_Section):
    """Battery budget: capacity [Wh] and the fraction kept in reserve."""

    capacity_wh: Annotated[float, Field(gt=0.0, le=1e6, allow_inf_nan=False)]
    reserve_fraction: Annotated[float, Field(ge=0.0, lt=1.0, allow_inf_nan=False)] = 0.0

    @property
    def usable_j(self) -> float:
        """Energy available to the mission [J]."""
        return self.capacity_wh * 3600.0 * (1.0 - self.reserve_fraction)


class OutputsSection(_Section):
    """Which artifacts ``ecoplan run`` writes into ``--out``."""

    csv: bool = True
    figures: Annotated[list[Literal["png", "svg"]], Field(max_length=2)] = Field(
        default_factory=lambda: list[Literal["png", "svg"]](["png"])
    )
    markdown: bool = True


class Variant(_Section):
    """One case of ``ecoplan compare``: a name and the sections it replaces."""

    name: Name
    waypoints: Annotated[list[XY], Field(min_length=1, max_length=10_000)] | None = None
    planner: PlannerSection | None = None
    speed: SpeedSection | None = None
    controller: ControllerSection | None = None


class ScenarioSpec(_Section):
    """The whole scenario file (see ``scenarios/README.md``)."""

    version: Literal[1] = 1
    name: Name
    description: Annotated[str, Field(max_length=5000)] = ""
    vehicle: VehicleSection
    terrain: TerrainSection = Field(default_factory=TerrainSection)
    map: MapSection
    start: Pose
    goal: Pose | None = None
    waypoints: Annotated[list[XY], Field(min_length=1, max_length=10_000)] | None = None
    planner: PlannerSection | None = None
    speed: SpeedSection = Field(default_factory=SpeedSection)
    controller: ControllerSection = Field(default_factory=ControllerSection)
    simulation: SimulationSection = Field(default_factory=SimulationSection)
    battery: BatterySection | None = None
    outputs: OutputsSection = Field(default_factory=OutputsSection)
    compare: Annotated[list[Variant], Field(max_length=500)] = Field(default_factory=list)

    @model_validator(mode="after")
    def _route(self) -> ScenarioSpec:
        planner = self.planner.type if self.planner is not None else None
        if self.waypoints is None and (planner in (None, "none")):
            if self.goal is None:
                raise ValueError("give a goal (with a planner) or a fixed waypoints list")
            if planner == "none":
                raise ValueError("planner type none needs a fixed waypoints list")
        if self.waypoints is not None and planner not in (None, "none"):
            raise ValueError("give either waypoints (planner none) or a planner, not both")
        names = [v.name for v in self.compare]
        if len(set(names)) != len(names):
            raise ValueError("compare variant names must be distinct")
        return self


# ------------------------------------------------------------------- built scenario


@dataclass(frozen=True)
class Case:
    """One independent run of a scenario: the spec with a variant's sections applied.

    Attributes
    ----------
    name : str
        Variant name (the scenario's name for the base case).
    spec : ScenarioSpec
        The resolved spec (picklable, so cases travel to worker processes).
    """

    name: str
    spec: ScenarioSpec
    source: str = "<string>"

    @property
    def planner(self) -> PlannerSection:
        """The planner section, ``type: none`` when the case has fixed waypoints."""
        if self.spec.waypoints is not None:
            return PlannerSection(type="none")
        return self.spec.planner if self.spec.planner is not None else PlannerSection()


@dataclass(frozen=True)
class Scenario:
    """A validated scenario with its geometry and vehicle built.

    Attributes
    ----------
    spec : ScenarioSpec
        The validated file contents.
    source : str
        Where it came from (a path or ``"<string>"``), for messages and reports.
    vehicle : VehicleSpec
        Vehicle preset, overrides and default terrain (``.on(terrain)`` gives parameters).
    bounds : shapely.Polygon
        Map bounds.
    obstacles : tuple of shapely.Polygon
        Obstacles, not inflated.
    regions : tuple of (str, str, shapely.Polygon)
        Terrain regions as (name, terrain preset, polygon), later ones on top.
    world : World
        The planning world (inflated obstacles, free space, terrain lookup).
    model : CorrectedModel or None
        The corrected model of ``vehicle.model`` (:mod:`ecoplan.diagnose.loop`), if any.
    """

    spec: ScenarioSpec
    source: str
    vehicle: VehicleSpec
    bounds: Polygon
    obstacles: tuple[Polygon, ...]
    regions: tuple[tuple[str, str, Polygon], ...]
    world: World
    model: Any = None

    @property
    def name(self) -> str:
        """Scenario name."""
        return self.spec.name

    @property
    def params(self) -> VehicleParams:
        """Vehicle parameters on the default terrain."""
        return self.vehicle.on()

    @property
    def default_terrain(self) -> str:
        """Default terrain preset name."""
        return self.vehicle.terrain or _default_terrain(self.vehicle.name)

    @property
    def goal_xy(self) -> tuple[float, float]:
        """The goal position: ``goal``, else the last fixed waypoint [m]."""
        if self.spec.goal is not None:
            return self.spec.goal.xy
        assert self.spec.waypoints is not None
        x, y = self.spec.waypoints[-1]
        return (x, y)

    def cases(self) -> list[Case]:
        """Independent cases: the ``compare`` variants, or the scenario itself."""
        if not self.spec.compare:
            return [Case(self.spec.name, self.spec, self.source)]
        out = []
        for v in self.spec.compare:
            update: dict[str, Any] = {}
            if v.waypoints is not None:
                update["waypoints"] = v.waypoints
                update["planner"] = None
            elif v.planner is not None:
                update["planner"] = v.planner
                update["waypoints"] = None if v.planner.type != "none" else self.spec.waypoints
            for key in ("speed", "controller"):
                if getattr(v, key) is not None:
                    update[key] = getattr(v, key)
            update["compare"] = []
            out.append(Case(v.name, self.spec.model_copy(update=update), self.source))
        return out


def _default_terrain(preset: str) -> str:
    from ecoplan.presets import default_terrain

    return default_terrain(preset)


# ------------------------------------------------------------------------ YAML layer


Path_ = tuple[str | int, ...]


class _LineMap:
    """Line (1-based) of every node of the document, by its path of keys and indices."""

    def __init__(self) -> None:
        self.lines: dict[Path_, int] = {}

    def line(self, path: Sequence[str | int]) -> int | None:
        """Line of ``path`` or of its longest existing prefix."""
        p = tuple(path)
        while p:
            if p in self.lines:
                return self.lines[p]
            p = p[:-1]
        return self.lines.get((), None)


def _check_size(root: yaml.Node) -> None:
    """Reject recursive aliases, too deep documents and alias bombs (expanded size)."""
    sizes: dict[int, int] = {}
    active: set[int] = set()

    def size(node: yaml.Node, depth: int) -> int:
        key = id(node)
        if key in sizes:
            return sizes[key]
        if key in active:
            raise ScenarioError("recursive YAML alias (an anchor used inside itself)")
        if depth > MAX_YAML_DEPTH:
            raise ScenarioError(f"YAML nested deeper than {MAX_YAML_DEPTH} levels")
        active.add(key)
        total = 1
        if isinstance(node, yaml.SequenceNode):
            for child in node.value:
                total += size(child, depth + 1)
                if total > MAX_YAML_NODES:
                    break
        elif isinstance(node, yaml.MappingNode):
            for k, v in node.value:
                total += size(k, depth + 1) + size(v, depth + 1)
                if total > MAX_YAML_NODES:
                    break
        active.discard(key)
        if total > MAX_YAML_NODES:
            raise ScenarioError(
                f"YAML document expands to more than {MAX_YAML_NODES} nodes "
                "(too many aliases: an alias bomb?)"
            )
        sizes[key] = total
        return total

    size(root, 0)


def _record_lines(node: yaml.Node, path: Path_, out: _LineMap) -> None:
    out.lines.setdefault(path, node.start_mark.line + 1)
    if isinstance(node, yaml.SequenceNode):
        for i, child in enumerate(node.value):
            _record_lines(child, (*path, i), out)
    elif isinstance(node, yaml.MappingNode):
        seen: set[str] = set()
        for k, v in node.value:
            if isinstance(k, yaml.ScalarNode):
                if k.value in seen and k.value != "<<":
                    raise ScenarioError(
                        f"{k.start_mark.line + 1}: duplicate key {k.value!r} in "
                        f"{_dotted(path)} (YAML would silently keep the last one)"
                    )
                seen.add(k.value)
                # the key's own line, so "unknown key" points at it
                out.lines.setdefault((*path, k.value), k.start_mark.line + 1)
                _record_lines(v, (*path, k.value), out)


class _SafeLoader(yaml.SafeLoader):
    """PyYAML's safe loader, also reading ``1e-3`` as a float (YAML 1.2; 1.1 needs ``1.0e-3``)."""


_SafeLoader.add_implicit_resolver(
    "tag:yaml.org,2002:float",
    re.compile(r"^[-+]?(?:[0-9][0-9_]*)(?:\.[0-9_]*)?[eE][-+]?[0-9]+$"),
    list("-+0123456789"),
)


def _read_yaml(text: str, source: str) -> tuple[Any, _LineMap]:
    """Parse YAML safely; return the data and the line map."""
    try:
        loader = _SafeLoader(text)
    except yaml.YAMLError as exc:  # e.g. a control character: the reader checks first
        raise ScenarioError(f"{source}: invalid YAML: {_one_line(str(exc))}") from None
    try:
        try:
            node = loader.get_single_node()
        except yaml.MarkedYAMLError as exc:
            mark = exc.problem_mark or exc.context_mark
            line = f":{mark.line + 1}" if mark is not None else ""
            problem = exc.problem or exc.context or "invalid YAML"
            raise ScenarioError(f"{source}{line}: invalid YAML: {problem}") from None
        except yaml.YAMLError as exc:
            raise ScenarioError(f"{source}: invalid YAML: {_one_line(str(exc))}") from None
        except RecursionError:
            raise ScenarioError(f"{source}: YAML nested too deeply") from None
        if node is None:
            raise ScenarioError(f"{source}: empty scenario file; expected a mapping")
        try:
            _check_size(node)
        except ScenarioError as exc:
            raise ScenarioError(f"{source}: {exc}") from None
        lines = _LineMap()
        try:
            _record_lines(node, (), lines)
        except ScenarioError as exc:
            raise ScenarioError(f"{source}:{exc}") from None
        try:
            data = loader.construct_document(node)
        except yaml.MarkedYAMLError as exc:
            mark = exc.problem_mark or exc.context_mark
            line = f":{mark.line + 1}" if mark is not None else ""
            problem = exc.problem or exc.context or "invalid value"
            raise ScenarioError(f"{source}{line}: invalid YAML value: {problem}") from None
        except (yaml.YAMLError, ValueError, TypeError, OverflowError, RecursionError) as exc:
            why = _one_line(str(exc))
            if "integer string conversion" in why:
                why = "an integer with more than 4300 digits"
            raise ScenarioError(f"{source}: invalid YAML value: {why}") from None
    finally:
        loader.dispose()
    return data, lines


def _one_line(text: str, limit: int = 160) -> str:
    flat = " ".join(text.split())
    return flat if len(flat) <= limit else flat[: limit - 3] + "..."


# --------------------------------------------------------------- pydantic -> message


def _dotted(loc: Sequence[str | int]) -> str:
    out = ""
    for part in loc:
        if isinstance(part, int):
            out += f"[{part}]"
        else:
            out += ("." if out else "") + str(part)
    return out or "(top level)"


def _unwrap(tp: Any) -> Any:
    """The model class inside ``X | None``, ``list[X]``, ``Annotated[X, ...]``."""
    while True:
        origin = typing.get_origin(tp)
        if origin is Annotated:
            tp = typing.get_args(tp)[0]
        elif origin in (Union, types.UnionType):
            args = [a for a in typing.get_args(tp) if a is not type(None)]
            tp = args[0] if len(args) == 1 else tp
            if len(args) != 1:
                return tp
        elif origin is list:
            tp = typing.get_args(tp)[0]
        else:
            return tp


def _model_at(loc: Sequence[str | int]) -> type[BaseModel] | None:
    model: Any = ScenarioSpec
    for part in loc:
        if isinstance(part, int):
            continue
        if not (isinstance(model, type) and issubclass(model, BaseModel)):
            return None
        field = model.model_fields.get(part)
        if field is None:
            return None
        model = _unwrap(field.annotation)
    return model if isinstance(model, type) and issubclass(model, BaseModel) else None


_EXPECTED = {
    "float_type": "expected a number",
    "int_type": "expected an integer",
    "string_type": "expected a string",
    "bool_type": "expected true or false",
    "list_type": "expected a list",
    "dict_type": "expected a mapping",
    "model_type": "expected a mapping",
    "model_attributes_type": "expected a mapping",
    "finite_number": "expected a finite number",
}


def _describe(err: Mapping[str, Any]) -> str:
    kind = str(err.get("type", ""))
    ctx = err.get("ctx") or {}
    if kind in _EXPECTED:
        return _EXPECTED[kind]
    bounds = {
        "greater_than": ">",
        "greater_than_equal": ">=",
        "less_than": "<",
        "less_than_equal": "<=",
    }
    if kind in bounds:
        limit = next(iter(ctx.values()), "?")
        return f"expected a number {bounds[kind]} {limit}"
    if kind == "literal_error":
        return f"expected one of {ctx.get('expected', '?')}"
    if kind in ("too_short", "too_long"):
        n = ctx.get("min_length") if kind == "too_short" else ctx.get("max_length")
        word = "at least" if kind == "too_short" else "at most"
        return f"expected {word} {n} items"
    if kind == "value_error":
        return str(err.get("msg", "")).removeprefix("Value error, ")
    return str(err.get("msg", "invalid value")).lower()


def _short_repr(value: Any) -> str:
    text = repr(value)
    return text if len(text) <= 40 else text[:37] + "..."


def _format_validation(exc: ValidationError, source: str, lines: _LineMap) -> str:
    # an unknown key (often a typo) explains more than the "missing" error it causes
    rank = {"extra_forbidden": 0, "missing": 2}
    errors = sorted(exc.errors(include_url=False), key=lambda e: rank.get(e["type"], 1))
    err = errors[0]
    loc = [p for p in err["loc"] if isinstance(p, str | int)]
    line = lines.line(loc)
    where = f"{source}:{line}" if line is not None else source
    kind = err["type"]
    if kind == "extra_forbidden":
        parent = loc[:-1]
        model = _model_at(parent)
        accepted = f"; accepted: {', '.join(model.model_fields)}" if model else ""
        msg = f"unknown key {loc[-1]!r} in {_dotted(parent)}{accepted}"
    elif kind == "missing":
        msg = f"{_dotted(loc[:-1])}: missing required key {loc[-1]!r}"
    else:
        msg = f"{_dotted(loc)}: {_describe(err)}"
        if kind != "value_error" and "input" in err:
            msg += f"; got {_short_repr(err['input'])}"
    more = len(errors) - 1
    suffix = f" (and {more} more error{'s' if more > 1 else ''})" if more else ""
    return _one_line(f"{where}: {msg}{suffix}", limit=400)


# ------------------------------------------------------------------------- loading


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
    p = Path(path)
    try:
        if not p.is_file():
            raise ScenarioError(f"{p}: no such scenario file")
        size = p.stat().st_size
        if size > MAX_FILE_BYTES:
            raise ScenarioError(f"{p}: file too large ({size} bytes; at most {MAX_FILE_BYTES})")
        raw = p.read_bytes()
    except OSError as exc:
        raise ScenarioError(f"{p}: cannot read: {exc.strerror or exc}") from None
    try:
        text = raw.decode("utf-8")
    except UnicodeDecodeError as exc:
        raise ScenarioError(f"{p}: not UTF-8 text (byte {exc.start})") from None
    return parse_scenario(text, source=str(p))


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
    data, lines = _read_yaml(text, source)
    if not isinstance(data, dict):
        kind = type(data).__name__
        raise ScenarioError(
            f"{source}:{lines.line(()) or 1}: expected a mapping of sections at top level; "
            f"got {kind}"
        )
    try:
        spec = ScenarioSpec.model_validate(data)
    except ValidationError as exc:
        raise ScenarioError(_format_validation(exc, source, lines)) from None
    except RecursionError:
        raise ScenarioError(f"{source}: document nested too deeply") from None
    return _build(spec, source, lines)


def _err(source: str, lines: _LineMap, loc: Sequence[str | int], msg: str) -> ScenarioError:
    line = lines.line(loc)
    where = f"{source}:{line}" if line is not None else source
    return ScenarioError(_one_line(f"{where}: {_dotted(loc)}: {msg}", limit=400))


def _valid_polygon(
    shape: Shape, source: str, lines: _LineMap, loc: tuple[str | int, ...]
) -> Polygon:
    poly = shape.geometry()
    if not poly.is_valid:
        reason = explain_validity(poly)
        what = "self-intersecting" if "Self-intersection" in reason else "invalid"
        raise _err(source, lines, (*loc, "polygon"), f"{what} polygon ({reason})")
    if poly.area <= 0.0:
        raise _err(source, lines, loc, "shape has zero area")
    return poly


def _build(spec: ScenarioSpec, source: str, lines: _LineMap) -> Scenario:
    model = _load_model(spec, source, lines) if spec.vehicle.model is not None else None
    veh = _build_vehicle(spec, source, lines, model)
    for i, region in enumerate(spec.terrain.regions):
        try:
            veh.on(region.terrain)
        except InputError as exc:
            raise _err(source, lines, ("terrain", "regions", i, "terrain"), str(exc)) from None
    bounds = spec.map.bounds.geometry()
    obstacles = tuple(
        _valid_polygon(o, source, lines, ("map", "obstacles", i))
        for i, o in enumerate(spec.map.obstacles)
    )
    regions = tuple(
        (
            r.name or f"{r.terrain} region {i}",
            r.terrain,
            _valid_polygon(r, source, lines, ("terrain", "regions", i)),
        )
        for i, r in enumerate(spec.terrain.regions)
    )
    try:
        world = World(
            bounds,
            obstacles,
            inflation_m=spec.map.inflation_m,
            regions=[(poly, terrain) for _, terrain, poly in regions],
            default_terrain=veh.terrain,
        )
    except GeometryError as exc:
        raise _err(source, lines, ("map",), str(exc)) from None
    scenario = Scenario(spec, source, veh, bounds, obstacles, regions, world, model)
    _check_speeds(scenario, lines)
    _check_points(scenario, lines)
    return scenario


def _load_model(spec: ScenarioSpec, source: str, lines: _LineMap) -> Any:
    """The corrected model named by ``vehicle.model`` (path relative to the scenario)."""
    assert spec.vehicle.model is not None
    try:
        from ecoplan.diagnose.loop import load_corrected_model
    except ImportError:  # pragma: no cover - the diagnosis package ships with ecoplan
        raise _err(
            source, lines, ("vehicle", "model"), "corrected models need ecoplan.diagnose.loop"
        ) from None
    path = Path(spec.vehicle.model).expanduser()
    if not path.is_absolute() and not source.startswith("<"):
        path = Path(source).parent / path
    loc = ("vehicle", "model")
    if not path.is_file():
        raise _err(source, lines, loc, f"no such corrected-model file {str(path)!r}")
    if path.stat().st_size > MAX_FILE_BYTES:
        raise _err(source, lines, loc, f"{str(path)!r} is too large for a corrected model")
    try:
        model = load_corrected_model(path)
    except InputError as exc:
        raise _err(source, lines, loc, _one_line(str(exc))) from None
    if spec.terrain.regions or spec.terrain.default not in (None, model.terrain):
        raise _err(
            source,
            lines,
            ("terrain",),
            f"a corrected model is calibrated on {model.terrain!r}: give no other terrain "
            "and no terrain regions",
        )
    return model


def _model_overrides(model: Any) -> dict[str, Any]:
    from ecoplan.models.wheeled import SideCoefficients

    params: dict[str, Any] = model.to_dict()["params"]
    return {k: SideCoefficients(**v) if isinstance(v, dict) else v for k, v in params.items()}


def _build_vehicle(
    spec: ScenarioSpec, source: str, lines: _LineMap, model: Any = None
) -> VehicleSpec:
    v = spec.vehicle
    if model is not None:
        try:
            return VehicleSpec.of(
                model.vehicle, model.terrain, {**_model_overrides(model), **v.overrides}
            )
        except (InputError, TypeError, ValueError) as exc:
            raise _err(source, lines, ("vehicle", "overrides"), _one_line(str(exc))) from None
    assert v.preset is not None
    try:
        return VehicleSpec.of(v.preset, spec.terrain.default, v.overrides)
    except (InputError, TypeError, ValueError) as exc:
        loc: tuple[str | int, ...] = ("vehicle",)
        try:
            VehicleSpec.of(v.preset)
        except (InputError, TypeError, ValueError):
            loc = ("vehicle", "preset")
        else:
            try:
                VehicleSpec.of(v.preset, spec.terrain.default)
            except (InputError, TypeError, ValueError):
                loc = ("terrain", "default")
            else:
                for key in v.overrides:
                    try:
                        VehicleSpec.of(v.preset, spec.terrain.default, {key: v.overrides[key]})
                    except (InputError, TypeError, ValueError):
                        loc = ("vehicle", "overrides", key)
                        break
        raise _err(source, lines, loc, _one_line(str(exc))) from None


def _check_speeds(sc: Scenario, lines: _LineMap) -> None:
    top = sc.params.top_track_speed_mps
    checks: list[tuple[tuple[str | int, ...], SpeedSection]] = [(("speed",), sc.spec.speed)]
    checks += [(("compare", i, "speed"), v.speed) for i, v in enumerate(sc.spec.compare) if v.speed]
    for loc, speed in checks:
        if speed.v_mps > top:
            raise _err(
                sc.source,
                lines,
                (*loc, "v_mps"),
                f"{speed.v_mps} m/s is above the top track speed of {sc.params.name} ({top} m/s)",
            )


def _check_points(sc: Scenario, lines: _LineMap) -> None:
    spec = sc.spec
    named: list[tuple[tuple[str | int, ...], tuple[float, float]]] = [(("start",), spec.start.xy)]
    if spec.goal is not None:
        named.append((("goal",), spec.goal.xy))
    for i, (x, y) in enumerate(spec.waypoints or []):
        named.append((("waypoints", i), (x, y)))
    for vi, variant in enumerate(spec.compare):
        for i, (x, y) in enumerate(variant.waypoints or []):
            named.append((("compare", vi, "waypoints", i), (x, y)))
    for loc, xy in named:
        pt = ShapelyPoint(xy)
        if not sc.bounds.covers(pt):
            raise _err(sc.source, lines, loc, f"point {xy} lies outside the map bounds")
        for j, obstacle in enumerate(sc.obstacles):
            if obstacle.covers(pt):
                raise _err(sc.source, lines, loc, f"point {xy} lies inside obstacle {j}")
    planned = any(case.planner.type != "none" for case in sc.cases())
    if not planned:
        return
    world = sc.world
    for loc, xy in ((("start",), spec.start.xy), (("goal",), sc.goal_xy)):
        try:
            world.check_point(xy, loc[0])
        except GeometryError as exc:
            msg = f"{exc}; the planner cannot start or end there"
            raise _err(sc.source, lines, loc, msg) from None
    start = ShapelyPoint(spec.start.xy)
    goal = ShapelyPoint(sc.goal_xy)
    for part in getattr(world.free_space, "geoms", [world.free_space]):
        if part.covers(start):
            if not part.covers(goal):
                raise _err(
                    sc.source,
                    lines,
                    ("goal",),
                    "unreachable: obstacles (inflated by "
                    f"{spec.map.inflation_m:g} m) separate the goal from the start",
                )
            return


# ------------------------------------------------------------------------- running


@dataclass(frozen=True, eq=False)
class PlanOutcome:
    """The route of one case: planned, or the fixed waypoints.

    Attributes
    ----------
    planner : str
        ``"fixed"``, ``"graph"`` or ``"ompl:<name>"``, with ``"/length"`` for the
        shortest-path baseline.
    waypoints : ndarray
        ``(n, 2)`` polyline [m]: the start, then the goals in order.
    speed_mps : float
        Speed set point of the heading controller ``v_sp`` [m/s].
    planning_time_s : float
        Wall-clock time of planning [s] (0 for fixed waypoints).
    estimate_energy_j : float or None
        Analytic energy of the route by :func:`ecoplan.cost.path_cost` [J].
    feasible : bool or None
        Whether every command of the analytic execution respects the vehicle's limits.
    violations : tuple of str
        The violated constraints, naming the segment or turn.
    alternatives : tuple of ndarray
        Further distinct waypoint sets the planner returned (``planner.k > 1``).
    speed_policy : str
        ``"fixed"`` or ``"optimal"`` (:func:`ecoplan.planning.speed.best_speed` on the
        route, after planning at the nominal ``speed.v_mps``).
    """

    planner: str
    waypoints: FloatArray
    speed_mps: float
    planning_time_s: float = 0.0
    estimate_energy_j: float | None = None
    feasible: bool | None = None
    violations: tuple[str, ...] = ()
    alternatives: tuple[FloatArray, ...] = ()
    speed_policy: str = "fixed"

    @property
    def length_m(self) -> float:
        """Length of the waypoint polyline [m]."""
        return float(np.sum(np.hypot(*np.diff(self.waypoints, axis=0).T)))


@dataclass(frozen=True)
class BatteryVerdict:
    """Whether a run fits its battery budget, and where the battery would run out.

    Attributes
    ----------
    capacity_wh : float
        Battery capacity [Wh].
    usable_j : float
        Energy available after the reserve [J].
    used_j : float
        Energy the simulated run used [J].
    completes : bool
        True when the run reached its goal within the usable energy.
    margin_j : float
        ``usable_j - used_j`` [J] (negative when the battery runs out).
    empty_at : tuple of float or None
        ``(t_s, x_m, y_m, distance_m)`` where the usable energy is exhausted, if it is.
    """

    capacity_wh: float
    usable_j: float
    used_j: float
    completes: bool
    margin_j: float
    empty_at: tuple[float, float, float, float] | None

    @property
    def margin_fraction(self) -> float:
        """Margin as a fraction of the usable energy."""
        return self.margin_j / self.usable_j

    def sentence(self) -> str:
        """One sentence for reports."""
        wh = self.used_j / 3600.0
        if self.completes:
            return (
                f"The plan completes on the battery: it uses {wh:.2f} Wh of "
                f"{self.usable_j / 3600.0:.2f} Wh usable, a margin of "
                f"{self.margin_j / 3600.0:.2f} Wh ({100 * self.margin_fraction:.0f} %)."
            )
        if self.empty_at is None:
            return (
                f"The run did not reach its goal (time limit); it used {wh:.2f} Wh of "
                f"{self.usable_j / 3600.0:.2f} Wh usable."
            )
        t, x, y, d = self.empty_at
        return (
            f"The plan does NOT complete: the {self.usable_j / 3600.0:.2f} Wh usable run out "
            f"after {t:.0f} s and {d:.1f} m, at ({x:.1f}, {y:.1f}) m; the whole run needs "
            f"{wh:.2f} Wh ({-self.margin_j / 3600.0:.2f} Wh more)."
        )


@dataclass(frozen=True, eq=False)
class CaseResult:
    """Plan, simulation and energy accounting of one case.

    The power is the simulator's, re-evaluated per step on the terrain under the
    vehicle when the map has terrain regions (the kinematics stay those of the default
    terrain).

    Attributes
    ----------
    name : str
        Case name.
    plan : PlanOutcome
        The route.
    sim : SimResult or None
        The heading-controller run (None for ``plan`` only).
    p_total_w : ndarray
        Electrical power per step [W] (terrain-aware).
    p_left_w, p_right_w : ndarray
        Mechanical power per side per step [W] (terrain-aware).
    components_w : dict of str to ndarray
        Power breakdown per step [W].
    terrain : tuple of str
        Terrain under the vehicle per step.
    energy_j : float
        Energy of locomotion [J].
    breakdown_j : dict of str to float
        Energy per component [J]; sums to ``energy_j``.
    battery : BatteryVerdict or None
        Battery check, when the scenario has a budget.
    violation_s : dict of str to float
        Time the simulated commands spent violating each of the vehicle's limits
        (:func:`ecoplan.models.limits.check_tracks`: top speed, power limits) [s].
    clearance_violation_s : float
        Time the vehicle's centre spent outside the free space (closer to an obstacle
        or to the map edge than ``map.inflation_m``) [s].
    over_limit : ndarray of bool
        Per step, True where the commands violate a limit of the vehicle.
    error : str or None
        Why the case has no route (the planner failed on valid input), else None.
    """

    name: str
    plan: PlanOutcome
    sim: SimResult | None
    p_total_w: FloatArray
    p_left_w: FloatArray
    p_right_w: FloatArray
    components_w: dict[str, FloatArray]
    terrain: tuple[str, ...]
    energy_j: float
    breakdown_j: dict[str, float]
    battery: BatteryVerdict | None
    violation_s: dict[str, float]
    clearance_violation_s: float
    over_limit: BoolArray
    error: str | None = None

    @classmethod
    def unsimulated(cls, name: str, plan: PlanOutcome, error: str | None = None) -> CaseResult:
        """A result holding only a route (``ecoplan plan``) or a planner failure."""
        empty = np.zeros(0)
        no_steps = np.zeros(0, dtype=np.bool_)
        return cls(
            name, plan, None, empty, empty, empty, {}, (), 0.0, {}, None, {}, 0.0, no_steps,
            error=error,
        )  # fmt: skip

    @property
    def cumulative_energy_j(self) -> FloatArray:
        """Energy used up to the start of each step [J]."""
        if self.sim is None:
            return np.zeros(0)
        dt = self.sim.dt_s
        return np.concatenate([[0.0], np.cumsum(self.p_total_w[:-1]) * dt])

    @property
    def peak_power_w(self) -> float:
        """Largest power of an integrated step [W]."""
        if self.sim is None or self.sim.n_steps == 0:
            return 0.0
        return float(np.max(self.p_total_w[:-1]))

    def summary(self) -> dict[str, Any]:
        """JSON-ready numbers of the case (SI units)."""
        out: dict[str, Any] = {
            "name": self.name,
            "planner": self.plan.planner,
            "waypoints": self.plan.waypoints.tolist(),
            "speed_mps": self.plan.speed_mps,
            "speed_policy": self.plan.speed_policy,
            "planning_time_s": round(self.plan.planning_time_s, 4),
            "planned_length_m": round(self.plan.length_m, 4),
            "estimate_energy_j": self.plan.estimate_energy_j,
            "plan_feasible": self.plan.feasible,
            "plan_violations": list(self.plan.violations),
            "error": self.error,
        }
        if self.sim is not None:
            out.update(
                energy_j=self.energy_j,
                time_s=self.sim.time_s,
                length_m=self.sim.length_m,
                psi_rad=self.sim.psi_rad,
                peak_power_w=self.peak_power_w,
                mean_power_w=self.energy_j / self.sim.time_s if self.sim.time_s else 0.0,
                completed=self.sim.completed,
                breakdown_j=dict(self.breakdown_j),
                limit_violation_s=dict(self.violation_s),
                clearance_violation_s=self.clearance_violation_s,
            )
        if self.battery is not None:
            b = self.battery
            out["battery"] = {
                "capacity_wh": b.capacity_wh,
                "usable_j": b.usable_j,
                "used_j": b.used_j,
                "completes": b.completes,
                "margin_j": b.margin_j,
                "margin_fraction": b.margin_fraction,
                "empty_at": (
                    None
                    if b.empty_at is None
                    else dict(zip(("t_s", "x_m", "y_m", "distance_m"), b.empty_at, strict=True))
                ),
            }
        return out


def _case_scenario(case: Case) -> Scenario:
    return _build(case.spec, case.source, _LineMap())


def plan_case(case: Case, *, time_budget_s: float | None = None) -> PlanOutcome:
    """Plan the route of a case (or take its fixed waypoints).

    Parameters
    ----------
    case : Case
        The case.
    time_budget_s : float, optional
        Caps the planner's time budget (tests and quick looks).

    Returns
    -------
    PlanOutcome
        The route and how it was found.

    Raises
    ------
    PlanningError
        The planner found no route within its budget.
    """
    sc = _case_scenario(case)
    spec = case.spec
    planner = case.planner
    speed = float(spec.speed.v_mps)  # the fixed speed, or the nominal one to plan at
    start = np.asarray([spec.start.xy], dtype=np.float64)
    if planner.type == "none":
        assert spec.waypoints is not None
        wps = np.vstack([start, np.asarray(spec.waypoints, dtype=np.float64)])
        plan = PlanOutcome("fixed", wps, speed)
    else:
        plan = _plan_with(sc, planner, speed, time_budget_s)
    if spec.speed.policy == "optimal":
        from ecoplan.planning.speed import best_speed

        top = sc.params.top_track_speed_mps
        choice = best_speed(
            plan.waypoints,
            sc.vehicle,
            world=sc.world,
            initial_heading_rad=spec.start.yaw_rad,
            v_min_mps=spec.speed.v_min_mps,
            v_max_mps=min(spec.speed.v_max_mps or top, top),
        )
        speed = float(choice.speed_mps)
    if plan.estimate_energy_j is None or speed != plan.speed_mps:
        pc = path_cost(
            plan.waypoints,
            sc.vehicle,
            speed,
            world=sc.world,
            initial_heading_rad=spec.start.yaw_rad,
        )
        plan = dataclasses.replace(
            plan,
            speed_mps=speed,
            estimate_energy_j=pc.energy_j,
            feasible=pc.feasible,
            violations=tuple(v.message() for v in pc.violations),
        )
    return dataclasses.replace(plan, speed_policy=spec.speed.policy)


def _plan_with(
    sc: Scenario, planner: PlannerSection, speed_mps: float, time_budget_s: float | None
) -> PlanOutcome:
    cost_cls = EnergyCost if planner.objective == "energy" else LengthCost
    cost = cost_cls(sc.vehicle, speed_mps, world=sc.world)
    budget = planner.time_s if time_budget_s is None else min(planner.time_s, time_budget_s)
    start, goal, heading = sc.spec.start.xy, sc.goal_xy, sc.spec.start.yaw_rad
    if planner.type == "graph":
        from ecoplan.planning.graph import GraphPlanner, GraphPlannerOptions

        options = GraphPlannerOptions(k_paths=planner.k, time_budget_s=budget)
        res = GraphPlanner(sc.world, cost, options).plan(start, goal, initial_heading_rad=heading)
    else:
        from ecoplan.planning.ompl import OmplOptions, OmplPlanner

        assert planner.name is not None
        opts = OmplOptions(
            planner.name,
            time_budget_s=budget,
            seed=planner.seed,
            max_iterations=planner.max_iterations,
        )
        res = OmplPlanner(sc.world, cost, opts).plan(start, goal, initial_heading_rad=heading)
    best = res.best
    name = res.planner
    if planner.objective == "length" and "length" not in name:
        name += "/length"
    return PlanOutcome(
        name,
        np.asarray(best.waypoints, dtype=np.float64),
        speed_mps,
        planning_time_s=res.planning_time_s,
        estimate_energy_j=best.cost.energy_j,
        feasible=best.cost.feasible,
        violations=tuple(v.message() for v in best.cost.violations),
        alternatives=tuple(np.asarray(p.waypoints) for p in res.alternatives[1:]),
    )


def simulate_case(
    case: Case, plan: PlanOutcome | None = None, *, time_budget_s: float | None = None
) -> CaseResult:
    """Plan (unless ``plan`` is given) and simulate one case with the heading controller.

    Parameters
    ----------
    case : Case
        The case.
    plan : PlanOutcome, optional
        A route to simulate instead of planning one.
    time_budget_s : float, optional
        Caps the planner's time budget.

    Returns
    -------
    CaseResult
        The simulated run with its energy accounting and battery verdict.
    """
    sc = _case_scenario(case)
    if plan is None:
        plan = plan_case(case, time_budget_s=time_budget_s)
    spec = case.spec
    ctrl = HeadingController(
        gain=spec.controller.gain, speed_mps=plan.speed_mps, switch_radius_m=spec.controller.d_th_m
    )
    sim = simulate_waypoints(
        sc.params,
        plan.waypoints,
        ctrl,
        start_yaw_rad=spec.start.yaw_rad,
        config=SimConfig(dt_s=spec.simulation.dt_s, t_max_s=spec.simulation.t_max_s),
    )
    return _account(sc, case.name, plan, sim)


def run_case(case: Case, time_budget_s: float | None = None) -> CaseResult:
    """Plan and simulate one case of a sweep; a planner failure becomes a failed result.

    The picklable task of ``ecoplan compare`` and ``bench``: one case that finds no route
    (:class:`~ecoplan.errors.PlanningError`) must not sink the others, so it comes back
    as a :class:`CaseResult` without simulation whose ``error`` says why.  Bad input
    still raises.

    Parameters
    ----------
    case : Case
        The case.
    time_budget_s : float, optional
        Caps the planner's time budget.

    Returns
    -------
    CaseResult
        The simulated case, or a failed one (``sim is None``, ``error`` set).
    """
    try:
        return simulate_case(case, time_budget_s=time_budget_s)
    except PlanningError as exc:
        spec = case.spec
        planner = case.planner
        name = planner.type if planner.name is None else f"{planner.type}:{planner.name}"
        plan = PlanOutcome(name, np.asarray([spec.start.xy]), spec.speed.v_mps)
        return CaseResult.unsimulated(case.name, plan, error=str(exc))


def _account(sc: Scenario, name: str, plan: PlanOutcome, sim: SimResult) -> CaseResult:
    dt = sim.dt_s
    n = sim.n_steps
    if sc.regions:
        pts = np.column_stack([sim.x, sim.y])
        terrain = tuple(t or sc.default_terrain for t in sc.world.terrain_at(pts))
        p_total = np.array(sim.p_total, dtype=np.float64, copy=True)
        p_left = np.array(sim.p_left, dtype=np.float64, copy=True)
        p_right = np.array(sim.p_right, dtype=np.float64, copy=True)
        comps = {k: np.array(v, dtype=np.float64, copy=True) for k, v in sim.components_w.items()}
        for terr in sorted(set(terrain)):
            idx = np.flatnonzero(np.asarray(terrain) == terr)
            pw = sc.vehicle.on(terr).power(sim.v_left[idx], sim.v_right[idx])
            p_total[idx] = pw.total_w
            p_left[idx] = pw.left_w
            p_right[idx] = pw.right_w
            for k, v in pw.components().items():
                comps[k][idx] = v
    else:
        terrain = (sc.default_terrain,) * len(sim.t)
        p_total = np.asarray(sim.p_total, dtype=np.float64)
        p_left = np.asarray(sim.p_left, dtype=np.float64)
        p_right = np.asarray(sim.p_right, dtype=np.float64)
        comps = {k: np.asarray(v, dtype=np.float64) for k, v in sim.components_w.items()}
    if sc.model is not None and sc.model.effect != "none":
        p_total, comps = _with_effect(sc.model, sim, p_total, comps)
    violated = np.full(len(sim.t), "", dtype=object)
    for terr in sorted(set(terrain)):
        idx = np.flatnonzero(np.asarray(terrain) == terr)
        check = check_tracks(sc.vehicle.on(terr), sim.v_left[idx], sim.v_right[idx])
        violated[idx] = check.violated
    names, counts = np.unique(violated[:n].astype(str), return_counts=True)
    violation_s = {str(k): float(c) * dt for k, c in zip(names, counts, strict=True) if k}
    outside = ~sc.world.is_free(sim.x[:n], sim.y[:n])
    clearance_s = float(np.count_nonzero(outside)) * dt
    energy = float(np.sum(p_total[:n]) * dt)
    breakdown = {k: float(np.sum(v[:n]) * dt) for k, v in comps.items()}
    battery = None
    if sc.spec.battery is not None:
        battery = _battery(sc.spec.battery, sim, p_total, energy)
    return CaseResult(
        name,
        plan,
        sim,
        p_total,
        p_left,
        p_right,
        comps,
        terrain,
        energy,
        breakdown,
        battery,
        violation_s,
        clearance_s,
        np.asarray(violated != "", dtype=np.bool_),
    )


def _with_effect(
    model: Any, sim: SimResult, p_total: FloatArray, comps: dict[str, FloatArray]
) -> tuple[FloatArray, dict[str, FloatArray]]:
    """Add a corrected model's fitted effect along the simulated trajectory.

    :meth:`CorrectedModel.trajectory_power` gives the total power with the effect (from the
    commanded speeds for ``actuator_lag``); the difference to the base model's power is
    booked under traction resistance, as the corrected model's steady-state power does.
    """
    lag = model.effect == "actuator_lag"
    vl = sim.v_left_cmd if lag else sim.v_left
    vr = sim.v_right_cmd if lag else sim.v_right
    total = np.asarray(
        model.trajectory_power(sim.t, vl, vr, x=sim.x, y=sim.y, yaw=sim.yaw), dtype=np.float64
    )
    comps = dict(comps)
    comps["resistance_w"] = comps["resistance_w"] + (total - p_total)
    return total, comps


def _battery(
    b: BatterySection, sim: SimResult, p_total: FloatArray, energy: float
) -> BatteryVerdict:
    usable = b.usable_j
    n = sim.n_steps
    cum = np.concatenate([[0.0], np.cumsum(p_total[:n]) * sim.dt_s])
    empty_at = None
    if cum[-1] > usable:
        k = int(np.searchsorted(cum, usable))  # first row with cum >= usable
        dist = np.concatenate([[0.0], np.cumsum(np.hypot(np.diff(sim.x), np.diff(sim.y)))])
        empty_at = (float(sim.t[k]), float(sim.x[k]), float(sim.y[k]), float(dist[k]))
    completes = sim.completed and energy <= usable
    return BatteryVerdict(b.capacity_wh, usable, energy, completes, usable - energy, empty_at)
