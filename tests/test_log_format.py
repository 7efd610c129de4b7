"""Tests of the log format (issue 6, item 1 and item 6: bad logs)."""

from __future__ import annotations

import math
from pathlib import Path
from typing import Any

import numpy as np
import pytest
from hypothesis import given, settings
from hypothesis import strategies as st

from ecoplan.diagnose.checks import check_logs
from ecoplan.dynamics.log import Log, fresh_readings, join_runs
from ecoplan.errors import InputError, LogFormatError
from ecoplan.io.logcsv import read_log_csv, write_log_csv
from ecoplan.io.logs import read_logs
from ecoplan.io.rosbag import FieldRef, TopicMap, read_rosbag
from ecoplan.presets import vehicle

BAD = Path(__file__).parent / "logs_bad"

# file -> fragments the one-line message must contain (column and/or 1-based file line)
BAD_CASES: dict[str, tuple[str, ...]] = {
    "missing_p_total.csv": ("'p_total'", "line 1", "missing"),
    "foreign_header.csv": ("'t'", "'v_left'", "'p_total'", "missing"),
    "semicolon_separated.csv": ("'p_total'", "missing", "separated by ';'", "comma-separated"),
    "tab_separated.csv": ("'t'", "missing", "separated by tabs", "comma-separated"),
    "empty.csv": ("empty file",),
    "metadata_only.csv": ("empty file",),
    "header_only.csv": ("no data rows",),
    "single_row.csv": ("single data row", "line 2"),
    "nan_required.csv": ("'p_total'", "line 3", "nan"),
    "inf_required.csv": ("'v_left'", "line 3", "inf"),
    "empty_required_cell.csv": ("'v_right'", "line 3", "empty"),
    "inf_optional.csv": ("'wz'", "line 3", "-inf"),
    "duplicated_time.csv": ("'t'", "line 4", "duplicated", "other readings"),
    "coarse_clock.csv": ("'t'", "line 3", "duplicated", "2 of 5 rows share", "coarser"),
    "time_backwards.csv": ("'t'", "line 4", "backwards", "out of order"),
    "runs_joined.csv": ("'t'", "line 5", "jumps back 60 s", "own file"),
    "only_repeats.csv": ("only 1 distinct row", "2 exact repeats"),
    "speeds_in_mm_per_s.csv": ("'v_left'", "line 2", "mm/s"),
    "command_in_mm_per_s.csv": ("'v_left_cmd'", "line 3", "mm/s"),
    "non_numeric.csv": ("'v_right'", "line 3", "'fast'"),
    "ragged_row.csv": ("line 3", "cells"),
    "duplicated_column.csv": ("'t'", "duplicated column"),
    "too_few_rows_after_drop.csv": ("dropping 2 rows",),
}


def test_corpus_and_table_agree() -> None:
    assert sorted(p.name for p in BAD.glob("*.csv")) == sorted(BAD_CASES)


@pytest.mark.parametrize("name", sorted(BAD_CASES))
def test_bad_log_gives_one_line_error_naming_column_or_row(name: str) -> None:
    with pytest.raises(LogFormatError) as info:
        read_log_csv(BAD / name)
    msg = str(info.value)
    assert "\n" not in msg
    assert msg.startswith(str(BAD / name))
    for fragment in BAD_CASES[name]:
        assert fragment in msg, (fragment, msg)
    assert isinstance(info.value, InputError)  # CLI exit code 2


def _write(tmp_path: Path, text: str, name: str = "log.csv") -> Path:
    p = tmp_path / name
    p.write_text(text)
    return p


def test_minimal_log_reads_required_columns(tmp_path: Path) -> None:
    p = _write(tmp_path, "t,v_left,v_right,p_total\n0,0.1,0.2,100\n0.5,0.3,-0.4,250.5\n")
    log = read_log_csv(p)
    assert len(log) == 2
    assert log.duration_s == 0.5
    np.testing.assert_array_equal(log.v_right, [0.2, -0.4])
    assert log.columns() == ("t", "v_left", "v_right", "p_total")
    assert log.x is None and log.terrain is None and not log.has_commands
    assert log.run_id == "log" and log.dropped_rows == 0


def test_simulator_columns_and_extras(tmp_path: Path) -> None:
    # The simulator writes these twelve columns plus extras that must be ignored.
    cols = "t,x,y,yaw,v_left_cmd,v_right_cmd,v_left,v_right,wz,p_total,p_left,p_right"
    text = cols + ",case,friction_w\n"
    text += "0,0,0,0,0.5,0.5,0.4,0.4,0,300,140,140,1,0\n"
    text += "0.1,0.04,0,0,0.5,0.5,0.45,0.45,0,310,145,145,1,0\n"
    log = read_log_csv(_write(tmp_path, text))
    assert log.columns() == (
        "t",
        "v_left",
        "v_right",
        "p_total",
        "v_left_cmd",
        "v_right_cmd",
        "x",
        "y",
        "yaw",
        "wz",
        "p_left",
        "p_right",
    )
    assert log.has_pose and log.has_commands
    assert any("case" in n and "friction_w" in n for n in log.notes)


def test_partial_nan_in_optional_column_drops_and_counts_rows(tmp_path: Path) -> None:
    text = (
        "t,v_left,v_right,p_total,wz,terrain\n"
        "0,0.1,0.1,100,0,asphalt\n"
        "0.1,0.1,0.1,100,,asphalt\n"  # empty optional cell -> dropped
        "0.2,0.1,0.1,100,nan,asphalt\n"  # NaN optional cell -> dropped
        "0.3,0.1,0.1,100,0.01,\n"  # empty terrain label -> dropped
        "0.4,0.1,0.1,100,0.02,grass\n"
    )
    log = read_log_csv(_write(tmp_path, text))
    assert log.dropped_rows == 3
    np.testing.assert_array_equal(log.t, [0.0, 0.4])
    assert log.terrain is not None and list(log.terrain) == ["asphalt", "grass"]
    assert any("dropped 3 of 5 rows" in n and "line 3" in n for n in log.notes)


def test_exact_repeats_of_earlier_rows_are_dropped_and_counted(tmp_path: Path) -> None:
    # two files of a rotating logger joined end to end: the second repeats the first's last
    # two rows; then a message logged twice.  Every repeat has an earlier row's time and values
    text = (
        "t,v_left,v_right,p_total,wz,terrain\n"
        "0.0,0.1,0.1,100,0.0,asphalt\n"
        "0.1,0.1,0.2,104,0.1,asphalt\n"
        "0.2,0.2,0.2,108,0.0,asphalt\n"
        "0.1,0.1,0.2,104,0.1,asphalt\n"  # line 5: repeat of line 3
        "0.2,0.2,0.2,108,0.0,asphalt\n"  # repeat of line 4
        "0.3,0.2,0.3,111,0.1,grass\n"
        "0.3,0.2,0.3,111,0.1,grass\n"  # repeat of line 7
        "0.4,0.3,0.3,115,0.0,grass\n"
    )
    log = read_log_csv(_write(tmp_path, text))
    np.testing.assert_array_equal(log.t, [0.0, 0.1, 0.2, 0.3, 0.4])
    np.testing.assert_array_equal(log.p_total, [100, 104, 108, 111, 115])
    assert log.terrain is not None and list(log.terrain) == ["asphalt"] * 3 + ["grass"] * 2
    assert log.dropped_rows == 3
    note = "dropped 3 of 8 rows repeating an earlier row"
    assert any(note in n and "line 5" in n for n in log.notes)


