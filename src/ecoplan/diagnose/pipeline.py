"""The diagnosis entry point: replay, calibrate, localise, attribute, report (issue 6).

>>> from ecoplan.diagnose.pipeline import diagnose  # doctest: +SKIP
>>> from ecoplan.diagnose.report import summary  # doctest: +SKIP
>>> d = diagnose(logs, "auriga-beta-wide", "asphalt")  # doctest: +SKIP
>>> print(summary(d))  # doctest: +SKIP

Steps, each in its module:

1. :mod:`~ecoplan.diagnose.replay` — the preset's power model on the measured side speeds and the
   kinematics on the commanded ones: residuals of power, energy, yaw rate, speed and pose;
2. :mod:`~ecoplan.diagnose.calibrate` — the base model's own parameters re-identified on the
   training split (with the friction law, :mod:`~ecoplan.diagnose.friction_law`, where the
   log rejects Coulomb's and the law beats every effect on held-out data,
   :mod:`~ecoplan.diagnose.law_rival`); the held-out gap it closes is reported apart;
3. :mod:`~ecoplan.diagnose.localise` — where the calibrated model's held-out gap lies;
4. :mod:`~ecoplan.diagnose.attribute` — which candidate effect explains what is left, whether
   the log can tell the candidates apart, and how far the gap shrinks;
5. :mod:`~ecoplan.diagnose.report` — text, plots and JSON; :mod:`~ecoplan.diagnose.corrected` —
   the corrected model written to a file.

**Known terrains and what the log measures.**  Parameters from a vehicle file that
describes several terrains (:func:`~ecoplan.diagnose.effects.terrain.known_terrains`) label
every ``where_time`` segment with its most likely terrain, and ``terrain_change`` can put the
labelled terrain's model in place of the base model per segment.  Those models predict what
the file's ``power_log`` says the log measures (:func:`ecoplan.models.logged_power.logged_power_w`):
for ``motor_current`` (the BorealTC Husky, ``24 V (|I_l| + |I_r|)``) the input check, the
terrain labels, ``where_time``'s known-terrain features and ``terrain_change``'s known
terrains compare the logged currents with the file's side-force model of them.  Calibration
and the other effects still refit the file's battery-power structure to the logged signal (a
stand-in in the logged quantity): modelling the currents there needs the side-force columns
(``K``, ``µ``, ``I0`` per side under the motoring mask) in
:func:`~ecoplan.diagnose.calibrate.base_design` and in the effects' prepared data.

The result is a :class:`~ecoplan.diagnose.result.Diagnosis`.  The command ``ecoplan diagnose``
(log files in, report folder out) is :mod:`ecoplan.app.diagnose`.
"""

from __future__ import annotations

import dataclasses
import math
from collections.abc import Sequence

import numpy as np

from ecoplan._typing import BoolArray, FloatArray, RngLike
from ecoplan.diagnose.attribute import split_masks
from ecoplan.diagnose.calibrate import SETTLE_S, settling
from ecoplan.diagnose.checks import check_logs, effect_resolution, sources
from ecoplan.diagnose.effects.terrain import known_terrains, segmentation_models
from ecoplan.diagnose.law_rival import calibrate_and_attribute, final_effect_name
from ecoplan.diagnose.localise import (
    by_regime,
    over_space,
    over_time,
)
from ecoplan.diagnose.replay import (
    Frame,
    LogLike,
    build_frame,
    case_tolerance,
    power_is_interval_mean,
    replay_residuals,
)
from ecoplan.diagnose.result import Diagnosis
from ecoplan.diagnose.stats import block_bootstrap
from ecoplan.diagnose.where_time import TimeSegment, label_segments, where_time
from ecoplan.dynamics.log import Log, fresh_readings
from ecoplan.errors import InputError
from ecoplan.models.logged_power import logged_power_w
from ecoplan.models.wheeled import WheeledParams
from ecoplan.presets import VehicleParams, vehicle

__all__ = [
    "INTERVAL_MEAN_NOTE",
    "POSE_PER_RUN_NOTE",
    "DiagnosisSplit",
    "diagnose",
    "diagnosis_split",
    "settling_note",
    "unresolved_stops",
]

#: What the report says of a log whose power is each interval's mean (its ``power_sampling``).
INTERVAL_MEAN_NOTE = (
    "power_sampling: interval_mean -- the power is the mean over the sample interval before "
    "each row; the speeds (and commands, pose) were read at the interval's middle"
)

