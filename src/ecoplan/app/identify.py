"""``ecoplan identify``: a vehicle file from a user's logs (any source the log reader takes).

Logs are read by :func:`ecoplan.io.logs.read_logs` (ecoplan CSV, ``borealtc:TERRAIN``,
ROS 2 bags); each is cut into pieces of one terrain by its ``terrain`` column (or given one
terrain with ``--terrain``) and passed to
:func:`ecoplan.models.identify_logs.identify_vehicle` (logs of battery power), or, when the
base vehicle file says its logs measure motor currents (``power_log: motor_current``, e.g.
``husky-a200`` and the BorealTC runs), to
:func:`ecoplan.models.identify_current.identify_from_currents` (the side-force model fitted
to the logged ``V_bus (I_l + I_r)``: per side where the log has the optional columns
``current_left`` and ``current_right`` [A] (aliases ``current_left_a``, ``current_right_a``;
the BorealTC runs have them), else their sum).
"""

from __future__ import annotations

import os
from collections.abc import Sequence
from pathlib import Path

import numpy as np

from ecoplan.dynamics.log import Log
from ecoplan.errors import InputError
from ecoplan.io.logs import read_logs
from ecoplan.io.vehicles import load_vehicle
from ecoplan.models.identify_current import (
    CurrentIdentification,
    CurrentLog,
    identify_from_currents,
)
from ecoplan.models.identify_current_vehicle import motor_current_spec
from ecoplan.models.identify_logs import DriveLog, VehicleIdentification, identify_vehicle
from ecoplan.models.vehicle_schema import VEHICLE_NAME_RULE, is_vehicle_name

__all__ = ["current_logs", "drive_logs", "identify_from_logs"]

#: Shortest piece of one terrain kept [samples].
MIN_PIECE_SAMPLES = 20


def drive_logs(log: Log, terrain: str | None = None) -> list[DriveLog]:
    """Pieces of one terrain of a log, as :class:`~ecoplan.models.identify_logs.DriveLog`.

    Parameters
    ----------
    log : Log
        A log in the ecoplan format.
    terrain : str, optional
        The terrain of the whole log; required when the log has no ``terrain`` column.

    Returns
    -------
    list of DriveLog
        Contiguous pieces of at least ``MIN_PIECE_SAMPLES`` samples, each on one terrain.

    Raises
    ------
    InputError
        No terrain column and no ``terrain`` given.
    """
    return [
        DriveLog(log.t[idx], log.v_left[idx], log.v_right[idx], log.p_total[idx], label, name)
        for label, name, idx in _pieces(log, terrain)
    ]


def current_logs(log: Log, bus_voltage_v: float, terrain: str | None = None) -> list[CurrentLog]:
    """Pieces of one terrain of a log as motor-current logs (:func:`drive_logs`' pieces).

    Per side where the log has both ``current_left`` and ``current_right`` [A], else the
    sum ``p_total / bus_voltage_v`` split evenly (the fit then uses the sum only).

    Raises
    ------
    InputError
        Only one of the two current columns, a negative current, or no terrain.
    """
    sides = (log.current_left, log.current_right)
    if (sides[0] is None) != (sides[1] is None):
        missing = "current_right" if sides[1] is None else "current_left"
        raise InputError(f"{log.source}: column {missing!r} is missing (per-side currents "
                         "need both current_left and current_right)")  # fmt: skip
    for col, arr in zip(("current_left", "current_right"), sides, strict=True):
        if arr is not None and np.any(arr < 0.0):
            i = int(np.flatnonzero(arr < 0.0)[0])
            raise InputError(f"{log.source}, sample {i}: column {col!r} is {float(arr[i])!r}; "
                             "motor currents are magnitudes, >= 0 A")  # fmt: skip
    out = []
    for label, name, idx in _pieces(log, terrain):
        if sides[0] is None or sides[1] is None:
            out.append(
                CurrentLog.from_signal(
                    log.t[idx],
                    log.v_left[idx],
                    log.v_right[idx],
                    log.p_total[idx],
                    bus_voltage_v,
                    label,
                    name,
                )
            )
        else:
            out.append(
                CurrentLog(
                    log.t[idx],
                    log.v_left[idx],
                    log.v_right[idx],
                    sides[0][idx],
                    sides[1][idx],
                    label,
                    name,
                )
            )
    return out  # fmt: skip


