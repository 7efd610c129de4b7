"""Route export: nav_msgs/Path in a ROS 2 MCAP bag, GeoJSON and CSV (read back here)."""

from __future__ import annotations

import csv
import json
import math
from pathlib import Path

import numpy as np
import pytest
from rosbags.rosbag2 import Reader
from rosbags.typesys import Stores, get_typestore

from ecoplan.errors import InputError
from ecoplan.io.route_export import write_route

WPS = np.array([[0.0, 0.0], [4.0, 0.0], [4.0, 3.0], [1.0, 7.0]])


def test_bag_geojson_csv_round_trip(tmp_path: Path) -> None:
    files = write_route(tmp_path, WPS, 0.5, planner="lattice:energy")
    assert {p.name for p in files} == {"route_bag", "route.geojson", "route.csv"}
    ts = get_typestore(Stores.ROS2_HUMBLE)
    with Reader(tmp_path / "route_bag") as reader:
        conns = [c for c in reader.connections if c.topic == "/plan"]
        assert [c.msgtype for c in conns] == ["nav_msgs/msg/Path"]
        msgs = [ts.deserialize_cdr(raw, c.msgtype) for c, _, raw in reader.messages(conns)]
    assert len(msgs) == 1
    path = msgs[0]
    assert path.header.frame_id == "map"
    xy = np.array([[p.pose.position.x, p.pose.position.y] for p in path.poses])
    np.testing.assert_allclose(xy, WPS)
    # headings of the leaving segments: 0, 90 deg, atan2(4, -3); the last repeats
    expect = [0.0, math.pi / 2, math.atan2(4.0, -3.0), math.atan2(4.0, -3.0)]
    got = [2.0 * math.atan2(p.pose.orientation.z, p.pose.orientation.w) for p in path.poses]
    np.testing.assert_allclose(got, expect, atol=1e-12)
    gj = json.loads((tmp_path / "route.geojson").read_text())
    line = gj["features"][0]
    assert line["geometry"]["type"] == "LineString"
    np.testing.assert_allclose(line["geometry"]["coordinates"], WPS)
    assert line["properties"]["speed_mps"] == 0.5
    with open(tmp_path / "route.csv") as fh:
        rows = list(csv.DictReader(fh))
    np.testing.assert_allclose([[float(r["x_m"]), float(r["y_m"])] for r in rows], WPS)
    np.testing.assert_allclose([float(r["yaw_rad"]) for r in rows], expect, atol=1e-6)


def test_one_point_route_is_rejected(tmp_path: Path) -> None:
    with pytest.raises(InputError, match="at least 2 waypoints"):
        write_route(tmp_path, WPS[:1], 0.5)


def test_cli_plan_out_writes_the_route(tmp_path: Path) -> None:
    from ecoplan.cli import main

    scenario = Path(__file__).resolve().parents[1] / "scenarios" / "field_site_ros.yaml"
    assert main(["plan", str(scenario), "--out", str(tmp_path), "-q"]) == 0
    assert (tmp_path / "route_bag" / "metadata.yaml").is_file()
    gj = json.loads((tmp_path / "route.geojson").read_text())
    coords = np.asarray(gj["features"][0]["geometry"]["coordinates"])
    np.testing.assert_allclose(coords[0], [3.0, 23.0])
    np.testing.assert_allclose(coords[-1], [57.0, 23.5])
