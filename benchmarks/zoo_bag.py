"""A zoo case written as a ROS 2 bag, the way a robot's drivers publish it.

Used by ``logger_conventions.py`` (transforms ``bag`` and ``bag_rates``).  The bag is
written with the ``rosbags`` library from the zoo's own columns; nothing of ecoplan's is
used to make it, so the reader (:func:`ecoplan.io.rosbag.read_rosbag`) meets the bag as it
would meet a robot's:

``/joint_states`` (``sensor_msgs/JointState``)
    The side speeds as wheel (sprocket) rates [rad/s] of joints ``left_wheel_joint`` and
    ``right_wheel_joint``, radius :data:`WHEEL_RADIUS_M`, stamped when sampled.
``/battery_state`` (``sensor_msgs/BatteryState``)
    ``voltage`` [V] and ``current`` [A], negative when discharging (REP-145's sign), whose
    product is the zoo's power; each message the mean over the rows since the one before
    (the zoo's meter averages), stamped at the end of its window.  Its fields are float32,
    as in ROS.
``/odom`` (``nav_msgs/Odometry``)
    The pose (heading as a quaternion) and ``twist.twist.angular.z`` the zoo's ``wz``.
``/cmd_vel`` (``geometry_msgs/Twist``)
    The side commands as ``linear.x`` and ``angular.z`` over :data:`CMD_SEPARATION_M`; no
    header, so only the bag's receive time stamps it.

Every message is received :data:`LATENCY_S` after it is stamped.  Rows the zoo dropped are
messages never sent, on every topic.  Stamps are epoch times (:data:`EPOCH_S`), as a
robot's clock gives them.
"""

from __future__ import annotations

import math
from pathlib import Path

import numpy as np

#: Wheel or sprocket radius the joint rates are written with [m].
WHEEL_RADIUS_M = 0.1
#: Separation the ``cmd_vel`` angular rate is split with [m] (the drive controller's).
CMD_SEPARATION_M = 0.5
#: Bus voltage of the battery messages [V].
BUS_V = 24.0
#: Receive time after the stamp [s].
LATENCY_S = 0.004
#: Epoch time of the zoo's t = 0 [s].
EPOCH_S = 1_764_000_000

Columns = dict[str, np.ndarray]


