"""The CSV form of the log format: one reader, :func:`read_log_csv`, and one writer.

A log file has one header row, SI units and REP-103 frames; its columns are those of
:data:`ecoplan.dynamics.log.COLUMNS` (or their aliases), in any order.  Lines starting
with ``#`` *before* the header are metadata (``# run_id: ...``, ``# note: ...``,
``# power_sampling: row | interval_mean``, how the power was taken,
:data:`~ecoplan.dynamics.log.POWER_SAMPLINGS`; ``# pose_frame: world | run``, whether the
pose of every run is in one frame, :data:`~ecoplan.dynamics.log.POSE_FRAMES`); blank lines
are skipped.  Any other column (e.g. the simulator's ``case`` or ``p_friction``) is ignored
by the reader and named in :attr:`~ecoplan.dynamics.log.Log.notes`.

Validation (every failure is a :class:`~ecoplan.errors.LogFormatError` whose one-line
message names the file, the column and/or the 1-based line number of the file):

* empty file, no header, no data rows or a single data row;
* a required column missing, a duplicated column name (also through an alias);
* a non-numeric cell (an empty cell counts as missing);
* NaN or inf in a required column;
* time not strictly increasing (duplicated with other readings, or going backwards; a
  jump back by more than :data:`~ecoplan.dynamics.log.RESTART_S` is named as runs joined in
  one file);
* a speed above :data:`~ecoplan.dynamics.log.MAX_PLAUSIBLE_SPEED_MPS` in magnitude.

Rows whose only defect is a missing/NaN value in an *optional* column are dropped and
counted in :attr:`~ecoplan.dynamics.log.Log.dropped_rows` (never silently), and so are rows
that repeat an earlier row exactly -- same time, same value in every column read -- as the
joined files of a rotating logger or a re-sent message write them (:func:`_drop_repeats`); an
optional column that is empty on every row is treated as absent.  Infinite values in optional
columns are errors.  Clean files are read by ``numpy.loadtxt`` (one hour at 100 Hz with
12 columns in about 1.4 s); anything unusual goes through a cell-by-cell parser that
names the offending line.

The writer, :func:`write_log_csv`, is the only one: the simulator
(:meth:`ecoplan.sim.SimResult.to_log`), the scenario reports and the blind-case
generator all write through it.
"""

from __future__ import annotations

import csv
import math
import os
from dataclasses import dataclass, field
from pathlib import Path
from typing import Any

import numpy as np
import numpy.typing as npt

from ecoplan._typing import BoolArray, FloatArray
from ecoplan.dynamics.log import (
    ALIASES,
    COLUMNS,
    FLOAT_COLUMNS,
    OPTIONAL_FLOAT_COLUMNS,
    REQUIRED_COLUMNS,
    Log,
    StrArray,
    check_pose_frame,
    check_power_sampling,
    check_values,
)
from ecoplan.errors import LogFormatError

__all__ = ["read_log_csv", "write_log_csv"]

_KNOWN = frozenset(c.name for c in COLUMNS)
_IntArray = npt.NDArray[np.int64]


def _where(source: str, line: int | None = None) -> str:
    return f"{source}, line {line}" if line is not None else source


@dataclass(slots=True)
class _Head:
    """What precedes the data rows: metadata, the header and its 1-based line."""

    header: list[str]
    line: int
    run_id: str | None = None
    notes: list[str] = field(default_factory=list)
    power_sampling: str = "row"
    pose_frame: str = "world"


@dataclass(slots=True)
class _Body:
    """Parsed data rows: numeric columns, terrain labels, file line of every row."""

    cols: dict[str, FloatArray]
    labels: StrArray | None
    lines: _IntArray

    def rows(self, keep: BoolArray) -> _Body:
        """The rows where ``keep`` is true."""
        labels = None if self.labels is None else self.labels[keep]
        return _Body({k: v[keep] for k, v in self.cols.items()}, labels, self.lines[keep])


# --------------------------------------------------------------------------- reading