#: What the report says of logs whose pose is each run's own frame (``pose_frame: run``).
POSE_PER_RUN_NOTE = (
    "pose_frame: run -- each run's pose is in its own frame (odometry restarted with every "
    "run): no positions or headings are compared between runs"
)


def unresolved_stops(frame: Frame, params: VehicleParams) -> BoolArray:
    """Samples whose power no model of the logged speeds can predict: a wheeled drive settling.

    Wheeled eq. (12) per side is ``a(r) v + b(r)``: as a drive slows along an arc, ``v -> 0``
    but ``b(r)`` stays, while the encoders already read zero
    (:func:`ecoplan.diagnose.calibrate.settling`: at rest, less than
    :data:`~ecoplan.diagnose.calibrate.SETTLE_S` after the run's last moving sample).  Every
    model of the logged speeds puts such a sample at rest, so its power is no evidence for or
    against any of them; the calibration already fits the wheeled coefficients without them,
    and the diagnosis leaves them out of both halves of its split.  On the plant zoo's variant
    f (seed 1, a clean log) they are 2.6 % of the samples, and leaving them out moves the
    calibrated model's held-out gap from 0.635 to 0.511 W (the power noise's MAE: 0.32 W); with
    noise-free speeds, 93 % of the plant's own law's error on the logged speeds lay on samples
    the log reads at rest.  The tracked model's friction and resistance powers go to zero
    with the speeds (Morales et al. 2009 §III; the power-up term, constant at rest, is fitted
    on every stop): nothing is left out.

    Parameters
    ----------
    frame : Frame
        The whole log.
    params : TrackedParams or WheeledParams
        The vehicle.

    Returns
    -------
    ndarray of bool
        The samples left out (all False for a tracked vehicle).
    """
    if not isinstance(params, WheeledParams):
        return np.zeros(frame.n, dtype=bool)
    return settling(frame, rest_mps=params.case_tol_mps)


def settling_note(n_left_out: int, n_total: int) -> str:
    """The report's line on the samples :func:`unresolved_stops` left out of the split.

    >>> settling_note(120, 3600)[:44]
    '120 of 3600 samples (3.3 %) left out of the '
    """
    share = 100.0 * n_left_out / max(n_total, 1)
    return (
        f"{n_left_out} of {n_total} samples ({share:.1f} %) left out of the split: at rest "
        f"less than {SETTLE_S:g} s after motion, where the encoders read zero while a wheeled "
        "drive slowing along an arc still draws b(r) (wheeled eq. 12 at v -> 0)"
    )


def _rng(rng: RngLike) -> np.random.Generator:
    return rng if isinstance(rng, np.random.Generator) else np.random.default_rng(rng)


def _terrain_labels(
    known: dict[str, VehicleParams],
    segments: Sequence[TimeSegment],
    frame: Frame,
    run_ids: Sequence[str],
    residual_w: FloatArray,
) -> tuple[tuple[str, ...], tuple[float, ...], tuple[float, ...]]:
    """Most likely terrain of each segment among the vehicle file's terrains (item 5).

    Only for parameters from a vehicle file that describes several terrains
    (:func:`~ecoplan.diagnose.effects.terrain.known_terrains`); parameters built by hand carry
    one terrain, and get no labels.  Returns the labels, their models' MAE on each segment
    and the calibrated model's (from ``residual_w``, every sample's calibrated residual) [W].
    """
    if not known or not segments:
        return (), (), ()
    run = [run_ids[int(i)] for i in frame.run]
    labels = label_segments(segments, frame.t, run, frame.vl, frame.vr, frame.p, known)
    run_arr = np.asarray(run)
    cal = []
    for seg in segments:
        inside = seg.mask(frame.t, run_arr)
        cal.append(float(np.mean(np.abs(residual_w[inside]))) if np.any(inside) else math.nan)
    return tuple(lab for lab, _ in labels), tuple(m for _, m in labels), tuple(cal)


def _with_case_tol(params: VehicleParams, tol_mps: float) -> VehicleParams:
    """``params`` with the motion-case tolerance ``tol_mps``, still tied to its vehicle file.

    ``dataclasses.replace`` drops the file (and with it the known terrains); a file's
    parameters are rebuilt through it with the tolerance as one more override.
    """
    source = params.source
    if source is not None:
        overrides = {**dict(params.overrides), "case_tol_mps": tol_mps}
        return source.params(params.terrain, overrides)  # type: ignore[no-any-return]
    return dataclasses.replace(params, case_tol_mps=tol_mps)


