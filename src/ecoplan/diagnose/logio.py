"""The ecoplan log format: a validated :class:`Log` and its CSV reader and writer.

Log format (a contract shared by the simulator, the diagnosis and the loaders)
-----------------------------------------------------------------------------
A CSV file with one header row, SI units and REP-103 frames (x forward, y left, yaw
counter-clockwise).  Lines starting with ``#`` *before* the header are metadata
(``# run_id: ...``, ``# note: ...``); blank lines are skipped.

==============  =========  ==========================================================
column          unit       meaning
==============  =========  ==========================================================
``t``           s          time, strictly increasing (required)
``v_left``      m/s        measured left side (track/wheel) speed (required)
``v_right``     m/s        measured right side speed (required)
``p_total``     W          electrical power of locomotion (required)
``v_left_cmd``  m/s        commanded left side speed (optional)
``v_right_cmd`` m/s        commanded right side speed (optional)
``x``, ``y``    m          position in the world frame (optional)
``yaw``         rad        heading, counter-clockwise from world x (optional)
``wz``          rad/s      measured yaw rate (optional)
``p_left``      W          mechanical power of the left motor (optional)
``p_right``     W          mechanical power of the right motor (optional)
``terrain``     label      terrain name under the robot (optional, text)
==============  =========  ==========================================================

Any other column (e.g. the simulator's ``case`` or ``friction_w``) is ignored and named
in :attr:`Log.notes`.

Validation (every failure is a :class:`~ecoplan.errors.LogFormatError` whose one-line
message names the file, the column and/or the 1-based line number of the file):

* empty file, no header, no data rows or a single data row;
* a required column missing, a duplicated column name;
* a non-numeric cell (an empty cell counts as missing);
* NaN or inf in a required column;
* time not strictly increasing (duplicated or going backwards);
* a speed above :data:`MAX_PLAUSIBLE_SPEED_MPS` in magnitude (it looks like mm/s).

Rows whose only defect is a missing/NaN value in an *optional* column are dropped and
counted in :attr:`Log.dropped_rows` (never silently); an optional column that is empty
on every row is treated as absent.  Infinite values in optional columns are errors.

Loaders
-------
* :func:`read_log_csv` / :func:`write_log_csv` -- the format above (clean files are read
  by ``numpy.loadtxt``: one hour at 100 Hz with 12 columns in about 1.4 s);
* :func:`load_borealtc` -- BorealTC hard-ground runs (Husky A200) through
  :mod:`ecoplan.datasets.borealtc`, the bus voltage an explicit assumption in the notes;
* :func:`read_rosbag` -- ROS 2 bags (``rosbags``) with a :class:`TopicMap` (wheel joint
  states, battery state or a power topic, odometry, IMU), resampled on a common time base;
* :func:`read_logs` -- any mix of the three: CSV paths, ``borealtc:TERRAIN[/RUN]`` and
  bags (topic map given, or ``<bag>.topics.yaml`` beside the bag, :func:`load_topic_map`).
"""

from __future__ import annotations

import csv
import dataclasses
import math
import os
from collections.abc import Iterable, Mapping, Sequence
from dataclasses import dataclass
from pathlib import Path
from typing import Any

import numpy as np
import numpy.typing as npt

from ecoplan._typing import BoolArray, FloatArray
from ecoplan.errors import LogFormatError

__all__ = [
    "FLOAT_COLUMNS",
    "MAX_PLAUSIBLE_SPEED_MPS",
    "OPTIONAL_COLUMNS",
    "REQUIRED_COLUMNS",
    "SPEED_COLUMNS",
    "FieldRef",
    "Log",
    "TopicMap",
    "load_borealtc",
    "load_borealtc_runs",
    "load_topic_map",
    "read_log_csv",
    "read_logs",
    "read_rosbag",
    "write_log_csv",
]

#: Columns every log must have, in file order.
REQUIRED_COLUMNS: tuple[str, ...] = ("t", "v_left", "v_right", "p_total")
#: Optional numeric columns, in file order.
OPTIONAL_FLOAT_COLUMNS: tuple[str, ...] = (
    "v_left_cmd",
    "v_right_cmd",
    "x",
    "y",
    "yaw",
    "wz",
    "p_left",
    "p_right",
)
#: Every optional column, numeric and text.
OPTIONAL_COLUMNS: tuple[str, ...] = (*OPTIONAL_FLOAT_COLUMNS, "terrain")
#: Every numeric column, in file order.
FLOAT_COLUMNS: tuple[str, ...] = (*REQUIRED_COLUMNS, *OPTIONAL_FLOAT_COLUMNS)
#: Columns holding side speeds, checked for plausible magnitude.
SPEED_COLUMNS: tuple[str, ...] = ("v_left", "v_right", "v_left_cmd", "v_right_cmd")
#: Side speeds above this magnitude [m/s] are taken for a unit error (mm/s, rpm, ...).
MAX_PLAUSIBLE_SPEED_MPS = 20.0