def windows(t: np.ndarray, every: int) -> list[tuple[np.ndarray, float]]:
    """Row indices and end time of each message of a stream that averages ``every`` rows.

    The zoo's rows are on a 0.05 s grid with some dropped; a message averages the rows of
    its window that are left, and is not sent (lost with them) when half of them are gone.
    """
    k = np.round((t - t[0]) / 0.05).astype(int)
    out = []
    for m in np.unique(k // every):
        idx = np.flatnonzero(k // every == m)
        if 2 * idx.size > every:
            out.append((idx, float(t[0] + 0.05 * (every * m + every - 1))))
    return out


def write_bag(cols: Columns, path: Path, *, battery_every: int = 1, cmd_every: int = 1) -> Path:
    """Write the zoo columns ``cols`` as a ROS 2 bag (sqlite3 storage) at ``path``.

    Parameters
    ----------
    cols : dict
        The zoo's columns (``t``, side speeds and commands, ``p_total``, pose, ``wz``).
    path : pathlib.Path
        The bag directory (must not exist; its parent is created).
    battery_every, cmd_every : int
        Rows per battery message (its mean) and per command message (a command held).

    Returns
    -------
    pathlib.Path
        ``path``.
    """
    from rosbags.rosbag2 import Writer
    from rosbags.typesys import Stores, get_typestore

    ts = get_typestore(Stores.ROS2_HUMBLE)
    T = ts.types
    t = np.asarray(cols["t"], dtype=np.float64)

    def ns(tk: float) -> int:
        return EPOCH_S * 1_000_000_000 + round(tk * 1e9)

    def header(tk: float, frame: str) -> object:
        n = ns(tk)
        return T["std_msgs/msg/Header"](
            T["builtin_interfaces/msg/Time"](n // 10**9, n % 10**9), frame
        )

    def recv(tk: float) -> int:
        return ns(tk + LATENCY_S)

    v3 = T["geometry_msgs/msg/Vector3"]
    path.parent.mkdir(parents=True, exist_ok=True)
    with Writer(path, version=9) as w:
        c_js = w.add_connection("/joint_states", "sensor_msgs/msg/JointState", typestore=ts)
        c_bat = w.add_connection("/battery_state", "sensor_msgs/msg/BatteryState", typestore=ts)
        c_odom = w.add_connection("/odom", "nav_msgs/msg/Odometry", typestore=ts)
        c_cmd = w.add_connection("/cmd_vel", "geometry_msgs/msg/Twist", typestore=ts)
        msgs: list[tuple[int, object, object]] = []
        for i, tk in enumerate(t):
            js = T["sensor_msgs/msg/JointState"](
                header(tk, "base_link"),
                ["left_wheel_joint", "right_wheel_joint"],
                np.zeros(2),
                np.array([cols["v_left"][i], cols["v_right"][i]]) / WHEEL_RADIUS_M,
                np.zeros(2),
            )
            msgs.append((recv(tk), c_js, js))
            yaw = float(cols["yaw"][i])
            q = T["geometry_msgs/msg/Quaternion"](0.0, 0.0, math.sin(yaw / 2), math.cos(yaw / 2))
            pt = T["geometry_msgs/msg/Point"](float(cols["x"][i]), float(cols["y"][i]), 0.0)
            odom = T["nav_msgs/msg/Odometry"](
                header(tk, "odom"),
                "base_link",
                T["geometry_msgs/msg/PoseWithCovariance"](
                    T["geometry_msgs/msg/Pose"](pt, q), np.zeros(36)
                ),
                T["geometry_msgs/msg/TwistWithCovariance"](
                    T["geometry_msgs/msg/Twist"](
                        v3(0.5 * (cols["v_left"][i] + cols["v_right"][i]), 0.0, 0.0),
                        v3(0.0, 0.0, float(cols["wz"][i])),
                    ),
                    np.zeros(36),
                ),
            )
            msgs.append((recv(tk), c_odom, odom))
        for idx, tk in windows(t, battery_every):
            amps = -float(np.mean(cols["p_total"][idx])) / BUS_V
            bat = T["sensor_msgs/msg/BatteryState"](
                header(tk, "battery"),
                BUS_V,
                25.0,
                amps,
                float("nan"),
                float("nan"),
                float("nan"),
                float("nan"),
                0,
                0,
                0,
                True,
                np.zeros(0, dtype=np.float32),
                np.zeros(0, dtype=np.float32),
                "",
                "",
            )
            msgs.append((recv(tk), c_bat, bat))
        for idx, _ in windows(t, cmd_every):
            i = int(idx[0])
            vl, vr = float(cols["v_left_cmd"][i]), float(cols["v_right_cmd"][i])
            tw = T["geometry_msgs/msg/Twist"](
                v3(0.5 * (vl + vr), 0.0, 0.0), v3(0.0, 0.0, (vr - vl) / CMD_SEPARATION_M)
            )
            msgs.append((recv(float(t[i])), c_cmd, tw))
        msgs.sort(key=lambda m: m[0])
        for stamp, conn, msg in msgs:
            w.write(conn, stamp, ts.serialize_cdr(msg, msg.__msgtype__))  # type: ignore[attr-defined]
    return path


def topic_map_kwargs() -> dict[str, object]:
    """The keys of the topic map that reads these bags (for ``ecoplan.io.rosbag.TopicMap``)."""
    return {
        "battery_topic": "/battery_state",
        "battery_current_sign": -1.0,
        "power_sampling": "interval_mean",
        "cmd_vel_topic": "/cmd_vel",
        "cmd_separation_m": CMD_SEPARATION_M,
        "odom_topic": "/odom",
    }
