"""Building a scenario: geometry, world and vehicle from a validated spec.

Turns a :class:`~ecoplan.app.scenario.schema.ScenarioSpec` into a :class:`Scenario`
(map polygons, the planning :class:`~ecoplan.geometry.world.World`, the vehicle with its
terrains, an optional corrected model) and checks what the schema alone cannot: valid
polygons, speeds under the vehicle's top track speed, points inside the map and outside
obstacles, a goal reachable from the start.  Errors name the file, line and field.
"""

from __future__ import annotations

from collections.abc import Sequence
from dataclasses import dataclass
from pathlib import Path
from typing import Any

from shapely import Point as ShapelyPoint
from shapely import Polygon
from shapely.validation import explain_validity

from ecoplan.app.scenario.elevation import GroundElevation, ground_elevation
from ecoplan.app.scenario.schema import (
    MAX_FILE_BYTES,
    PlannerSection,
    ScenarioSpec,
    Shape,
    SpeedSection,
)
from ecoplan.errors import InputError, ScenarioError
from ecoplan.geometry.maps import GridMap
from ecoplan.geometry.world import GeometryError, World, rectangle
from ecoplan.io.vehicles import load_vehicle
from ecoplan.io.yaml import LineMap, error_at, one_line
from ecoplan.presets import VehicleParams, vehicle

__all__ = ["Case", "Scenario", "build_scenario"]


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
    vehicle : TrackedParams or WheeledParams
        Vehicle preset, overrides and default terrain (``.on(terrain)`` gives parameters).
    bounds : shapely.Polygon
        Map bounds.
    obstacles : tuple of shapely.Polygon
        Obstacles, not inflated.
    regions : tuple of (str, str, shapely.Polygon)
        Terrain regions as (name, terrain preset, polygon), later ones on top.
    world : World or GridMap
        The planning world (inflated obstacles, free space, terrain lookup): a polygon
        world, or the inflated occupancy grid of a ``map: {ros: ...}`` scenario.
    model : CorrectedModel or None
        The corrected model of ``vehicle.model`` (:mod:`ecoplan.diagnose.corrected`), if any.
    """

    spec: ScenarioSpec
    source: str
    vehicle: VehicleParams
    bounds: Polygon
    obstacles: tuple[Polygon, ...]
    regions: tuple[tuple[str, str, Polygon], ...]
    world: World | GridMap
    model: Any = None

    @property
    def name(self) -> str:
        """Scenario name."""
        return self.spec.name

    @property
    def params(self) -> VehicleParams:
        """Vehicle parameters on the default terrain."""
        return self.vehicle

    @property
    def elevation(self) -> GroundElevation | None:
        """Ground elevation ``z(x, y)`` of ``terrain.elevation`` (None: flat ground)."""
        t = self.spec.terrain
        return None if t.elevation is None else ground_elevation(t.elevation)

    @property
    def default_terrain(self) -> str:
        """Default terrain preset name."""
        return str(self.vehicle.terrain)

    @property
    def vehicle_name(self) -> str:
        """The vehicle's stable name (its preset or file name)."""
        src = self.vehicle.source
        return self.vehicle.name if src is None else src.name

    @property
    def goal_xy(self) -> tuple[float, float]:
        """The goal position: ``goal``, else the last fixed waypoint [m]."""
        if self.spec.goal is not None:
            return self.spec.goal.xy
        assert self.spec.waypoints is not None
        x, y = self.spec.waypoints[-1]
        return (x, y)

    def base_case(self) -> Case:
        """The scenario itself as one case (its ``compare`` variants left out)."""
        return Case(self.spec.name, self.spec.model_copy(update={"compare": []}), self.source)

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


def _err(source: str, lines: LineMap, loc: Sequence[str | int], msg: str) -> InputError:
    return error_at(source, lines, loc, msg, ScenarioError)


