"""The one time-series type of ecoplan, :class:`Log`, and its column specification.

A run of a skid-steer robot -- simulated (:meth:`ecoplan.sim.SimResult.to_log`), read from
a CSV file (:mod:`ecoplan.io.logcsv`), a ROS 2 bag (:mod:`ecoplan.io.rosbag`) or the
BorealTC data (:mod:`ecoplan.io.borealtc`) -- is a :class:`Log`, and the diagnosis reads
nothing else.  SI units, REP-103 frames (x forward, y left, yaw counter-clockwise).

Columns (:data:`COLUMNS`, in file order; a CSV header may also use an alias)
----------------------------------------------------------------------------
=================  =========  ==================================================  ========
column             unit       meaning                                             required
=================  =========  ==================================================  ========
``t``              s          time, strictly increasing                           yes
``v_left``         m/s        measured left side (track/wheel) speed              yes
``v_right``        m/s        measured right side speed                           yes
``p_total``        W          electrical power of locomotion                      yes
``v_left_cmd``     m/s        commanded left side speed                           no
``v_right_cmd``    m/s        commanded right side speed                          no
``x``, ``y``       m          position in the world frame                         no
``yaw``            rad        heading, counter-clockwise from world x             no
``wz``             rad/s      measured yaw rate                                   no
``p_left``         W          mechanical power of the left motor                  no
``p_right``        W          mechanical power of the right motor                 no
``current_left``   A          motor current of the left side (magnitude, >= 0)    no
``current_right``  A          motor current of the right side (magnitude, >= 0)   no
``terrain``        label      terrain name under the robot (text)                 no
=================  =========  ==================================================  ========

Aliases: every numeric column also answers to its name with the unit appended
(``t_s``, ``v_left_mps``, ``p_total_w``, ``x_m``, ``yaw_rad``, ``wz_radps``, the
currents ``current_left_a`` and ``current_right_a``, ...).
Further numeric columns a producer wants to keep (the simulator's motion ``case`` and
power breakdown) ride along in :attr:`Log.extra`; the diagnosis ignores them.

Validation (every failure is a :class:`~ecoplan.errors.LogFormatError` with a one-line
message naming the source, the column and the sample): required columns present and
finite, optional ones finite, equal lengths, at least 2 samples, time strictly
increasing, side speeds below :data:`MAX_PLAUSIBLE_SPEED_MPS` in magnitude (a larger one
looks like mm/s).  The CSV reader runs the same checks with the file's line numbers.

>>> log = Log(t=[0.0, 0.1], v_left=[0.2, 0.2], v_right=[0.2, 0.3], p_total=[50.0, 55.0])
>>> log.columns(), log.duration_s
(('t', 'v_left', 'v_right', 'p_total'), 0.1)
>>> Log(t=[0.0, 0.0], v_left=[0.2, 0.2], v_right=[0.2, 0.3], p_total=[50.0, 55.0])
Traceback (most recent call last):
...
ecoplan.errors.LogFormatError: <memory>, sample 1: time duplicated in column 't' ...
"""

from __future__ import annotations

import dataclasses
from collections.abc import Collection, Mapping, Sequence
from dataclasses import dataclass, field
from typing import Any, Literal

import numpy as np
import numpy.typing as npt

from ecoplan._typing import BoolArray, FloatArray
from ecoplan.errors import LogFormatError

__all__ = [
    "ALIASES",
    "COLUMNS",
    "FLOAT_COLUMNS",
    "HELD_REGULARITY",
    "HELD_STREAMS",
    "INTERPOLATED_STREAMS",
    "MAX_PLAUSIBLE_SPEED_MPS",
    "OPTIONAL_COLUMNS",
    "OPTIONAL_FLOAT_COLUMNS",
    "POSE_COLUMNS",
    "POSE_FRAMES",
    "POWER_SAMPLINGS",
    "REQUIRED_COLUMNS",
    "RESTART_S",
    "SPEED_COLUMNS",
    "Column",
    "Log",
    "StrArray",
    "check_pose_frame",
    "check_power_sampling",
    "check_values",
    "fresh_readings",
    "join_runs",
]

