"""Loader of the BorealTC runs (Clearpath Husky A200, a 4-wheel skid-steer).

BorealTC (LaRocque et al. 2024, CC0 1.0) holds proprioceptive logs of a Husky A200
(about 70 kg) on five terrains (:func:`list_terrains`: ``ASPHALT``, ``FLOORING``, ``ICE``,
``SANDY_LOAM``, ``SNOW``), one folder each, with per run:

* ``pro_XX.csv`` -- ``time`` [s], ``curL``, ``curR`` [A, motor current per side, stored
  as magnitudes], ``velL``, ``velR`` [m/s, side speeds from wheel odometry]; ≈ 6.5 Hz;
* ``imu_XX.csv`` -- ``time`` [s], ``wx``, ``wy``, ``wz`` [rad/s], ``ax``, ``ay``, ``az``
  [m/s²]; 100 Hz.  FLOORING ``imu_04`` and ``imu_06`` and ICE ``imu_01`` are missing.

Data root: the environment variable ``ECOPLAN_BOREALTC`` if set, else
``<repository root>/../shared/data/borealtc`` (the repository root is the first parent
of this file holding ``pyproject.toml``).  The data are read in place.

Electrical power needs the bus voltage, which the logs do not record:
``p_total = bus_voltage_v (curL + curR)`` with the Husky's nominal 24 V battery by
default -- an assumption; the true voltage sags under load and with charge.

:func:`load_run` gives the raw run (:class:`BorealRun`, with the motor currents);
:func:`load_borealtc` gives it as a :class:`~ecoplan.dynamics.log.Log` (with the
per-side currents) for the diagnosis and ``ecoplan identify``; :func:`at_rest_mask` marks
where a run's robot is stuck (wheels turning, body at rest by the IMU's gyroscope);
:func:`imu_grade_rad` gives the slope climbed, from the IMU's accelerometer (the runs have
no pose and no elevation map).
"""

from __future__ import annotations

import csv
import os
from dataclasses import dataclass
from pathlib import Path

import numpy as np

from ecoplan._typing import BoolArray, FloatArray
from ecoplan.dynamics.log import Log
from ecoplan.errors import InputError, LogFormatError
from ecoplan.io.timebase import window_means
from ecoplan.models.identify_screen import AT_REST_MAX_RATE_RADPS, body_at_rest

__all__ = [
    "ENV_VAR",
    "HUSKY_BUS_VOLTAGE_V",
    "BorealRun",
    "at_rest_mask",
    "data_root",
    "imu_grade_rad",
    "list_runs",
    "list_terrains",
    "load_borealtc",
    "load_borealtc_runs",
    "load_run",
    "load_runs",
]

#: Environment variable that overrides the data root.
ENV_VAR = "ECOPLAN_BOREALTC"
#: Nominal battery voltage of the Husky A200 [V] (no voltage column in the logs).
HUSKY_BUS_VOLTAGE_V = 24.0

_PRO_COLUMNS = ("time", "curL", "curR", "velL", "velR")
_IMU_COLUMNS = ("time", "wz")
_GYRO_COLUMNS = ("time", "wx", "wy", "wz")
_ACCEL_COLUMNS = ("time", "ax")
#: Standard gravity [m/s²] (the accelerometer's reading of a level body at rest is -g on z).
_G_MPS2 = 9.81