def _valid_polygon(
    shape: Shape, source: str, lines: LineMap, loc: tuple[str | int, ...]
) -> Polygon:
    poly = shape.geometry()
    if not poly.is_valid:
        reason = explain_validity(poly)
        what = "self-intersecting" if "Self-intersection" in reason else "invalid"
        raise _err(source, lines, (*loc, "polygon"), f"{what} polygon ({reason})")
    if poly.area <= 0.0:
        raise _err(source, lines, loc, "shape has zero area")
    return poly


def build_scenario(
    spec: ScenarioSpec, source: str = "<string>", lines: LineMap | None = None
) -> Scenario:
    """Build the geometry, world and vehicle of a validated spec and check them.

    Parameters
    ----------
    spec : ScenarioSpec
        The validated file contents.
    source : str
        Where it came from, for messages; relative corrected-model paths are resolved
        against its folder.
    lines : LineMap, optional
        Lines of the YAML document, so errors name the line.

    Returns
    -------
    Scenario
        The built scenario.

    Raises
    ------
    ScenarioError
        Invalid polygons, an unknown preset, terrain or override, a speed above the
        vehicle's top track speed, a point outside the map or inside an obstacle, an
        unreachable goal.
    """
    lines = LineMap() if lines is None else lines
    model = _load_model(spec, source, lines) if spec.vehicle.model is not None else None
    veh = _build_vehicle(spec, source, lines, model)
    # terrain outside every region: the scenario's (the corrected model's) default
    default = spec.terrain.default if model is None else model.terrain
    for i, region in enumerate(spec.terrain.regions):
        try:
            veh.on(region.terrain)
        except InputError as exc:
            raise _err(source, lines, ("terrain", "regions", i, "terrain"), str(exc)) from None
    if spec.map.ros is not None:
        grid = _load_grid(spec, source, lines, veh, default)
        xmin, ymin, xmax, ymax = (float(v) for v in grid.extent())
        scenario = Scenario(
            spec, source, veh, rectangle(xmin, ymin, xmax, ymax), (), (), grid, model
        )
        _check_speeds(scenario, lines)
        _check_points(scenario, lines)
        return scenario
    assert spec.map.bounds is not None  # the schema asks for bounds or ros
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
            default_terrain=default,
        )
    except GeometryError as exc:
        raise _err(source, lines, ("map",), str(exc)) from None
    scenario = Scenario(spec, source, veh, bounds, obstacles, regions, world, model)
    _check_speeds(scenario, lines)
    _check_points(scenario, lines)
    return scenario


def _load_grid(
    spec: ScenarioSpec, source: str, lines: LineMap, veh: VehicleParams, default: str | None
) -> GridMap:
    """The inflated occupancy grid (and terrain layer) of ``map: {ros: FILE.yaml}``."""
    from ecoplan.io.rosmap import load_ros_map

    assert spec.map.ros is not None
    base = Path(source).parent if source != "<string>" else Path(".")
    layer = spec.terrain.layer
    if layer is not None:
        for value, terrain in layer.legend.items():
            try:
                veh.on(terrain)
            except InputError as exc:
                loc = ("terrain", "layer", "legend", value)
                raise _err(source, lines, loc, str(exc)) from None
    try:
        return load_ros_map(
            base / spec.map.ros,
            inflation_m=spec.map.inflation_m,
            unknown=spec.map.unknown,
            terrain_image=None if layer is None else (base / layer.image).resolve(),
            terrain_legend=None if layer is None else layer.legend,
            default_terrain=default,
        )
    except InputError as exc:
        where = ("terrain", "layer") if layer is not None and "terrain" in str(exc) else ("map",)
        raise _err(
            source, lines, (*where, "ros") if where == ("map",) else where, str(exc)
        ) from None