def _read_lines(p: Path, source: str) -> list[str]:
    """The file's lines without line ends (a byte-order mark is dropped)."""
    try:
        with p.open(newline="", encoding="utf-8-sig") as fh:
            text = fh.read()
    except OSError as exc:
        raise LogFormatError(f"{source}: cannot open log: {exc.strerror}") from None
    except UnicodeDecodeError as exc:
        raise LogFormatError(f"{source}: not UTF-8 text: {exc.reason}") from None
    lines = [ln[:-1] if ln.endswith("\r") else ln for ln in text.split("\n")]
    if lines and not lines[-1]:
        lines.pop()  # the final newline
    return lines


def _read_head(lines: list[str], source: str) -> _Head:
    """Metadata lines, then the header row (names mapped from aliases and checked)."""
    run_id: str | None = None
    notes: list[str] = []
    sampling = "row"
    pose_frame = "world"
    for k, raw in enumerate(lines):
        if not raw.replace(",", "").strip():
            continue
        if raw.lstrip().startswith("#"):
            key, _, value = raw.lstrip("# ").partition(":")
            if key.strip() == "run_id":
                run_id = value.strip()
            elif key.strip() == "note":
                notes.append(value.strip())
            elif key.strip() == "power_sampling":
                sampling = check_power_sampling(value.strip(), _where(source, k + 1))
            elif key.strip() == "pose_frame":
                pose_frame = check_pose_frame(value.strip(), _where(source, k + 1))
            continue
        names = [c.strip() for c in next(csv.reader([raw]))]
        header = _canonical_header(names, _where(source, k + 1), notes)
        return _Head(header, k + 1, run_id, notes, sampling, pose_frame)
    raise LogFormatError(f"{source}: empty file (no header row)")


def _canonical_header(names: list[str], where: str, notes: list[str]) -> list[str]:
    """Map aliases to column names; reject duplicates and missing required columns."""
    header: list[str] = []
    for name in names:
        col = ALIASES.get(name, name)
        if col in header:
            also = f" (header names {_alias_names(names, col)})" if col != name else ""
            raise LogFormatError(f"{where}: duplicated column {col!r}{also}")
        if col != name:
            notes.append(f"column {name!r} read as {col!r}")
        header.append(col)
    missing = [c for c in REQUIRED_COLUMNS if c not in header]
    if missing:
        raise LogFormatError(
            f"{where}: missing required column(s) "
            f"{', '.join(repr(c) for c in missing)}; header is {', '.join(names)}"
            f"{_separator_hint(names)}"
        )
    return header


def _separator_hint(names: list[str]) -> str:
    """Why a header misses columns when its one name splits at another separator into them.

    A spreadsheet in a locale with a decimal comma exports ``;``-separated files; other
    loggers write tabs.  The reader takes commas only (and ``.`` as the decimal point).
    """
    if len(names) != 1:
        return ""
    for sep, said in ((";", "';'"), ("\t", "tabs"), ("|", "'|'")):
        parts = [ALIASES.get(c.strip(), c.strip()) for c in names[0].split(sep)]
        if all(c in parts for c in REQUIRED_COLUMNS):
            return (
                f" -- separated by {said}: the log format is comma-separated, with '.' as the "
                "decimal point"
            )
    return ""


def _alias_names(names: list[str], col: str) -> str:
    """The header names that denote column ``col``, quoted: ``"'t', 'time'"``."""
    return ", ".join(repr(n) for n in names if ALIASES.get(n, n) == col)


def _parse_fast(body: list[str], head: _Head) -> _Body | None:
    """Vectorised parse (``numpy.loadtxt``) of a clean body; None when anything is unusual.

    Unusual -- quotes, blank lines, ragged rows, empty or non-numeric cells -- goes to
    :func:`_parse_slow`, which finds and names the offending line.
    """
    width = len(head.header)
    if not body or any(('"' in ln) or ln.count(",") != width - 1 for ln in body):
        return None
    index = {c: i for i, c in enumerate(head.header)}
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
    lines = head.line + 1 + np.arange(len(body), dtype=np.int64)
    return _Body(cols, labels, lines)


