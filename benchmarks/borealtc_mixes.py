"""Terrain switches in real data: joined BorealTC runs (issue 12, items 5 and 7).

Seeded mixes join stretches of BorealTC runs of different terrains (five terrains: ASPHALT,
FLOORING, ICE, SANDY_LOAM, SNOW; Husky A200, ``p_total = 24 V x (|I_L| + |I_R|)``) into one
log with one continuous clock, so the terrain switch times are known.  Each mix is diagnosed
blind, without pose, and the script prints, for the tuning mixes 0-9 (on which the
change-point penalty and shortest segment were chosen), the measured-only mixes 10-19 and all:

* the share of switches that ``where_time`` finds within ±5 s (a segment boundary);
* the share of mixes whose verdict is ``terrain_change``, and of single-terrain stretches
  (the control) whose verdict is;
* the held-out MAE after the correction over the calibrated model's, on the mixes: on the raw
  6.5 Hz samples (the diagnosis's gap), and on the power averaged over :data:`WINDOW_S`
  windows of each run's clock (what an energy planner costs: the energy of a few metres of
  route, not each 0.15 s sample);
* two ceilings of that ratio: ``terrain_change`` fitted on the *true* switch times with the
  *true* terrains' models (the diagnosis's split, calibration and fit; perfect localisation
  and labelling) -- and beside it those models as they are, no gain fitted (:func:`as_known`)
  -- and the best a per-terrain model of the mean power could do at all -- a
  flexible per-terrain regression on the motion (:func:`flexible_ceiling`) fitted on the
  held-out samples themselves, so an optimistic bound;
* on how many mixes the flexible ceiling and the true segments would pass the naming rule's
  bar (:func:`nameable`): with the Husky's known terrains, the true terrains' own held-out
  error (:meth:`~ecoplan.diagnose.effects.TerrainChange.naming_bar_w`), printed per mix as
  ``bar W``.  Those errors are leave-one-run-out figures, but the mixes' runs are among those
  the file's models were fitted on, so the bar is easier to meet here than on new runs.  And
  on how many the true segments' reduction is also significant as the diagnosis requires of
  every candidate (:func:`significant`): the most mixes on which ``terrain_change`` could be
  named with these models, even with perfect segments and labels;
* which MAE the line is judged on -- the raw samples, the held-out MAE the issue names and the
  diagnosis's own gap -- and on how many mixes the noise floor alone is above 0.7 times the
  calibrated gap (no correction can meet the line on raw samples there);
* the share of segment time whose terrain label
  (:func:`ecoplan.diagnose.where_time.label_segments`) is right, with the ``husky-a200``
  vehicle file's per-terrain models (identified on all BorealTC runs, so in-sample here);
  the share of the mix's time on which ``terrain_change``'s own fit carries the true terrain
  (:func:`fit_labels_right`); and, measured beside it (not what the diagnosis does), the
  labels and held-out ratios of ``terrain_change`` fitted on the known terrains' most likely
  path (:func:`path_fit`, :func:`~ecoplan.diagnose.where_time.known_terrain_path`).

``--separability`` first prints which known terrains the file's models tell apart on whole
runs (:func:`separability`): ice from all the others; snow lies within its own 103 W error of
flooring (76 W apart) and sandy loam (71 W), sandy loam within its 65 W of asphalt (46 W), and
asphalt and flooring (64 W apart) and asphalt and snow (103 W) are at the edge.  By the same
rule a run is labelled right on 72 % of asphalt, 100 % of flooring, 98 % of ice, 78 % of
sandy loam and 67 % of snow time (in-sample).

Vehicle: the ``husky-a200`` vehicle file (default terrain), whose ``power_log:
motor_current`` says the log's ``p_total`` is ``24 V (|I_l| + |I_r|)``: the input check and
the per-terrain models (terrain labels, ``terrain_change``'s known terrains) predict that
logged quantity (:func:`ecoplan.models.logged_power.logged_power_w`); calibration and the
other effects refit the file's contact-friction battery-power structure to it.  The first run
of every terrain is left out of the mixes and controls.  Targets (issue 12): switches >= 80 %,
terrain_change on mixes >= 80 % and on single-terrain stretches <= 10 %, MAE ratio <= 0.7::

    PYTHONPATH=src .venv/bin/python benchmarks/borealtc_mixes.py [--mixes 20] [--seed 0]

Figures (2026-11-24 s8, wip/mixes, defaults; switches and labels re-measured 2026-11-26 s25,
after the known terrains' levels were floored at rest and the change-point search moved to
C, where nothing else changed; all re-measured in s31 after ``husky-a200.yaml`` was
re-identified with the readers' one window mean, whose small changes moved three verdicts, one
up and two down): switches 27/30 = 90 % (tuning 16/18, measured 11/12; 24/30, 13/18 and 11/12
before s25); labels right on 70.7 % of segment time; ``terrain_change`` on 8/20 mixes (tuning
5/10, measured 3/10; 9/20 with the s25 file) and on 1/20 single-terrain stretches (SNOW_04);
the true segments with the true terrains pass the bar significantly on only 7/20 mixes (4/10,
3/10): the line (16/20) is out of reach of these models.  Held-out MAE after / calibrated,
median, raw samples 1.00 (tuning 0.95); own fit 0.87 (tuning 0.77) with its segments begun
halfway across the held-out gap before them; true segments 0.95, their models as they are
0.93; flexible ceiling 0.65.  On 5 s windows 1.00; own fit 0.76 (tuning 0.58), true segments
0.80, as they are 0.84, flexible ceiling 0.49: the gain per segment is worth its fit.  The
noise floor alone is above 0.7 x calibrated on 10/20 mixes.  ``terrain_change``'s own labels
right on 45.2 % of mix time; on the known terrains' path 65.4 %, whose fit leaves 0.91 raw,
0.71 on windows.  ``--seed 1`` (never tuned on): switches 26/28, ``terrain_change`` 2/20,
singles 0/20, true segments significant on 9/20; own labels 32.0 %, path 69.5 % (fit 0.86
raw, 0.75 windows; own fit 0.96 / 0.87); true segments 0.78 / 0.71, as they are 0.87 / 0.82.
The bar ignores significance, so with snow's 103 W error it passes easily: the "naming bar
passed by" counts before "and significantly so" are an upper bound.
"""