StrArray = npt.NDArray[np.str_]


def _where(source: str, line: int | None = None) -> str:
    return f"{source}, line {line}" if line is not None else source


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
    terrain : ndarray of str or None
        Terrain label of every sample.
    source : str
        File path or name the log came from.
    run_id : str
        Identifier of the run (file stem by default).
    dropped_rows : int
        Rows dropped by the reader for a missing value in an optional column.
    notes : tuple of str
        Assumptions and remarks (bus voltage, ignored columns, dropped rows, ...).
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
    terrain: StrArray | None = None
    source: str = "<memory>"
    run_id: str = ""
    dropped_rows: int = 0
    notes: tuple[str, ...] = ()

    def __post_init__(self) -> None:
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
            if n is None:
                n = arr.size
            elif arr.size != n:
                raise LogFormatError(
                    f"{self.source}: column {name!r} has {arr.size} samples, 't' has {n}"
                )
            arr.flags.writeable = False
            object.__setattr__(self, name, arr)
        assert n is not None
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
        object.__setattr__(self, "notes", tuple(self.notes))
        cols = {c: getattr(self, c) for c in FLOAT_COLUMNS}
        _check_values(cols, self.source, np.arange(n), line_label="sample")

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
        return tuple(c for c in (*FLOAT_COLUMNS, "terrain") if getattr(self, c) is not None)

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
        for name in (*FLOAT_COLUMNS, "terrain"):
            val = getattr(self, name)
            if val is not None:
                changes[name] = val[keep]
        return dataclasses.replace(self, **changes)

    def with_notes(self, *notes: str) -> Log:
        """A copy with more notes appended."""
        return dataclasses.replace(self, notes=(*self.notes, *notes))

    def to_csv(self, path: str | os.PathLike[str], *, overwrite: bool = False) -> Path:
        """Write this log as CSV; see :func:`write_log_csv`."""
        return write_log_csv(self, path, overwrite=overwrite)


def _check_required_finite(
    cols: Mapping[str, Any], source: str, lines: npt.NDArray[Any], line_label: str
) -> None:
    """Every required column finite; else name the column and the first bad line/sample."""
    for name in REQUIRED_COLUMNS:
        arr = cols[name]
        bad = np.flatnonzero(~np.isfinite(arr))
        if bad.size:
            i = int(bad[0])
            raise LogFormatError(
                f"{source}, {line_label} {int(lines[i])}: required column {name!r} is "
                f"{float(arr[i])!r}; required columns must be finite"
            )