StrArray = npt.NDArray[np.str_]

#: Unit suffix of a column's alias, by unit.
_UNIT_SUFFIX = {
    "s": "_s",
    "m/s": "_mps",
    "W": "_w",
    "m": "_m",
    "rad": "_rad",
    "rad/s": "_radps",
    "A": "_a",
}


@dataclass(frozen=True, slots=True)
class Column:
    """One column of the log format.

    Attributes
    ----------
    name : str
        Canonical name (the :class:`Log` attribute and the CSV header).
    unit : str
        SI unit (``"label"`` for text).
    meaning : str
        What the column holds.
    required : bool
        Every log must have it.
    kind : {"float", "text"}
        Numeric (float64) or a text label.
    speed : bool
        A side speed, checked for plausible magnitude.
    extra_aliases : tuple of str
        Header names accepted besides the name and its unit-suffixed alias.
    """

    name: str
    unit: str
    meaning: str
    required: bool = False
    kind: Literal["float", "text"] = "float"
    speed: bool = False
    extra_aliases: tuple[str, ...] = ()

    @property
    def aliases(self) -> tuple[str, ...]:
        """Other header names of this column: ``name + unit suffix`` and the extra ones."""
        suffix = _UNIT_SUFFIX.get(self.unit)
        unit_alias = (self.name + suffix,) if suffix else ()
        return (*unit_alias, *self.extra_aliases)


#: The log format, in file order.
COLUMNS: tuple[Column, ...] = (
    Column("t", "s", "time, strictly increasing", required=True),
    Column("v_left", "m/s", "measured left side speed", required=True, speed=True),
    Column("v_right", "m/s", "measured right side speed", required=True, speed=True),
    Column("p_total", "W", "electrical power of locomotion", required=True),
    Column("v_left_cmd", "m/s", "commanded left side speed", speed=True),
    Column("v_right_cmd", "m/s", "commanded right side speed", speed=True),
    Column("x", "m", "position in the world frame, x"),
    Column("y", "m", "position in the world frame, y"),
    Column("yaw", "rad", "heading, counter-clockwise from world x"),
    Column("wz", "rad/s", "measured yaw rate"),
    Column("p_left", "W", "mechanical power of the left motor"),
    Column("p_right", "W", "mechanical power of the right motor"),
    Column("current_left", "A", "motor current of the left side (magnitude)"),
    Column("current_right", "A", "motor current of the right side (magnitude)"),
    Column("terrain", "label", "terrain name under the robot", kind="text"),
)

#: Columns every log must have, in file order.
REQUIRED_COLUMNS: tuple[str, ...] = tuple(c.name for c in COLUMNS if c.required)
#: Optional numeric columns, in file order.
OPTIONAL_FLOAT_COLUMNS: tuple[str, ...] = tuple(
    c.name for c in COLUMNS if not c.required and c.kind == "float"
)
#: Every optional column, numeric and text.
OPTIONAL_COLUMNS: tuple[str, ...] = tuple(c.name for c in COLUMNS if not c.required)
#: Every numeric column, in file order.
FLOAT_COLUMNS: tuple[str, ...] = tuple(c.name for c in COLUMNS if c.kind == "float")
#: The pose: each run's own, so it jumps where runs are joined (:func:`join_runs`).
POSE_COLUMNS: tuple[str, ...] = ("x", "y", "yaw")
#: Columns holding side speeds, checked for plausible magnitude.
SPEED_COLUMNS: tuple[str, ...] = tuple(c.name for c in COLUMNS if c.speed)
#: Header name -> column name, for every alias.
ALIASES: Mapping[str, str] = {a: c.name for c in COLUMNS for a in c.aliases}
#: Side speeds above this magnitude [m/s] are taken for a unit error (mm/s, rpm, ...).
MAX_PLAUSIBLE_SPEED_MPS = 20.0
#: Time falling back by more than this [s] is read as a restarted clock: runs joined in one
#: file (each run belongs in its own file); a smaller step back, as rows out of order.
RESTART_S = 1.0

