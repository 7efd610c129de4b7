"""The diagnosis entry point: replay, calibrate, localise, attribute, report (issue 6).

>>> from ecoplan.diagnose.pipeline import diagnose  # doctest: +SKIP
>>> d = diagnose(logs, "auriga-beta-wide", "asphalt")  # doctest: +SKIP
>>> print(d.summary())  # doctest: +SKIP

Steps, each in its module:

1. :mod:`~ecoplan.diagnose.replay` — the preset's power model on the measured side speeds and the
   kinematics on the commanded ones: residuals of power, energy, yaw rate, speed and pose;
2. :mod:`~ecoplan.diagnose.calibrate` — the base model's own parameters re-identified on the
   training split; the held-out gap it closes is reported apart;
3. :mod:`~ecoplan.diagnose.localise` — where the calibrated model's held-out gap lies;
4. :mod:`~ecoplan.diagnose.attribute` — which candidate effect explains what is left, whether
   the log can tell the candidates apart, and how far the gap shrinks;
5. :mod:`~ecoplan.diagnose.report` — text, plots and JSON; :mod:`~ecoplan.diagnose.loop` —
   the corrected model written to a file.
"""

from __future__ import annotations

import dataclasses
import json
import math
import sys
from collections.abc import Mapping, Sequence
from dataclasses import dataclass, field
from pathlib import Path
from typing import TYPE_CHECKING, Any

import numpy as np

from ecoplan._typing import BoolArray, FloatArray, IntArray, RngLike
from ecoplan.diagnose.attribute import Attribution, attribute, block_bootstrap, split_masks
from ecoplan.diagnose.calibrate import Calibration, calibrate
from ecoplan.diagnose.checks import check_logs
from ecoplan.diagnose.effects import EffectData, prepare
from ecoplan.diagnose.localise import (
    RegimeShare,
    SpaceMap,
    TimeProfile,
    by_regime,
    over_space,
    over_time,
)
from ecoplan.diagnose.replay import (
    Frame,
    LogLike,
    ReplayResiduals,
    build_frame,
    case_tolerance,
    replay_residuals,
)
from ecoplan.diagnose.where_time import TimeSegment, where_time
from ecoplan.errors import InputError
from ecoplan.presets import VehicleParams, vehicle

if TYPE_CHECKING:
    from ecoplan.diagnose.loop import Route

__all__ = ["Diagnosis", "diagnose", "run_diagnose_cli"]