from __future__ import annotations

import argparse
import inspect
import itertools
import sys
import time

import numpy as np

from ecoplan.diagnose.attribute import GAP_OVER_FLOOR, attribute
from ecoplan.diagnose.calibrate import calibrate
from ecoplan.diagnose.effects import EffectData, NoEffect, TerrainChange, prepare
from ecoplan.diagnose.effects.terrain import known_terrain_errors, known_terrains
from ecoplan.diagnose.pipeline import diagnose, diagnosis_split
from ecoplan.diagnose.replay import Frame
from ecoplan.diagnose.result import Diagnosis
from ecoplan.diagnose.stats import block_bootstrap
from ecoplan.diagnose.where_time import known_terrain_path, label_segments
from ecoplan.dynamics.log import Log, join_runs
from ecoplan.errors import InputError
from ecoplan.io.borealtc import load_borealtc_runs
from ecoplan.models.logged_power import logged_power_w
from ecoplan.presets import VehicleParams, terrain_names, vehicle

TERRAINS = ("ASPHALT", "FLOORING", "ICE", "SANDY_LOAM", "SNOW")
VEHICLE = "husky-a200"
TOL_S = 5.0
#: Window of the averaged-power MAE [s]: 2.5 m of route at the runs' typical 0.5 m/s.
WINDOW_S = 5.0
#: Share of the gap above the noise floor an effect must close to be named (the diagnosis's).
EXPLAIN_MIN = float(inspect.signature(attribute).parameters["explain_min"].default)
#: Least relative held-out reduction of a significant candidate (the diagnosis's).
MIN_GAIN = float(inspect.signature(attribute).parameters["min_gain"].default)
#: Family-wise significance level of the candidates (the diagnosis's, before Bonferroni).
ALPHA = float(inspect.signature(attribute).parameters["alpha"].default)


