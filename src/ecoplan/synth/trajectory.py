"""The true motion of a synthetic run: commands -> actual speeds -> pose.

One :class:`Trajectory` per run, built by the one drive law
(:func:`ecoplan.dynamics.drive.follow_commands`: acceleration limit, optional lag) and
the one integrator (:func:`ecoplan.dynamics.integrate.integrate_tracks`: exact arcs of
each interval's mean twist, the speeds ramping linearly between samples).
"""

from __future__ import annotations

import dataclasses
from dataclasses import dataclass

import numpy as np

from ecoplan._typing import FloatArray
from ecoplan.dynamics.drive import follow_commands
from ecoplan.dynamics.integrate import integrate_tracks
from ecoplan.models.kinematics import TrackICR, tracks_to_twist
from ecoplan.presets import VehicleParams

__all__ = ["Trajectory", "trajectory_from_commands"]


@dataclass(frozen=True, slots=True, eq=False)
class Trajectory:
    """True motion of one run (noise-free), in session time.

    Attributes
    ----------
    t : ndarray
        Time [s], uniform steps.
    cmd_left, cmd_right : ndarray
        Commanded side speeds [m/s].
    v_left, v_right : ndarray
        Actual side speeds [m/s].
    vx, vy, wz : ndarray
        Body twist from the actual speeds (tracked eqs. 1-3) [m/s, m/s, rad/s].
    ax, alpha : ndarray
        Time derivatives of ``vx`` [m/s²] and ``wz`` [rad/s²].
    x, y, yaw : ndarray
        Pose [m, m, rad] (yaw unwrapped).
    manoeuvre : str
        Kind of run (``grid``, ``spiral``, ``waypoints``).
    """

    t: FloatArray
    cmd_left: FloatArray
    cmd_right: FloatArray
    v_left: FloatArray
    v_right: FloatArray
    vx: FloatArray
    vy: FloatArray
    wz: FloatArray
    ax: FloatArray
    alpha: FloatArray
    x: FloatArray
    y: FloatArray
    yaw: FloatArray
    manoeuvre: str = ""

    def __len__(self) -> int:
        return int(self.t.size)

    def shifted(self, t0_s: float) -> Trajectory:
        """The same motion with ``t0_s`` [s] added to every time stamp."""
        return dataclasses.replace(self, t=self.t + t0_s)

    @classmethod
    def of(
        cls,
        t: FloatArray,
        cmd: tuple[FloatArray, FloatArray],
        speeds: tuple[FloatArray, FloatArray],
        icr: TrackICR,
        pose: tuple[FloatArray, FloatArray, FloatArray],
        manoeuvre: str = "",
    ) -> Trajectory:
        """A trajectory from its commands, actual speeds and pose; the twist by eqs. (1)-(3).

        Parameters
        ----------
        t : ndarray
            Time [s].
        cmd, speeds : tuple of ndarray
            Commanded and actual ``(left, right)`` side speeds [m/s].
        icr : TrackICR
            The true track ICRs.
        pose : tuple of ndarray
            ``(x, y, yaw)`` [m, m, rad].
        manoeuvre : str
            Kind of run.

        Returns
        -------
        Trajectory
            With ``vx, vy, wz`` from :func:`~ecoplan.models.kinematics.tracks_to_twist` and
            their time derivatives by :func:`numpy.gradient`.
        """
        tw = tracks_to_twist(speeds[0], speeds[1], icr)
        return cls(
            t=t,
            cmd_left=cmd[0],
            cmd_right=cmd[1],
            v_left=speeds[0],
            v_right=speeds[1],
            vx=tw.vx,
            vy=tw.vy,
            wz=tw.wz,
            ax=np.gradient(tw.vx, t),
            alpha=np.gradient(tw.wz, t),
            x=pose[0],
            y=pose[1],
            yaw=pose[2],
            manoeuvre=manoeuvre,
        )

    @property
    def world_velocity(self) -> tuple[FloatArray, FloatArray]:
        """World-frame velocity ``(xdot, ydot)`` [m/s]."""
        c, s = np.cos(self.yaw), np.sin(self.yaw)
        return self.vx * c - self.vy * s, self.vx * s + self.vy * c


def trajectory_from_commands(
    t: FloatArray,
    cmd_left: FloatArray,
    cmd_right: FloatArray,
    vehicle: VehicleParams,
    *,
    tau_s: float = 0.0,
    pose0: tuple[float, float, float] = (0.0, 0.0, 0.0),
    manoeuvre: str = "",
) -> Trajectory:
    """Open-loop run: commands -> actual speeds -> pose, by the one drive law and integrator.

    Speeds by :func:`ecoplan.dynamics.drive.follow_commands` (acceleration limit, lag),
    pose by :func:`ecoplan.dynamics.integrate.integrate_tracks` (exact arcs of the mean
    twist of each interval: the speeds ramp linearly between samples).

    Parameters
    ----------
    t, cmd_left, cmd_right : ndarray
        Time [s] and commanded side speeds [m/s].
    vehicle : TrackedParams or WheeledParams
        The true vehicle (its acceleration limit and ICRs are used).
    tau_s : float
        Actuator lag time constant [s] (0: none).
    pose0 : tuple of float
        Start pose ``(x, y, yaw)``.
    manoeuvre : str
        Label stored in the trajectory.

    Returns
    -------
    Trajectory
        True motion.
    """
    vl = follow_commands(t, cmd_left, vehicle.accel_max_mps2, tau_s)
    vr = follow_commands(t, cmd_right, vehicle.accel_max_mps2, tau_s)
    pose = integrate_tracks(t, vl, vr, vehicle.icr, pose0, hold="mean")
    return Trajectory.of(t, (cmd_left, cmd_right), (vl, vr), vehicle.icr, pose, manoeuvre)