@pytest.mark.parametrize(
    ("row", "fragment"),
    [
        ("0.1,0.1,0.2,105,0.1,asphalt", "duplicated"),  # same time, another power
        ("0.1,0.1,0.2,104,0.1,grass", "duplicated"),  # same time, another terrain
        ("0.05,0.1,0.2,104,0.1,asphalt", "backwards"),  # same readings, another time
    ],
)
def test_a_row_that_differs_from_the_earlier_one_is_not_a_repeat(
    tmp_path: Path, row: str, fragment: str
) -> None:
    text = (
        "t,v_left,v_right,p_total,wz,terrain\n"
        "0.0,0.1,0.1,100,0.0,asphalt\n"
        "0.1,0.1,0.2,104,0.1,asphalt\n"
        f"{row}\n"
        "0.2,0.2,0.2,108,0.0,asphalt\n"
    )
    with pytest.raises(LogFormatError, match=fragment) as err:
        read_log_csv(_write(tmp_path, text))
    assert "line 4" in str(err.value)


@settings(max_examples=40, deadline=None)
@given(
    n=st.integers(3, 40),
    picks=st.lists(st.tuples(st.integers(0, 39), st.integers(1, 4)), min_size=1, max_size=4),
    seed=st.integers(0, 2**16),
)
def test_a_log_with_repeated_blocks_reads_as_the_log_without_them(
    n: int, picks: list[tuple[int, int]], seed: int
) -> None:
    """Blocks of rows written again after themselves (a rotated logger's overlap) vanish."""
    import tempfile

    rng = np.random.default_rng(seed)
    rows = [
        f"{0.05 * i!r},{rng.uniform(-1, 1)!r},{rng.uniform(-1, 1)!r},{rng.uniform(0, 200)!r}"
        for i in range(n)
    ]
    written = list(rows)
    repeated = 0
    for at, width in sorted(picks, reverse=True):  # from the end: earlier positions hold
        end = min(at, n - 1) + 1
        block = rows[max(end - width, 0) : end]
        pos = written.index(rows[end - 1]) + 1
        written[pos:pos] = block
        repeated += len(block)
    with tempfile.TemporaryDirectory() as d:
        path = Path(d) / "r.csv"
        path.write_text("t,v_left,v_right,p_total\n" + "\n".join(written) + "\n")
        log = read_log_csv(path)
    want = np.array([[float(c) for c in r.split(",")] for r in rows])
    np.testing.assert_array_equal(log.t, want[:, 0])
    np.testing.assert_array_equal(log.p_total, want[:, 3])
    assert log.dropped_rows == repeated


def test_all_empty_optional_column_is_absent_not_dropped(tmp_path: Path) -> None:
    text = "t,v_left,v_right,p_total,x\n0,0.1,0.1,100,\n0.1,0.1,0.1,100,\n"
    log = read_log_csv(_write(tmp_path, text))
    assert log.x is None and log.dropped_rows == 0 and len(log) == 2


def test_blank_lines_keep_file_line_numbers(tmp_path: Path) -> None:
    text = "# run_id: r7\nt,v_left,v_right,p_total\n\n0,0.1,0.1,100\n0.1,0.1,0.1,100\n0.1,0,0,1\n"
    with pytest.raises(LogFormatError, match="line 6"):
        read_log_csv(_write(tmp_path, text))


