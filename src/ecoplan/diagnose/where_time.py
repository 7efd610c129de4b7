"""Where the gap lies in the log's own time: change points of the residual (issue 12, item 4).

The calibrated model's power residual of each run is averaged over bins of ``bin_s`` seconds
(on the run's own time column) and segmented by penalised change-point detection (PELT with
the least-squares cost, a change of the mean of the features: ``ruptures.KernelCPD`` with the
linear kernel, in C; ``ruptures.Pelt(model="l2")`` searches the same cost in Python, took
over half of the diagnosis of one continuous hour of 100 Hz log, and on the BorealTC mixes
gave the same breakpoints on 102 of 103 searches, a higher cost on the other) on two
features per bin:

* the residual's level (relative to the model's power when it is given: a terrain scales the
  power);
* its ripple, ``ln`` of the mean absolute first difference within the bin (relative to the
  model's power likewise): rough ground shakes the wheels, and on BorealTC's 6.5 Hz currents
  a switch from flooring to snow shows in the ripple when the level hides it;
* when the vehicle's per-terrain models are known (``known_w``), the logged power's level
  relative to each of them.

Each feature is divided by its noise scale, the robust scale of neighbouring-bin differences
(``scipy.stats.median_abs_deviation`` / √2, so that the level changes themselves do not
inflate it), and a change point costs ``penalty * m * ln(n)`` (``m`` features, ``n`` bins: a
BIC-like choice).  The penalty (3) and the shortest segment (12 s) were chosen on the
training mixes 0-9 of ``benchmarks/borealtc_mixes.py``: 17 of their 18 switches within ±5 s.

A segment is reported when its run has change points (every segment of that run, so that
each switch is a boundary ``t_end_s`` / ``t_start_s``) or when the whole run departs from the
session (its mean residual more than three standard errors from the session's).
``excess_w`` is the segment's mean residual minus the session's mean residual [W]: positive
where the robot draws more than the calibrated model says.

With a vehicle's known terrains, :func:`label_segments` labels those segments afterwards;
:func:`known_terrain_path` instead segments and labels at once, on the known terrains' own
models (the most likely sequence of terrains).  ``benchmarks/borealtc_mixes.py`` measures it
beside the diagnosis's labels; the diagnosis does not use it (yet): on the BorealTC mixes it
labels the true terrain on 66-71 % of the time against 27-41 % for ``terrain_change``'s own
fit, but snow and sandy loam (and asphalt and flooring) alternate along one ground where the
models differ less than their errors.

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
from collections.abc import Mapping, Sequence
from dataclasses import dataclass
from pathlib import Path

import numpy as np
from scipy.stats import median_abs_deviation

from ecoplan._typing import ArrayLike, BoolArray, FloatArray, IntArray
from ecoplan.errors import InputError
from ecoplan.models.logged_power import logged_power_w
from ecoplan.presets import VehicleParams

__all__ = [
    "TerrainSpan",
    "TimeSegment",
    "known_terrain_path",
    "label_segments",
    "where_time",
    "write_where_time_csv",
]

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
    excess_se_w : float or None
        Standard error of ``excess_w`` [W]: the scatter of the run's bin means (robust scale
        of neighbouring-bin differences / √2) over the square root of the segment's bins;
        None where not computed.  A stretch is cut where the level, the ripple or a known
        terrain's level changes, so its level alone may lie within this scatter.  Neighbouring
        differences leave out slow drifts of the residual, so on a drifting residual the
        error is on the small side: more stretches count as departures, not fewer.
    """

    run: str
    t_start_s: float
    t_end_s: float
    excess_w: float
    excess_se_w: float | None = None

    def mask(self, t: ArrayLike, run: ArrayLike) -> BoolArray:
        """The samples of this stretch, from every sample's time [s] and run name (str array)."""
        t = np.asarray(t, dtype=np.float64)
        return np.asarray(
            (np.asarray(run) == self.run) & (t >= self.t_start_s) & (t <= self.t_end_s)
        )

    @property
    def excess_z(self) -> float:
        """``excess_w`` in standard errors (nan without one)."""
        se = self.excess_se_w
        return self.excess_w / se if se is not None and se > 0.0 else math.nan

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


