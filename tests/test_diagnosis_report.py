"""A report people can read (issue 12, item 8): report.md, ``--json -``, assumptions stated.

The logs are BorealTC-like current logs converted at an assumed bus voltage (the reader states
it in the log's notes) and a CSV with a column the log format does not know (ignored and
named); both must appear in the JSON and in ``report.md``.
"""

from __future__ import annotations

import json

import numpy as np
import pytest

from ecoplan.cli import main
from ecoplan.diagnose.pipeline import diagnose
from ecoplan.diagnose.report_md import report_markdown
from ecoplan.dynamics.drive import follow_commands
from ecoplan.dynamics.log import Log
from ecoplan.io.logcsv import read_log_csv
from ecoplan.presets import vehicle
from ecoplan.synth.cases import generate_case
from synth_logs import mixed_commands


def _logs_with_an_extra_column(tmp_path):  # type: ignore[no-untyped-def]
    case = generate_case(3, "sensor_delay", "large", n_waypoint_runs=1, rate_hz=10.0)
    paths = []
    for p in case.write(tmp_path / "logs"):
        lines = p.read_text().splitlines()
        head = next(i for i, line in enumerate(lines) if not line.startswith("#"))
        lines[head] += ",battery_temp_c"
        for i in range(head + 1, len(lines)):
            lines[i] += ",31.5"
        p.write_text("\n".join(lines) + "\n")
        paths.append(str(p))
    return case, paths


def test_json_dash_prints_only_json_on_stdout(tmp_path, capsys) -> None:  # type: ignore[no-untyped-def]
    case, paths = _logs_with_an_extra_column(tmp_path)
    code = main(
        ["diagnose", *paths, "--vehicle", case.vehicle, "--terrain", case.terrain, "--json", "-"]
    )
    cap = capsys.readouterr()
    assert code == 0
    obj = json.loads(cap.out)  # stdout is exactly one JSON document
    assert obj["verdict"]["effect"] == "sensor_delay"
    assert "verdict: sensor_delay" in cap.err  # the text went to stderr
    notes = " ".join(obj["log"]["notes"])
    assert "battery_temp_c" in notes  # the ignored column is named


def test_out_writes_a_readable_report(tmp_path, capsys) -> None:  # type: ignore[no-untyped-def]
    case, paths = _logs_with_an_extra_column(tmp_path)
    assert "battery_temp_c" in " ".join(read_log_csv(paths[0]).notes)
    out = tmp_path / "out"
    code = main(
        [
            "diagnose",
            *paths,
            "--vehicle",
            case.vehicle,
            "--terrain",
            case.terrain,
            "--out",
            str(out),
        ]
    )
    assert code == 0
    text = (out / "report.md").read_text()
    for heading in (
        "## What was found",
        "## The numbers",
        "## Where",
        "## What to do next",
        "## Input and assumptions",
    ):
        assert heading in text
    assert "`sensor_delay`" in text and "battery_temp_c" in text
    # every gap figure of the JSON is in the report, with its meaning
    obj = json.loads((out / "diagnosis.json").read_text())
    assert f"{obj['gap']['before']:.1f} W" in text and f"{obj['gap']['after']:.1f} W" in text


def test_bus_voltage_assumption_is_stated(tmp_path) -> None:  # type: ignore[no-untyped-def]
    from ecoplan.diagnose.pipeline import diagnose
    from ecoplan.diagnose.report import to_json_dict
    from ecoplan.diagnose.report_md import report_markdown

    case = generate_case(4, "none", "large", n_waypoint_runs=1, rate_hz=10.0)
    logs = [
        lg.with_notes("p_total = 24 V x (curL + curR): the bus voltage is an assumption")
        for lg in case.logs
    ]  # type: ignore[attr-defined]
    d = diagnose(logs, case.vehicle, case.terrain)
    assert "24 V" in " ".join(to_json_dict(d)["log"]["notes"])
    assert "24 V" in report_markdown(d)
    assert np.isfinite(d.gap_final_w)


