"""Where the gap lies in the log's own time: change points of the residual (issue 12, item 4).

The calibrated model's power residual of each run is averaged over bins of ``bin_s`` seconds
(on the run's own time column) and segmented by penalised change-point detection
(``ruptures.Pelt``, least-squares cost: a change of the mean level).  The penalty is
``penalty * σ² * ln(n)`` (a BIC-like choice) with ``σ`` the robust scale of the binned
residual's first differences (``scipy.stats.median_abs_deviation`` / √2, so that the level
changes themselves do not inflate it).

A segment is reported when its run has change points (every segment of that run, so that
each switch is a boundary ``t_end_s`` / ``t_start_s``) or when the whole run departs from the
session (its mean residual more than three standard errors from the session's).
``excess_w`` is the segment's mean residual minus the session's mean residual [W]: positive
where the robot draws more than the calibrated model says.

>>> import numpy as np
>>> t = np.arange(0.0, 120.0, 0.1)
>>> r = np.where(t < 60.0, 0.0, 50.0) + np.random.default_rng(0).normal(0.0, 10.0, t.size)
>>> segs = where_time(t, r, np.zeros(t.size, dtype=int), ["run0"])
>>> [(s.run, round(s.t_end_s)) for s in segs][:1]
[('run0', 60)]
"""

from __future__ import annotations

import csv
import itertools
import math
import os
from collections.abc import Sequence
from dataclasses import dataclass
from pathlib import Path

import numpy as np
from scipy.stats import median_abs_deviation

from ecoplan._typing import FloatArray, IntArray

__all__ = ["TimeSegment", "where_time", "write_where_time_csv"]

#: Keys of one ``where_time`` entry of the diagnosis JSON, in order.
WHERE_TIME_KEYS: tuple[str, ...] = ("run", "t_start_s", "t_end_s", "excess_w")


@dataclass(frozen=True, slots=True)
class TimeSegment:
    """A stretch of one run whose residual level differs from the rest.

    Attributes
    ----------
    run : str
        Run identifier (the log's ``run_id``).
    t_start_s, t_end_s : float
        Start and end on the log's own time column [s].
    excess_w : float
        Mean residual (measured minus calibrated model) in the segment minus the session's
        mean residual [W].
    """

    run: str
    t_start_s: float
    t_end_s: float
    excess_w: float

    def to_json(self) -> dict[str, str | float]:
        """The JSON entry ``{"run", "t_start_s", "t_end_s", "excess_w"}``."""
        return {
            "run": self.run,
            "t_start_s": float(self.t_start_s),
            "t_end_s": float(self.t_end_s),
            "excess_w": float(self.excess_w),
        }


def _bins(
    t: FloatArray, r: FloatArray, bin_s: float
) -> tuple[FloatArray, FloatArray, IntArray, IntArray]:
    """Mean residual per time bin: (bin start times, means, sample counts, bin numbers).

    Empty bins (gaps of the log, or the held-out blocks of a training split) are left out.
    """
    k = np.floor((t - t[0]) / bin_s).astype(np.int64)
    counts = np.bincount(k)
    sums = np.bincount(k, weights=r)
    keep = counts > 0
    starts = t[0] + bin_s * np.arange(counts.size)
    return starts[keep], sums[keep] / counts[keep], counts[keep], np.flatnonzero(keep)


def where_time(
    t: FloatArray,
    residual_w: FloatArray,
    run: IntArray,
    run_ids: Sequence[str],
    *,
    model_w: FloatArray | None = None,
    bin_s: float = 1.0,
    min_segment_s: float = 8.0,
    penalty: float = 4.0,
) -> list[TimeSegment]:
    """Segments of each run where the residual departs from the rest (change points).

    Parameters
    ----------
    t : ndarray
        Time of every sample on its log's own clock [s].
    residual_w : ndarray
        Measured minus model power [W].
    run : ndarray of int
        Run index of every sample (into ``run_ids``).
    run_ids : sequence of str
        Name of each run.
    model_w : ndarray, optional
        The model's power [W].  With it the change points are searched on the *relative*
        residual of every bin (``Σ residual / Σ |model|``): a terrain scales the power, so its
        residual in watts follows the manoeuvre while its relative residual stays level.
    bin_s : float
        Width of the averaging bins [s].
    min_segment_s : float
        Shortest segment [s].
    penalty : float
        Multiplier of the ``σ² ln(n)`` penalty of a change point.

    Returns
    -------
    list of TimeSegment
        In run order, then time order.
    """
    import ruptures

    t = np.asarray(t, dtype=np.float64)
    r = np.asarray(residual_w, dtype=np.float64)
    run = np.asarray(run)
    if r.size == 0:
        return []
    session_mean = float(np.mean(r))
    out: list[TimeSegment] = []
    for i in np.unique(run):
        idx = np.flatnonzero(run == i)
        name = run_ids[int(i)] if int(i) < len(run_ids) else f"run{int(i)}"
        tr, rr = t[idx], r[idx]
        starts, means, counts, number = _bins(tr, rr, bin_s)
        signal = means
        if model_w is not None:
            m_abs = _bins(tr, np.abs(np.asarray(model_w, dtype=np.float64)[idx]), bin_s)[1]
            signal = means / np.maximum(m_abs, 0.05 * float(np.mean(m_abs)) + 1e-9)
        n = means.size
        # differences of neighbouring bins only (not across a gap)
        diffs = np.diff(signal)[np.diff(number) == 1]
        sigma = (
            float(median_abs_deviation(diffs, scale="normal")) / math.sqrt(2.0) if n > 2 else 0.0
        )
        bkps: list[int] = [n]
        min_bins = max(round(min_segment_s / bin_s), 2)
        if n >= 2 * min_bins and sigma > 0.0:
            algo = ruptures.Pelt(model="l2", min_size=min_bins, jump=1).fit(signal[:, None])
            bkps = list(algo.predict(pen=penalty * sigma**2 * math.log(n)))
        edges = [0, *bkps]
        segs = []
        for a, b in itertools.pairwise(edges):
            w = counts[a:b]
            level = float(np.sum(means[a:b] * w) / np.sum(w))
            t0 = float(starts[a]) if a > 0 else float(tr[0])
            t1 = float(starts[b]) if b < n else float(tr[-1])
            segs.append(TimeSegment(name, t0, t1, level - session_mean))
        if len(segs) > 1:
            out.extend(segs)
        else:
            se = float(np.std(rr)) / math.sqrt(max(n, 1))
            if abs(segs[0].excess_w) > 3.0 * max(se, 1e-12):
                out.extend(segs)
    return out


def write_where_time_csv(segments: Sequence[TimeSegment], path: str | os.PathLike[str]) -> Path:
    """Write the segments as CSV with the columns ``run, t_start_s, t_end_s, excess_w``."""
    p = Path(path)
    with p.open("w", newline="") as fh:
        w = csv.writer(fh)
        w.writerow(WHERE_TIME_KEYS)
        for s in segments:
            w.writerow([s.run, f"{s.t_start_s:.6g}", f"{s.t_end_s:.6g}", f"{s.excess_w:.6g}"])
    return p