@dataclass(frozen=True, slots=True)
class Diagnosis:
    """Everything the diagnosis found (see :mod:`ecoplan.diagnose.report` for its outputs).

    Attributes
    ----------
    vehicle : str
        Preset name.
    terrain : str or None
        Terrain preset.
    preset : TrackedParams or WheeledParams
        Preset parameters as given.
    calibration : Calibration
        Calibrated parameters (fitted on the training split).
    replay : ReplayResiduals
        Residuals of the preset model on all samples.
    gap_preset_w : float
        Held-out MAE of the preset model [W].
    gap_calibrated_w : float
        Held-out MAE of the calibrated model [W].
    gap_final_w : float
        Held-out MAE of the final model (calibrated plus the verdict's effect) [W].
    final_ci_w : tuple of float
        95 % block-bootstrap interval of the final model's reduction of the calibrated gap [W].
    where : list of RegimeShare
        Error share against time share of the calibrated model on the held-out split.
    time_profile : TimeProfile
        Calibrated residual per block (held-out split).
    space_map : SpaceMap or None
        Map of the calibrated residual (held-out split), when pose is logged.
    attribution : Attribution
        Ranked candidates and verdict.
    test_frame : Frame
        The held-out samples.
    residual_calibrated_w : ndarray
        Held-out residual of the calibrated model [W].
    prediction_final_w : ndarray
        Held-out power predicted by the final model [W].
    test_mask : ndarray of bool
        Held-out samples among all the logs' rows (concatenated in order).
    dropped_rows : int
        Rows the log reader dropped for a missing optional value (summed over logs).
    n_runs : int
        Number of logs.
    duration_s : float
        Total logged time [s].
    split : str
        How the held-out split was drawn (``"time blocks"``).
    input_notes : tuple of str
        What the input check found the log does not excite (:mod:`ecoplan.diagnose.checks`).
    log_notes : tuple of str
        The readers' notes on the logs (assumptions such as the bus voltage, ignored columns,
        dropped rows), each once.
    where_time : list of TimeSegment
        Stretches of the runs, on each log's own time, where the calibrated model's residual
        (all samples) changes level (:mod:`ecoplan.diagnose.where_time`).
    run_ids : tuple of str
        Identifier of every run, in order.
    all_t_s, all_run, all_residual_w : ndarray
        Every sample's time on its log's clock [s], run index and calibrated residual [W].
    """

    vehicle: str
    terrain: str | None
    preset: VehicleParams
    calibration: Calibration
    replay: ReplayResiduals
    gap_preset_w: float
    gap_calibrated_w: float
    gap_final_w: float
    final_ci_w: tuple[float, float]
    where: list[RegimeShare]
    time_profile: TimeProfile
    space_map: SpaceMap | None
    attribution: Attribution
    test_frame: Frame = field(repr=False)
    residual_calibrated_w: FloatArray = field(repr=False)
    prediction_final_w: FloatArray = field(repr=False, default_factory=lambda: np.zeros(0))
    test_mask: BoolArray = field(repr=False, default_factory=lambda: np.zeros(0, dtype=bool))
    dropped_rows: int = 0
    n_runs: int = 1
    duration_s: float = 0.0
    split: str = "blocks"
    input_notes: tuple[str, ...] = ()
    log_notes: tuple[str, ...] = ()
    where_time: list[TimeSegment] = field(default_factory=list)
    run_ids: tuple[str, ...] = ()
    all_t_s: FloatArray = field(repr=False, default_factory=lambda: np.zeros(0))
    all_run: IntArray = field(repr=False, default_factory=lambda: np.zeros(0, dtype=np.int64))
    all_residual_w: FloatArray = field(repr=False, default_factory=lambda: np.zeros(0))

    @property
    def verdict(self) -> str:
        """An effect name, ``none``, ``unexplained`` or ``ambiguous``."""
        return self.attribution.verdict

    def to_json_dict(self) -> dict[str, Any]:
        """The stable JSON shape (see :func:`ecoplan.diagnose.report.to_json_dict`)."""
        from ecoplan.diagnose.report import to_json_dict

        return to_json_dict(self)

    def summary(self) -> str:
        """Plain-text summary (see :func:`ecoplan.diagnose.report.summary`)."""
        from ecoplan.diagnose.report import summary

        return summary(self)


def _rng(rng: RngLike) -> np.random.Generator:
    return rng if isinstance(rng, np.random.Generator) else np.random.default_rng(rng)


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
        params, name = vehicle_name, vehicle_name.name
    log_list: list[LogLike] = [logs] if hasattr(logs, "t") else list(logs)  # type: ignore[list-item]
    checked = check_logs(log_list, params)
    tol = case_tolerance(log_list)
    if tol > params.case_tol_mps:
        params = dataclasses.replace(params, case_tol_mps=tol)
    frame = build_frame(log_list, params, block_s, snap_mps=params.case_tol_mps)
    train_m, test_m = split_masks(frame)
    if np.count_nonzero(train_m) < 20 or np.count_nonzero(test_m) < 20:
        raise InputError("log too short to diagnose: need at least 40 samples after the split")
    replay = replay_residuals(
        frame, params.power(frame.vl, frame.vr).total_w, params.accel_max_mps2
    )
    train_f, test_f = frame.subset(train_m), frame.subset(test_m)
    cal = calibrate(train_f, params)
    run_ids = [str(getattr(lg, "run_id", "") or f"run{i}") for i, lg in enumerate(log_list)]
    p_cal = np.asarray(cal.params.power(frame.vl, frame.vr).total_w)
    r_all = frame.p - p_cal
    segments = where_time(frame.t, r_all, frame.run, run_ids, model_w=p_cal)
    train = prepare(train_f, cal.params, prior=params)
    test = prepare(test_f, cal.params, prior=params)
    att = attribute(train, test, gen, effects)
    if checked.excitation_notes and att.verdict == "none":
        # a log that does not excite turning cannot rule out turning effects (issue 12 item 3)
        att = dataclasses.replace(att, confidence=min(att.confidence, 0.5))
    r_cal = test.p - att.fitted["none"].predict(test)
    gap_cal = float(np.mean(np.abs(r_cal)))
    final_name = att.tied[0] if att.verdict == "ambiguous" and att.tied else att.verdict
    if final_name == "actuator_lag" or final_name not in att.fitted:
        final_name = "none"  # a lag changes no power at the measured speeds
    final = att.fitted[final_name]
    r_fin = test.p - final.predict(test)
    _, lo, hi, _ = block_bootstrap(r_cal, r_fin, test_f.block.astype(np.float64), gen)
    dropped = int(sum(int(getattr(lg, "dropped_rows", 0) or 0) for lg in log_list))
    log_notes: list[str] = []
    for lg in log_list:
        for note in getattr(lg, "notes", ()) or ():
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
        input_notes=checked.excitation_notes,
        log_notes=tuple(log_notes),
        where_time=segments,
        run_ids=tuple(run_ids),
        all_t_s=frame.t,
        all_run=frame.run,
        all_residual_w=r_all,
    )