def _ripple(t: FloatArray, r: FloatArray, bin_s: float, number: IntArray) -> FloatArray:
    """``ln`` of the mean absolute first difference of the residual within each kept bin.

    A terrain changes the ripple of the drive's current as well as its level (rough ground
    shakes the wheels); a bin without two samples takes its neighbour's value.
    """
    k = np.floor((t - t[0]) / bin_s).astype(np.int64)
    same = k[1:] == k[:-1]
    kk = k[1:][same]
    size = int(k[-1]) + 1 if k.size else 0
    cnt = np.bincount(kk, minlength=size)[number]
    tot = np.bincount(kk, weights=np.abs(np.diff(r))[same], minlength=size)[number]
    with np.errstate(invalid="ignore", divide="ignore"):
        rip = np.where(cnt > 0, tot / np.maximum(cnt, 1), np.nan)
    if np.all(np.isnan(rip)):
        return np.zeros(number.size)
    good = np.flatnonzero(~np.isnan(rip))
    rip = rip[good[np.clip(np.searchsorted(good, np.arange(rip.size)), 0, good.size - 1)]]
    return np.asarray(np.log(rip + 0.01 * float(np.median(rip)) + 1e-12), dtype=np.float64)


def _bin_scatter(x: FloatArray, number: IntArray) -> float:
    """Noise scale of bin values: robust scale of neighbouring-bin differences / √2 (0: none).

    Differences of neighbours, so that the level changes themselves hardly inflate it.
    """
    d = np.diff(x)[np.diff(number) == 1]
    return float(median_abs_deviation(d, scale="normal")) / math.sqrt(2.0) if d.size > 1 else 0.0


def _standardise(features: FloatArray, number: IntArray) -> tuple[FloatArray, int]:
    """Each feature over its noise scale (robust scale of neighbouring-bin differences / √2).

    Features without noise (a constant) are dropped; returns the scaled features and their
    number.
    """
    cols = []
    for x in features.T:
        s = _bin_scatter(x, number)
        if s > 0.0:
            cols.append(x / s)
    if not cols:
        return np.zeros((features.shape[0], 0)), 0
    return np.column_stack(cols), len(cols)


def _power_scale(t: FloatArray, model_w: FloatArray, bin_s: float) -> FloatArray:
    """Per kept bin, the mean ``|model|`` a relative feature divides by [W].

    Floored at 5 % of its mean over the run: where the robot stands, a model's power is near
    zero and a relative residual over it would be a residual over nothing (unfloored, the
    known terrains' levels reached 4e10 at rest on 11 of the 40 runs of the BorealTC mixes,
    and a stop outweighed the switches).
    """
    m_abs = _bins(t, np.abs(model_w), bin_s)[1]
    return np.maximum(m_abs, 0.05 * float(np.mean(m_abs)) + 1e-9)


def _known_levels(
    t: FloatArray,
    r: FloatArray,
    idx: IntArray,
    model_w: FloatArray | None,
    known_w: Sequence[FloatArray],
    bin_s: float,
) -> list[FloatArray]:
    """Per bin, the logged power's departure from each known terrain's model, relative to it.

    ``(Σ p - Σ P_k) / Σ |P_k|`` per bin for every known terrain ``k`` (``p = r + model``): on
    ground a known model describes, its feature stays level whatever the manoeuvre, and a
    switch between two known terrains moves all of them.  Empty without ``model_w``.
    """
    if model_w is None:
        return []
    p = r + np.asarray(model_w, dtype=np.float64)[idx]
    out = []
    for pk_all in known_w:
        pk = np.asarray(pk_all, dtype=np.float64)[idx]
        out.append(_bins(t, p - pk, bin_s)[1] / _power_scale(t, pk, bin_s))
    return out