def _load_model(spec: ScenarioSpec, source: str, lines: LineMap) -> Any:
    """The corrected model named by ``vehicle.model`` (path relative to the scenario)."""
    assert spec.vehicle.model is not None
    try:
        from ecoplan.diagnose.corrected import load_corrected_model
    except ImportError:  # pragma: no cover - the diagnosis package ships with ecoplan
        raise _err(
            source, lines, ("vehicle", "model"), "corrected models need ecoplan.diagnose.corrected"
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
        raise _err(source, lines, loc, one_line(str(exc))) from None
    if spec.terrain.regions or spec.terrain.default not in (None, model.terrain):
        ground = (
            f"on {model.terrain!r}"
            if model.terrain is not None
            else "on its logs' ground, which it does not name (diagnosed without --terrain)"
        )
        raise _err(
            source,
            lines,
            ("terrain",),
            f"a corrected model is calibrated {ground}: give no other terrain and no terrain "
            "regions",
        )
    return model


def _model_overrides(model: Any) -> dict[str, Any]:
    from ecoplan.models.wheeled import SideCoefficients

    params: dict[str, Any] = model.to_dict()["params"]
    return {k: SideCoefficients(**v) if isinstance(v, dict) else v for k, v in params.items()}


def _file_vehicle(spec: ScenarioSpec, source: str, lines: LineMap) -> VehicleParams:
    """The vehicle file named by ``vehicle.file`` (path relative to the scenario)."""
    v = spec.vehicle
    assert v.file is not None
    path = Path(v.file).expanduser()
    if not path.is_absolute() and not source.startswith("<"):
        path = Path(source).parent / path
    try:
        veh = load_vehicle(path)
    except InputError as exc:
        raise _err(source, lines, ("vehicle", "file"), one_line(str(exc))) from None
    try:
        vehicle(veh)
    except InputError as exc:  # pragma: no cover - load_vehicle builds every terrain
        raise _err(source, lines, ("vehicle", "file"), one_line(str(exc))) from None
    if spec.terrain.default is not None and spec.terrain.default.lower() not in veh.terrains:
        raise _err(
            source,
            lines,
            ("terrain", "default"),
            f"{veh.name} has no terrain {spec.terrain.default!r}; "
            f"accepted: {', '.join(veh.terrains)}",
        )
    try:
        return vehicle(veh, spec.terrain.default, v.overrides)
    except (InputError, TypeError, ValueError) as exc:
        raise _err(source, lines, ("vehicle", "overrides"), one_line(str(exc))) from None


def _build_vehicle(
    spec: ScenarioSpec, source: str, lines: LineMap, model: Any = None
) -> VehicleParams:
    v = spec.vehicle
    if model is not None:
        try:
            return vehicle(model.vehicle, model.terrain, {**_model_overrides(model), **v.overrides})
        except (InputError, TypeError, ValueError) as exc:
            raise _err(source, lines, ("vehicle", "overrides"), one_line(str(exc))) from None
    if v.file is not None:
        return _file_vehicle(spec, source, lines)
    assert v.preset is not None
    try:
        return vehicle(v.preset, spec.terrain.default, v.overrides)
    except (InputError, TypeError, ValueError) as exc:
        loc: tuple[str | int, ...] = ("vehicle",)
        try:
            vehicle(v.preset)
        except (InputError, TypeError, ValueError):
            loc = ("vehicle", "preset")
        else:
            try:
                vehicle(v.preset, spec.terrain.default)
            except (InputError, TypeError, ValueError):
                loc = ("terrain", "default")
            else:
                for key in v.overrides:
                    try:
                        vehicle(v.preset, spec.terrain.default, {key: v.overrides[key]})
                    except (InputError, TypeError, ValueError):
                        loc = ("vehicle", "overrides", key)
                        break
        raise _err(source, lines, loc, one_line(str(exc))) from None


def _check_speeds(sc: Scenario, lines: LineMap) -> None:
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


def _check_points(sc: Scenario, lines: LineMap) -> None:
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
    if isinstance(world, GridMap):
        if not world.connected(spec.start.xy, sc.goal_xy):
            raise _err(
                sc.source,
                lines,
                ("goal",),
                "unreachable: obstacles (inflated by "
                f"{spec.map.inflation_m:g} m) separate the goal from the start",
            )
        return
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