def nameable(gap_w: float, floor_w: float, after_w: float, bar_w: float | None = None) -> bool:
    """Whether a correction leaving ``after_w`` of ``gap_w`` passes the naming rule's bar.

    The diagnosis names an effect only if it closes :data:`EXPLAIN_MIN` of the gap above the
    noise floor, or leaves no more than ``1 + GAP_OVER_FLOOR`` times the floor
    (:mod:`ecoplan.diagnose.attribute`); significance aside.  ``terrain_change`` on known
    terrains that state their held-out error ``bar_w`` (the true terrains' here) passes as
    well with ``after_w <= bar_w``, and not at all with a bar of 0
    (:meth:`~ecoplan.diagnose.effects.TerrainChange.naming_bar_w`).
    """
    near = (
        after_w <= gap_w - EXPLAIN_MIN * (gap_w - floor_w)
        or after_w <= (1.0 + GAP_OVER_FLOOR) * floor_w
    )
    return near if bar_w is None else bar_w > 0.0 and (near or after_w <= bar_w)


def _chunk(lg: Log, g: np.random.Generator, lo_s: float, hi_s: float) -> Log:
    length = float(g.uniform(lo_s, hi_s))
    if lg.duration_s <= length:
        return lg
    start = float(lg.t[0]) + float(g.uniform(0.0, lg.duration_s - length))
    return lg.slice(start_s=start, stop_s=start + length)


def join(parts: list[Log], run_id: str) -> tuple[Log, list[float]]:
    """The parts on one clock (side speeds and power only); the log and the switch times [s]."""
    return join_runs(parts, run_id, columns=(), source=f"<mix {run_id}>")


def ceiling(
    mix: Log, switches: list[float], names: list[str], params: VehicleParams, level: float
) -> tuple[float, float, float | None, float]:
    """Held-out MAE ratios (raw, windowed) of ``terrain_change`` on the *true* segments.

    The same split, calibration and fit as the diagnosis, with the segments and their known
    terrains given instead of detected and labelled: what the effect could reach on this mix
    with perfect localisation and labels.  Third, the naming bar of that fit: the true
    terrains' own held-out error over the held-out samples
    (:meth:`~ecoplan.diagnose.effects.TerrainChange.terrain_error_w`) [W].  Fourth, whether
    its held-out reduction is significant as the diagnosis requires of a candidate
    (:func:`significant`, at the diagnosis's Bonferroni ``level``): 1.0 or 0.0.
    """
    _, test_f, train, test = _splits(mix, params)
    edges = [float(mix.t[0]), *switches, float(mix.t[-1]) + 1.0]
    spans = tuple(
        (0, a, b - 1e-6, n.lower())
        for (a, b), n in zip(itertools.pairwise(edges), names, strict=True)
    )
    tc = TerrainChange(theta=spans).fit(train)
    r_tc = test.p - tc.predict(test)
    r_cal = test.p - NoEffect().fit(train).predict(test)
    return (
        _mae(r_tc) / _mae(r_cal),
        windowed_mae(test_f, r_tc) / windowed_mae(test_f, r_cal),
        tc.terrain_error_w(test),
        float(significant(r_cal, r_tc, test_f, level)),
    )


def as_known(
    mix: Log, switches: list[float], names: list[str], params: VehicleParams
) -> tuple[float, float]:
    """Held-out MAE ratios (raw, windowed) of the true terrains' models as they are.

    No fit at all: each held-out sample of a true segment is predicted by that terrain's
    model of the logged quantity in the vehicle file (steady, as ``terrain_change``'s
    columns), over the calibrated model's held-out MAE.  A segment of a known terrain needs
    no fitting if this is as good as the fit with a gain per segment (the true segments'
    ratio).
    """
    _, test_f, train, test = _splits(mix, params)
    known = known_terrains(params)
    seg = np.searchsorted(switches, test_f.t, "right")
    pred = np.empty(test_f.n)
    for i, name in enumerate(names):
        at = seg == i
        pred[at] = logged_power_w(known[name.lower()], test_f.vl[at], test_f.vr[at])
    r = test.p - pred
    r_cal = test.p - NoEffect().fit(train).predict(test)
    return _mae(r) / _mae(r_cal), windowed_mae(test_f, r) / windowed_mae(test_f, r_cal)


