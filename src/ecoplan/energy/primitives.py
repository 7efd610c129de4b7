"""Cost primitives: the energy of one steady motion, and the vehicle and world the costs see.

Steady motions (the tracked paper's static model; energy = power x duration):

* straight driving at ``v``: ``P_T(v, v) L / v``;
* an on-the-spot turn by ``dpsi`` at yaw rate ``w``: ``P_T(setpoint_to_tracks(0, w))
  |dpsi| / w`` (tracked eqs. 4, 20);
* an arc turn of radius ``r`` at ``v``: ``P_T(vr_to_tracks(v, r)) r |dpsi| / v``.

The energy module sees a vehicle either as parameters on one terrain
(:class:`~ecoplan.models.tracked.TrackedParams`, :class:`~ecoplan.models.wheeled.WheeledParams`)
or as anything with ``on(terrain) -> parameters`` (:class:`TerrainVehicle`, e.g. a preset
spec), and a world as anything with the few queries of :class:`WorldLike`: it imports the
models and the dynamics, nothing above.
"""

from __future__ import annotations

import functools
import math
from collections.abc import Sequence
from typing import Literal, Protocol

import numpy as np

from ecoplan._typing import ArrayLike, BoolArray, FloatArray
from ecoplan.errors import InputError
from ecoplan.models.kinematics import max_yaw_rate, setpoint_to_tracks
from ecoplan.models.limits import check_tracks, min_radius_for_speed, vr_to_tracks
from ecoplan.models.tracked import TrackedParams
from ecoplan.models.wheeled import WheeledParams

__all__ = [
    "TerrainVehicle",
    "TurnMode",
    "Vehicle",
    "VehicleParams",
    "WorldLike",
    "arc_turn_energy",
    "best_spot_yaw_rate",
    "params_on",
    "spot_turn_energy",
    "straight_energy",
]

VehicleParams = TrackedParams | WheeledParams


class TerrainVehicle(Protocol):
    """A vehicle whose parameters follow the terrain (parameters from a vehicle file)."""

    def on(self, terrain: str | None = None) -> VehicleParams:
        """Parameters on ``terrain`` (None: the vehicle's default terrain)."""
        ...


class TerrainPieceLike(Protocol):
    """A straight piece on one terrain (:class:`ecoplan.geometry.world.TerrainPiece`)."""

    @property
    def length_m(self) -> float:
        """Length of the piece [m]."""
        ...

    @property
    def terrain(self) -> str | None:
        """Terrain name (None: the default)."""
        ...


class WorldLike(Protocol):
    """The queries the energy module asks of a map (:class:`ecoplan.geometry.world.World`)."""

    @property
    def has_regions(self) -> bool:
        """True when some region has its own terrain."""
        ...

    @property
    def default_terrain(self) -> str | None:
        """Terrain outside every region."""
        ...

    def terrain_at(self, points: ArrayLike) -> list[str | None]:
        """Terrain at each point."""
        ...

    def split_by_terrain(self, p0: ArrayLike, p1: ArrayLike) -> Sequence[TerrainPieceLike]:
        """Pieces of the segment ``p0 -> p1`` in order, one terrain each."""
        ...

    def segment_free(self, p0: ArrayLike, p1: ArrayLike) -> bool:
        """True when the segment stays in free space."""
        ...

    def polyline_free(self, points: ArrayLike) -> bool:
        """True when the polyline stays in free space."""
        ...

    def polylines_free(self, points: ArrayLike) -> BoolArray:
        """Per polyline of a stack ``(m, n, 2)``, whether it stays in free space."""
        ...


Vehicle = TerrainVehicle | VehicleParams
TurnMode = Literal["auto", "spot", "arc"]

_N_YAW = 256  # yaw-rate grid for the best on-the-spot turn


def params_on(vehicle: Vehicle, terrain: str | None = None) -> VehicleParams:
    """Vehicle parameters on ``terrain``.

    Parameters from a vehicle file (:func:`ecoplan.presets.vehicle`) are evaluated on the
    terrain (``None``: their own); parameters built by hand are returned as they are, which
    is only right in a world without terrain regions (:func:`check_vehicle_world`).
    """
    if isinstance(vehicle, TrackedParams | WheeledParams) and vehicle.source is None:
        return vehicle
    return vehicle.on(terrain)


def check_vehicle_world(vehicle: Vehicle, world: WorldLike | None) -> None:
    """Refuse hand-built parameters in a world with terrain regions (one clear line)."""
    if world is None or not isinstance(vehicle, TrackedParams | WheeledParams):
        return
    if vehicle.source is None and (world.has_regions or world.default_terrain is not None):
        raise InputError(
            "the world has terrain regions: build the vehicle with "
            "ecoplan.presets.vehicle(name or vehicle file, terrain, overrides=...) so that "
            "its parameters follow the terrain (parameters built by hand or changed with "
            "dataclasses.replace hold one terrain)"
        )


def positive_speed(name: str, v: ArrayLike) -> FloatArray:
    """``v`` as an array, or an :class:`~ecoplan.errors.InputError` unless finite and > 0."""
    arr = np.asarray(v, dtype=np.float64)
    if not np.all(np.isfinite(arr)) or np.any(arr <= 0.0):
        raise InputError(f"{name} must be finite and > 0 m/s, got {arr.tolist()!r}")
    return arr