#: How the logged power was taken (``# power_sampling:`` in a CSV log): ``"row"``, the power
#: at the row's time (the default); ``"interval_mean"``, the mean over the sample interval
#: before the row (an energy counter or an averaging current sensor read at every row).
POWER_SAMPLINGS = ("row", "interval_mean")

#: Where a log's pose is expressed (``# pose_frame:`` in a CSV log): ``"world"``, one frame for
#: every run (a map, GNSS; the default); ``"run"``, each run's own frame, as odometry that
#: restarts with every run writes it (REP-105's ``odom`` of separate launches): two runs'
#: positions and headings are then not comparable.
POSE_FRAMES = ("world", "run")


def check_pose_frame(value: str, where: str) -> str:
    """``value`` if it is one of :data:`POSE_FRAMES`; else a one-line error naming ``where``.

    Raises
    ------
    LogFormatError
        ``value`` is not a known pose frame.
    """
    if value not in POSE_FRAMES:
        raise LogFormatError(
            f"{where}: pose_frame {value!r} is not one of {', '.join(POSE_FRAMES)}"
        )
    return value


def check_power_sampling(value: str, where: str) -> str:
    """``value`` if it is one of :data:`POWER_SAMPLINGS`; else a one-line error naming ``where``.

    Raises
    ------
    LogFormatError
        ``value`` is not a known way of taking the power.
    """
    if value not in POWER_SAMPLINGS:
        raise LogFormatError(
            f"{where}: power_sampling {value!r} is not one of {', '.join(POWER_SAMPLINGS)}"
        )
    return value


_NAMES = frozenset(c.name for c in COLUMNS)


