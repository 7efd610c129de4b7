"""The result of a diagnosis: what :func:`ecoplan.diagnose.pipeline.diagnose` returns.

A plain record.  Its renderings live apart, so that nothing here imports them:
:mod:`ecoplan.diagnose.report` (text summary, JSON, figures), :mod:`ecoplan.diagnose.report_md`
(``report.md``) and :mod:`ecoplan.diagnose.corrected` (the corrected model).
"""

from __future__ import annotations

from dataclasses import dataclass, field

import numpy as np

from ecoplan._typing import BoolArray, FloatArray, IntArray
from ecoplan.diagnose.attribute import Attribution
from ecoplan.diagnose.calibrate import Calibration
from ecoplan.diagnose.localise import RegimeShare, SpaceMap, TimeProfile
from ecoplan.diagnose.replay import Frame, ReplayResiduals
from ecoplan.diagnose.where_time import TimeSegment
from ecoplan.presets import VehicleParams

__all__ = ["Diagnosis"]


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
        Held-out MAE of the base model refitted on the training split beside the effects, with
        no effect (the ``none`` candidate): the baseline every effect's reduction and the final
        gap are measured against [W].  It keeps calibration's physical bounds
        (:func:`~ecoplan.diagnose.effects.fitting.base_bounds`) but not calibration's pull
        towards the preset (a thousandth of it wheeled, none tracked), so it can differ from
        ``gap_calibrated_params_w``.
    gap_calibrated_params_w : float
        Held-out MAE of the calibrated parameters themselves (``calibration.params``, within
        their physical bounds) [W].
    gap_final_w : float
        Held-out MAE of the final model: the base refitted with the verdict's effect (without
        one, or for ``actuator_lag``, the refit of ``gap_calibrated_w``) [W].
    final_ci_w : tuple of float
        95 % block-bootstrap interval of the final model's reduction of the calibrated gap [W].
    where : list of RegimeShare
        Error share against time share of the effects' baseline (``gap_calibrated_w``) on the
        held-out split.
    time_profile : TimeProfile
        The baseline's residual per block (held-out split).
    space_map : SpaceMap or None
        Map of the baseline's residual (held-out split), when pose is logged.
    attribution : Attribution
        Ranked candidates and verdict.
    test_frame : Frame
        The held-out samples.
    residual_calibrated_w : ndarray
        Held-out residual of the effects' baseline (``gap_calibrated_w``) [W].
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
    where_time_terrain : tuple of str
        The most likely known terrain of each ``where_time`` segment, when the vehicle preset
        describes several (:func:`ecoplan.diagnose.where_time.label_segments`); else empty.
    where_time_terrain_mae_w, where_time_calibrated_mae_w : tuple of float
        Per labelled segment, the mean absolute error of the labelled terrain's model (as the
        vehicle file gives it) and of the calibrated model [W]: a label whose model misses
        its stretch by far more than the calibrated model names the least wrong of the
        file's models, not the ground.
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
    gap_calibrated_params_w: float
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
    where_time_terrain: tuple[str, ...] = ()
    where_time_terrain_mae_w: tuple[float, ...] = ()
    where_time_calibrated_mae_w: tuple[float, ...] = ()
    all_t_s: FloatArray = field(repr=False, default_factory=lambda: np.zeros(0))
    all_run: IntArray = field(repr=False, default_factory=lambda: np.zeros(0, dtype=np.int64))
    all_residual_w: FloatArray = field(repr=False, default_factory=lambda: np.zeros(0))

    @property
    def verdict(self) -> str:
        """An effect name, ``none``, ``unexplained`` or ``ambiguous``."""
        return self.attribution.verdict