def _effect_data(d: Diagnosis) -> EffectData:
    return prepare(d.test_frame, d.calibration.params, prior=d.preset)


def run_diagnose_cli(
    log_paths: list[str],
    vehicle: str,
    terrain: str | None,
    json_path: str | None,
    out_dir: str | None,
    *,
    topics_path: str | None = None,
    bus_voltage_v: float = 24.0,
    routes: Mapping[str, Route] | None = None,
) -> int:
    """Back end of ``ecoplan diagnose LOG [LOG ...] --vehicle PRESET [--terrain PRESET]``.

    Reads the logs, prints the text summary, writes the JSON (``--json FILE``; ``--json -``
    prints it on stdout and the text on stderr) and the figures, ``report.md``, ``where_time``
    CSV and corrected model (``--out``).  Bad input raises :class:`~ecoplan.errors.InputError`
    subclasses (exit code 2 in the CLI).

    ``topics_path`` is the topic map of ROS 2 bags (``--topics``), ``bus_voltage_v`` the bus
    voltage assumed for BorealTC runs (``--bus-voltage``).  With ``routes`` (candidate routes of
    a scenario, ``--scenario``) the energy ranking of the routes under the preset and under the
    corrected model is printed (:func:`ecoplan.diagnose.loop.ranking_change`), added to the JSON
    as the extra key ``ranking`` and written to ``ranking.json`` in ``out_dir``.

    Returns
    -------
    int
        Exit code (0).
    """
    from ecoplan.diagnose.loop import corrected_model, ranking_change, save_corrected_model
    from ecoplan.diagnose.report import json_report, save_figures, save_where_time, write_json
    from ecoplan.diagnose.report_md import write_report_md
    from ecoplan.io.logs import read_logs
    from ecoplan.io.rosbag import load_topic_map

    if not log_paths:
        raise InputError("no log file given")
    if not (math.isfinite(bus_voltage_v) and bus_voltage_v > 0.0):
        raise InputError(f"--bus-voltage must be a positive number of volts, got {bus_voltage_v}")
    topic_map = load_topic_map(topics_path) if topics_path is not None else None
    logs = read_logs(log_paths, topic_map=topic_map, bus_voltage_v=bus_voltage_v)
    if vehicle.endswith((".yaml", ".yml")) or Path(vehicle).is_file():  # a vehicle file
        from ecoplan.io.vehicles import load_vehicle

        d = diagnose(logs, load_vehicle(vehicle).params(terrain), terrain)
    else:
        d = diagnose(logs, vehicle, terrain)
    # with --json - the JSON is the only thing on stdout; the text goes to stderr
    text = sys.stderr if json_path == "-" else sys.stdout
    print(d.summary(), file=text)
    extra: dict[str, Any] = {}
    if routes is not None:
        rc = ranking_change(routes, corrected_model(d))
        print("route ranking under the preset and the corrected model:", file=text)
        print(rc.summary(), file=text)
        extra["ranking"] = {
            "routes": [
                {"name": n, "energy_preset_j": float(eb), "energy_corrected_j": float(ec)}
                for n, eb, ec in zip(rc.names, rc.energy_base_j, rc.energy_corrected_j, strict=True)
            ],
            "rank_preset": rc.rank_base,
            "rank_corrected": rc.rank_corrected,
            "changed": rc.changed,
            "best_changed": rc.best_changed,
        }
    if json_path == "-":
        print(json.dumps(json_report(d, extra), indent=2))
    elif json_path is not None:
        write_json(d, json_path, extra)
    if out_dir is not None:
        out = Path(out_dir)
        out.mkdir(parents=True, exist_ok=True)
        write_json(d, out / "diagnosis.json", extra)
        if "ranking" in extra:
            (out / "ranking.json").write_text(json.dumps(extra["ranking"], indent=2))
        for p in [*save_figures(d, out), *save_where_time(d, out)]:
            print(f"figure: {p}", file=text)
        path = save_corrected_model(d, out / "corrected_model.json")
        print(f"corrected model: {path}", file=text)
        print(f"report: {write_report_md(d, out / 'report.md', extra)}", file=text)
    return 0