def _check_values(
    cols: Mapping[str, Any], source: str, lines: npt.NDArray[Any], line_label: str
) -> None:
    """Finiteness, time order and plausible speeds; names the column and line/sample."""
    _check_required_finite(cols, source, lines, line_label)
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
        what = "duplicated" if dt[i - 1] == 0.0 else "goes backwards"
        raise LogFormatError(
            f"{source}, {line_label} {int(lines[i])}: time {what} in column 't' "
            f"({float(t[i - 1])!r} then {float(t[i])!r}); 't' must be strictly increasing"
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


def _parse_floats(name: str, cells: list[str], lines: list[int], source: str) -> FloatArray:
    """Convert a column of CSV cells to float64; empty cells become NaN."""
    try:
        return np.array(cells, dtype=np.float64)
    except ValueError:
        pass
    out = np.empty(len(cells), dtype=np.float64)
    for i, cell in enumerate(cells):
        s = cell.strip()
        if not s:
            out[i] = math.nan
            continue
        try:
            out[i] = float(s)
        except ValueError:
            raise LogFormatError(
                f"{_where(source, lines[i])}: column {name!r} has non-numeric value {cell!r}"
            ) from None
    return out


_Parsed = tuple[dict[str, Any], "StrArray | None", npt.NDArray[np.int64]]


def _parse_fast(body: list[str], header: list[str], header_line: int) -> _Parsed | None:
    """Vectorised parse (``numpy.loadtxt``) of a clean body; None when anything is unusual.

    Unusual -- quotes, blank lines, ragged rows, empty or non-numeric cells -- goes to
    :func:`_parse_slow`, which finds and names the offending line.
    """
    width = len(header)
    if not body or any(('"' in ln) or ln.count(",") != width - 1 for ln in body):
        return None
    index = {c: i for i, c in enumerate(header)}
    names = [c for c in FLOAT_COLUMNS if c in index]
    try:
        arr = np.loadtxt(
            body,
            delimiter=",",
            usecols=[index[c] for c in names],
            comments=None,
            ndmin=2,
            dtype=np.float64,
        )
    except ValueError:
        return None
    cols = {c: np.ascontiguousarray(arr[:, k]) for k, c in enumerate(names)}
    labels = None
    if "terrain" in index:
        j = index["terrain"]
        labels = np.array([ln.split(",")[j].strip() for ln in body], dtype=np.str_)
    lines = header_line + 1 + np.arange(len(body), dtype=np.int64)
    return cols, labels, lines


def _parse_slow(body: list[str], header: list[str], header_line: int, source: str) -> _Parsed:
    """Cell-by-cell parse that names the first bad line, column and cell."""
    rows: list[list[str]] = []
    lines: list[int] = []
    reader = csv.reader(body)
    try:
        for row in reader:
            if not row or all(not c.strip() for c in row):
                continue
            rows.append(row)
            lines.append(header_line + reader.line_num)
    except csv.Error as exc:
        where = _where(source, header_line + reader.line_num)
        raise LogFormatError(f"{where}: unreadable CSV: {exc}") from None
    width = len(header)
    for row, line in zip(rows, lines, strict=True):
        if len(row) != width:
            raise LogFormatError(
                f"{_where(source, line)}: {len(row)} cells, the header has {width}"
            )
    index = {c: i for i, c in enumerate(header)}
    cols: dict[str, Any] = {}
    for name in FLOAT_COLUMNS:
        if name in index:
            j = index[name]
            cells = [r[j] for r in rows]
            if name in REQUIRED_COLUMNS:
                for cell, line in zip(cells, lines, strict=True):
                    if not cell.strip():
                        raise LogFormatError(
                            f"{_where(source, line)}: required column {name!r} is empty; "
                            "required columns must be finite"
                        )
            cols[name] = _parse_floats(name, cells, lines, source)
    labels = None
    if "terrain" in index:
        j = index["terrain"]
        labels = np.array([r[j].strip() for r in rows], dtype=np.str_)
    return cols, labels, np.asarray(lines, dtype=np.int64)


def read_log_csv(path: str | os.PathLike[str], *, run_id: str | None = None) -> Log:
    """Read and validate a log CSV (format in the module docstring).

    Parameters
    ----------
    path : path-like
        CSV file.
    run_id : str, optional
        Run identifier; default the ``# run_id:`` metadata line, else the file stem.

    Returns
    -------
    Log
        The validated log; rows with a missing optional value are dropped and counted.

    Raises
    ------
    LogFormatError
        Any violation of the format, naming the file, column and line.
    """
    p = Path(path)
    source = str(p)
    try:
        fh = p.open(newline="", encoding="utf-8-sig")
    except OSError as exc:
        raise LogFormatError(f"{source}: cannot open log: {exc.strerror}") from None
    try:
        with fh:
            text = fh.read()
    except UnicodeDecodeError as exc:
        raise LogFormatError(f"{source}: not UTF-8 text: {exc.reason}") from None
    meta_run: str | None = None
    notes: list[str] = []
    all_lines = [ln[:-1] if ln.endswith("\r") else ln for ln in text.split("\n")]
    if all_lines and not all_lines[-1]:
        all_lines.pop()  # the final newline
    header: list[str] | None = None
    header_line = 0
    for k, raw in enumerate(all_lines):
        if not raw.strip() or not raw.replace(",", "").strip():
            continue
        if raw.lstrip().startswith("#"):
            key, _, value = raw.lstrip("# ").partition(":")
            if key.strip() == "run_id":
                meta_run = value.strip()
            elif key.strip() == "note":
                notes.append(value.strip())
            continue
        header = [c.strip() for c in next(csv.reader([raw]))]
        header_line = k + 1
        break
    if header is None:
        raise LogFormatError(f"{source}: empty file (no header row)")
    seen: set[str] = set()
    for col in header:
        if col in seen:
            raise LogFormatError(f"{_where(source, header_line)}: duplicated column {col!r}")
        seen.add(col)
    missing = [c for c in REQUIRED_COLUMNS if c not in seen]
    if missing:
        raise LogFormatError(
            f"{_where(source, header_line)}: missing required column(s) "
            f"{', '.join(repr(c) for c in missing)}; header is {', '.join(header)}"
        )
    body = all_lines[header_line:]
    parsed = _parse_fast(body, header, header_line)
    if parsed is None:
        parsed = _parse_slow(body, header, header_line, source)
    cols, labels, line_arr = parsed
    n_rows = line_arr.size
    if n_rows == 0:
        raise LogFormatError(f"{source}: no data rows after the header (line {header_line})")
    if n_rows < 2:
        raise LogFormatError(
            f"{_where(source, int(line_arr[0]))}: a single data row; a log needs at least 2"
        )
    ignored = [c for c in header if c not in REQUIRED_COLUMNS and c not in OPTIONAL_COLUMNS]
    _check_required_finite(cols, source, line_arr, "line")  # before rows are dropped
    drop = np.zeros(n_rows, dtype=np.bool_)
    for name in OPTIONAL_FLOAT_COLUMNS:
        if name not in cols:
            continue
        arr = cols[name]
        if np.all(np.isnan(arr)):
            del cols[name]
            notes.append(f"column {name!r} is empty on every row; treated as absent")
            continue
        inf = np.flatnonzero(np.isinf(arr))
        if inf.size:
            i = int(inf[0])
            raise LogFormatError(
                f"{_where(source, int(line_arr[i]))}: column {name!r} is {float(arr[i])!r}; "
                "values must be finite"
            )
        drop |= np.isnan(arr)
    if labels is not None:
        empty = labels == ""
        if np.all(empty):
            notes.append("column 'terrain' is empty on every row; treated as absent")
        else:
            cols["terrain"] = labels
            drop |= empty
    n_drop = int(drop.sum())
    if n_drop:
        keep = ~drop
        first_line = int(line_arr[int(np.flatnonzero(drop)[0])])
        notes.append(
            f"dropped {n_drop} of {n_rows} rows with a missing optional value "
            f"(first at line {first_line})"
        )
        if int(keep.sum()) < 2:
            raise LogFormatError(
                f"{source}: only {int(keep.sum())} row(s) left after dropping {n_drop} rows "
                "with missing optional values; a log needs at least 2"
            )
        cols = {k: v[keep] for k, v in cols.items()}
        line_arr = line_arr[keep]
    if ignored:
        notes.append(f"ignored columns: {', '.join(ignored)}")
    # check with the file's line numbers first; the constructor re-validates by sample
    _check_values(cols, source, line_arr, line_label="line")
    return Log(
        **cols,
        source=source,
        run_id=run_id if run_id is not None else (meta_run or p.stem),
        dropped_rows=n_drop,
        notes=tuple(notes),
    )


def _csv_cell(text: str) -> str:
    if any(ch in text for ch in ',"\r\n') or text != text.strip():
        return '"' + text.replace('"', '""') + '"'
    return text


def write_log_csv(log: Log, path: str | os.PathLike[str], *, overwrite: bool = False) -> Path:
    """Write a log as CSV in the ecoplan format (shortest round-trip float text).

    ``run_id`` and ``notes`` are written as ``#`` metadata lines before the header, so
    :func:`read_log_csv` gives back an equal log.

    Parameters
    ----------
    log : Log
        The log.
    path : path-like
        Destination file.
    overwrite : bool
        Replace an existing file; by default an existing file is an error.

    Returns
    -------
    Path
        The written file.

    Raises
    ------
    LogFormatError
        The file exists and ``overwrite`` is False, or it cannot be written.
    """
    p = Path(path)
    if p.exists() and not overwrite:
        raise LogFormatError(f"{p}: file exists; pass overwrite=True to replace it")
    names = log.columns()
    cells: list[list[str]] = []
    for c in names:
        val = getattr(log, c)
        if c == "terrain":
            quoted = {lab: _csv_cell(str(lab)) for lab in set(val.tolist())}
            cells.append([quoted[lab] for lab in val.tolist()])
        else:
            cells.append(list(map(repr, val.tolist())))  # shortest round-trip text
    try:
        with p.open("w", newline="", encoding="utf-8") as fh:
            if log.run_id:
                fh.write(f"# run_id: {log.run_id}\n")
            for note in log.notes:
                fh.write("# note: " + note.replace("\n", " ") + "\n")
            fh.write(",".join(names) + "\n")
            fh.write("\n".join(map(",".join, zip(*cells, strict=True))))
            fh.write("\n")
    except OSError as exc:
        raise LogFormatError(f"{p}: cannot write log: {exc.strerror}") from None
    return p


def read_logs(
    paths: Iterable[str | os.PathLike[str]],
    *,
    topic_map: TopicMap | None = None,
    bus_voltage_v: float = 24.0,
) -> list[Log]:
    """Read several logs (one run each) of any supported source; errors name the source.

    Each entry is one of:

    * a CSV file in the ecoplan format (:func:`read_log_csv`);
    * ``borealtc:TERRAIN`` (every run) or ``borealtc:TERRAIN/RUN`` -- BorealTC runs
      (:func:`load_borealtc`, with ``bus_voltage_v``);
    * a ROS 2 bag (a directory holding ``metadata.yaml``, or an ``.mcap``/``.db3`` file),
      read with ``topic_map`` or, when it is None, with the topic map in the file
      ``<bag>.topics.yaml`` beside the bag (:func:`load_topic_map`).

    Raises
    ------
    LogFormatError
        No entries, a malformed source, or a bag without a topic map.
    """
    seq: Sequence[str | os.PathLike[str]] = list(paths)
    if not seq:
        raise LogFormatError("no log files given")
    out: list[Log] = []
    for entry in seq:
        text = os.fspath(entry)
        if text.lower().startswith("borealtc:"):
            terrain, _, run = text.split(":", 1)[1].partition("/")
            if run:
                out.append(load_borealtc(terrain, run, bus_voltage_v))
            else:
                out.extend(load_borealtc_runs(terrain, bus_voltage_v))
            continue
        path = Path(text)
        is_bag = (path.is_dir() and (path / "metadata.yaml").is_file()) or path.suffix in (
            ".mcap",
            ".db3",
        )
        if is_bag:
            tmap = topic_map
            if tmap is None:
                side = path.with_name(path.name + ".topics.yaml")
                if not side.is_file():
                    raise LogFormatError(
                        f"{path}: a ROS 2 bag needs a topic map; none given and no {side.name} "
                        "beside the bag"
                    )
                tmap = load_topic_map(side)
            out.append(read_rosbag(path, tmap))
            continue
        out.append(read_log_csv(path))
    return out


def load_borealtc(
    terrain: str,
    run_id: str | int,
    bus_voltage_v: float = 24.0,
    root: str | os.PathLike[str] | None = None,
) -> Log:
    """One BorealTC hard-ground run (Husky A200) as a :class:`Log`.

    Built on :func:`ecoplan.datasets.borealtc.load_run`: side speeds from wheel
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
        Data root (default: see :func:`ecoplan.datasets.borealtc.data_root`).

    Returns
    -------
    Log
        Columns ``t, v_left, v_right, p_total`` (+ ``wz`` when the IMU file exists) and a
        ``terrain`` label (lower case); ``run_id`` like ``"FLOORING_03"``.
    """
    from ecoplan.datasets.borealtc import data_root, load_run

    run = load_run(terrain, run_id, root, bus_voltage_v)
    source = str(data_root(root) / run.terrain / f"pro_{run.run_id}.csv")
    notes = [
        f"p_total = {run.bus_voltage_v:g} V x (curL + curR): the bus voltage is an "
        "assumption (BorealTC has no voltage column; the battery sags under load)",
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
    """Every run of a BorealTC terrain as logs, in run order (see :func:`load_borealtc`)."""
    from ecoplan.datasets.borealtc import list_runs

    return [load_borealtc(terrain, rid, bus_voltage_v, root) for rid in list_runs(terrain, root)]


# --------------------------------------------------------------------------- ROS 2 bags


@dataclass(frozen=True, slots=True)
class FieldRef:
    """A numeric field of the messages of one topic.

    Attributes
    ----------
    topic : str
        Topic name (``/joint_states``).
    field : str
        Dotted path into the message; an index may be a number or, for messages with a
        ``name`` list such as ``sensor_msgs/JointState``, a name looked up in it:
        ``data``, ``velocity[left_wheel_joint]``, ``data[1]``, ``twist.linear.x``.
    scale : float
        Factor applied to the value (e.g. the wheel radius to turn rad/s into m/s).
    """

    topic: str
    field: str = "data"
    scale: float = 1.0


@dataclass(frozen=True, slots=True)
class TopicMap:
    """Which topics and fields of a ROS 2 bag make the log columns.

    Attributes
    ----------
    v_left, v_right : FieldRef
        Measured side speeds (after ``scale``: m/s).
    power : FieldRef, optional
        Electrical locomotion power [W] published directly.
    battery_topic : str, optional
        A ``sensor_msgs/BatteryState`` topic: ``p = sign * voltage * current - offset``.
        Exactly one of ``power`` and ``battery_topic`` must be given.
    battery_current_sign : float
        ``-1`` for the ROS convention (current negative when discharging), ``+1`` for
        drivers that publish the drawn current as positive.
    p_offset_w : float
        Power of non-locomotion loads subtracted from the battery power [W].
    v_left_cmd, v_right_cmd : FieldRef, optional
        Commanded side speeds (m/s after ``scale``).
    odom_topic : str, optional
        A ``nav_msgs/Odometry`` topic: ``x``, ``y``, ``yaw`` (from the quaternion) and
        ``wz`` (``twist.twist.angular.z``).
    wz : FieldRef, optional
        Yaw rate from another source (e.g. ``/imu/data`` ``angular_velocity.z``); takes
        precedence over the odometry's.
    rate_hz : float, optional
        Rate of the common time base; default the power stream's median rate.
    use_header_stamp : bool
        Time-stamp messages by ``header.stamp`` when they have one (else, and for
        messages without a header, by the bag's receive time).
    """

    v_left: FieldRef
    v_right: FieldRef
    power: FieldRef | None = None
    battery_topic: str | None = None
    battery_current_sign: float = -1.0
    p_offset_w: float = 0.0
    v_left_cmd: FieldRef | None = None
    v_right_cmd: FieldRef | None = None
    odom_topic: str | None = None
    wz: FieldRef | None = None
    rate_hz: float | None = None
    use_header_stamp: bool = True

    def __post_init__(self) -> None:
        if (self.power is None) == (self.battery_topic is None):
            raise LogFormatError("TopicMap needs exactly one of 'power' and 'battery_topic'")
        if (self.v_left_cmd is None) != (self.v_right_cmd is None):
            raise LogFormatError("TopicMap needs both 'v_left_cmd' and 'v_right_cmd' or neither")
        if self.battery_current_sign not in (-1.0, 1.0):
            raise LogFormatError(
                f"TopicMap.battery_current_sign = {self.battery_current_sign!r}; accepted: -1, 1"
            )
        if self.rate_hz is not None and not (0.0 < self.rate_hz <= 10000.0):
            raise LogFormatError(f"TopicMap.rate_hz = {self.rate_hz!r}; accepted: (0, 10000]")

    @classmethod
    def from_mapping(cls, data: Mapping[str, Any], source: str = "topic map") -> TopicMap:
        """Build from a mapping (a YAML/JSON document); unknown keys are rejected.

        Column keys (``v_left``, ``v_right``, ``power``, ``v_left_cmd``, ``v_right_cmd``,
        ``wz``) take either a topic name (field ``data``) or a mapping with ``topic`` and
        optional ``field`` and ``scale``; the other keys are the attributes' values.
        """
        if not isinstance(data, Mapping):
            raise LogFormatError(f"{source}: a topic map must be a mapping of keys to values")
        names = {f.name for f in dataclasses.fields(cls)}
        unknown = sorted(set(data) - names)
        if unknown:
            accepted = ", ".join(sorted(names))
            raise LogFormatError(
                f"{source}: unknown key(s) {', '.join(unknown)}; accepted: {accepted}"
            )
        kw: dict[str, Any] = {}
        for key, val in data.items():
            if key in _REF_KEYS and val is not None:
                kw[key] = _field_ref(val, f"{source}: {key}")
            else:
                kw[key] = val
        for key in ("v_left", "v_right"):
            if key not in kw:
                raise LogFormatError(f"{source}: missing required key {key!r}")
        try:
            return cls(**kw)
        except (TypeError, LogFormatError) as exc:
            raise LogFormatError(f"{source}: {exc}") from None

    @classmethod
    def joint_states(
        cls,
        topic: str,
        left_joint: str,
        right_joint: str,
        wheel_radius_m: float,
        **kwargs: Any,
    ) -> TopicMap:
        """Side speeds from a ``sensor_msgs/JointState`` topic's wheel velocities [rad/s]."""
        return cls(
            v_left=FieldRef(topic, f"velocity[{left_joint}]", wheel_radius_m),
            v_right=FieldRef(topic, f"velocity[{right_joint}]", wheel_radius_m),
            **kwargs,
        )


_REF_KEYS = ("v_left", "v_right", "power", "v_left_cmd", "v_right_cmd", "wz")


def _field_ref(val: Any, where: str) -> FieldRef:
    if isinstance(val, str):
        return FieldRef(val)
    if isinstance(val, Mapping) and isinstance(val.get("topic"), str):
        extra = sorted(set(val) - {"topic", "field", "scale"})
        if extra:
            raise LogFormatError(f"{where}: unknown key(s) {', '.join(extra)}")
        scale = val.get("scale", 1.0)
        if not isinstance(scale, int | float) or isinstance(scale, bool):
            raise LogFormatError(f"{where}: scale must be a number, got {scale!r}")
        return FieldRef(str(val["topic"]), str(val.get("field", "data")), float(scale))
    raise LogFormatError(f"{where}: expected a topic name or {{topic, field, scale}}, got {val!r}")


def load_topic_map(path: str | os.PathLike[str]) -> TopicMap:
    """Read a :class:`TopicMap` from a YAML (or JSON) file; see :meth:`TopicMap.from_mapping`.

    Raises
    ------
    LogFormatError
        Unreadable file or invalid content, naming the file and key.
    """
    import yaml

    p = Path(path)
    try:
        data = yaml.safe_load(p.read_text(encoding="utf-8"))
    except OSError as exc:
        raise LogFormatError(f"{p}: cannot read topic map: {exc.strerror}") from None
    except yaml.YAMLError as exc:
        first = str(exc).splitlines()[0] if str(exc) else "invalid YAML"
        raise LogFormatError(f"{p}: invalid YAML: {first}") from None
    return TopicMap.from_mapping(data, str(p))


def _field_value(msg: Any, path: str) -> float:
    obj = msg
    for part in path.split("."):
        name, _, rest = part.partition("[")
        obj = getattr(obj, name)
        if rest:
            key = rest.rstrip("]")
            if key.lstrip("-").isdigit():
                obj = obj[int(key)]
            else:
                obj = obj[list(msg.name).index(key)]
    return float(obj)


def _stamp(msg: Any, bag_ns: int, use_header: bool) -> float:
    header = getattr(msg, "header", None)
    if use_header and header is not None:
        st = header.stamp
        return float(st.sec) + 1e-9 * float(st.nanosec)
    return 1e-9 * float(bag_ns)


def _yaw_of(q: Any) -> float:
    return math.atan2(2.0 * (q.w * q.z + q.x * q.y), 1.0 - 2.0 * (q.y * q.y + q.z * q.z))


def read_rosbag(
    path: str | os.PathLike[str], topics: TopicMap, *, run_id: str | None = None
) -> Log:
    """Read a ROS 2 bag (``rosbags`` library) into a :class:`Log` on a common time base.

    Every series is read with its own time stamps, NaN samples are skipped (and counted
    in the notes), then all are linearly interpolated onto a uniform grid over the span
    the series share (``yaw`` unwrapped before and wrapped after).  Time starts at 0 on
    the first grid point; the bag time of that point is stated in the notes.

    Parameters
    ----------
    path : path-like
        The bag (a rosbag2 directory or ``.mcap``/``.db3`` file).
    topics : TopicMap
        Which topics and fields make which columns.
    run_id : str, optional
        Run identifier (default: the bag's name).

    Returns
    -------
    Log
        The log (``v_left, v_right, p_total`` and, if mapped, commands, pose, ``wz``).

    Raises
    ------
    LogFormatError
        Unreadable bag, missing topic or field (named), a series with fewer than two
        samples, or series whose time spans do not overlap.
    """
    from rosbags.highlevel import AnyReader
    from rosbags.typesys import Stores, get_typestore

    p = Path(path)
    source = str(p)
    series: dict[str, list[tuple[float, float]]] = {}
    extract: dict[str, list[tuple[str, Any]]] = {}

    def add(column: str, topic: str, fn: Any) -> None:
        series[column] = []
        extract.setdefault(topic, []).append((column, fn))

    def ref_fn(ref: FieldRef) -> Any:
        return lambda m: ref.scale * _field_value(m, ref.field)

    add("v_left", topics.v_left.topic, ref_fn(topics.v_left))
    add("v_right", topics.v_right.topic, ref_fn(topics.v_right))
    if topics.power is not None:
        add("p_total", topics.power.topic, ref_fn(topics.power))
    else:
        assert topics.battery_topic is not None
        sign, off = topics.battery_current_sign, topics.p_offset_w
        add("p_total", topics.battery_topic, lambda m: sign * m.voltage * m.current - off)
    if topics.v_left_cmd is not None and topics.v_right_cmd is not None:
        add("v_left_cmd", topics.v_left_cmd.topic, ref_fn(topics.v_left_cmd))
        add("v_right_cmd", topics.v_right_cmd.topic, ref_fn(topics.v_right_cmd))
    if topics.odom_topic is not None:
        o = topics.odom_topic
        add("x", o, lambda m: m.pose.pose.position.x)
        add("y", o, lambda m: m.pose.pose.position.y)
        add("yaw", o, lambda m: _yaw_of(m.pose.pose.orientation))
        if topics.wz is None:
            add("wz", o, lambda m: m.twist.twist.angular.z)
    if topics.wz is not None:
        add("wz", topics.wz.topic, ref_fn(topics.wz))
    try:
        reader = AnyReader([p], default_typestore=get_typestore(Stores.ROS2_HUMBLE))
        reader.open()
    except Exception as exc:  # rosbags raises several unrelated types
        raise LogFormatError(f"{source}: cannot read ROS 2 bag: {exc}") from None
    try:
        available = {c.topic for c in reader.connections}
        missing = sorted(set(extract) - available)
        if missing:
            raise LogFormatError(
                f"{source}: topic(s) {', '.join(missing)} not in the bag; "
                f"available: {', '.join(sorted(available))}"
            )
        conns = [c for c in reader.connections if c.topic in extract]
        for conn, bag_ns, raw in reader.messages(connections=conns):
            msg = reader.deserialize(raw, conn.msgtype)
            stamp = _stamp(msg, bag_ns, topics.use_header_stamp)
            for column, fn in extract[conn.topic]:
                try:
                    series[column].append((stamp, float(fn(msg))))
                except (AttributeError, IndexError, ValueError, TypeError) as exc:
                    raise LogFormatError(
                        f"{source}: column {column!r} from topic {conn.topic} "
                        f"({conn.msgtype}): cannot read the mapped field: {exc}"
                    ) from None
    finally:
        reader.close()
    return _resample(series, topics, source, run_id if run_id is not None else p.stem)


def _resample(
    series: dict[str, list[tuple[float, float]]], topics: TopicMap, source: str, run_id: str
) -> Log:
    notes: list[str] = []
    clean: dict[str, tuple[FloatArray, FloatArray]] = {}
    for column, pairs in series.items():
        arr = np.array(pairs, dtype=np.float64).reshape(-1, 2)
        ok = np.isfinite(arr[:, 1])
        if not np.all(ok):
            notes.append(f"{column}: skipped {int((~ok).sum())} non-finite messages")
        arr = arr[ok]
        order = np.argsort(arr[:, 0], kind="stable")
        ts, vals = arr[order, 0], arr[order, 1]
        ts, idx = np.unique(ts, return_index=True)
        vals = vals[idx]
        if ts.size < 2:
            raise LogFormatError(
                f"{source}: column {column!r} has {ts.size} usable message(s); need at least 2"
            )
        if column == "yaw":
            vals = np.unwrap(vals)
        clean[column] = (ts, vals)
    t0 = max(ts[0] for ts, _ in clean.values())
    t1 = min(ts[-1] for ts, _ in clean.values())
    if not t1 > t0:
        raise LogFormatError(f"{source}: the mapped topics' time spans do not overlap")
    pt = clean["p_total"][0]
    rate = topics.rate_hz or 1.0 / float(np.median(np.diff(pt)))
    rel = np.arange(math.floor((t1 - t0) * rate + 1e-9) + 1) / rate
    grid = t0 + rel
    cols: dict[str, Any] = {}
    for column, (ts, vals) in clean.items():
        cols[column] = np.interp(grid, ts, vals)
    if "yaw" in cols:
        cols["yaw"] = np.arctan2(np.sin(cols["yaw"]), np.cos(cols["yaw"]))
    notes.append(f"resampled to {rate:g} Hz by linear interpolation; t = 0 at bag time {t0:.9f} s")
    if topics.battery_topic is not None:
        notes.append(
            f"p_total = {topics.battery_current_sign:+g} x voltage x current of "
            f"{topics.battery_topic} - {topics.p_offset_w:g} W: battery power, assumed all "
            "locomotion beyond the offset"
        )
    return Log(
        **cols,
        t=rel,
        source=source,
        run_id=run_id,
        notes=tuple(notes),
    )