def significant(r_cal: np.ndarray, r_after: np.ndarray, test_f: Frame, level: float) -> bool:
    """Whether a correction's held-out reduction passes the diagnosis's significance test.

    As :func:`ecoplan.diagnose.attribute.attribute` scores a candidate: the block bootstrap
    over the held-out time blocks (one-sided p below ``level``, the diagnosis's
    Bonferroni-corrected level) and a reduction above ``MIN_GAIN`` of the calibrated gap.
    """
    red, _, _, p = block_bootstrap(
        r_cal, r_after, test_f.block.astype(np.float64), np.random.default_rng(0)
    )
    return p < level and red > MIN_GAIN * _mae(r_cal)


def _splits(mix: Log, params: VehicleParams) -> tuple[Frame, Frame, EffectData, EffectData]:
    """The diagnosis's split of a mix, calibrated on its training half: frames and data.

    The frame and halves are the diagnosis's own
    (:func:`~ecoplan.diagnose.pipeline.diagnosis_split`: the case tolerance from the encoder
    noise, the samples no model of the logged speeds can predict left out).
    """
    split = diagnosis_split([mix], params)
    params = split.params
    train_f, test_f = split.frame.subset(split.train), split.frame.subset(split.test)
    cal = calibrate(train_f, params)
    return (
        train_f,
        test_f,
        prepare(train_f, cal.params, prior=params),
        prepare(test_f, cal.params, prior=params),
    )


def path_fit(
    mix: Log, switches: list[float], names: list[str], params: VehicleParams
) -> tuple[float, float, float]:
    """``terrain_change`` on the known terrains' most likely path instead of its own labels.

    The measured alternative labelling (not the diagnosis's): on the training split,
    :func:`~ecoplan.diagnose.where_time.known_terrain_path` segments and labels at once with
    each known terrain's *whole* model of the logged quantity (on the run's clock: its
    start-up and mass terms) and its stated held-out error (Laplace scale), a switch at the
    BIC's ``ln n``; each stretch starts halfway across the held-out gap before it.
    ``terrain_change`` is fitted on those spans (each terrain's model with its gain) like the
    diagnosis's.  Returns the held-out MAE ratios over the calibrated model (raw, windowed)
    and the share of the mix's time whose path label is the true terrain.
    """
    train_f, test_f, train, test = _splits(mix, params)
    known = known_terrains(params)
    errors = known_terrain_errors(params)
    preds = {k: logged_power_w(m, train_f.vl, train_f.vr, train_f.t) for k, m in known.items()}
    path = known_terrain_path(train_f.t, train_f.p, train_f.run, ["0"], preds, errors)
    starts = [sp.t_start_s for sp in path]
    starts[1:] = [0.5 * (a.t_end_s + b.t_start_s) for a, b in itertools.pairwise(path)]
    theta = tuple((0, t0, sp.t_end_s, sp.terrain) for t0, sp in zip(starts, path, strict=True))
    tc = TerrainChange(theta=theta).fit(train)
    r_tc = test.p - tc.predict(test)
    r_cal = test.p - NoEffect().fit(train).predict(test)
    which = np.clip(np.searchsorted(starts, mix.t, side="right") - 1, 0, len(theta) - 1)
    truth = np.array([names[i].lower() for i in np.searchsorted(switches, mix.t, "right")])
    right = float(np.mean(np.array([theta[i][3] for i in which]) == truth))
    return _mae(r_tc) / _mae(r_cal), windowed_mae(test_f, r_tc) / windowed_mae(test_f, r_cal), right


def own_ratio(d: Diagnosis) -> tuple[float, float]:
    """Held-out MAE ratios (raw, windowed) of the diagnosis's ``terrain_change`` fit.

    Whatever the verdict: the correction as fitted on the training split, over the
    calibrated model, on the held-out samples.
    """
    tc = d.attribution.fitted.get("terrain_change")
    if tc is None:
        return 1.0, 1.0
    test = prepare(d.test_frame, d.calibration.params, prior=d.preset)
    r_tc = test.p - tc.predict(test)
    r_cal = d.residual_calibrated_w
    return _mae(r_tc) / _mae(r_cal), windowed_mae(d.test_frame, r_tc) / windowed_mae(
        d.test_frame, r_cal
    )