@dataclass(frozen=True, slots=True, eq=False)
class Log:
    """One run of a skid-steer robot: time series in SI units, REP-103 frames.

    Arrays are 1-D float64 of equal length ``n >= 2``; optional columns are ``None``
    when absent.  The constructor validates everything the CSV reader does (without
    line numbers: it names the sample index instead), so a :class:`Log` built in code
    is as trustworthy as one read from a file.

    Attributes
    ----------
    t : ndarray
        Time [s], strictly increasing.
    v_left, v_right : ndarray
        Measured side speeds [m/s].
    p_total : ndarray
        Electrical power of locomotion [W].
    v_left_cmd, v_right_cmd : ndarray or None
        Commanded side speeds [m/s].
    x, y : ndarray or None
        Position in the world frame [m].
    yaw : ndarray or None
        Heading [rad], counter-clockwise.
    wz : ndarray or None
        Measured yaw rate [rad/s].
    p_left, p_right : ndarray or None
        Mechanical power of each side's motor [W].
    current_left, current_right : ndarray or None
        Motor current of each side [A], magnitudes (``ecoplan identify`` fits them per side
        when the base vehicle's logs are motor currents).
    terrain : ndarray of str or None
        Terrain label of every sample.
    source : str
        File path or name the log came from.
    run_id : str
        Identifier of the run (file stem by default).
    dropped_rows : int
        Rows dropped by the reader: a missing value in an optional column, or an exact repeat
        of an earlier row.
    notes : tuple of str
        Assumptions and remarks (bus voltage, ignored columns, dropped rows, ...).
    power_sampling : str
        How ``p_total`` was taken (:data:`POWER_SAMPLINGS`): at the row's time (``"row"``,
        default) or as the mean over the sample interval before the row (``"interval_mean"``;
        the diagnosis then reads the speeds at the interval's middle).
    pose_frame : str
        Where the pose is expressed (:data:`POSE_FRAMES`): one ``"world"`` frame for all runs
        (default), or each ``"run"``'s own (odometry restarted with every run).
    extra : mapping of str to ndarray
        Further numeric columns outside the format (the simulator's motion ``case`` and
        power breakdown ``p_friction``, ...), one value per sample, written after the
        format's columns; the diagnosis ignores them.
    """

    t: FloatArray
    v_left: FloatArray
    v_right: FloatArray
    p_total: FloatArray
    v_left_cmd: FloatArray | None = None
    v_right_cmd: FloatArray | None = None
    x: FloatArray | None = None
    y: FloatArray | None = None
    yaw: FloatArray | None = None
    wz: FloatArray | None = None
    p_left: FloatArray | None = None
    p_right: FloatArray | None = None
    current_left: FloatArray | None = None
    current_right: FloatArray | None = None
    terrain: StrArray | None = None
    source: str = "<memory>"
    run_id: str = ""
    dropped_rows: int = 0
    notes: tuple[str, ...] = ()
    power_sampling: str = "row"
    pose_frame: str = "world"
    extra: Mapping[str, npt.NDArray[Any]] = field(default_factory=dict)

    def __post_init__(self) -> None:
        n = self._set_float_columns()
        if self.terrain is not None:
            lab = np.array(self.terrain, dtype=np.str_)
            if lab.shape != (n,):
                raise LogFormatError(
                    f"{self.source}: column 'terrain' has shape {lab.shape}, expected ({n},)"
                )
            lab.flags.writeable = False
            object.__setattr__(self, "terrain", lab)
        if n < 2:
            raise LogFormatError(f"{self.source}: a log needs at least 2 samples, got {n}")
        if self.dropped_rows < 0:
            raise LogFormatError(f"{self.source}: dropped_rows must be >= 0")
        check_power_sampling(self.power_sampling, self.source)
        check_pose_frame(self.pose_frame, self.source)
        object.__setattr__(self, "notes", tuple(self.notes))
        object.__setattr__(self, "extra", self._checked_extra(n))
        cols = {c: getattr(self, c) for c in FLOAT_COLUMNS}
        check_values(cols, self.source, np.arange(n), line_label="sample")

    def _set_float_columns(self) -> int:
        """Store every numeric column as a read-only 1-D float64 array; their length."""
        n: int | None = None
        for name in FLOAT_COLUMNS:
            val = getattr(self, name)
            if val is None:
                if name in REQUIRED_COLUMNS:
                    raise LogFormatError(f"{self.source}: required column {name!r} is missing")
                continue
            arr = np.array(val, dtype=np.float64)
            if arr.ndim != 1:
                raise LogFormatError(
                    f"{self.source}: column {name!r} must be 1-D, got shape {arr.shape}"
                )
            if n is not None and arr.size != n:
                raise LogFormatError(
                    f"{self.source}: column {name!r} has {arr.size} samples, 't' has {n}"
                )
            n = arr.size
            arr.flags.writeable = False
            object.__setattr__(self, name, arr)
        assert n is not None  # 't' is required
        return n

    def _checked_extra(self, n: int) -> dict[str, npt.NDArray[Any]]:
        out: dict[str, npt.NDArray[Any]] = {}
        for name, val in self.extra.items():
            if name in _NAMES or name in ALIASES:
                raise LogFormatError(
                    f"{self.source}: extra column {name!r} is a column of the log format"
                )
            if not name or name != name.strip() or any(ch in name for ch in ',"#\r\n'):
                raise LogFormatError(
                    f"{self.source}: extra column name {name!r} is not a plain CSV header"
                )
            arr = np.array(val)
            if arr.shape != (n,) or arr.dtype.kind not in "iuf":
                raise LogFormatError(
                    f"{self.source}: extra column {name!r} must be numeric with shape ({n},), "
                    f"got {arr.dtype} {arr.shape}"
                )
            arr.flags.writeable = False
            out[name] = arr
        return out

    def __len__(self) -> int:
        return int(self.t.size)

    @property
    def duration_s(self) -> float:
        """Time from the first to the last sample [s]."""
        return float(self.t[-1] - self.t[0])

    @property
    def has_commands(self) -> bool:
        """True when both commanded side speeds are logged."""
        return self.v_left_cmd is not None and self.v_right_cmd is not None

    @property
    def has_pose(self) -> bool:
        """True when ``x``, ``y`` and ``yaw`` are logged."""
        return self.x is not None and self.y is not None and self.yaw is not None

    def columns(self) -> tuple[str, ...]:
        """Names of the columns present, in file order."""
        return tuple(c.name for c in COLUMNS if getattr(self, c.name) is not None)

    def column(self, name: str) -> FloatArray:
        """A numeric column by name; :class:`LogFormatError` when it is absent or unknown."""
        if name not in FLOAT_COLUMNS:
            raise LogFormatError(
                f"unknown log column {name!r}; accepted: {', '.join(FLOAT_COLUMNS)}"
            )
        val = getattr(self, name)
        if val is None:
            raise LogFormatError(f"{self.source}: column {name!r} is not in this log")
        return val  # type: ignore[no-any-return]

    def slice(
        self,
        mask: npt.ArrayLike | None = None,
        *,
        start_s: float | None = None,
        stop_s: float | None = None,
    ) -> Log:
        """A sub-log: samples selected by a boolean mask and/or ``start_s <= t < stop_s``.

        Parameters
        ----------
        mask : array_like of bool, optional
            One flag per sample.
        start_s, stop_s : float, optional
            Time window [s] (absolute times of ``t``).

        Returns
        -------
        Log
            The selected samples (same source, run id, notes and dropped-row count).

        Raises
        ------
        LogFormatError
            The mask has the wrong shape, or fewer than 2 samples are selected.
        """
        keep: BoolArray = np.ones(len(self), dtype=np.bool_)
        if mask is not None:
            m = np.asarray(mask)
            if m.dtype != np.bool_ or m.shape != keep.shape:
                raise LogFormatError(
                    f"slice mask must be a boolean array of shape {keep.shape}, "
                    f"got {m.dtype} {m.shape}"
                )
            keep &= m
        if start_s is not None:
            keep &= self.t >= start_s
        if stop_s is not None:
            keep &= self.t < stop_s
        if int(keep.sum()) < 2:
            raise LogFormatError(
                f"{self.source}: slice keeps {int(keep.sum())} sample(s); a log needs at least 2"
            )
        changes: dict[str, Any] = {}
        for name in _NAMES:
            val = getattr(self, name)
            if val is not None:
                changes[name] = val[keep]
        changes["extra"] = {k: v[keep] for k, v in self.extra.items()}
        return dataclasses.replace(self, **changes)

    def with_notes(self, *notes: str) -> Log:
        """A copy with more notes appended."""
        return dataclasses.replace(self, notes=(*self.notes, *notes))