def _full_log(n: int = 50) -> Log:
    rng = np.random.default_rng(3)
    t = np.cumsum(rng.uniform(0.005, 0.02, n))
    return Log(
        t=t,
        v_left=rng.uniform(-1, 1, n),
        v_right=rng.uniform(-1, 1, n),
        p_total=rng.uniform(0, 900, n),
        v_left_cmd=rng.uniform(-1, 1, n),
        v_right_cmd=rng.uniform(-1, 1, n),
        x=rng.normal(size=n),
        y=rng.normal(size=n),
        yaw=rng.uniform(-math.pi, math.pi, n),
        wz=rng.normal(size=n),
        p_left=rng.normal(size=n) * 100,
        p_right=rng.normal(size=n) * 100,
        terrain=np.array(["asphalt", "marble"] * (n // 2)),
        run_id="run-1",
        notes=("bus voltage 24 V assumed", "second, with, commas"),
    )


def test_round_trip_is_exact(tmp_path: Path) -> None:
    log = _full_log()
    p = write_log_csv(log, tmp_path / "a.csv")
    back = read_log_csv(p)
    for c in log.columns():
        np.testing.assert_array_equal(getattr(back, c), getattr(log, c))
    assert back.run_id == "run-1" and back.notes == log.notes and back.dropped_rows == 0


@pytest.mark.parametrize(
    ("key", "default", "value", "bad"),
    [("power_sampling", "row", "interval_mean", "mean"), ("pose_frame", "world", "run", "odom")],
)
def test_metadata_is_read_written_and_checked(
    tmp_path: Path, key: str, default: str, value: str, bad: str
) -> None:
    rows = "t,v_left,v_right,p_total,x,y,yaw\n0,0.1,0.1,100,0,0,0\n0.05,0.1,0.1,100,0.005,0,0\n"
    assert getattr(read_log_csv(_write(tmp_path, rows)), key) == default
    log = read_log_csv(_write(tmp_path, f"# {key}: {value}\n" + rows))
    assert getattr(log, key) == value
    back = read_log_csv(write_log_csv(log, tmp_path / "back.csv"))
    assert getattr(back, key) == value
    # a value outside the format names the file's line and the values it knows
    with pytest.raises(LogFormatError, match=rf"line 2: {key} '{bad}'.*{default}, {value}"):
        read_log_csv(_write(tmp_path, f"# run_id: r\n# {key}: {bad}\n" + rows))
    with pytest.raises(LogFormatError, match=f"{key} 'other'"):
        Log(t=np.array([0.0, 1.0]), v_left=np.zeros(2), v_right=np.zeros(2),
            p_total=np.zeros(2), **{key: "other"})  # fmt: skip


def test_write_refuses_to_overwrite(tmp_path: Path) -> None:
    log = _full_log()
    p = write_log_csv(log, tmp_path / "a.csv")
    with pytest.raises(LogFormatError, match="exists"):
        write_log_csv(log, p)
    write_log_csv(log, p, overwrite=True)
    assert len(read_log_csv(p)) == len(log)


@settings(max_examples=40, deadline=None)
@given(
    st.lists(
        st.tuples(
            st.floats(0.001, 10.0),
            st.floats(-19.9, 19.9),
            st.floats(-19.9, 19.9),
            st.floats(-1e4, 1e4, allow_subnormal=False),
        ),
        min_size=2,
        max_size=30,
    )
)
def test_round_trip_property(rows: list[tuple[float, float, float, float]]) -> None:
    import tempfile

    dt, vl, vr, p = (np.array(c) for c in zip(*rows, strict=True))
    log = Log(t=np.cumsum(dt), v_left=vl, v_right=vr, p_total=p)
    if np.any(np.diff(log.t) <= 0):  # cumsum rounding can tie; not the point here
        return
    with tempfile.TemporaryDirectory() as d:
        back = read_log_csv(write_log_csv(log, Path(d) / "h.csv"))
    for c in ("t", "v_left", "v_right", "p_total"):
        np.testing.assert_array_equal(getattr(back, c), getattr(log, c))


def test_slice_by_time_and_mask() -> None:
    log = _full_log()
    mid = float(log.t[20])
    part = log.slice(start_s=mid)
    assert part.t[0] == mid and len(part) == len(log) - 20
    assert part.terrain is not None and len(part.terrain) == len(part)
    mask = np.zeros(len(log), dtype=bool)
    mask[[1, 5, 9]] = True
    three = log.slice(mask)
    np.testing.assert_array_equal(three.p_total, log.p_total[[1, 5, 9]])
    with pytest.raises(LogFormatError, match="at least 2"):
        log.slice(start_s=float(log.t[-1]))
    with pytest.raises(LogFormatError, match="boolean"):
        log.slice(np.ones(3, dtype=bool))


def test_constructor_validates_like_the_reader() -> None:
    t = np.array([0.0, 0.1, 0.1])
    with pytest.raises(LogFormatError, match=r"sample 2.*duplicated.*logged twice"):
        Log(t=t, v_left=np.zeros(3), v_right=np.zeros(3), p_total=np.zeros(3))
    with pytest.raises(LogFormatError, match=r"sample 2.*duplicated.*other readings"):
        Log(t=t, v_left=np.zeros(3), v_right=np.zeros(3), p_total=np.array([0.0, 1.0, 2.0]))
    with pytest.raises(LogFormatError, match="'p_total' has 2 samples"):
        Log(t=np.arange(3.0), v_left=np.zeros(3), v_right=np.zeros(3), p_total=np.zeros(2))
    with pytest.raises(LogFormatError, match=r"'v_left'.*mm/s"):
        Log(t=np.arange(2.0), v_left=np.array([0.0, 350.0]), v_right=np.zeros(2), p_total=[1, 2])


def test_log_arrays_are_read_only() -> None:
    log = _full_log()
    with pytest.raises(ValueError, match="read-only"):
        log.p_total[0] = 1.0


def test_read_logs_names_the_bad_file(tmp_path: Path) -> None:
    good = write_log_csv(_full_log(), tmp_path / "good.csv")
    logs = read_logs([good])
    assert [lg.run_id for lg in logs] == ["run-1"]
    with pytest.raises(LogFormatError, match=r"single_row\.csv"):
        read_logs([good, BAD / "single_row.csv"])
    with pytest.raises(LogFormatError, match="no log files"):
        read_logs([])
    with pytest.raises(LogFormatError, match="cannot open"):
        read_log_csv(tmp_path / "absent.csv")


# --------------------------------------------------------------------------- BorealTC

BOREAL = Path(__file__).resolve().parents[1].parent / "shared" / "data" / "borealtc"
needs_boreal = pytest.mark.skipif(not BOREAL.is_dir(), reason="BorealTC data not available")


@needs_boreal
def test_borealtc_run_as_log_states_the_voltage_assumption() -> None:
    from ecoplan.io.borealtc import load_borealtc

    log = load_borealtc("flooring", 3, bus_voltage_v=24.0, root=BOREAL)
    assert log.run_id == "FLOORING_03" and log.terrain is not None
    assert set(log.terrain) == {"flooring"}
    assert any("24 V" in n and "assumption" in n for n in log.notes)
    # p = V (|I_l| + |I_r|), checked against the raw file read independently
    raw = np.genfromtxt(BOREAL / "FLOORING" / "pro_03.csv", delimiter=",", names=True)
    first = int(np.flatnonzero(np.isclose(raw["time"], log.t[0]))[0])
    assert log.p_total[0] == pytest.approx(24.0 * (raw["curL"][first] + raw["curR"][first]))
    assert log.v_left[0] == pytest.approx(raw["velL"][first])
    assert log.wz is not None and log.dropped_rows == len(raw) - len(log)
    doubled = load_borealtc("FLOORING", "03", bus_voltage_v=48.0, root=BOREAL)
    np.testing.assert_allclose(doubled.p_total, 2.0 * log.p_total)


@needs_boreal
def test_borealtc_run_without_imu_has_no_wz() -> None:
    from ecoplan.io.borealtc import load_borealtc_runs

    logs = load_borealtc_runs("FLOORING", root=BOREAL)
    assert len(logs) == 10
    by_id = {lg.run_id: lg for lg in logs}
    assert by_id["FLOORING_04"].wz is None and by_id["FLOORING_04"].dropped_rows == 0
    assert any("no IMU" in n for n in by_id["FLOORING_04"].notes)


# --------------------------------------------------------------------------- ROS 2 bags


def _write_bag(
    path: Path,
    *,
    battery_nan_at: int | None = None,
    battery_silent: range = range(0),
    wobble_hz: float = 0.0,
) -> dict[str, np.ndarray]:
    """A small bag: JointState wheels, BatteryState, Odometry, Float64MultiArray commands.

    Signals are linear in time (exact under linear interpolation) except the yaw, which
    turns at a constant rate through +-pi.  The battery messages numbered in
    ``battery_silent`` are not sent; ``wobble_hz`` adds a 2 rad/s sine of that frequency to
    the left wheel.
    """
    from rosbags.rosbag2 import Writer
    from rosbags.typesys import Stores, get_typestore

    ts = get_typestore(Stores.ROS2_HUMBLE)
    T = ts.types
    Time, Header = T["builtin_interfaces/msg/Time"], T["std_msgs/msg/Header"]
    base_ns = 1_700_000_000 * 10**9

    def stamp_ns(t: float) -> int:
        return base_ns + round(t * 1e9)

    def header(t: float) -> object:
        return Header(Time(stamp_ns(t) // 10**9, stamp_ns(t) % 10**9), "base_link")

    truth: dict[str, list[float]] = {k: [] for k in ("t", "wl", "wr", "p", "yaw")}
    with Writer(path, version=9) as w:
        c_js = w.add_connection("/joint_states", "sensor_msgs/msg/JointState", typestore=ts)
        c_bat = w.add_connection("/battery", "sensor_msgs/msg/BatteryState", typestore=ts)
        c_odom = w.add_connection("/odom", "nav_msgs/msg/Odometry", typestore=ts)
        c_cmd = w.add_connection("/wheel_cmd", "std_msgs/msg/Float64MultiArray", typestore=ts)
        for k in range(201):  # joint states at 50 Hz, 4 s
            t = 0.02 * k
            wl, wr = 2.0 + 0.5 * t, 3.0 - 0.25 * t  # rad/s
            wl += 2.0 * math.sin(2.0 * math.pi * wobble_hz * t)
            msg = T["sensor_msgs/msg/JointState"](
                header(t),
                ["right_wheel", "left_wheel"],  # order differs from the map on purpose
                np.zeros(2),
                np.array([wr, wl]),
                np.zeros(2),
            )
            w.write(c_js, stamp_ns(t), ts.serialize_cdr(msg, msg.__msgtype__))
        for k in range(41):  # battery at 10 Hz, offset by 5 ms
            t = 0.005 + 0.1 * k
            volts, amps = 24.0, -(5.0 + 2.0 * t)
            if battery_nan_at == k:
                amps = float("nan")
            if k in battery_silent:
                continue
            bat = T["sensor_msgs/msg/BatteryState"](
                header(t),
                volts,
                25.0,
                amps,
                10.0,
                20.0,
                20.0,
                0.5,
                2,
                1,
                2,
                True,
                np.zeros(0, dtype=np.float32),
                np.zeros(0, dtype=np.float32),
                "",
                "",
            )
            w.write(c_bat, stamp_ns(t), ts.serialize_cdr(bat, bat.__msgtype__))
            truth["t"].append(t)
            truth["p"].append(24.0 * (5.0 + 2.0 * t))
        for k in range(81):  # odometry at 20 Hz, yaw turning through +-pi
            t = 0.05 * k
            yaw = 2.8 + 0.2 * t
            q = T["geometry_msgs/msg/Quaternion"](0.0, 0.0, math.sin(yaw / 2), math.cos(yaw / 2))
            pose = T["geometry_msgs/msg/Pose"](T["geometry_msgs/msg/Point"](1.0 + t, -t, 0.0), q)
            v3 = T["geometry_msgs/msg/Vector3"]
            odom = T["nav_msgs/msg/Odometry"](
                header(t),
                "base_link",
                T["geometry_msgs/msg/PoseWithCovariance"](pose, np.zeros(36)),
                T["geometry_msgs/msg/TwistWithCovariance"](
                    T["geometry_msgs/msg/Twist"](v3(0.3, 0.0, 0.0), v3(0.0, 0.0, 0.2)),
                    np.zeros(36),
                ),
            )
            w.write(c_odom, stamp_ns(t), ts.serialize_cdr(odom, odom.__msgtype__))
        layout = T["std_msgs/msg/MultiArrayLayout"]([], 0)
        for k in range(21):  # commands at 5 Hz, no header: bag time stamps
            t = 0.2 * k
            cmd = T["std_msgs/msg/Float64MultiArray"](layout, np.array([0.25, 0.3 + 0.01 * t]))
            w.write(c_cmd, stamp_ns(t), ts.serialize_cdr(cmd, cmd.__msgtype__))
        # a velocity command (cmd_vel) at 10 Hz, stamped and plain: v = 0.3 m/s, w = 0.2 + 0.1 t
        c_tw = w.add_connection("/cmd_vel", "geometry_msgs/msg/TwistStamped", typestore=ts)
        c_tp = w.add_connection("/cmd_vel_plain", "geometry_msgs/msg/Twist", typestore=ts)
        v3 = T["geometry_msgs/msg/Vector3"]
        for k in range(41):
            t = 0.1 * k
            twist = T["geometry_msgs/msg/Twist"](v3(0.3, 0.0, 0.0), v3(0.0, 0.0, 0.2 + 0.1 * t))
            stamped = T["geometry_msgs/msg/TwistStamped"](header(t), twist)
            w.write(c_tw, stamp_ns(t), ts.serialize_cdr(stamped, stamped.__msgtype__))
            w.write(c_tp, stamp_ns(t), ts.serialize_cdr(twist, twist.__msgtype__))
    return {k: np.array(v) for k, v in truth.items()}


def _topic_map(**kw: Any) -> TopicMap:
    return TopicMap.joint_states(
        "/joint_states",
        "left_wheel",
        "right_wheel",
        0.1,
        battery_topic="/battery",
        odom_topic="/odom",
        v_left_cmd=FieldRef("/wheel_cmd", "data[0]"),
        v_right_cmd=FieldRef("/wheel_cmd", "data[1]"),
        **kw,
    )


def test_rosbag_round_trip_on_a_common_time_base(tmp_path: Path) -> None:
    truth = _write_bag(tmp_path / "bag")
    log = read_rosbag(tmp_path / "bag", _topic_map())
    # common span: the battery starts last (5 ms), the others end first (4 s)
    t_abs = 0.005 + log.t
    assert log.t[0] == 0.0 and t_abs[-1] <= 4.0 + 1e-9
    assert np.median(np.diff(log.t)) == pytest.approx(0.1)  # the power stream's rate
    np.testing.assert_allclose(log.v_left, 0.1 * (2.0 + 0.5 * t_abs), atol=1e-6)
    np.testing.assert_allclose(log.v_right, 0.1 * (3.0 - 0.25 * t_abs), atol=1e-6)
    np.testing.assert_allclose(log.p_total, 24.0 * (5.0 + 2.0 * t_abs), rtol=1e-6)
    assert log.v_left_cmd is not None and log.v_right_cmd is not None
    np.testing.assert_allclose(log.v_right_cmd, 0.3 + 0.01 * t_abs, atol=1e-6)
    assert log.x is not None and log.y is not None and log.yaw is not None
    np.testing.assert_allclose(log.x, 1.0 + t_abs, atol=1e-6)
    yaw = 2.8 + 0.2 * t_abs
    np.testing.assert_allclose(np.cos(log.yaw), np.cos(yaw), atol=1e-6)  # across +-pi
    np.testing.assert_allclose(np.sin(log.yaw), np.sin(yaw), atol=1e-6)
    assert log.wz is not None and np.allclose(log.wz, 0.2)
    assert any("voltage x current" in n for n in log.notes)
    assert len(truth["t"]) == 41


def test_a_bag_read_with_the_wrong_current_sign_is_refused_by_the_diagnosis(
    tmp_path: Path,
) -> None:
    # the bag's battery follows the ROS convention (current negative when discharging); read
    # with the sign of a driver that publishes the drawn current positive, every power sample
    # is negative: the diagnosis's input check names the column and the map's key
    _write_bag(tmp_path / "bag")
    log = read_rosbag(tmp_path / "bag", _topic_map(battery_current_sign=1.0))
    assert np.all(log.p_total < 0)
    with pytest.raises(InputError, match=r"'p_total' is negative.*battery_current_sign"):
        check_logs([log], vehicle("pioneer-3at"))


@pytest.mark.parametrize("topic", ["/cmd_vel", "/cmd_vel_plain"])
def test_rosbag_side_commands_from_a_velocity_command(tmp_path: Path, topic: str) -> None:
    # a differential-drive controller sends v -+ w s / 2 to the sides (s = 0.5 m here)
    _write_bag(tmp_path / "bag")
    tmap = TopicMap.joint_states(
        "/joint_states", "left_wheel", "right_wheel", 0.1, battery_topic="/battery",
        cmd_vel_topic=topic, cmd_separation_m=0.5,
    )  # fmt: skip
    log = read_rosbag(tmp_path / "bag", tmap)
    t_abs = 0.005 + log.t
    w = 0.2 + 0.1 * t_abs
    assert log.v_left_cmd is not None and log.v_right_cmd is not None
    np.testing.assert_allclose(log.v_left_cmd, 0.3 - 0.25 * w, atol=1e-9)
    np.testing.assert_allclose(log.v_right_cmd, 0.3 + 0.25 * w, atol=1e-9)
    assert any(topic in n and "0.5 m" in n for n in log.notes)


def test_rosbag_odometry_in_each_runs_own_frame_is_said_so(tmp_path: Path) -> None:
    _write_bag(tmp_path / "bag")
    assert read_rosbag(tmp_path / "bag", _topic_map()).pose_frame == "world"
    log = read_rosbag(tmp_path / "bag", _topic_map(pose_frame="run"))
    assert log.pose_frame == "run" and log.yaw is not None
    with pytest.raises(InputError, match="pose_frame"):
        read_rosbag(tmp_path / "bag", _topic_map(pose_frame="odom"))


def test_rosbag_power_stated_as_interval_means_is_stamped_at_their_middles(
    tmp_path: Path,
) -> None:
    _write_bag(tmp_path / "bag")
    log = read_rosbag(tmp_path / "bag", _topic_map(power_sampling="interval_mean"))
    # each 10 Hz battery message, the mean over the 0.1 s before it, stands for 0.05 s earlier:
    # the power at a row's time is the message 0.05 s later (the ramp is linear); the power
    # stream now starts first (-0.045 s), so the common time base starts at the wheels' 0 s
    t_abs = log.t
    assert t_abs[-1] <= 4.005 - 0.05 + 1e-9
    np.testing.assert_allclose(log.p_total, 24.0 * (5.0 + 2.0 * (t_abs + 0.05)), rtol=1e-6)
    np.testing.assert_allclose(log.v_left, 0.1 * (2.0 + 0.5 * t_abs), atol=1e-6)
    assert log.power_sampling == "row"  # the stamps already say where the power stands
    assert any("interval_mean" in n for n in log.notes)
    with pytest.raises(LogFormatError, match="power_sampling"):
        _topic_map(power_sampling="window")


def test_rosbag_time_is_exact_and_a_silent_stream_is_a_gap_not_a_line(tmp_path: Path) -> None:
    # the battery (10 Hz, from 0.005 s) sends nothing from 1.005 s to 1.905 s: a 1.1 s gap
    # between its messages at 0.905 s and 2.005 s.  A straight line across it would invent
    # 10 power readings; the log has no time points there, as a CSV logger writes no rows
    truth = _write_bag(tmp_path / "bag", battery_silent=range(10, 20))
    log = read_rosbag(tmp_path / "bag", _topic_map())
    t_abs = 0.005 + log.t
    inside = (t_abs > 0.905 + 1e-9) & (t_abs < 2.005 - 1e-9)
    assert not inside.any()
    expected = truth["t"][truth["t"] <= 4.0]  # the battery's own stamps, as sent
    np.testing.assert_allclose(t_abs, expected, atol=1e-9)
    np.testing.assert_allclose(log.p_total, 24.0 * (5.0 + 2.0 * t_abs), rtol=1e-6)
    np.testing.assert_allclose(log.v_left, 0.1 * (2.0 + 0.5 * t_abs), atol=1e-6)
    assert any("1 gap" in n and "p_total" in n and "0.9 to 2 s" in n for n in log.notes)
    # stamps 1.7e9 s after the epoch resolve only 0.24 us as float seconds; the time
    # base is exact to the nanosecond: multiples of the battery's 0.1 s
    full = read_rosbag(tmp_path / "bag", _topic_map(rate_hz=10.0))
    assert np.max(np.abs(full.t * 10.0 - np.round(full.t * 10.0))) < 1e-9
    assert any("bag time 1700000000.005000000 s" in n for n in full.notes)


def test_rosbag_faster_streams_are_averaged_over_the_time_step_not_sampled(
    tmp_path: Path,
) -> None:
    # the left wheel (50 Hz) wobbles at 9 Hz, 0.2 m/s; the time base is the battery's 10 Hz.
    # Sampled at 10 Hz, the wobble aliases to a 1 Hz swing of the full 0.2 m/s; the mean
    # over each 0.1 s step keeps |sinc(0.9)| = 0.11 of it (0.022 m/s), and lines stay exact
    _write_bag(tmp_path / "bag", wobble_hz=9.0)
    log = read_rosbag(tmp_path / "bag", _topic_map())
    t_abs = 0.005 + log.t
    wobble = log.v_left - 0.1 * (2.0 + 0.5 * t_abs)
    assert np.max(np.abs(wobble[1:-1])) < 0.04  # the ends: a shorter window
    np.testing.assert_allclose(log.v_right, 0.1 * (3.0 - 0.25 * t_abs), atol=1e-9)
    np.testing.assert_allclose(log.p_total, 24.0 * (5.0 + 2.0 * t_abs), rtol=1e-6)
    assert any(n.startswith("v_left, v_right") and "mean over the 0.1 s" in n for n in log.notes)
    # a time base as fast as the wheels samples them: nothing to average
    fast = read_rosbag(tmp_path / "bag", _topic_map(rate_hz=50.0))
    t50 = 0.005 + fast.t
    wl = 2.0 + 0.5 * t50 + 2.0 * np.sin(2.0 * np.pi * 9.0 * t50)
    np.testing.assert_allclose(fast.v_left, 0.1 * wl, atol=0.08)  # between 50 Hz samples
    assert not any("mean over" in n for n in fast.notes)


def test_rosbag_rate_nan_and_missing_topic(tmp_path: Path) -> None:
    _write_bag(tmp_path / "bag", battery_nan_at=3)
    log = read_rosbag(tmp_path / "bag", _topic_map(rate_hz=50.0))
    assert np.median(np.diff(log.t)) == pytest.approx(0.02)
    # 50 Hz is 5x the battery's 10 Hz: the power is a line between its messages, said so
    assert any(n.startswith("p_total: the time base (50 Hz) is 5x") for n in log.notes)
    at_20 = read_rosbag(tmp_path / "bag", _topic_map(rate_hz=20.0)).notes
    assert not any("time base (20 Hz)" in n for n in at_20)
    assert any("p_total: skipped 1 non-finite" in n for n in log.notes)
    bad = TopicMap(v_left=FieldRef("/wheels"), v_right=FieldRef("/wheels"), power=FieldRef("/p"))
    with pytest.raises(LogFormatError, match="/p, /wheels not in the bag"):
        read_rosbag(tmp_path / "bag", bad)
    wrong_field = _topic_map(wz=FieldRef("/odom", "twist.nope"))
    with pytest.raises(LogFormatError, match="'wz' from topic /odom"):
        read_rosbag(tmp_path / "bag", wrong_field)
    with pytest.raises(LogFormatError, match="cannot read ROS 2 bag"):
        read_rosbag(tmp_path / "absent", bad)
    with pytest.raises(LogFormatError, match="exactly one"):
        TopicMap(v_left=FieldRef("/a"), v_right=FieldRef("/b"))


def test_rosbag_damaged_message_or_storage_is_a_format_error(tmp_path: Path) -> None:
    # a bag whose metadata opens can still hold a record that does not decode, or a damaged
    # database page that sqlite3 reports only when the messages are read (found by corrupting
    # bags, session 24: AnyReaderError and CorruptError escaped as internal errors)
    import shutil
    import sqlite3

    _write_bag(tmp_path / "bag")
    broken = tmp_path / "broken"
    shutil.copytree(tmp_path / "bag", broken)
    db = next(broken.glob("*.db3"))
    con = sqlite3.connect(db)
    with con:
        con.execute(
            "UPDATE messages SET data = x'00010000' WHERE id = (SELECT MIN(m.id) FROM messages m "
            "JOIN topics t ON m.topic_id = t.id WHERE t.name = '/joint_states')"
        )
    con.close()
    with pytest.raises(LogFormatError, match=r"message \d+ .*/joint_states.*damaged"):
        read_rosbag(broken, _topic_map())
    # 512 zero bytes anywhere in the database: a log or one LogFormatError, nothing else
    size = next((tmp_path / "bag").glob("*.db3")).stat().st_size
    outcomes = set()
    for k in range(1, 20):
        copy = tmp_path / f"zeroed{k}"
        shutil.copytree(tmp_path / "bag", copy)
        db = next(copy.glob("*.db3"))
        data = bytearray(db.read_bytes())
        at = k * size // 20
        data[at : at + 512] = bytes(512)
        db.write_bytes(bytes(data))
        try:
            read_rosbag(copy, _topic_map())
            outcomes.add("read")
        except LogFormatError as exc:
            outcomes.add("damaged" if "damaged" in str(exc) else "refused")
    # the net catches damage at all (where sqlite3 reports it, at open or only while the
    # messages are read, depends on its page layout: here both happen)
    assert outcomes - {"read"}


def test_byte_order_mark_is_accepted(tmp_path: Path) -> None:
    p = tmp_path / "bom.csv"
    p.write_bytes("\ufefft,v_left,v_right,p_total\n0,0,0,1\n1,0,0,1\n".encode())
    assert len(read_log_csv(p)) == 2


_CELLS = st.sampled_from(["0", "1.5", "-2", "nan", "inf", "", "x", "1e3", " 3 ", "25", '"4"'])


@settings(max_examples=150, deadline=None)
@given(
    st.lists(
        st.sampled_from(["t", "v_left", "v_right", "p_total", "wz", "terrain", "extra", "t"]),
        min_size=0,
        max_size=7,
    ),
    st.lists(st.lists(_CELLS, min_size=0, max_size=8), min_size=0, max_size=6),
)
def test_any_csv_gives_a_log_or_a_log_format_error(
    header: list[str], rows: list[list[str]]
) -> None:
    import tempfile

    text = ",".join(header) + "\n" + "".join(",".join(r) + "\n" for r in rows)
    with tempfile.TemporaryDirectory() as d:
        p = Path(d) / "fuzz.csv"
        p.write_text(text)
        try:
            log = read_log_csv(p)
        except LogFormatError as exc:
            assert "\n" not in str(exc)
        else:
            assert len(log) >= 2 and np.all(np.diff(log.t) > 0)
            assert np.all(np.isfinite(log.p_total))


def test_read_logs_dispatches_bags_with_a_topic_map_file(tmp_path: Path) -> None:
    _write_bag(tmp_path / "bag")
    with pytest.raises(LogFormatError, match=r"needs a topic map.*bag\.topics\.yaml"):
        read_logs([tmp_path / "bag"])
    (tmp_path / "bag.topics.yaml").write_text(
        "v_left: {topic: /joint_states, field: 'velocity[left_wheel]', scale: 0.1}\n"
        "v_right: {topic: /joint_states, field: 'velocity[right_wheel]', scale: 0.1}\n"
        "battery_topic: /battery\n"
        "odom_topic: /odom\n"
        "rate_hz: 20\n"
    )
    csv_log = write_log_csv(_full_log(), tmp_path / "run.csv")
    logs = read_logs([tmp_path / "bag", csv_log])
    assert [lg.run_id for lg in logs] == ["bag", "run-1"]
    assert np.median(np.diff(logs[0].t)) == pytest.approx(0.05)
    np.testing.assert_allclose(logs[0].v_left, 0.1 * (2.0 + 0.5 * (0.005 + logs[0].t)), atol=1e-6)


@pytest.mark.parametrize(
    ("text", "fragment"),
    [
        ("v_left: /a\nv_right: /b\npower: /p\nspeed: 3\n", ":4: unknown key 'speed'"),
        ("v_left: /a\npower: /p\n", "missing required key 'v_right'"),
        ("v_left: {topic: /a, gain: 2}\nv_right: /b\npower: /p\n", "unknown key 'gain' in v_left"),
        ("v_left: {topic: /a, scale: yes}\nv_right: /b\npower: /p\n", "v_left.scale: expected a"),
        ("v_left: /a\nv_right: /b\npower: /p\nrate_hz: 0\n", ":4: rate_hz: expected a number > 0"),
        ("v_left: /a\nv_right: /b\npower: /p\nbattery_current_sign: 2\n", "accepted: -1, 1"),
        ("v_left: [1, 2]\nv_right: /b\npower: /p\n", "v_left: expected a topic name"),
        ("v_left: /a\nv_right: /b\n", "exactly one of 'power' and 'battery_topic'"),
        ("v_left: /a\nv_right: /b\npower: /p\ncmd_vel_topic: /c\n", "'cmd_separation_m'"),
        (
            "v_left: /a\nv_right: /b\npower: /p\ncmd_vel_topic: /c\ncmd_separation_m: 0.5\n"
            "v_left_cmd: /l\nv_right_cmd: /r\n",
            "'cmd_vel_topic' or 'v_left_cmd' and 'v_right_cmd', not both",
        ),
        ("v_left: /a\nv_right: /b\npower: /p\ncmd_separation_m: -1\n", "cmd_separation_m"),
        ("- just\n- a list\n", "must be a mapping"),
        ("v_left: {topic: /a\n", "invalid YAML"),
    ],
)
def test_bad_topic_map_files_name_the_key(tmp_path: Path, text: str, fragment: str) -> None:
    from ecoplan.io.rosbag import load_topic_map

    p = tmp_path / "map.yaml"
    p.write_text(text)
    with pytest.raises(LogFormatError) as info:
        load_topic_map(p)
    assert fragment in str(info.value) and str(p) in str(info.value)
    assert "\n" not in str(info.value)


@needs_boreal
def test_read_logs_accepts_borealtc_specs() -> None:
    logs = read_logs(["borealtc:ASPHALT/02", "borealtc:asphalt"], bus_voltage_v=25.0)
    assert logs[0].run_id == "ASPHALT_02" and len(logs) == 1 + 7
    assert any("25 V" in n for n in logs[0].notes)


def test_fast_and_cell_by_cell_parsers_agree(tmp_path: Path) -> None:
    # a quoted cell anywhere sends the file to the cell-by-cell parser; the result must
    # not depend on which parser read it
    log = _full_log()
    plain = write_log_csv(log, tmp_path / "plain.csv")
    lines = plain.read_text().splitlines()
    head = next(i for i, ln in enumerate(lines) if not ln.startswith("#"))
    lines[head] += ",comment"
    for i in range(head + 1, len(lines)):
        lines[i] += ',"a, b"' if i == head + 5 else ",x"
    quoted = tmp_path / "quoted.csv"
    quoted.write_text("\n".join(lines) + "\n")
    a, b = read_log_csv(plain), read_log_csv(quoted)
    for col in log.columns():
        np.testing.assert_array_equal(getattr(a, col), getattr(b, col))
    assert any("ignored columns: comment" in n for n in b.notes)


def test_logs_compare_by_identity_and_hash() -> None:
    a, b = _full_log(), _full_log()
    assert a == a and a != b  # arrays: no element-wise ambiguity
    assert len({a, b}) == 2


def test_the_docstring_table_lists_every_column_with_its_unit() -> None:
    # the format's table in the module docstring and the column specification must agree
    import ecoplan.dynamics.log as logmod

    rows = [ln for ln in (logmod.__doc__ or "").splitlines() if ln.startswith("``")]
    table = {}
    for row in rows:
        cells = row.split()
        names = [c.strip("`,") for c in cells if c.startswith("``")]
        unit = cells[len(names)]
        table.update(dict.fromkeys(names, (unit, cells[-1] == "yes")))
    expected = {c.name: (c.unit, c.required) for c in logmod.COLUMNS}
    assert table == expected


def test_unit_suffixed_aliases_read_as_the_columns(tmp_path: Path) -> None:
    text = "t_s,v_left_mps,v_right_mps,p_total_w,wz_radps\n0,0.1,0.2,100,0\n0.5,0.3,-0.4,250,0.1\n"
    log = read_log_csv(_write(tmp_path, text))
    assert log.columns() == ("t", "v_left", "v_right", "p_total", "wz")
    np.testing.assert_array_equal(log.p_total, [100.0, 250.0])
    assert "column 't_s' read as 't'" in log.notes
    dup = _write(tmp_path, "t,v_left,v_right,p_total,p_total_w\n0,0,0,1,1\n1,0,0,1,1\n", "d.csv")
    with pytest.raises(LogFormatError, match=r"line 1: duplicated column 'p_total' .*'p_total_w'"):
        read_log_csv(dup)


def test_extra_columns_are_written_after_the_format_and_ignored_on_reading(
    tmp_path: Path,
) -> None:
    log = Log(
        t=[0.0, 0.1, 0.2],
        v_left=[0.1, 0.2, 0.3],
        v_right=[0.1, 0.2, 0.3],
        p_total=[10.0, 20.0, 30.0],
        extra={"case": np.array([1, 2, 2]), "p_friction": np.array([0.5, 0.25, 0.125])},
    )
    p = write_log_csv(log, tmp_path / "x.csv")
    lines = p.read_text().splitlines()
    assert lines[0] == "t,v_left,v_right,p_total,case,p_friction"
    assert lines[1] == "0.0,0.1,0.1,10.0,1,0.5"  # integers stay integers
    back = read_log_csv(p)
    assert back.extra == {} and "ignored columns: case, p_friction" in back.notes
    np.testing.assert_array_equal(log.slice(start_s=0.05).extra["case"], [2, 2])
    with pytest.raises(LogFormatError, match="'wz' is a column of the log format"):
        Log(t=[0, 1], v_left=[0, 0], v_right=[0, 0], p_total=[1, 1], extra={"wz": [0, 0]})
    with pytest.raises(LogFormatError, match=r"'case' must be numeric with shape \(2,\)"):
        Log(t=[0, 1], v_left=[0, 0], v_right=[0, 0], p_total=[1, 1], extra={"case": [0]})
    with pytest.raises(LogFormatError, match="not a plain CSV header"):
        Log(t=[0, 1], v_left=[0, 0], v_right=[0, 0], p_total=[1, 1], extra={"a,b": [0, 0]})


_MAP_KEYS = (
    *("v_left", "v_right", "power", "battery_topic", "battery_current_sign", "rate_hz"),
    *("p_offset_w", "v_left_cmd", "v_right_cmd", "odom_topic", "wz", "speed"),
    *("cmd_vel_topic", "cmd_separation_m"),
)
_MAP_VALUES = st.one_of(
    st.none(),
    st.booleans(),
    st.integers(-3, 3),
    st.floats(allow_nan=True),
    st.sampled_from(["/a", "", "x[1]"]),
    st.lists(st.integers(), max_size=2),
    st.dictionaries(st.sampled_from(["topic", "field", "scale", "gain"]), st.text(max_size=3)),
)


@settings(max_examples=200, deadline=None)
@given(
    st.dictionaries(
        st.sampled_from(_MAP_KEYS),
        _MAP_VALUES,
        max_size=8,
    )
)
def test_any_topic_map_gives_a_map_or_one_line(data: dict[str, Any]) -> None:
    import tempfile

    import yaml

    with tempfile.TemporaryDirectory() as d:
        p = Path(d) / "map.yaml"
        p.write_text(yaml.safe_dump(data))
        from ecoplan.io.rosbag import load_topic_map

        try:
            tmap = load_topic_map(p)
        except LogFormatError as exc:
            assert "\n" not in str(exc) and str(exc).startswith(str(p))
        else:
            # what was accepted obeys the documented rules
            assert (tmap.power is None) != (tmap.battery_topic is None)
            assert tmap.battery_current_sign in (-1.0, 1.0)
            assert tmap.rate_hz is None or 0.0 < tmap.rate_hz <= 10000.0
            assert isinstance(tmap.v_left, FieldRef) and tmap.v_left.topic
            assert math.isfinite(tmap.p_offset_w) and math.isfinite(tmap.v_left.scale)
            assert (tmap.cmd_vel_topic is None) == (tmap.cmd_separation_m is None)
            assert tmap.cmd_vel_topic is None or tmap.v_left_cmd is None


def _run(t0: float, dt: float, n: int, *, pose: bool = True, wz: bool = True, **kw: Any) -> Log:
    t = t0 + dt * np.arange(n)
    return Log(
        t=t,
        v_left=np.full(n, 0.2),
        v_right=np.full(n, 0.3),
        p_total=100.0 + np.arange(n, dtype=float),
        x=t if pose else None,
        y=np.zeros(n) if pose else None,
        yaw=np.zeros(n) if pose else None,
        wz=np.full(n, 0.1) if wz else None,
        **kw,
    )


def test_join_runs_puts_the_runs_on_one_clock_and_leaves_the_pose_out() -> None:
    # Run 1: 3 samples at 0.1 s from t = 7 s; run 2: 4 at 0.5 s from t = 100 s.  Run 2 starts
    # one sample period of run 1 (0.1 s) after run 1's last sample (0.2 s on the new clock).
    a = _run(7.0, 0.1, 3, notes=("24 V assumed",), dropped_rows=2)
    b = _run(100.0, 0.5, 4, notes=("24 V assumed", "no IMU"), dropped_rows=1)
    joined, starts = join_runs([a, b], "ab")
    np.testing.assert_allclose(joined.t, [0.0, 0.1, 0.2, 0.3, 0.8, 1.3, 1.8])
    assert starts == pytest.approx([0.3])
    np.testing.assert_array_equal(joined.p_total, [100, 101, 102, 100, 101, 102, 103])
    assert joined.x is None and joined.y is None and joined.yaw is None
    assert joined.wz is not None and joined.wz.size == 7
    assert joined.notes == ("24 V assumed", "no IMU") and joined.dropped_rows == 3
    assert joined.run_id == "ab"
    only, _ = join_runs([a, b], "ab", columns=())
    assert only.wz is None


def test_join_runs_refuses_what_it_cannot_join_in_one_line() -> None:
    a, b = _run(0.0, 0.1, 3), _run(0.0, 0.1, 3, wz=False, run_id="r2")
    with pytest.raises(LogFormatError, match="run 'r2' has no column 'wz'"):
        join_runs([a, b], "ab", columns=("wz",))
    with pytest.raises(LogFormatError, match="'speed' is not an optional column"):
        join_runs([a], "a", columns=("speed",))
    with pytest.raises(LogFormatError, match="power_sampling"):
        join_runs([a, _run(0.0, 0.1, 3, power_sampling="interval_mean")], "ab")
    with pytest.raises(LogFormatError, match="no run"):
        join_runs([], "none")
    # a column only some runs have is left out by default, not refused
    assert join_runs([a, b], "ab")[0].wz is None


@given(
    st.lists(
        st.tuples(st.floats(-1e3, 1e3), st.floats(1e-3, 1.0), st.integers(2, 30)),
        min_size=1,
        max_size=6,
    )
)
def test_joined_clock_is_increasing_and_each_run_starts_where_it_was_said(
    runs: list[tuple[float, float, int]],
) -> None:
    logs = [_run(t0, dt, n) for t0, dt, n in runs]
    joined, starts = join_runs(logs, "all")
    assert np.all(np.diff(joined.t) > 0)
    assert joined.t.size == sum(n for _, _, n in runs)
    first = np.cumsum([0] + [n for _, _, n in runs])[1:-1]
    np.testing.assert_allclose(joined.t[first], starts)
    # within a run the clock keeps its spacing
    for (_, dt, n), i0 in zip(runs, np.cumsum([0] + [n for _, _, n in runs]), strict=False):
        np.testing.assert_allclose(np.diff(joined.t[i0 : i0 + n]), dt, rtol=1e-6, atol=1e-9)


@settings(max_examples=60, deadline=None)
@given(
    steps=st.lists(st.integers(1, 5), min_size=3, max_size=60),
    rows=st.integers(2, 12),
    offset=st.integers(0, 11),
)
def test_fresh_readings_keeps_the_row_where_each_reading_arrives(
    steps: list[int], rows: int, offset: int
) -> None:
    # a meter read every ``rows`` rows of a 100 Hz log (each reading differs from the one
    # before), repeated until the next; the log starts ``offset`` rows into the first reading
    readings = np.cumsum(np.array(steps, dtype=float))
    skip = offset % rows
    p = np.repeat(readings, rows)[skip:]
    n = p.size
    log = Log(t=np.arange(n) * 0.01, v_left=np.zeros(n), v_right=np.zeros(n), p_total=p)
    fresh = fresh_readings(log)
    # by construction: row 0, then reading k arrives at row k * rows - skip
    arrive = np.r_[0, np.arange(1, readings.size) * rows - skip]
    np.testing.assert_array_equal(fresh.t, np.arange(n)[arrive] * 0.01)
    np.testing.assert_array_equal(fresh.p_total, readings)
    assert fresh.notes[-1].startswith(f"p_total held: repeated on {n - readings.size} of {n} rows")


def test_a_quantised_meter_is_not_taken_for_fresh_readings() -> None:
    # a 1 W meter on a power that changes by a few W per row: values repeat on a share of the
    # rows (here about a quarter), at random, not in runs: every row is a fresh reading
    g = np.random.default_rng(3)
    n = 2000
    p = np.round(40.0 + np.cumsum(g.normal(0.0, 0.8, n)))
    log = Log(t=np.arange(n) * 0.05, v_left=np.ones(n), v_right=np.ones(n), p_total=p)
    repeats = float(np.mean(p[1:] == p[:-1]))
    assert 0.15 < repeats < 0.5
    assert fresh_readings(log) is log
    # a drive of constant-speed legs (noise-free encoders, a simulator): plateaus of every
    # length, not readings at a steady rate
    legs = g.integers(5, 200, size=30)
    v = np.repeat(g.uniform(0.1, 0.5, size=legs.size), legs)
    m = v.size
    plateaus = Log(t=np.arange(m) * 0.05, v_left=v, v_right=v, p_total=g.normal(50.0, 5.0, m))
    assert fresh_readings(plateaus) is plateaus


def _arc(n: int, dt: float = 0.05) -> tuple[np.ndarray, ...]:
    """Pose and yaw rate of a robot on a circle (0.5 m/s, 0.6 rad/s), started at yaw 2.9 rad."""
    t = np.arange(n) * dt
    v, w, yaw0 = 0.5, 0.6, 2.9
    yaw = yaw0 + w * t
    x = (v / w) * (np.sin(yaw) - np.sin(yaw0))
    y = -(v / w) * (np.cos(yaw) - np.cos(yaw0))
    return t, x, y, np.arctan2(np.sin(yaw), np.cos(yaw)), np.full(n, w)


def test_a_held_pose_is_interpolated_between_its_readings_and_every_row_kept() -> None:
    # a 1 Hz position fix, a 2 Hz heading and a 5 Hz gyro in the rows of a 20 Hz log; the
    # heading crosses +-pi (starts at 2.9 rad, turns left)
    n = 400
    t, x, y, yaw, wz = _arc(n)
    g = np.random.default_rng(0)
    wz = wz + g.normal(0.0, 0.01, n)  # a gyro's noise: each reading differs

    def held(a: np.ndarray, rows: int) -> np.ndarray:
        return a[(np.arange(n) // rows) * rows]

    p = g.normal(80.0, 5.0, n)
    log = Log(
        t=t, v_left=np.full(n, 0.4), v_right=np.full(n, 0.6), p_total=p,
        x=held(x, 20), y=held(y, 20), yaw=held(yaw, 10), wz=held(wz, 4),
    )  # fmt: skip
    fresh = fresh_readings(log)
    assert len(fresh) == n  # nothing thinned: the power and the speeds are fresh
    np.testing.assert_array_equal(fresh.p_total, p)
    reading = np.arange(n) % 20 == 0
    np.testing.assert_allclose(fresh.x[reading], x[reading], atol=1e-12)
    inside = np.arange(n) < 380  # after the last fix the pose stays at it
    chord_err = np.max(np.hypot(fresh.x - x, fresh.y - y)[inside])
    held_err = np.max(np.hypot(log.x - x, log.y - y)[inside])
    # between two fixes 1 s apart the robot turns 0.6 rad on a circle of r = 0.5 / 0.6 m: at
    # the same time, the chord's point is at most the sagitta r (1 - cos 0.3) = 37 mm from the
    # arc's; holding is off by up to the 0.475 m driven meanwhile
    sagitta = (0.5 / 0.6) * (1.0 - np.cos(0.3))
    assert chord_err < sagitta + 1e-9 < 0.4 < held_err
    dyaw = np.angle(np.exp(1j * (fresh.yaw - yaw)))[np.arange(n) < 390]
    assert np.max(np.abs(dyaw)) < 1e-9  # a constant turn rate: linear in time, across +-pi
    assert np.all(np.abs(fresh.yaw) <= np.pi)
    for said in ("x and y held", "yaw held", "wz held"):
        assert any(note.startswith(said) and "interpolated" in note for note in fresh.notes)


def test_a_pose_that_stands_still_and_moves_is_not_taken_for_held() -> None:
    # a noise-free pose (a simulator) that rests now and then: runs of every length
    g = np.random.default_rng(1)
    legs = g.integers(5, 200, size=20)
    moving = np.repeat(np.arange(legs.size) % 2 == 0, legs)
    m = moving.size
    x = np.cumsum(np.where(moving, 0.02, 0.0))
    log = Log(
        t=np.arange(m) * 0.05, v_left=np.ones(m), v_right=np.ones(m),
        p_total=g.normal(50.0, 5.0, m), x=x, y=np.zeros(m), yaw=np.zeros(m),
    )  # fmt: skip
    assert fresh_readings(log) is log