@dataclass(frozen=True, slots=True, eq=False)
class BorealRun:
    """One BorealTC run resampled on the motor-log (``pro_XX.csv``) timestamps.

    Attributes
    ----------
    t : ndarray
        Time since the start of the run [s], strictly increasing.
    v_left, v_right : ndarray
        Side speeds from wheel odometry [m/s] (REP-103: positive forward).
    current_left, current_right : ndarray
        Motor current per side [A], magnitudes as stored in the log.
    p_total : ndarray
        Electrical locomotion power ``bus_voltage_v (current_left + current_right)`` [W];
        the voltage is an assumption (see :attr:`bus_voltage_v`).
    wz : ndarray or None
        Yaw rate from the IMU [rad/s], linearly interpolated onto ``t``; at timestamps
        outside the IMU's time span the nearest IMU value is held (see ``wz_valid``).
        None when the run has no IMU file (FLOORING 04 and 06).
    wz_valid : ndarray of bool or None
        True where ``t`` lies inside the IMU's time span (``wz`` interpolated, not held).
    terrain : str
        Terrain folder name, upper case (``"ASPHALT"``, ``"FLOORING"``).
    run_id : str
        Two-digit run number (``"00"``...).
    bus_voltage_v : float
        Bus voltage assumed for ``p_total`` [V] (Husky A200 battery: 24 V nominal).
    """

    t: FloatArray
    v_left: FloatArray
    v_right: FloatArray
    current_left: FloatArray
    current_right: FloatArray
    p_total: FloatArray
    wz: FloatArray | None
    wz_valid: BoolArray | None
    terrain: str
    run_id: str
    bus_voltage_v: float

    @property
    def n_samples(self) -> int:
        """Number of motor-log samples."""
        return int(self.t.size)

    @property
    def duration_s(self) -> float:
        """Time span of the run [s]."""
        return float(self.t[-1] - self.t[0]) if self.t.size else 0.0

    @property
    def p_left(self) -> FloatArray:
        """Electrical power of the left side ``bus_voltage_v current_left`` [W]."""
        return self.bus_voltage_v * self.current_left

    @property
    def p_right(self) -> FloatArray:
        """Electrical power of the right side ``bus_voltage_v current_right`` [W]."""
        return self.bus_voltage_v * self.current_right

    @property
    def has_imu(self) -> bool:
        """True when the run has an IMU log (so ``wz`` is an array)."""
        return self.wz is not None


def _repo_root() -> Path | None:
    for parent in Path(__file__).resolve().parents:
        if (parent / "pyproject.toml").is_file():
            return parent
    return None


def data_root(root: str | os.PathLike[str] | None = None) -> Path:
    """Folder holding the BorealTC terrain folders.

    Parameters
    ----------
    root : path-like, optional
        Explicit root; default ``$ECOPLAN_BOREALTC`` or ``<repo root>/../shared/data/borealtc``.

    Returns
    -------
    pathlib.Path
        The root (not checked for existence; the listing functions check it).

    Raises
    ------
    InputError
        No root given, no environment variable and no repository root found.
    """
    if root is not None:
        return Path(root)
    env = os.environ.get(ENV_VAR)
    if env:
        return Path(env)
    repo = _repo_root()
    if repo is None:
        raise InputError(
            f"cannot locate the BorealTC data: set {ENV_VAR} or pass root= "
            "(no pyproject.toml above the installed package)"
        )
    return repo.parent / "shared" / "data" / "borealtc"


def _existing_root(root: str | os.PathLike[str] | None) -> Path:
    path = data_root(root)
    if not path.is_dir():
        raise InputError(f"BorealTC data root {str(path)!r} is not a folder (set {ENV_VAR})")
    return path


def list_terrains(root: str | os.PathLike[str] | None = None) -> list[str]:
    """Terrain folders present under the data root (e.g. ``["ASPHALT", "FLOORING"]``)."""
    path = _existing_root(root)
    return sorted(p.name for p in path.iterdir() if p.is_dir() and any(p.glob("pro_*.csv")))


def _terrain_dir(terrain: str, root: str | os.PathLike[str] | None) -> tuple[str, Path]:
    path = _existing_root(root)
    name = str(terrain).upper()
    accepted = list_terrains(path)
    # only a terrain folder of the root: an empty name is the root itself, '..' leaves it
    if name not in accepted:
        raise InputError(f"unknown BorealTC terrain {terrain!r}; accepted: {', '.join(accepted)}")
    return name, path / name


def list_runs(terrain: str, root: str | os.PathLike[str] | None = None) -> list[str]:
    """Run ids present for a terrain, from its ``pro_XX.csv`` files, sorted.

    Parameters
    ----------
    terrain : str
        Terrain folder name, case-insensitive (``"asphalt"``, ``"FLOORING"``).
    root : path-like, optional
        Data root (see :func:`data_root`).

    Returns
    -------
    list of str
        Run ids such as ``["00", "01", ...]``.
    """
    _, folder = _terrain_dir(terrain, root)
    return sorted(p.stem[len("pro_") :] for p in folder.glob("pro_*.csv"))