#: The measured streams a logger may repeat between readings, each read together:
#: ``p_total``, and the two side speeds (one encoder driver).
HELD_STREAMS: tuple[tuple[str, ...], ...] = (("p_total",), ("v_left", "v_right"))
#: The streams a logger may repeat between readings that :func:`fresh_readings` interpolates
#: in time instead (a pose fix at 1-5 Hz, a slower gyro): the position, the heading, the yaw
#: rate, each read together.
INTERPOLATED_STREAMS: tuple[tuple[str, ...], ...] = (("x", "y"), ("yaw",), ("wz",))
#: Share of a stream's inner runs of equal values that must be within one row (or 10 %) of
#: their median length for the stream to count as held: readings arrive at a steady rate.
HELD_REGULARITY = 0.8


def _arrivals(values: Sequence[FloatArray]) -> tuple[BoolArray, float]:
    """Rows where any of ``values`` changes (row 0 included), and the held run length (0: not held).

    Held: the median run of unchanged rows is at least 2 and at least
    :data:`HELD_REGULARITY` of the runs between the first and the last (which the log's ends
    cut) are within ``max(1, 0.1 median)`` rows of the median.  A speed plateau or a
    quantised meter repeats on runs of every length, or on few rows.
    """
    n = values[0].size
    fresh = np.ones(n, dtype=np.bool_)
    fresh[1:] = np.any([v[1:] != v[:-1] for v in values], axis=0)
    runs = np.diff(np.append(np.flatnonzero(fresh), n))
    inner = runs[1:-1]
    if inner.size == 0:
        return fresh, 0.0
    median = float(np.median(runs))
    steady = float(np.mean(np.abs(inner - median) <= max(1.0, 0.1 * median)))
    return fresh, (median if median >= 2.0 and steady >= HELD_REGULARITY else 0.0)