@dataclasses.dataclass(frozen=True)
class DiagnosisSplit:
    """The diagnosis's view of its logs: one frame and its two halves.

    Attributes
    ----------
    params : TrackedParams or WheeledParams
        The vehicle, with the motion-case tolerance the logs' encoder noise calls for
        (:func:`~ecoplan.diagnose.replay.case_tolerance`) where it exceeds the vehicle's.
    frame : Frame
        Every log on one time base, speeds snapped to rest within that tolerance.
    train, test : ndarray of bool
        The two halves (:func:`~ecoplan.diagnose.attribute.split_masks`), both without
        ``stops``.
    stops : ndarray of bool
        Samples left out of both halves (:func:`unresolved_stops`).
    """

    params: VehicleParams
    frame: Frame
    train: BoolArray
    test: BoolArray
    stops: BoolArray


def diagnosis_split(
    logs: Sequence[LogLike], params: VehicleParams, block_s: float | None = None
) -> DiagnosisSplit:
    """The frame and the split :func:`diagnose` works on, for a caller that needs the same.

    The one place where the diagnosis turns logs into its frame and halves: the case
    tolerance from the encoder noise, the frame, the time-block (or run) split, and the
    samples no model of the logged speeds can predict left out of both halves.
    ``benchmarks/borealtc_mixes.py`` measures its ceilings on this split, so that they are the
    diagnosis's and cannot drift from it.

    Parameters
    ----------
    logs : sequence of Log
        Runs, already checked (:func:`~ecoplan.diagnose.checks.check_logs`).
    params : TrackedParams or WheeledParams
        The vehicle.
    block_s : float, optional
        Time-block length for the split [s].

    Returns
    -------
    DiagnosisSplit
        Parameters with the logs' case tolerance, the frame and the halves.
    """
    tol = case_tolerance(logs)
    if tol > params.case_tol_mps:
        params = _with_case_tol(params, tol)
    frame = build_frame(logs, params, block_s, snap_mps=params.case_tol_mps)
    train_m, test_m = split_masks(frame)
    stops = unresolved_stops(frame, params)
    return DiagnosisSplit(params, frame, train_m & ~stops, test_m & ~stops, stops)