def _pieces(log: Log, terrain: str | None) -> list[tuple[str, str, np.ndarray]]:
    """(terrain, name, sample indices) of each piece of one terrain (see :func:`drive_logs`)."""
    name = log.run_id or Path(log.source).stem
    if terrain is not None:
        labels = np.full(log.t.size, terrain.lower())
    elif log.terrain is not None:
        labels = np.char.lower(np.asarray(log.terrain, dtype=np.str_))
    else:
        raise InputError(
            f"{log.source}: the log has no terrain column; give its terrain with --terrain"
        )
    cuts = np.flatnonzero(labels[1:] != labels[:-1]) + 1
    return [
        (str(labels[idx[0]]), name if cuts.size == 0 else f"{name}#{k}", idx)
        for k, idx in enumerate(np.split(np.arange(log.t.size), cuts))
        if idx.size >= MIN_PIECE_SAMPLES
    ]


def identify_from_logs(
    paths: Sequence[str | os.PathLike[str]],
    base: str | os.PathLike[str],
    *,
    terrain: str | None = None,
    name: str | None = None,
    clamp: bool = False,
    n_boot: int = 200,
    speed_noise_mps: float = 0.005,
    bus_voltage_v: float = 24.0,
    rng: int = 0,
) -> VehicleIdentification | CurrentIdentification:
    """Read logs, cut them by terrain and identify the base vehicle's model on them.

    Parameters
    ----------
    paths : sequence of str or path
        Log sources (see :func:`ecoplan.io.logs.read_logs`).
    base : str or path
        Base vehicle: a vehicle file or a preset name.
    terrain : str, optional
        Terrain of logs without a ``terrain`` column.
    name : str, optional
        Name of the identified vehicle.
    clamp : bool
        Hold parameters the logs drive negative at 0 instead of refusing.
    n_boot : int
        Bootstrap resamples per terrain.
    speed_noise_mps : float
        Encoder noise of the logs' side speeds [m/s] (SIMEX correction; 0 = none).
    bus_voltage_v : float
        Bus voltage assumed for ``borealtc:`` sources [V]; with a ``motor_current`` base,
        the voltage of every log's ``p_total = V_bus (I_l + I_r)``.
    rng : int
        Seed of the bootstrap.

    Returns
    -------
    VehicleIdentification or CurrentIdentification
        The latter when the base's logs measure motor currents (``clamp`` does not apply:
        its coefficients are bounded and cannot be driven negative).
    """
    if name and not is_vehicle_name(name):
        # checked before the fit: the vehicle file written with it would not load
        raise InputError(f"name {name!r} is not a vehicle name: {VEHICLE_NAME_RULE}")
    vehicle = load_vehicle(base)
    logs = read_logs(paths, bus_voltage_v=bus_voltage_v)
    if vehicle.spec.power_log.signal == "motor_current":
        currents = [p for log in logs for p in current_logs(log, bus_voltage_v, terrain)]
        if not currents:
            raise InputError(f"no piece of at least {MIN_PIECE_SAMPLES} samples on one terrain")
        return identify_from_currents(
            currents,
            vehicle,
            motor_current_spec(vehicle),
            name=name,
            n_boot=n_boot,
            speed_noise_mps=speed_noise_mps,
            rng=rng,
        )
    pieces = [p for log in logs for p in drive_logs(log, terrain)]
    if not pieces:
        raise InputError(f"no piece of at least {MIN_PIECE_SAMPLES} samples on one terrain")
    return identify_vehicle(
        pieces,
        vehicle,
        name=name,
        clamp=clamp,
        n_boot=n_boot,
        speed_noise_mps=speed_noise_mps,
        rng=rng,
    )
