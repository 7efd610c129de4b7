"""``ecoplan identify``: a vehicle file from a user's logs (any source the log reader takes).

Logs are read by :func:`ecoplan.io.logs.read_logs` (ecoplan CSV, ``borealtc:TERRAIN``,
ROS 2 bags); each is cut into pieces of one terrain by its ``terrain`` column (or given one
terrain with ``--terrain``) and passed to
:func:`ecoplan.models.identify_logs.identify_vehicle` (logs of battery power), or, when the
base vehicle file says its logs measure motor currents (``power_log: motor_current``, e.g.
``husky-a200`` and the BorealTC runs), to
:func:`ecoplan.models.identify_current.identify_from_currents` (the side-force model fitted
to the logged ``V_bus (I_l + I_r)``).
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
    motor_current_spec,
)
from ecoplan.models.identify_logs import DriveLog, VehicleIdentification, identify_vehicle

__all__ = ["drive_logs", "identify_from_logs"]

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
    out = []
    for k, idx in enumerate(np.split(np.arange(log.t.size), cuts)):
        if idx.size < MIN_PIECE_SAMPLES:
            continue
        label = str(labels[idx[0]])
        out.append(
            DriveLog(
                log.t[idx],
                log.v_left[idx],
                log.v_right[idx],
                log.p_total[idx],
                label,
                f"{name}" if cuts.size == 0 else f"{name}#{k}",
            )
        )
    return out


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
    vehicle = load_vehicle(base)
    logs = read_logs(paths, bus_voltage_v=bus_voltage_v)
    pieces = [p for log in logs for p in drive_logs(log, terrain)]
    if not pieces:
        raise InputError(f"no piece of at least {MIN_PIECE_SAMPLES} samples on one terrain")
    if vehicle.spec.power_log.signal == "motor_current":
        currents = [
            CurrentLog.from_signal(
                p.t_s, p.v_left, p.v_right, p.p_total_w, bus_voltage_v, p.terrain, p.run_id
            )
            for p in pieces
        ]
        return identify_from_currents(
            currents,
            vehicle,
            motor_current_spec(vehicle),
            name=name,
            n_boot=n_boot,
            speed_noise_mps=speed_noise_mps,
            rng=rng,
        )
    return identify_vehicle(
        pieces,
        vehicle,
        name=name,
        clamp=clamp,
        n_boot=n_boot,
        speed_noise_mps=speed_noise_mps,
        rng=rng,
    )