def _held_note(names: Sequence[str], log: Log, fresh: BoolArray, run: float, how: str) -> str:
    kept = int(fresh.sum())
    period = float(np.median(np.diff(log.t[fresh])))
    return (
        f"{' and '.join(names)} held: repeated on {len(log) - kept} of {len(log)} rows (a reading "
        f"every {run:g} rows, about {period:.3g} s); {how}"
    )


def _interpolate_held(log: Log) -> Log:
    """``log`` with each held stream of :data:`INTERPOLATED_STREAMS` interpolated in time.

    Between two rows where a reading arrives the stream moves linearly in time, as ROS ``tf``
    interpolates between stamped transforms; after the last reading it stays.  The heading is
    interpolated unwrapped and wrapped back to ``(-pi, pi]``.
    """
    changes: dict[str, Any] = {}
    notes: list[str] = []
    for names in INTERPOLATED_STREAMS:
        cols = [getattr(log, c) for c in names]
        if any(c is None for c in cols):
            continue
        values = [np.asarray(c, dtype=np.float64) for c in cols]
        fresh, run = _arrivals(values)
        if run <= 0.0 or int(fresh.sum()) < 2:
            continue
        for name, v in zip(names, values, strict=True):
            at = np.unwrap(v[fresh]) if name == "yaw" else v[fresh]
            out = np.interp(log.t, log.t[fresh], at)
            changes[name] = np.arctan2(np.sin(out), np.cos(out)) if name == "yaw" else out
        how = "interpolated in time between the rows where a reading arrives"
        notes.append(_held_note(names, log, fresh, run, how))
    if not changes:
        return log
    return dataclasses.replace(log, **changes).with_notes(*notes)


def fresh_readings(log: Log) -> Log:
    """``log`` with its held streams' readings taken where they arrive (``log`` if none is held).

    A logger that writes a row whenever any stream updates (a merged CSV, PlotJuggler's
    export) repeats a slower stream's last value until its next message: a power meter at
    5 Hz in a 20 Hz log shows each reading on four rows.  Read as fresh samples, the repeats
    lag the other columns by up to one reading interval, which a diagnosis takes for a
    ``sensor_delay`` (held power) or an ``actuator_lag`` (held speeds).  A stream is held when
    its readings repeat on runs of a steady length of at least 2 rows (:func:`_arrivals`).

    * The pose and the yaw rate (:data:`INTERPOLATED_STREAMS`): a held stream is interpolated
      in time between its readings, every row kept (a 1 Hz fix held over a second made the
      pose speed lag the side speeds and hid an ICR offset).
    * The power and the side speeds (:data:`HELD_STREAMS`): the log keeps the rows at which
      the slowest held stream's readings arrive; a faster held stream is then at most one of
      its own intervals old.  With ``power_sampling: interval_mean`` a kept reading stands
      for the interval since the one before (an energy counter read at its own rate), which
      is what the kept rows' time steps then say.

    Each change is said in a note.

    >>> import numpy as np
    >>> p = np.repeat([10.0, 12.0, 11.0, 15.0], 4)  # 4 rows per reading
    >>> log = Log(t=np.arange(16) * 0.05, v_left=np.ones(16), v_right=np.ones(16), p_total=p)
    >>> fresh = fresh_readings(log)
    >>> fresh.t.tolist(), fresh.p_total.tolist()
    ([0.0, 0.2, 0.4, 0.6000000000000001], [10.0, 12.0, 11.0, 15.0])
    """
    log = _interpolate_held(log)
    best: tuple[float, BoolArray, tuple[str, ...]] | None = None
    for names in HELD_STREAMS:
        fresh, run = _arrivals([np.asarray(getattr(log, c)) for c in names])
        if run > 0.0 and (best is None or run > best[0]):
            best = (run, fresh, names)
    if best is None or int(best[1].sum()) < 2:
        return log
    run, fresh, names = best
    how = f"only the {int(fresh.sum())} rows where a reading arrives are used"
    return log.slice(fresh).with_notes(_held_note(names, log, fresh, run, how))