def _mae(r: np.ndarray) -> float:
    return float(np.mean(np.abs(r)))


def windowed_mae(frame: Frame, residual_w: np.ndarray, window_s: float = WINDOW_S) -> float:
    """MAE of the residual averaged over ``window_s`` windows of each run's clock [W]."""
    out = []
    for r in np.unique(frame.run):
        i = frame.run == r
        k = np.floor((frame.t[i] - frame.t[i][0]) / window_s).astype(np.int64)
        n, s = np.bincount(k), np.bincount(k, weights=residual_w[i])
        out.append(np.abs(s[n > 0] / n[n > 0]))
    return float(np.mean(np.concatenate(out))) if out else 0.0


def _motion_features(frame: Frame) -> np.ndarray:
    """A flexible basis of the motion: speed, turn rate, their products, saturations, accels."""
    v, w = np.abs(frame.vx), np.abs(frame.vr - frame.vl)
    moving = (v + w > 0.02).astype(float)
    cols = [np.ones(frame.n), moving, v, v**2, v**3, w, w**2, w**3, v * w, v * w**2, v**2 * w]
    cols += [np.tanh(w / s) for s in (0.05, 0.1, 0.2, 0.4)]
    cols += [frame.ax, np.abs(frame.ax), frame.alpha, np.abs(frame.alpha), frame.ax * v]
    return np.column_stack(cols)


def flexible_ceiling(mix: Log, switches: list[float], params: VehicleParams) -> tuple[float, float]:
    """Held-out MAE ratios (raw, windowed) of the best per-terrain model of the mean power.

    On the held-out samples, each *true* terrain stretch gets its own least-squares regression
    of the logged power on a flexible basis of the motion (:func:`_motion_features`: 20
    columns), fitted *on those samples themselves*: no model of the mean power as a function of
    the motion, per terrain, does better than this on them (an optimistic bound; the ratio is
    over the calibrated model's held-out MAE, as the diagnosis's).
    """
    _, test_f, train, test = _splits(mix, params)
    r_cal = test.p - NoEffect().fit(train).predict(test)
    X, seg = _motion_features(test_f), np.searchsorted(np.asarray(switches), test_f.t, "right")
    pred = np.empty(test_f.n)
    for s in np.unique(seg):
        i = seg == s
        beta = np.linalg.lstsq(X[i], test_f.p[i], rcond=None)[0]
        pred[i] = X[i] @ beta
    r = test_f.p - pred
    return _mae(r) / _mae(r_cal), windowed_mae(test_f, r) / windowed_mae(test_f, r_cal)


def fit_labels_right(d: Diagnosis, mix: Log, names: list[str], switches: list[float]) -> float:
    """Share of the mix's time where ``terrain_change``'s own fitted terrain is the true one.

    Whatever the verdict: each sample of the mix takes the known terrain of the fitted span
    begun last (the first span for earlier samples), as the fit tiles its run.  A fit with
    level factors, or none, labels nothing: 0.
    """
    tc = d.attribution.fitted.get("terrain_change")
    theta = tc.theta_ if tc is not None else None
    if not theta or len(theta[0]) != 4:
        return 0.0
    starts = np.array([float(sp[1]) for sp in theta])
    which = np.clip(np.searchsorted(starts, mix.t, side="right") - 1, 0, len(theta) - 1)
    fitted = np.array([str(theta[i][3]) for i in which])
    truth = np.array([names[i].lower() for i in np.searchsorted(switches, mix.t, "right")])
    return float(np.mean(fitted == truth))


def truth_at(t0: float, t1: float, names: list[str], switches: list[float], end: float) -> str:
    """The terrain that covers most of ``[t0, t1]`` in a mix."""
    edges = [0.0, *switches, end]
    cover = [max(0.0, min(t1, b) - max(t0, a)) for a, b in itertools.pairwise(edges)]
    return names[int(np.argmax(cover))]