def _read_csv(path: Path, columns: tuple[str, ...]) -> dict[str, FloatArray]:
    """Read the named numeric columns of a CSV file with a header row."""
    try:
        with path.open(newline="") as fh:
            rows = list(csv.reader(fh))
    except OSError as exc:
        raise LogFormatError(f"{path}: cannot read ({exc.strerror})") from None
    except (UnicodeDecodeError, csv.Error) as exc:
        raise LogFormatError(f"{path}: not a readable CSV file ({exc})") from None
    if not rows:
        raise LogFormatError(f"{path}: empty file, expected a header with {', '.join(columns)}")
    header = [h.strip() for h in rows[0]]
    missing = [c for c in columns if c not in header]
    if missing:
        raise LogFormatError(
            f"{path}: missing column(s) {', '.join(missing)}; header is {', '.join(header)}"
        )
    index = {c: header.index(c) for c in columns}
    body = rows[1:]
    while body and not body[-1]:  # trailing blank lines
        body.pop()
    if not body:
        raise LogFormatError(f"{path}: no data rows after the header")
    out = _fast_columns(body, index, len(header))
    if out is None:
        out = _checked_columns(path, body, index, len(header))
    t = out["time"]
    bad = np.flatnonzero(np.diff(t) <= 0.0)
    if bad.size:
        k = int(bad[0]) + 1
        raise LogFormatError(
            f"{path}: line {k + 2}, column 'time': {t[k]!r} does not increase "
            f"(previous {t[k - 1]!r})"
        )
    return out


def _fast_columns(
    body: list[list[str]], index: dict[str, int], width: int
) -> dict[str, FloatArray] | None:
    """Columns as float arrays, or None if any row is ragged or any value is not finite."""
    if any(len(row) != width for row in body):
        return None
    try:
        table = np.array(body, dtype=np.float64)
    except ValueError:
        return None
    cols = {c: np.ascontiguousarray(table[:, j]) for c, j in index.items()}
    if not all(np.all(np.isfinite(v)) for v in cols.values()):
        return None
    return cols


def _checked_columns(
    path: Path, body: list[list[str]], index: dict[str, int], width: int
) -> dict[str, FloatArray]:
    """Row-by-row parse that names the first bad line and column."""
    out = {c: np.empty(len(body)) for c in index}
    for i, row in enumerate(body):
        line = i + 2  # 1-based, header is line 1
        if len(row) != width:
            raise LogFormatError(
                f"{path}: row at line {line} has {len(row)} fields, header has {width}"
            )
        for c, j in index.items():
            try:
                value = float(row[j])
            except ValueError:
                raise LogFormatError(
                    f"{path}: line {line}, column {c!r}: {row[j]!r} is not a number"
                ) from None
            if not np.isfinite(value):
                raise LogFormatError(f"{path}: line {line}, column {c!r}: {row[j]!r} is not finite")
            out[c][i] = value
    return out


def load_run(
    terrain: str,
    run_id: str | int,
    root: str | os.PathLike[str] | None = None,
    bus_voltage_v: float = HUSKY_BUS_VOLTAGE_V,
) -> BorealRun:
    """Load one run: motor log plus the IMU yaw rate on the motor-log timestamps.

    Parameters
    ----------
    terrain : str
        Terrain folder name, case-insensitive (``"ASPHALT"`` or ``"FLOORING"``).
    run_id : str or int
        Run id, ``"03"`` or ``3``.
    root : path-like, optional
        Data root (see :func:`data_root`).
    bus_voltage_v : float
        Bus voltage for ``p_total`` [V]; default the Husky's nominal 24 V (assumed: the
        logs have no voltage column).

    Returns
    -------
    BorealRun
        The run; ``wz`` is None when the IMU file is missing.

    Raises
    ------
    InputError
        Unknown terrain or run id (the message lists the accepted ones), bad voltage.
    LogFormatError
        A malformed file; the message names the file and the column or row.
    """
    if not (isinstance(bus_voltage_v, int | float) and 0.0 < bus_voltage_v < 1e4):
        raise InputError(f"bus_voltage_v = {bus_voltage_v!r} V; accepted: (0, 10000)")
    name, folder = _terrain_dir(terrain, root)
    rid = f"{run_id:02d}" if isinstance(run_id, int) else str(run_id)
    pro_path = folder / f"pro_{rid}.csv"
    if not pro_path.is_file():
        raise InputError(
            f"unknown BorealTC run {run_id!r} for {name}; accepted: "
            f"{', '.join(list_runs(name, folder.parent))}"
        )
    pro = _read_csv(pro_path, _PRO_COLUMNS)
    t = pro["time"]
    imu_path = folder / f"imu_{rid}.csv"
    wz: FloatArray | None = None
    wz_valid: BoolArray | None = None
    if imu_path.is_file():
        imu = _read_csv(imu_path, _IMU_COLUMNS)
        wz = np.interp(t, imu["time"], imu["wz"])
        wz_valid = (t >= imu["time"][0]) & (t <= imu["time"][-1])
    cur_l, cur_r = pro["curL"], pro["curR"]
    return BorealRun(
        t=t,
        v_left=pro["velL"],
        v_right=pro["velR"],
        current_left=cur_l,
        current_right=cur_r,
        p_total=float(bus_voltage_v) * (cur_l + cur_r),
        wz=wz,
        wz_valid=wz_valid,
        terrain=name,
        run_id=rid,
        bus_voltage_v=float(bus_voltage_v),
    )