def join_runs(
    logs: Sequence[Log],
    run_id: str,
    columns: Collection[str] | None = None,
    source: str | None = None,
) -> tuple[Log, list[float]]:
    """The runs as one log on one clock, and the times where the second and later runs start.

    Each run starts one sample period (the previous run's median) after the previous run's
    last sample, its own clock shifted, as a robot logging without a break would have
    written them.
    The required columns are joined, and the optional ones in ``columns`` (default: every
    optional column all runs have, but the pose :data:`POSE_COLUMNS`, which jumps between
    runs).  Dropped rows add up; notes are kept once each, in order; ``extra`` is left out.

    Parameters
    ----------
    logs : sequence of Log
        The runs, in the order they are joined.
    run_id : str
        Run id of the joined log.
    columns : collection of str, optional
        Optional columns to keep (:data:`OPTIONAL_COLUMNS`); every run must have them.
    source : str, optional
        Source of the joined log (default ``"<joined run_id>"``).

    Returns
    -------
    (Log, list of float)
        The joined log and the start time of every run after the first [s].

    Raises
    ------
    LogFormatError
        No run; a column that is not optional or that a run lacks; runs whose power was
        taken differently (``power_sampling``).

    Examples
    --------
    >>> a = Log(t=np.array([5.0, 5.1]), v_left=np.zeros(2), v_right=np.zeros(2),
    ...         p_total=np.ones(2))
    >>> joined, starts = join_runs([a, a], "both")
    >>> joined.t.round(2).tolist(), [round(s, 2) for s in starts]
    ([0.0, 0.1, 0.2, 0.3], [0.2])
    """
    if not logs:
        raise LogFormatError("join_runs: no run to join")
    keep = (
        [c for c in OPTIONAL_COLUMNS if c not in POSE_COLUMNS and _all_have(logs, c)]
        if columns is None
        else list(columns)
    )
    for c in keep:
        if c not in OPTIONAL_COLUMNS:
            accepted = ", ".join(OPTIONAL_COLUMNS)
            raise LogFormatError(
                f"join_runs: {c!r} is not an optional column; accepted: {accepted}"
            )
        lacking = [lg.run_id or lg.source for lg in logs if getattr(lg, c) is None]
        if lacking:
            raise LogFormatError(f"join_runs: run {lacking[0]!r} has no column {c!r}")
    samplings = sorted({lg.power_sampling for lg in logs})
    if len(samplings) > 1:
        raise LogFormatError(
            f"join_runs: the runs' power was taken differently (power_sampling {samplings})"
        )
    clocks, starts, t_next = [], [], 0.0
    for i, lg in enumerate(logs):
        t = lg.t - lg.t[0] + t_next
        if i:
            starts.append(float(t[0]))
        clocks.append(t)
        t_next = float(t[-1]) + float(np.median(np.diff(lg.t)))
    joined: dict[str, Any] = {"t": np.concatenate(clocks)}
    for c in (*REQUIRED_COLUMNS, *keep):
        if c != "t":
            joined[c] = np.concatenate([getattr(lg, c) for lg in logs])
    notes = tuple(dict.fromkeys(n for lg in logs for n in lg.notes))
    log = Log(
        **joined,
        source=source if source is not None else f"<joined {run_id}>",
        run_id=run_id,
        dropped_rows=sum(lg.dropped_rows for lg in logs),
        notes=notes,
        power_sampling=samplings[0],
    )
    return log, starts