def where_time(
    t: FloatArray,
    residual_w: FloatArray,
    run: IntArray,
    run_ids: Sequence[str],
    *,
    model_w: FloatArray | None = None,
    known_w: Sequence[FloatArray] = (),
    bin_s: float = 1.0,
    min_segment_s: float = 12.0,
    penalty: float = 3.0,
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
    known_w : sequence of ndarray
        What the log would show on each known terrain of the vehicle (its vehicle file's
        per-terrain models, :func:`ecoplan.models.logged_power.logged_power_w`) [W].  With
        ``model_w``, each adds a feature: the logged power's relative departure from that
        terrain's model (:func:`_known_levels`).  On BorealTC mixes the five Husky terrains
        keep the switches found within ±5 s at 16/18 on the tuning mixes 0-9 and take them
        from 7/12 to 11/12 on the measured mixes 10-19 (penalty 3 kept; before their scale
        was floored, :func:`_power_scale`, a stop cost three switches of the tuning mixes);
        the diagnosis gives them for motor-current logs only
        (:func:`~ecoplan.diagnose.effects.terrain.segmentation_models`).
    bin_s : float
        Width of the averaging bins [s].
    min_segment_s : float
        Shortest segment [s]; at most a quarter of the run, so that a short run can still
        hold a stretch of other ground between two of the same.
    penalty : float
        Multiplier of the ``m ln(n)`` penalty of a change point (``m`` standardised features).

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
        rel, ripple = means, _ripple(tr, rr, bin_s, number)
        if model_w is not None:
            m_abs = _power_scale(tr, np.asarray(model_w, dtype=np.float64)[idx], bin_s)
            rel, ripple = means / m_abs, ripple - np.log(m_abs)
        n = means.size
        features = np.column_stack([rel, ripple])
        known = _known_levels(tr, rr, idx, model_w, known_w, bin_s)
        bkps: list[int] = [n]
        shortest = min(min_segment_s, 0.25 * float(tr[-1] - tr[0]))  # room for four in a run
        min_bins = max(round(shortest / bin_s), 2)
        if n >= 2 * min_bins:
            scaled, m = _standardise(features, number)
            if known:
                # the known terrains' levels weigh together as one feature
                extra, m_known = _standardise(np.column_stack(known), number)
                scaled = np.column_stack([scaled, extra / math.sqrt(max(m_known, 1))])
                m += min(m_known, 1)
            if m:
                algo = ruptures.KernelCPD(kernel="linear", min_size=min_bins).fit(scaled)
                bkps = [int(b) for b in algo.predict(pen=penalty * m * math.log(n))]
        edges = [0, *bkps]
        scatter = _bin_scatter(means, number)
        segs = []
        for a, b in itertools.pairwise(edges):
            w = counts[a:b]
            level = float(np.sum(means[a:b] * w) / np.sum(w))
            t0 = float(starts[a]) if a > 0 else float(tr[0])
            t1 = float(starts[b]) if b < n else float(tr[-1])
            se = scatter / math.sqrt(b - a) if scatter > 0.0 else None
            segs.append(TimeSegment(name, t0, t1, level - session_mean, se))
        if len(segs) > 1:
            out.extend(segs)
        else:
            se = float(np.std(rr)) / math.sqrt(max(n, 1))
            if abs(segs[0].excess_w) > 3.0 * max(se, 1e-12):
                out.extend(segs)
    return out


def label_segments(
    segments: Sequence[TimeSegment],
    t: FloatArray,
    run: Sequence[str] | IntArray,
    v_left: FloatArray,
    v_right: FloatArray,
    p_w: FloatArray,
    models: Mapping[str, VehicleParams],
) -> list[tuple[str, float]]:
    """The most likely known terrain of each segment: the model that leaves the least MAE.

    With per-terrain models of the vehicle (the terrains of its vehicle file), each segment is
    labelled with the terrain whose model predicts the segment's logged power best: the least
    mean absolute error, the most likely terrain under Laplace-distributed power errors.

    Parameters
    ----------
    segments : sequence of TimeSegment
        Segments of :func:`where_time`.
    t : ndarray
        Time of every sample on its log's own clock [s].
    run : sequence of str or ndarray
        Run name of every sample (the segments' ``run``).
    v_left, v_right : ndarray
        Measured side speeds [m/s].
    p_w : ndarray
        Logged power [W].
    models : mapping of str to TrackedParams or WheeledParams
        The vehicle's model on each known terrain, by terrain name.

    Returns
    -------
    list of (str, float)
        Per segment, the terrain's name and its model's MAE on the segment [W] (``("", nan)``
        for a segment without samples).
    """
    names = list(models)
    if not names:
        raise InputError("label_segments needs at least one terrain model")
    t = np.asarray(t, dtype=np.float64)
    run_arr = np.asarray(run).astype(str)
    p = np.asarray(p_w, dtype=np.float64)
    # the quantity the log shows (battery power, or motor currents: models.logged_power)
    preds = np.array([logged_power_w(models[k], v_left, v_right) for k in names])
    out: list[tuple[str, float]] = []
    for s in segments:
        inside = s.mask(t, run_arr)
        if not np.any(inside):
            out.append(("", math.nan))
            continue
        mae = np.mean(np.abs(preds[:, inside] - p[inside]), axis=1)
        best = int(np.argmin(mae))
        out.append((names[best], float(mae[best])))
    return out


@dataclass(frozen=True, slots=True)
class TerrainSpan:
    """A stretch of one run that one known terrain's model describes best.

    Attributes
    ----------
    run : str
        Run identifier.
    t_start_s, t_end_s : float
        First and last sample of the stretch on the log's own time column [s].
    terrain : str
        The known terrain.
    mae_w : float
        That terrain's model's mean absolute error on the stretch's samples [W].
    """

    run: str
    t_start_s: float
    t_end_s: float
    terrain: str
    mae_w: float


def _viterbi(cost: FloatArray, switch: float, min_bins: int) -> IntArray:
    """Least-cost label per bin: ``Σ cost[b, label_b] + switch × (number of switches)``.

    Every stretch of one label lasts at least ``min_bins`` bins (the first one too; the last
    one may be cut by the end).  A hidden semi-Markov chain written as a Markov one: the
    state is (label, bins spent in it, capped at ``min_bins``), and a label may only be left
    from the capped count.  ``cost`` has shape ``(bins, labels)``.
    """
    nb, k = cost.shape
    d = max(int(min_bins), 1)
    value = np.full((k, d), math.inf)
    value[:, 0] = cost[0]
    flat = np.arange(k * d).reshape(k, d)
    back = np.zeros((nb, k, d), dtype=np.int64)  # the flattened state each state came from
    labels_k = np.arange(k)
    for b in range(1, nb):
        stay = value[:, d - 1]
        order = np.argsort(stay)
        # a label is entered from the best other one that has run its shortest stretch
        src = np.where(labels_k == order[0], order[1] if k > 1 else order[0], order[0])
        new = np.empty((k, d))
        new[:, 0] = stay[src] + switch if k > 1 else math.inf
        back[b, :, 0] = flat[src, d - 1]
        if d > 1:
            new[:, 1:] = value[:, :-1]
            back[b, :, 1:] = flat[:, :-1]
        longer = stay < new[:, d - 1]  # staying on beyond the shortest stretch
        new[longer, d - 1] = stay[longer]
        back[b, longer, d - 1] = flat[longer, d - 1]
        value = new + cost[b][:, None]
    done = value[:, d - 1]
    # the last stretch has run its shortest length unless the run is shorter than that
    finite = bool(np.isfinite(done).any())
    state = int(flat[int(np.argmin(done)), d - 1]) if finite else int(np.argmin(value))
    labels = np.empty(nb, dtype=np.int64)
    for b in range(nb - 1, -1, -1):
        labels[b] = state // d
        state = int(back[b].ravel()[state])
    return labels


def known_terrain_path(
    t: FloatArray,
    p_w: FloatArray,
    run: IntArray,
    run_ids: Sequence[str],
    predictions_w: Mapping[str, FloatArray],
    errors_w: Mapping[str, float],
    *,
    bin_s: float = 1.0,
    min_segment_s: float = 12.0,
    penalty: float = 1.0,
) -> list[TerrainSpan]:
    """The most likely sequence of known terrains along each run, and where it switches.

    Each known terrain's *whole* model (what the log would show on it, over the run's own
    manoeuvres) is compared with the logged power sample by sample; a sample's error on
    terrain ``k`` is taken as Laplace-distributed with the scale that terrain's model states
    as its held-out error (``errors_w[k]``, the MAE of a Laplace law is its scale ``b_k``):
    negative log-likelihood ``|p - P_k| / b_k + ln(2 b_k)``.  A terrain whose runs vary much
    (snow's depth) so costs less per watt of error.  The labels of 1 s bins are the maximum
    of the penalised likelihood (a Viterbi pass over a semi-Markov chain): every switch costs
    ``penalty × ln n`` (``n`` the run's samples; BIC for the two parameters a switch adds, its
    time and its terrain, at ``penalty`` 1), and every stretch lasts at least
    ``min_segment_s`` (at most a quarter of the run, as in :func:`where_time`).  Unlike
    :func:`where_time` followed by :func:`label_segments`, the segmentation *is* the
    labelling: a switch is placed where one known model stops describing the power and
    another starts, and a change that no pair of known models tells apart is no switch.

    Parameters
    ----------
    t : ndarray
        Time of every sample on its log's own clock [s] (gaps allowed: a split's blocks).
    p_w : ndarray
        Logged power [W].
    run : ndarray of int
        Run index of every sample (into ``run_ids``).
    run_ids : sequence of str
        Name of each run.
    predictions_w : mapping of str to ndarray
        Each known terrain's model of the logged quantity at every sample [W]
        (:func:`ecoplan.models.logged_power.logged_power_w`).
    errors_w : mapping of str to float
        Each terrain's held-out MAE [W] (> 0); terrains without one are left out.
    bin_s : float
        Width of the bins that carry one label [s].
    min_segment_s : float
        Shortest stretch of one terrain [s].
    penalty : float
        Multiplier of the ``ln n`` cost of a switch.

    Returns
    -------
    list of TerrainSpan
        In run order, then time order; consecutive spans of a run have different terrains.

    >>> t = np.arange(0.0, 60.0, 0.2)
    >>> v = np.full(t.size, 0.5)
    >>> on_a, on_b = 100.0 + 0 * t, 160.0 + 0 * t
    >>> p = np.where(t < 30.0, on_a, on_b) + np.random.default_rng(1).laplace(0, 10, t.size)
    >>> spans = known_terrain_path(t, p, np.zeros(t.size, int), ["r"],
    ...                            {"a": on_a, "b": on_b}, {"a": 10.0, "b": 10.0})
    >>> [(s.terrain, round(s.t_start_s)) for s in spans]
    [('a', 0), ('b', 30)]
    """
    if bin_s <= 0.0 or min_segment_s < 0.0 or penalty < 0.0:
        raise InputError("known_terrain_path needs bin_s > 0, min_segment_s >= 0, penalty >= 0")
    names = [k for k in predictions_w if k in errors_w and errors_w[k] > 0.0]
    t = np.asarray(t, dtype=np.float64)
    p = np.asarray(p_w, dtype=np.float64)
    run = np.asarray(run)
    if not names or p.size == 0:
        return []
    scale = np.array([float(errors_w[k]) for k in names])
    preds = np.array([np.asarray(predictions_w[k], dtype=np.float64) for k in names])
    nll = np.abs(p[None, :] - preds) / scale[:, None] + np.log(2.0 * scale)[:, None]
    out: list[TerrainSpan] = []
    for i in np.unique(run):
        idx = np.flatnonzero(run == i)
        name = run_ids[int(i)] if int(i) < len(run_ids) else f"run{int(i)}"
        tr = t[idx]
        k = np.floor((tr - tr[0]) / bin_s).astype(np.int64)
        # empty bins (a split's held-out blocks) cost nothing but count as time
        cost = np.column_stack([np.bincount(k, weights=row[idx]) for row in nll]).astype(float)
        shortest = min(min_segment_s, 0.25 * float(tr[-1] - tr[0]))
        labels = _viterbi(cost, penalty * math.log(max(idx.size, 2)), round(shortest / bin_s))
        which = labels[k]  # every sample's bin label
        cuts = np.flatnonzero(np.diff(which)) + 1
        for a, b in itertools.pairwise([0, *cuts.tolist(), idx.size]):
            j = int(which[a])
            mae = float(np.mean(np.abs(p[idx[a:b]] - preds[j, idx[a:b]])))
            out.append(TerrainSpan(name, float(tr[a]), float(tr[b - 1]), names[j], mae))
    return out


def write_where_time_csv(segments: Sequence[TimeSegment], path: str | os.PathLike[str]) -> Path:
    """Write the segments as CSV: ``run, t_start_s, t_end_s, excess_w, excess_se_w``.

    The JSON's keys (:data:`WHERE_TIME_KEYS`), then the standard error of the excess (empty
    where not computed).
    """
    p = Path(path)
    with p.open("w", newline="") as fh:
        w = csv.writer(fh)
        w.writerow([*WHERE_TIME_KEYS, "excess_se_w"])
        for s in segments:
            se = "" if s.excess_se_w is None else f"{s.excess_se_w:.6g}"
            w.writerow([s.run, f"{s.t_start_s:.6g}", f"{s.t_end_s:.6g}", f"{s.excess_w:.6g}", se])
    return p