def _summary(label: str, rows: list[dict[str, float]]) -> None:
    if not rows:
        return
    found = sum(r["found"] for r in rows)
    total = sum(r["switches"] for r in rows)
    tc = sum(r["tc"] for r in rows)

    def med(key: str) -> str:
        return f"{np.median([r[key] for r in rows]):.2f}"

    reach, reach_true = sum(r["reach"] for r in rows), sum(r["reach_true"] for r in rows)
    reach_sig = sum(r["reach_sig"] for r in rows)
    print(
        f"  {label:14s} switches {found:.0f}/{total:.0f} = {100 * found / max(total, 1):5.1f} %, "
        f"terrain_change {tc:.0f}/{len(rows)} = {100 * tc / len(rows):5.1f} %, "
        f"labels right {_share(rows, 'file_ok')} of segment time "
        f"(terrain_change's own: {100 * np.mean([r['fit_ok'] for r in rows]):5.1f} % of mix "
        f"time; on the known terrains' path {100 * np.mean([r['path_ok'] for r in rows]):5.1f} "
        f"%, which leaves held-out raw {med('path')}, {WINDOW_S:g} s windows {med('path_w')})\n"
        f"  {'':14s} naming bar passed by: the flexible ceiling on {reach:.0f}/{len(rows)} mixes, "
        f"terrain_change on the true segments on {reach_true:.0f}/{len(rows)}, and "
        f"significantly so (as a candidate must be) on {reach_sig:.0f}/{len(rows)}\n"
        f"  {'':14s} MAE after / calibrated, median: raw {med('ratio')} "
        f"(terrain_change's own fit, whatever the verdict, {med('own')}; "
        f"true segments {med('ceiling')}, their models as they are {med('known')}, "
        f"flexible per-terrain ceiling {med('flex')}); "
        f"{WINDOW_S:g} s windows {med('ratio_w')} (own fit {med('own_w')}, true segments "
        f"{med('ceiling_w')}, as they are {med('known_w')}, "
        f"flexible ceiling {med('flex_w')})\n"
        f"  {'':14s} judged on the raw samples (the held-out MAE of the issue, the diagnosis's "
        f"gap); on {sum(r['floor_share'] > 0.7 for r in rows)}/{len(rows)} mixes the noise "
        f"floor alone is above 0.7 x calibrated"
    )


def _share(rows: list[dict[str, float]], key: str) -> str:
    n = sum(r["label_n"] for r in rows)
    return f"{100 * sum(r[key] for r in rows) / n:5.1f} %" if n > 0 else "  n/a"


def _refused(switches: int) -> dict[str, float]:
    """A refused mix: nothing found, named or closed."""
    ratios = ("ratio", "ratio_w", "own", "own_w", "ceiling", "ceiling_w", "flex", "flex_w", "path")
    ratios += ("path_w", "known", "known_w")
    zeros = ("found", "tc", "file_ok", "fit_ok", "label_n", "reach", "reach_true", "reach_sig")
    zeros += ("floor_share", "path_ok")
    return {"switches": float(switches), **dict.fromkeys(ratios, 1.0), **dict.fromkeys(zeros, 0.0)}