def _all_have(logs: Sequence[Log], column: str) -> bool:
    return all(getattr(lg, column) is not None for lg in logs)


def _tie_hint(cols: Mapping[str, Any], ties: int, i: int) -> str:
    """Why row ``i`` may share the time of row ``i - 1`` (``ties`` rows do so in all)."""
    n = np.size(cols["t"])
    if ties > 1:
        return (
            f" ({ties} of {n} rows share the time of the row before: a clock coarser than the "
            "logging rate? stamp each row when it is sampled)"
        )
    rows = [np.asarray(v) for v in cols.values() if v is not None and np.size(v) == n]
    if any(v.ndim == 1 and v[i] != v[i - 1] for v in rows):
        return " (one row at the time of the row before, with other readings)"
    return " (the row before, logged twice)"


def check_values(
    cols: Mapping[str, Any],
    source: str,
    lines: npt.NDArray[Any],
    line_label: str,
    *,
    required_only: bool = False,
) -> None:
    """Check finiteness, time order and plausible speeds, naming the column and line.

    Parameters
    ----------
    cols : mapping of str to ndarray
        Numeric columns by name; absent optional ones may be missing or None.
    source : str
        File or name the values came from.
    lines : ndarray of int
        Line (or sample) number of each value, for the message.
    line_label : str
        ``"line"`` or ``"sample"``.
    required_only : bool
        Only check that the required columns are finite (the CSV reader does this
        before it drops rows with a missing optional value).

    Raises
    ------
    LogFormatError
        A non-finite value, time not strictly increasing, or a speed above
        :data:`MAX_PLAUSIBLE_SPEED_MPS`.
    """
    for name in REQUIRED_COLUMNS:
        arr = cols[name]
        bad = np.flatnonzero(~np.isfinite(arr))
        if bad.size:
            i = int(bad[0])
            raise LogFormatError(
                f"{source}, {line_label} {int(lines[i])}: required column {name!r} is "
                f"{float(arr[i])!r}; required columns must be finite"
            )
    if required_only:
        return
    for name in OPTIONAL_FLOAT_COLUMNS:
        arr = cols.get(name)
        if arr is None:
            continue
        bad = np.flatnonzero(~np.isfinite(arr))
        if bad.size:
            i = int(bad[0])
            raise LogFormatError(
                f"{source}, {line_label} {int(lines[i])}: column {name!r} is {float(arr[i])!r}; "
                "values must be finite"
            )
    t = cols["t"]
    dt = np.diff(t)
    bad = np.flatnonzero(dt <= 0.0)
    if bad.size:
        i = int(bad[0]) + 1
        back = float(t[i - 1] - t[i])
        if back == 0.0:
            what, hint = "duplicated", _tie_hint(cols, int(np.sum(dt == 0.0)), i)
        elif back > RESTART_S:
            what = f"jumps back {back:.6g} s"
            hint = (
                " (runs joined in one file? write each run to its own file and pass them "
                "all: ecoplan diagnose run1.csv run2.csv ...)"
            )
        else:
            what, hint = "goes backwards", " (rows out of order? sort them by time)"
        raise LogFormatError(
            f"{source}, {line_label} {int(lines[i])}: time {what} in column 't' "
            f"({float(t[i - 1])!r} then {float(t[i])!r}); 't' must be strictly increasing{hint}"
        )
    for name in SPEED_COLUMNS:
        arr = cols.get(name)
        if arr is None:
            continue
        bad = np.flatnonzero(np.abs(arr) > MAX_PLAUSIBLE_SPEED_MPS)
        if bad.size:
            i = int(bad[0])
            raise LogFormatError(
                f"{source}, {line_label} {int(lines[i])}: column {name!r} = {float(arr[i])!r} m/s "
                f"exceeds {MAX_PLAUSIBLE_SPEED_MPS:g} m/s; speeds must be in m/s "
                "(this looks like mm/s)"
            )