def _split_rows(body: list[str], head: _Head, source: str) -> tuple[list[list[str]], list[int]]:
    """Non-blank CSV rows of the body and their file lines; ragged rows are errors."""
    rows: list[list[str]] = []
    lines: list[int] = []
    reader = csv.reader(body)
    try:
        for row in reader:
            if any(c.strip() for c in row):
                rows.append(row)
                lines.append(head.line + reader.line_num)
    except csv.Error as exc:
        where = _where(source, head.line + reader.line_num)
        raise LogFormatError(f"{where}: unreadable CSV: {exc}") from None
    width = len(head.header)
    for row, line in zip(rows, lines, strict=True):
        if len(row) != width:
            raise LogFormatError(
                f"{_where(source, line)}: {len(row)} cells, the header has {width}"
            )
    return rows, lines


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


def _parse_slow(body: list[str], head: _Head, source: str) -> _Body:
    """Cell-by-cell parse that names the first bad line, column and cell."""
    rows, lines = _split_rows(body, head, source)
    index = {c: i for i, c in enumerate(head.header)}
    cols: dict[str, FloatArray] = {}
    for name in (c for c in FLOAT_COLUMNS if c in index):
        cells = [r[index[name]] for r in rows]
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
        labels = np.array([r[index["terrain"]].strip() for r in rows], dtype=np.str_)
    return _Body(cols, labels, np.asarray(lines, dtype=np.int64))


def _check_row_count(body: _Body, head: _Head, source: str) -> None:
    if body.lines.size == 0:
        raise LogFormatError(f"{source}: no data rows after the header (line {head.line})")
    if body.lines.size < 2:
        raise LogFormatError(
            f"{_where(source, int(body.lines[0]))}: a single data row; a log needs at least 2"
        )


def _missing_optional(body: _Body, source: str, notes: list[str]) -> BoolArray:
    """Rows with a missing optional value; all-empty optional columns are removed."""
    missing = np.zeros(body.lines.size, dtype=np.bool_)
    for name in OPTIONAL_FLOAT_COLUMNS:
        arr = body.cols.get(name)
        if arr is None:
            continue
        if np.all(np.isnan(arr)):
            del body.cols[name]
            notes.append(f"column {name!r} is empty on every row; treated as absent")
            continue
        inf = np.flatnonzero(np.isinf(arr))
        if inf.size:
            i = int(inf[0])
            raise LogFormatError(
                f"{_where(source, int(body.lines[i]))}: column {name!r} is {float(arr[i])!r}; "
                "values must be finite"
            )
        missing |= np.isnan(arr)
    if body.labels is not None:
        empty = body.labels == ""
        if np.all(empty):
            notes.append("column 'terrain' is empty on every row; treated as absent")
            body.labels = None
        else:
            missing |= empty
    return missing


def _drop_rows(body: _Body, drop: BoolArray, source: str, notes: list[str]) -> _Body:
    """The body without the dropped rows (counted in the notes)."""
    n_drop, n_rows = int(drop.sum()), drop.size
    if not n_drop:
        return body
    keep = ~drop
    first_line = int(body.lines[int(np.flatnonzero(drop)[0])])
    notes.append(
        f"dropped {n_drop} of {n_rows} rows with a missing optional value "
        f"(first at line {first_line})"
    )
    if int(keep.sum()) < 2:
        raise LogFormatError(
            f"{source}: only {int(keep.sum())} row(s) left after dropping {n_drop} rows "
            "with missing optional values; a log needs at least 2"
        )
    return body.rows(keep)