def separability(runs: dict[str, list[Log]], shipped: dict[str, VehicleParams]) -> None:
    """Print which known terrains the vehicle file's models tell apart on whole runs.

    Every BorealTC run is labelled with the known terrain whose model of the logged quantity
    (on the run's own clock, :func:`ecoplan.models.logged_power.logged_power_w`) leaves the
    least MAE over the run (the labelling of the diagnosis, no gain); rows are the runs' true
    terrains, columns the labels, in seconds of run.  Then each model's MAE on each terrain's
    runs (time-weighted), and how far apart each pair of models is on the manoeuvres of all
    runs against their stated held-out errors.  The models were identified on all these
    runs: in-sample.
    """
    names = list(shipped)
    seconds = np.zeros((len(TERRAINS), len(names)))
    mae = np.zeros((len(TERRAINS), len(names)))
    apart = np.zeros((len(names), len(names)))  # Σ |P_i - P_j| over all runs' samples
    n_all = 0
    for i, terrain in enumerate(TERRAINS):
        total = 0.0
        for lg in runs[terrain]:
            p = np.asarray(lg.p_total)
            pred = np.array(
                [logged_power_w(shipped[k], lg.v_left, lg.v_right, lg.t) for k in names]
            )
            err = np.mean(np.abs(pred - p), axis=1)
            seconds[i, int(np.argmin(err))] += lg.duration_s
            mae[i] += err * lg.duration_s
            total += lg.duration_s
            apart += np.abs(pred[:, None, :] - pred[None, :, :]).sum(axis=2)
            n_all += p.size
        mae[i] /= max(total, 1e-9)
    head = " ".join(f"{k[:8]:>9s}" for k in names)
    print(f"runs labelled by the least-MAE known model [s] (rows: true terrain)\n{'':11s}{head}")
    for i, terrain in enumerate(TERRAINS):
        print(f"{terrain[:10]:11s}" + " ".join(f"{x:9.0f}" for x in seconds[i]))
    print(f"each model's MAE on each terrain's runs [W]\n{'':11s}{head}")
    for i, terrain in enumerate(TERRAINS):
        print(f"{terrain[:10]:11s}" + " ".join(f"{x:9.1f}" for x in mae[i]))
    errors = known_terrain_errors(next(iter(shipped.values())))
    print(
        "how far apart two models are on all runs' manoeuvres, mean |P_i - P_j| [W]; on the "
        "diagonal each terrain's stated held-out MAE; * apart by less than the larger of the "
        f"two errors (not told apart beyond the models' own error)\n{'':11s}{head}"
    )
    for i, a in enumerate(names):
        cells = []
        for j, b in enumerate(names):
            gap = apart[i, j] / max(n_all, 1)
            near = gap < max(errors.get(a.lower(), 0.0), errors.get(b.lower(), 0.0))
            diag = f"{errors.get(a.lower(), np.nan):8.1f} "
            cells.append(diag if i == j else f"{gap:8.1f}{'*' if near else ' '}")
        print(f"{a[:10].upper():11s}" + " ".join(cells))
    print()