def at_rest_mask(
    run: BorealRun,
    root: str | os.PathLike[str] | None = None,
    max_rate_radps: float = AT_REST_MAX_RATE_RADPS,
) -> BoolArray:
    """Samples of a run where the wheels turn but the body rests (the robot is stuck).

    The rule of :func:`ecoplan.models.identify_screen.body_at_rest` (5 s windows, the
    gyroscope's three axes from ``imu_XX.csv``); all False when the run has no IMU file.

    Parameters
    ----------
    run : BorealRun
        A run of :func:`load_run`.
    root : path-like, optional
        Data root (see :func:`data_root`).
    max_rate_radps : float
        Gyroscope rms below which the body rests [rad/s].

    Returns
    -------
    ndarray of bool
        Per sample of ``run.t``.
    """
    _, folder = _terrain_dir(run.terrain, root)
    path = folder / f"imu_{run.run_id}.csv"
    if not path.is_file():
        return np.zeros(run.t.size, dtype=np.bool_)
    imu = _read_csv(path, _GYRO_COLUMNS)
    gyro = np.column_stack([imu["wx"], imu["wy"], imu["wz"]])
    return body_at_rest(
        run.t, run.v_left, run.v_right, imu["time"], gyro, max_rate_radps=max_rate_radps
    )


def imu_grade_rad(
    run: BorealRun,
    root: str | os.PathLike[str] | None = None,
    window_s: float = 2.0,
    max_grade_rad: float = np.pi / 6,
) -> FloatArray | None:
    """Slope climbed along the robot's +x per sample [rad], from the IMU's accelerometer.

    An accelerometer on a body pitched nose-up by θ reads ``a_x = dv/dt + g sin θ``; with
    ``dv/dt`` from the odometry (the mean side speed), ``θ = asin((a_x - dv/dt) / g)``,
    both sides averaged over ``window_s`` (the accelerometer's vibration and the
    odometry's steps average out), clipped to ``±max_grade_rad``.  This is the body's
    pitch: on firm ground the grade of the path; on deformable ground it also holds the
    trim of a body that sinks in at the rear (a planner's grade comes from its elevation
    map instead).

    Parameters
    ----------
    run : BorealRun
        A run of :func:`load_run`.
    root : path-like, optional
        Data root (see :func:`data_root`).
    window_s : float
        Width of the centred means [s], > 0.
    max_grade_rad : float
        Largest grade magnitude returned [rad], in (0, π/2).

    Returns
    -------
    ndarray or None
        Per sample of ``run.t``; None when the run has no IMU file.

    Raises
    ------
    InputError
        A bad window or bound.
    """
    if not (isinstance(window_s, int | float) and 0.0 < window_s <= 1e3):
        raise InputError(f"imu_grade_rad: window_s = {window_s!r} s; accepted: (0, 1000]")
    if not (isinstance(max_grade_rad, int | float) and 0.0 < max_grade_rad < np.pi / 2):
        raise InputError(f"imu_grade_rad: max_grade_rad = {max_grade_rad!r}; accepted: (0, pi/2)")
    _, folder = _terrain_dir(run.terrain, root)
    path = folder / f"imu_{run.run_id}.csv"
    if not path.is_file():
        return None
    imu = _read_csv(path, _ACCEL_COLUMNS)
    ax = window_means(imu["time"], imu["ax"], run.t, window_s)
    v = window_means(run.t, 0.5 * (run.v_left + run.v_right), run.t, window_s)
    accel = np.gradient(v, run.t) if run.t.size >= 2 else np.zeros_like(v)
    sin_grade = np.clip((ax - accel) / _G_MPS2, -np.sin(max_grade_rad), np.sin(max_grade_rad))
    return np.asarray(np.arcsin(sin_grade), dtype=np.float64)


