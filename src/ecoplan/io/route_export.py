"""Write a planned route for the field's tools: a ROS 2 bag, GeoJSON and CSV.

* ``route_bag/`` -- a ROS 2 bag (rosbags, MCAP storage) with one ``nav_msgs/msg/Path``
  message on ``/plan`` in frame ``map`` (REP-103: x east/forward, y north/left); each
  pose's orientation is the heading of the segment leaving it (a yaw about +z, as a
  quaternion ``(0, 0, sin(yaw/2), cos(yaw/2))``); the last pose keeps the last heading.
* ``route.geojson`` -- a FeatureCollection with one LineString in **map-frame metres**
  (not WGS84: the map has no geodetic anchor; ``properties.crs_note`` says so), with the
  speed and the planner as properties.
* ``route.csv`` -- ``x_m, y_m, yaw_rad, speed_mps``, one row per waypoint.

>>> import numpy as np, tempfile, pathlib
>>> d = pathlib.Path(tempfile.mkdtemp())
>>> files = write_route(d, np.array([[0.0, 0.0], [1.0, 0.0], [1.0, 1.0]]), 0.5)
>>> sorted(p.name for p in files)
['route.csv', 'route.geojson', 'route_bag']
"""

from __future__ import annotations

import csv
import json
import math
import shutil
from pathlib import Path

import numpy as np

from ecoplan._typing import ArrayLike, FloatArray
from ecoplan.errors import InputError

__all__ = ["route_headings", "write_route", "write_route_bag"]


def route_headings(waypoints: ArrayLike) -> FloatArray:
    """Heading of the segment leaving each waypoint [rad]; the last repeats the previous."""
    pts = np.asarray(waypoints, dtype=np.float64).reshape(-1, 2)
    if len(pts) < 2:
        raise InputError(f"a route needs at least 2 waypoints, got {len(pts)}")
    d = np.diff(pts, axis=0)
    yaw = np.arctan2(d[:, 1], d[:, 0])
    return np.asarray(np.append(yaw, yaw[-1]), dtype=np.float64)


def write_route_bag(
    folder: str | Path,
    waypoints: ArrayLike,
    *,
    topic: str = "/plan",
    frame_id: str = "map",
    stamp_ns: int = 0,
) -> Path:
    """Write the route as one ``nav_msgs/msg/Path`` in a ROS 2 MCAP bag (module doc).

    Parameters
    ----------
    folder : str or Path
        Bag directory to create (replaced if it exists).
    waypoints : array_like, shape (N, 2)
        Route in the map frame [m].
    topic, frame_id : str
        Topic and frame of the message.
    stamp_ns : int
        Header stamp and bag timestamp [ns].

    Returns
    -------
    Path
        The bag directory.
    """
    from rosbags.rosbag2 import StoragePlugin, Writer
    from rosbags.typesys import Stores, get_typestore

    pts = np.asarray(waypoints, dtype=np.float64).reshape(-1, 2)
    yaw = route_headings(pts)
    ts = get_typestore(Stores.ROS2_HUMBLE)
    t = ts.types
    stamp = t["builtin_interfaces/msg/Time"](sec=stamp_ns // 10**9, nanosec=stamp_ns % 10**9)
    header = t["std_msgs/msg/Header"](stamp=stamp, frame_id=frame_id)
    poses = [
        t["geometry_msgs/msg/PoseStamped"](
            header=header,
            pose=t["geometry_msgs/msg/Pose"](
                position=t["geometry_msgs/msg/Point"](x=float(x), y=float(y), z=0.0),
                orientation=t["geometry_msgs/msg/Quaternion"](
                    x=0.0, y=0.0, z=math.sin(a / 2.0), w=math.cos(a / 2.0)
                ),
            ),
        )
        for (x, y), a in zip(pts, yaw, strict=True)
    ]
    msg = t["nav_msgs/msg/Path"](header=header, poses=poses)
    out = Path(folder)
    if out.exists():
        shutil.rmtree(out)
    with Writer(out, version=8, storage_plugin=StoragePlugin.MCAP) as writer:
        conn = writer.add_connection(topic, "nav_msgs/msg/Path", typestore=ts)
        writer.write(conn, stamp_ns, ts.serialize_cdr(msg, "nav_msgs/msg/Path"))
    return out


def write_route(
    folder: str | Path,
    waypoints: ArrayLike,
    speed_mps: float,
    *,
    planner: str = "",
    frame_id: str = "map",
) -> list[Path]:
    """Write ``route_bag/``, ``route.geojson`` and ``route.csv`` into ``folder``.

    Parameters
    ----------
    folder : str or Path
        Output folder (created).
    waypoints : array_like, shape (N, 2)
        Route in the map frame [m].
    speed_mps : float
        Cruise speed of the route [m/s].
    planner : str
        Planner name, kept as a GeoJSON property.
    frame_id : str
        Frame of the route.

    Returns
    -------
    list of Path
        The files written.
    """
    out = Path(folder)
    out.mkdir(parents=True, exist_ok=True)
    pts = np.asarray(waypoints, dtype=np.float64).reshape(-1, 2)
    yaw = route_headings(pts)
    bag = write_route_bag(out / "route_bag", pts, frame_id=frame_id)
    feature = {
        "type": "Feature",
        "geometry": {"type": "LineString", "coordinates": pts.tolist()},
        "properties": {
            "frame_id": frame_id,
            "crs_note": "map-frame metres (REP-103), not WGS84",
            "speed_mps": float(speed_mps),
            "planner": planner,
        },
    }
    gj = out / "route.geojson"
    gj.write_text(json.dumps({"type": "FeatureCollection", "features": [feature]}, indent=1))
    path_csv = out / "route.csv"
    with open(path_csv, "w", newline="") as fh:
        w = csv.writer(fh)
        w.writerow(["x_m", "y_m", "yaw_rad", "speed_mps"])
        for (x, y), a in zip(pts, yaw, strict=True):
            w.writerow([f"{x:.6f}", f"{y:.6f}", f"{a:.6f}", f"{speed_mps:g}"])
    return [bag, gj, path_csv]