def _drop_repeats(body: _Body, source: str, notes: list[str]) -> tuple[_Body, int]:
    """The body without rows that repeat an earlier row exactly, and how many were dropped.

    A repeat has an earlier row's time and its value in every column read (and its terrain
    label): files of a rotating logger joined end to end overlap by a few rows, a driver that
    re-sends a message logs it twice.  Dropping the repeats loses nothing.  A row at an
    earlier row's time with *other* readings stays, for the time check to refuse (which of
    the two is right is unknown).  Looked for only when time is not strictly increasing.
    """
    t = body.cols["t"]
    if np.all(np.diff(t) > 0.0):
        return body, 0
    n = body.lines.size
    table = [body.cols[k] for k in sorted(body.cols)]
    if body.labels is not None:
        table.append(np.unique(body.labels, return_inverse=True)[1].astype(np.float64))
    _, first = np.unique(np.column_stack(table), axis=0, return_index=True)
    repeat = np.ones(n, dtype=np.bool_)
    repeat[first] = False
    n_drop = int(repeat.sum())
    if not n_drop:
        return body, 0
    first_line = int(body.lines[int(np.flatnonzero(repeat)[0])])
    notes.append(
        f"dropped {n_drop} of {n} rows repeating an earlier row exactly (same time and "
        f"readings; first at line {first_line})"
    )
    keep = ~repeat
    if int(keep.sum()) < 2:
        raise LogFormatError(
            f"{source}: only {int(keep.sum())} distinct row after dropping {n_drop} exact "
            "repeats of it; a log needs at least 2"
        )
    return body.rows(keep), n_drop


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
        The validated log; rows with a missing optional value, and exact repeats of an
        earlier row, are dropped and counted.

    Raises
    ------
    LogFormatError
        Any violation of the format, naming the file, column and line.
    """
    p = Path(path)
    source = str(p)
    lines = _read_lines(p, source)
    head = _read_head(lines, source)
    body_lines = lines[head.line :]
    body = _parse_fast(body_lines, head) or _parse_slow(body_lines, head, source)
    _check_row_count(body, head, source)
    # required columns finite before rows are dropped, all the checks after
    check_values(body.cols, source, body.lines, "line", required_only=True)
    notes = head.notes
    drop = _missing_optional(body, source, notes)
    body = _drop_rows(body, drop, source, notes)
    body, repeats = _drop_repeats(body, source, notes)
    ignored = [c for c in head.header if c not in _KNOWN]
    if ignored:
        notes.append(f"ignored columns: {', '.join(ignored)}")
    check_values(body.cols, source, body.lines, "line")  # the constructor checks again by sample
    cols: dict[str, Any] = dict(body.cols)
    if body.labels is not None:
        cols["terrain"] = body.labels
    return Log(
        **cols,
        source=source,
        run_id=run_id if run_id is not None else (head.run_id or p.stem),
        dropped_rows=int(drop.sum()) + repeats,
        notes=tuple(notes),
        power_sampling=head.power_sampling,
        pose_frame=head.pose_frame,
    )


# --------------------------------------------------------------------------- writing


def _csv_cell(text: str) -> str:
    if any(ch in text for ch in ',"\r\n') or text != text.strip():
        return '"' + text.replace('"', '""') + '"'
    return text


def _cells(values: npt.NDArray[Any]) -> list[str]:
    """Text of every value: shortest round-trip floats, integers, quoted labels."""
    if values.dtype.kind in "US":
        quoted = {lab: _csv_cell(str(lab)) for lab in set(values.tolist())}
        return [quoted[lab] for lab in values.tolist()]
    return list(map(repr, values.tolist()))


def write_log_csv(log: Log, path: str | os.PathLike[str], *, overwrite: bool = False) -> Path:
    """Write a log as CSV in the ecoplan format (shortest round-trip float text).

    ``run_id`` and ``notes`` are written as ``#`` metadata lines before the header, so
    :func:`read_log_csv` gives back an equal log.  The format's columns come first, in
    the order of :data:`~ecoplan.dynamics.log.COLUMNS`, then :attr:`Log.extra` (which
    the reader ignores).

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
    columns = {c: getattr(log, c) for c in log.columns()}
    columns.update(log.extra)
    cells = [_cells(np.asarray(v)) for v in columns.values()]
    try:
        with p.open("w", newline="", encoding="utf-8") as fh:
            if log.run_id:
                fh.write(f"# run_id: {log.run_id}\n")
            if log.power_sampling != "row":
                fh.write(f"# power_sampling: {log.power_sampling}\n")
            if log.pose_frame != "world":
                fh.write(f"# pose_frame: {log.pose_frame}\n")
            for note in log.notes:
                fh.write("# note: " + note.replace("\n", " ") + "\n")
            fh.write(",".join(columns) + "\n")
            fh.write("\n".join(map(",".join, zip(*cells, strict=True))))
            fh.write("\n")
    except OSError as exc:
        raise LogFormatError(f"{p}: cannot write log: {exc.strerror}") from None
    return p