@pytest.mark.parametrize("odometry", [False, True])
def test_a_slope_without_one_frame_says_where_its_heading_is_counted_from(
    odometry: bool,
) -> None:
    # Three runs on one plane (0.05 rad rising towards world heading 1.0 rad), written here
    # with numpy: each run starts facing another way (0, 2.0, -2.2 rad) and logs no pose, only
    # a gyro -- or a pose from odometry restarted at the run's start (pose_frame "run").  The
    # uphill heading can only be told in the first run's frame; the report says so, and the
    # value is the plane's heading seen from run 1's start (1.0 - 0 rad).
    params = vehicle("auriga-beta-wide", "asphalt")
    hz, grade, uphill = 20.0, 0.05, 1.0
    runs = []
    for k, start in enumerate((0.0, 2.0, -2.2)):
        rng = np.random.default_rng(40 + k)
        n = int(120 * hz)
        t = np.arange(n) / hz
        cl, cr = mixed_commands(rng, n, hz, params.top_track_speed_mps)
        vl = follow_commands(t, cl, params.accel_max_mps2)
        vr = follow_commands(t, cr, params.accel_max_mps2)
        wz = (vr - vl) / params.icr.spread_m
        own = np.cumsum(wz) / hz  # the heading in the frame the run started in
        climb = 0.5 * (vl + vr) * np.cos(start + own - uphill)
        p = params.power(vl, vr).total_w + params.mass_kg * 9.81 * np.sin(grade) * climb / (
            params.eta
        )
        p = p + rng.normal(0.0, 3.0, n)
        vx = 0.5 * (vl + vr)
        pose = {
            "x": np.cumsum(vx * np.cos(own)) / hz if odometry else None,
            "y": np.cumsum(vx * np.sin(own)) / hz if odometry else None,
            "yaw": own if odometry else None,
        }
        runs.append(
            Log(
                t=t,
                v_left=vl,
                v_right=vr,
                p_total=p,
                v_left_cmd=cl,
                v_right_cmd=cr,
                wz=wz,
                run_id=f"r{k}",
                pose_frame="run" if odometry else "world",
                **pose,
            )
        )
    d = diagnose(runs, params)
    assert d.attribution.verdict == "slope"
    text = report_markdown(d)
    if odometry:
        assert "counted from the x axis of run `r0`'s frame" in text
        assert "pose_frame: run" in text  # the stated assumption
        assert d.space_map is None  # three frames are no map
    else:
        assert "counted from the heading run `r0` started in" in text
    heading = d.attribution.fitted["slope"].params_["uphill_heading_rad"]
    assert abs(np.angle(np.exp(1j * (heading - uphill)))) < 0.2


def test_pose_frame_given_on_the_command_line_is_used_and_stated(tmp_path, capsys) -> None:  # type: ignore[no-untyped-def]
    # The simulator's runs log a pose in one world frame; --pose-frame run says otherwise for
    # every log (as a user with odometry files would, without editing them): the report
    # states it, and no place on a map is searched.
    case = generate_case(1, "none", "large", n_waypoint_runs=1, rate_hz=10.0)
    paths = [str(p) for p in case.write(tmp_path / "logs")]
    assert len(paths) >= 2
    args = ["diagnose", *paths, "--vehicle", case.vehicle, "--terrain", case.terrain]
    assert main([*args, "--pose-frame", "run", "--json", "-"]) == 0
    obj = json.loads(capsys.readouterr().out)
    assert any(n.startswith("pose_frame: run") for n in obj["log"]["notes"])
    assert "terrain_patch" not in [e["name"] for e in obj["effects"]]
    assert main([*args, "--json", "-"]) == 0
    obj = json.loads(capsys.readouterr().out)
    assert not any(n.startswith("pose_frame") for n in obj["log"]["notes"])
    assert "terrain_patch" in [e["name"] for e in obj["effects"]]
    # a value outside the format is a usage error (exit 2), before any log is read
    assert main([*args, "--pose-frame", "odom"]) == 2
    assert "--pose-frame" in capsys.readouterr().err