def load_runs(
    terrain: str,
    root: str | os.PathLike[str] | None = None,
    bus_voltage_v: float = HUSKY_BUS_VOLTAGE_V,
) -> list[BorealRun]:
    """Every run of a terrain, in run-id order (see :func:`load_run`)."""
    return [load_run(terrain, rid, root, bus_voltage_v) for rid in list_runs(terrain, root)]


def load_borealtc(
    terrain: str,
    run_id: str | int,
    bus_voltage_v: float = 24.0,
    root: str | os.PathLike[str] | None = None,
) -> Log:
    """One BorealTC hard-ground run (Husky A200) as a :class:`Log`.

    Built on :func:`load_run`: side speeds from wheel
    odometry, ``p_total = bus_voltage_v (|I_left| + |I_right|)`` and the IMU yaw rate
    interpolated onto the motor-log time stamps.  Samples outside the IMU's time span
    (where the loader holds the nearest value) count as a missing ``wz`` and are dropped
    and counted in :attr:`Log.dropped_rows`.  The bus voltage is an assumption (the data
    have no voltage column) and is stated in :attr:`Log.notes`.

    Parameters
    ----------
    terrain : str
        ``"ASPHALT"`` or ``"FLOORING"`` (case-insensitive).
    run_id : str or int
        Run number (``"03"`` or ``3``).
    bus_voltage_v : float
        Assumed bus voltage [V] (Husky A200: 24 V nominal).
    root : path-like, optional
        Data root (default: see :func:`data_root`).

    Returns
    -------
    Log
        Columns ``t, v_left, v_right, p_total, current_left, current_right`` (+ ``wz``
        when the IMU file exists) and a ``terrain`` label (lower case); ``run_id`` like
        ``"FLOORING_03"``.
    """
    run = load_run(terrain, run_id, root, bus_voltage_v)
    source = str(data_root(root) / run.terrain / f"pro_{run.run_id}.csv")
    notes = [
        f"p_total = {run.bus_voltage_v:g} V x (curL + curR): the bus voltage is an "
        "assumption (BorealTC has no voltage column; the battery sags under load)",
        "curL, curR are motor currents: p_total is a torque (force) signal, not battery "
        "power (husky-a200: power_log motor_current, ecoplan.models.motor_current)",
        "BorealTC: Clearpath Husky A200 (wheeled skid-steer, about 70 kg), ~6.5 Hz motor log",
    ]
    n = run.t.size
    keep: BoolArray = np.ones(n, dtype=np.bool_)
    wz = None
    if run.wz is not None:
        wz = run.wz
        if run.wz_valid is not None:
            keep = run.wz_valid.copy()
        notes.append("wz: IMU yaw rate (100 Hz) interpolated onto the motor-log time stamps")
    else:
        notes.append("no IMU file for this run: wz absent")
    dropped = int(n - keep.sum())
    if dropped:
        notes.append(f"dropped {dropped} of {n} rows outside the IMU's time span (no wz)")
    if int(keep.sum()) < 2:
        raise LogFormatError(f"{source}: fewer than 2 samples inside the IMU's time span")
    return Log(
        t=run.t[keep],
        v_left=run.v_left[keep],
        v_right=run.v_right[keep],
        p_total=run.p_total[keep],
        current_left=run.current_left[keep],
        current_right=run.current_right[keep],
        wz=None if wz is None else wz[keep],
        terrain=np.full(int(keep.sum()), run.terrain.lower()),
        source=source,
        run_id=f"{run.terrain}_{run.run_id}",
        dropped_rows=dropped,
        notes=tuple(notes),
    )


def load_borealtc_runs(
    terrain: str, bus_voltage_v: float = 24.0, root: str | os.PathLike[str] | None = None
) -> list[Log]:
    """Every run of a BorealTC terrain as logs, in run order (see :func:`load_borealtc`).

    Parameters
    ----------
    terrain : str
        ``"ASPHALT"`` or ``"FLOORING"`` (case-insensitive).
    bus_voltage_v : float
        Assumed bus voltage [V].
    root : path-like, optional
        Data root (default: see :func:`data_root`).

    Returns
    -------
    list of Log
        One log per run.
    """
    return [load_borealtc(terrain, rid, bus_voltage_v, root) for rid in list_runs(terrain, root)]