def wrap_pi(angle: ArrayLike) -> FloatArray:
    """Angles wrapped to ``[-pi, pi)`` [rad]."""
    x = np.asarray(angle, dtype=np.float64)
    return np.asarray((x + np.pi) % (2.0 * np.pi) - np.pi, dtype=np.float64)


def straight_energy(params: VehicleParams, length_m: ArrayLike, speed_mps: ArrayLike) -> FloatArray:
    """Energy of straight driving ``P_T(v, v) L / v`` [J] (vectorised).

    Parameters
    ----------
    params : TrackedParams or WheeledParams
        Vehicle on one terrain.
    length_m : array_like
        Segment length(s) [m], >= 0.
    speed_mps : array_like
        Speed(s) [m/s], > 0.

    Examples
    --------
    10 m at 0.5 m/s takes 20 s at the straight-line 421.05 W of Auriga-β on asphalt:

    >>> from ecoplan.presets import vehicle
    >>> round(float(straight_energy(vehicle("auriga-beta-wide", "asphalt"), 10.0, 0.5)), 1)
    8421.1
    """
    v = positive_speed("speed_mps", speed_mps)
    length = np.asarray(length_m, dtype=np.float64)
    return np.asarray(params.power(v, v).total_w * length / v, dtype=np.float64)


def spot_turn_energy(
    params: VehicleParams, dpsi_rad: ArrayLike, yaw_rate_radps: ArrayLike
) -> FloatArray:
    """Energy of an on-the-spot turn by ``dpsi`` at yaw rate ``w`` [J] (vectorised).

    ``P_T(setpoint_to_tracks(0, sign(dpsi) w)) |dpsi| / w`` (tracked eqs. 4, 20).
    """
    dpsi = np.asarray(dpsi_rad, dtype=np.float64)
    w = positive_speed("yaw_rate_radps", yaw_rate_radps)
    sgn = np.where(dpsi < 0.0, -1.0, 1.0)
    vl, vr = setpoint_to_tracks(0.0, sgn * w, params.icr)
    return np.asarray(params.power(vl, vr).total_w * np.abs(dpsi) / w, dtype=np.float64)


def arc_turn_energy(
    params: VehicleParams, dpsi_rad: ArrayLike, speed_mps: ArrayLike, radius_m: ArrayLike
) -> FloatArray:
    """Energy of an arc turn by ``dpsi`` of radius ``r`` at speed ``v`` [J] (vectorised).

    ``P_T(vr_to_tracks(v, sign(dpsi) r)) r |dpsi| / v`` (tracked eq. 4 with ``w = v/r``).
    """
    dpsi = np.asarray(dpsi_rad, dtype=np.float64)
    v = positive_speed("speed_mps", speed_mps)
    r = np.asarray(radius_m, dtype=np.float64)
    if np.any(~(r > 0.0)):
        raise InputError("arc turn radius must be > 0 m (use an on-the-spot turn for r = 0)")
    sgn = np.where(dpsi < 0.0, -1.0, 1.0)
    vl, vr = vr_to_tracks(params, v, sgn * r)
    return np.asarray(params.power(vl, vr).total_w * r * np.abs(dpsi) / v, dtype=np.float64)


@functools.lru_cache(maxsize=256)
def best_spot_yaw_rate(params: VehicleParams) -> tuple[float, float]:
    """Yaw rate of the cheapest feasible on-the-spot turn and its energy per radian.

    Scans ``w`` in ``(0, w_max]`` (tracked eq. 6) for turns both ways; the energy per
    radian ``P_T(w) / w`` falls with ``w`` while the power-up and braking terms dominate,
    so the answer is usually the largest feasible yaw rate.

    Returns
    -------
    tuple of float
        ``(w [rad/s], energy per radian [J/rad])``; ``(nan, inf)`` when no on-the-spot
        turn is feasible (the wheeled model's ``b(0)`` exceeds the side limit).
    """
    wmax = max_yaw_rate(params.icr, params.top_track_speed_mps)
    w = np.linspace(wmax / _N_YAW, wmax, _N_YAW)
    ok = np.ones(w.shape, dtype=bool)
    e = np.zeros(w.shape)
    for sgn in (1.0, -1.0):
        vl, vr = setpoint_to_tracks(0.0, sgn * w, params.icr)
        ok &= check_tracks(params, vl, vr).ok
        e = np.maximum(e, params.power(vl, vr).total_w / w)
    if not ok.any():
        return math.nan, math.inf
    i = int(np.argmin(np.where(ok, e, np.inf)))
    return float(w[i]), float(e[i])


@functools.lru_cache(maxsize=1024)
def _min_radius(params: VehicleParams, speed_mps: float) -> float:
    return float(min_radius_for_speed(params, speed_mps))


def _spot_violation(params: VehicleParams) -> str:
    wmax = max_yaw_rate(params.icr, params.top_track_speed_mps)
    vl, vr = setpoint_to_tracks(0.0, wmax / _N_YAW, params.icr)
    name = str(check_tracks(params, vl, vr).violated.ravel()[0])
    return name or "top_track_speed_mps"
