"""Power and kinematic models of skid-steer vehicles (the layer everything stands on)."""

from ecoplan.models.kinematics import (
    BodyTwist,
    TrackICR,
    efficiency_index,
    max_forward_speed,
    max_yaw_rate,
    setpoint_to_tracks,
    tracks_to_twist,
)
from ecoplan.models.limits import (
    Feasibility,
    VehicleParams,
    check_tracks,
    feasibility,
    feasible,
    max_speed_for_radius,
    min_radius_for_speed,
    vr_to_tracks,
)
from ecoplan.models.power import COMPONENTS, MotionCase, PowerBreakdown, motion_case
from ecoplan.models.tracked import (
    TrackedParams,
    dynamic_friction_views,
    tracked_power,
    tracked_total_power,
)
from ecoplan.models.wheeled import SideCoefficients, WheeledParams, side_power, wheeled_power

__all__ = [
    "COMPONENTS",
    "BodyTwist",
    "Feasibility",
    "MotionCase",
    "PowerBreakdown",
    "SideCoefficients",
    "TrackICR",
    "TrackedParams",
    "VehicleParams",
    "WheeledParams",
    "check_tracks",
    "dynamic_friction_views",
    "efficiency_index",
    "feasibility",
    "feasible",
    "max_forward_speed",
    "max_speed_for_radius",
    "max_yaw_rate",
    "min_radius_for_speed",
    "motion_case",
    "setpoint_to_tracks",
    "side_power",
    "tracked_power",
    "tracked_total_power",
    "tracks_to_twist",
    "vr_to_tracks",
    "wheeled_power",
]