def diagnose(
    logs: Sequence[LogLike] | LogLike,
    vehicle_name: str | VehicleParams,
    terrain: str | None = None,
    *,
    effects: Sequence[str] | None = None,
    rng: RngLike = 0,
    block_s: float | None = None,
) -> Diagnosis:
    """Diagnose the gap between logged runs and the model of a vehicle.

    Parameters
    ----------
    logs : Log or sequence of Log
        Runs (anything with ``t``, ``v_left``, ``v_right``, ``p_total`` arrays and the optional
        columns of the log format).
    vehicle_name : str or TrackedParams or WheeledParams
        Vehicle preset name, or parameters directly.
    terrain : str, optional
        Terrain preset (ignored when parameters are given).
    effects : sequence of str, optional
        Candidates to try (default: the whole library).
    rng : Generator, int or None
        Randomness of the bootstrap (default seed 0: reproducible reports).
    block_s : float, optional
        Time-block length for splits and bootstrap [s].

    Returns
    -------
    Diagnosis
        The full result.
    """
    gen = _rng(rng)
    if isinstance(vehicle_name, str):
        params = vehicle(vehicle_name, terrain)
        name = vehicle_name
    else:
        # the vehicle file's stable name (a corrected model names its base vehicle by it);
        # parameters built by hand keep their own label
        params = vehicle_name
        name = params.source.name if params.source is not None else params.name
    log_list: list[LogLike] = [logs] if hasattr(logs, "t") else list(logs)  # type: ignore[list-item]
    checked = check_logs(log_list, params)
    # a reading repeated on the rows until the next lags the other columns: power and speeds
    # at the rows where their readings arrive, pose and wz interpolated between them
    log_list = [fresh_readings(lg) if isinstance(lg, Log) else lg for lg in log_list]
    split = diagnosis_split(log_list, params, block_s)
    params, frame, train_m, test_m, stops = (
        split.params,
        split.frame,
        split.train,
        split.test,
        split.stops,
    )
    n_train, n_test = int(np.count_nonzero(train_m)), int(np.count_nonzero(test_m))
    if n_train < 20 or n_test < 20:
        span = float(np.sum(frame.dt))
        raise InputError(
            f"{sources(log_list)}: log too short to "
            f"diagnose: {span:.3g} s in column 't' gives {n_train} training and {n_test} "
            "held-out samples in alternating time blocks of at least 5 s (need 20 each); "
            "log at least 10 s of driving (or is 't' in minutes? expected seconds)"
        )
    replay = replay_residuals(
        frame, params.power(frame.vl, frame.vr).total_w, params.accel_max_mps2
    )
    train_f, test_f = frame.subset(train_m), frame.subset(test_m)
    # the friction law, where identified, is held against the effects first (law_rival)
    base = calibrate_and_attribute(train_f, test_f, params, gen, effects)
    cal, train, test, att = base.calibration, base.train, base.test, base.attribution
    run_ids = [str(getattr(lg, "run_id", "") or f"run{i}") for i, lg in enumerate(log_list)]
    p_cal = np.asarray(cal.params.power(frame.vl, frame.vr).total_w)
    r_all = frame.p - p_cal
    # the vehicle file's terrains, as the log shows them (power_log: battery or motor current)
    known = known_terrains(params)
    known_w = [logged_power_w(m, frame.vl, frame.vr) for m in segmentation_models(params)]
    segments = where_time(frame.t, r_all, frame.run, run_ids, model_w=p_cal, known_w=known_w)
    labels, label_mae, cal_mae = _terrain_labels(known, segments, frame, run_ids, r_all)
    # effects the log cannot resolve at a physical size: said, never ruled out (issue 12 item 3)
    unresolved = tuple(r.note for r in effect_resolution(train) if not r.resolved)
    input_notes = checked.excitation_notes + unresolved
    if input_notes and att.verdict == "none":
        # a log that does not excite an effect cannot rule it out (issue 12 item 3)
        att = dataclasses.replace(att, confidence=min(att.confidence, 0.5))
    r_cal = test.p - att.fitted["none"].predict(test)
    gap_cal = float(np.mean(np.abs(r_cal)))
    # the calibrated parameters' own held-out gap (test.base_w is their power), which the
    # base refitted beside the effects (gap_cal, their common baseline) need not equal
    gap_params = float(np.mean(np.abs(test.p - test.base_w)))
    final_name = final_effect_name(att)  # a lag changes no power at the measured speeds
    final = att.fitted[final_name]
    refit = base.refit  # a kept law refitted with the effect predicts at its own exponent
    on = refit.test if refit is not None and refit.effect == final_name else test
    r_fin = on.p - final.predict(on)
    _, lo, hi, _ = block_bootstrap(r_cal, r_fin, test_f.block.astype(np.float64), gen)
    dropped = int(sum(int(getattr(lg, "dropped_rows", 0) or 0) for lg in log_list))
    log_notes: list[str] = []
    if stops.any():
        log_notes.append(settling_note(int(np.count_nonzero(stops)), frame.n))
    if frame.pose_per_run and frame.x is not None:
        log_notes.append(POSE_PER_RUN_NOTE)
    for lg in log_list:
        notes = list(getattr(lg, "notes", ()) or ())
        if power_is_interval_mean(lg):
            notes.append(INTERVAL_MEAN_NOTE)
        for note in notes:
            if note not in log_notes:
                log_notes.append(str(note))
    return Diagnosis(
        vehicle=name,
        terrain=terrain,
        preset=params,
        calibration=cal,
        replay=replay,
        gap_preset_w=float(np.mean(np.abs(replay.power_w[test_m]))),
        gap_calibrated_w=gap_cal,
        gap_calibrated_params_w=gap_params,
        gap_final_w=float(np.mean(np.abs(r_fin))),
        final_ci_w=(lo, hi),
        where=by_regime(test_f, r_cal, cal.params),
        time_profile=over_time(test_f, r_cal),
        space_map=over_space(test_f, r_cal),
        attribution=att,
        test_frame=test_f,
        residual_calibrated_w=r_cal,
        prediction_final_w=test.p - r_fin,
        test_mask=test_m,
        dropped_rows=dropped,
        n_runs=len(log_list),
        duration_s=frame.duration_s,
        split="time blocks",
        input_notes=input_notes,
        log_notes=tuple(log_notes),
        where_time=segments,
        run_ids=tuple(run_ids),
        where_time_terrain=labels,
        where_time_terrain_mae_w=label_mae,
        where_time_calibrated_mae_w=cal_mae,
        all_t_s=frame.t,
        all_run=frame.run,
        all_residual_w=r_all,
    )