def main() -> int:
    ap = argparse.ArgumentParser(description="terrain switches in joined BorealTC runs")
    ap.add_argument("--mixes", type=int, default=20)
    ap.add_argument("--singles", type=int, default=20)
    ap.add_argument("--seed", type=int, default=0)
    ap.add_argument(
        "--separability",
        action="store_true",
        help="first print which known terrains the models tell apart on whole runs",
    )
    args = ap.parse_args()
    g = np.random.default_rng(args.seed)
    runs = {t: load_borealtc_runs(t) for t in TERRAINS}
    params = vehicle(VEHICLE)
    # the vehicle file's per-terrain models (identified on all runs: in-sample here)
    shipped = {t.upper(): vehicle(VEHICLE, t) for t in terrain_names(VEHICLE)}
    pool = {t: runs[t][1:] for t in TERRAINS}
    if args.separability:
        separability(runs, shipped)
    t0 = time.perf_counter()
    rows: list[dict[str, float]] = []
    print(f"{'mix':6s} {'terrains':30s} {'switches':8s} {'verdict':14s} cal -> final W  "
          f"ratio raw/{WINDOW_S:g}s  own  true flex floor W  bar W  labels")  # fmt: skip
    for m in range(args.mixes):
        k = int(g.integers(2, 4))
        names = [str(x) for x in g.choice(TERRAINS, size=k, replace=False)]
        parts = [_chunk(pool[n][int(g.integers(len(pool[n])))], g, 60.0, 120.0) for n in names]
        mix, switches = join(parts, f"mix{m:02d}")
        try:
            d = diagnose(mix, VEHICLE, rng=m)
        except InputError as e:
            print(f"mix{m:02d} refused: {e}")
            rows.append(_refused(len(switches)))
            continue
        end = float(mix.t[-1])
        bounds = [s.t_end_s for s in d.where_time if s.t_end_s < end - 1e-9]
        hit = sum(any(abs(b - sw) <= TOL_S for b in bounds) for sw in switches)
        ratio = d.gap_final_w / d.gap_calibrated_w if d.gap_calibrated_w > 0 else 1.0
        r_fin = d.test_frame.p - d.prediction_final_w
        ratio_w = windowed_mae(d.test_frame, r_fin) / windowed_mae(
            d.test_frame, d.residual_calibrated_w
        )
        own, own_w = own_ratio(d)
        tags = [mix.run_id] * len(mix)
        from_file = label_segments(
            d.where_time, mix.t, tags, mix.v_left, mix.v_right, mix.p_total, shipped
        )
        n = ok_file = 0.0
        for seg, (lab_f, _) in zip(d.where_time, from_file, strict=True):
            dur = seg.t_end_s - seg.t_start_s
            n += dur
            ok_file += dur * (lab_f == truth_at(seg.t_start_s, seg.t_end_s, names, switches, end))
        # the diagnosis's Bonferroni level: alpha over the candidates it scored
        level = ALPHA / max(len(d.attribution.scores), 1)
        ceil, ceil_w, bar, ceil_sig = ceiling(mix, switches, names, params, level)
        known_r, known_w = as_known(mix, switches, names, params)
        reach_true = float(
            nameable(
                d.gap_calibrated_w, d.attribution.noise_floor_w, ceil * d.gap_calibrated_w, bar
            )
        )
        flex, flex_w = flexible_ceiling(mix, switches, params)
        fit_ok = fit_labels_right(d, mix, names, switches)
        path, path_w, path_ok = path_fit(mix, switches, names, params)
        rows.append(dict(found=hit, fit_ok=fit_ok, path=path, path_w=path_w, path_ok=path_ok,
                         switches=len(switches),
                         tc=float(d.verdict == "terrain_change"),
                         ratio=ratio, ratio_w=ratio_w, own=own, own_w=own_w, ceiling=ceil,
                         known=known_r, known_w=known_w,
                         ceiling_w=ceil_w, flex=flex,
                         floor_share=d.attribution.noise_floor_w / max(d.gap_calibrated_w, 1e-9),
                         flex_w=flex_w, file_ok=ok_file, label_n=n,
                         reach=float(nameable(d.gap_calibrated_w, d.attribution.noise_floor_w,
                                              flex * d.gap_calibrated_w, bar)),
                         reach_true=reach_true, reach_sig=ceil_sig * reach_true))  # fmt: skip
        short = ",".join(lab[:2] if lab else "?" for lab, _ in from_file)
        print(
            f"mix{m:02d}  {'+'.join(names):30s} {hit}/{len(switches):<6d} {d.verdict:14s} "
            f"{d.gap_calibrated_w:6.1f} -> {d.gap_final_w:6.1f}  {ratio:4.2f}/{ratio_w:4.2f}  "
            f"{own:4.2f} {ceil:4.2f} {flex:4.2f} {d.attribution.noise_floor_w:5.1f}  "
            f"{bar if bar is not None else float('nan'):5.1f}  "
            f"{short}"
        )
    tc_single = n_single = 0
    singles = [(t, lg) for t in TERRAINS for lg in pool[t]]
    order = g.permutation(len(singles))[: args.singles]
    for i in order:
        _, lg = singles[int(i)]
        stretch = _chunk(lg, g, 120.0, 240.0)
        try:
            d = diagnose(stretch, VEHICLE, rng=int(i))
        except InputError as e:
            print(f"single {lg.run_id} refused: {e}")
            continue
        n_single += 1
        tc_single += d.verdict == "terrain_change"
        print(f"single {lg.run_id:16s} verdict {d.verdict}")
    print()
    print(f"switches within ±{TOL_S:g} s (target >= 80 %), terrain_change on mixes (>= 80 %), "
          "husky-a200 terrain labels, held-out MAE after / calibrated (<= 0.7):")  # fmt: skip
    _summary("tuning 0-9", rows[:10])
    _summary("measured 10-", rows[10:])
    _summary("all", rows)
    print(
        f"terrain_change on single-terrain stretches: {tc_single}/{n_single} = "
        f"{100 * tc_single / max(n_single, 1):.1f} % (target <= 10 %)"
    )
    print(f"wall time {time.perf_counter() - t0:.1f} s")
    return 0


if __name__ == "__main__":
    sys.exit(main())
