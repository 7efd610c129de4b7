"""Diagnosis report: text summary, figures and JSON with a stable shape.

JSON shape (stable; the four first keys are the contract of issue 6)::

    {"gap": {"metric": "mae_w", "before": float, "after": float},
     "where": [{"regime": str, "error_share": float, "time_share": float}, ...],
     "effects": [{"name": str, "before": float, "after": float, "params": {...}}, ...],
     "verdict": {"effect": str, "confidence": float},
     ...extra keys below}

* ``gap.before`` is the held-out MAE of the preset model as given, ``gap.after`` that of the
  final model (the base model refitted with the verdict's effect; alone without one or for
  ``actuator_lag``) [W].
* ``where`` lists every regime of :mod:`ecoplan.diagnose.localise` (``group:name``) for the
  held-out residual of the effects' baseline (the base refitted without an effect,
  ``how_far.before_w``).
* ``effects`` are ranked best first; ``before``/``after`` are the held-out power MAE without and
  with the effect [W] (for ``actuator_lag``: of the power the model predicts from the commands);
  ``params`` are the fitted physical parameters (non-finite values written as null).
* ``verdict.effect`` is an effect name, ``none``, ``unexplained`` or ``ambiguous``.

Extra top-level keys (documented, optional for readers): ``calibration`` (held-out MAE before
and after re-identifying the base parameters, and the changed parameters; ``refit_after``, the
held-out MAE of the base model refitted beside the effects without one, the baseline of
``how_far``, see :func:`refit_baseline_note`), ``how_far`` (the
winner's held-out reduction in W and %, its 95 % bootstrap interval, the best pair), ``channels``
(each effect's deciding channel, its reduction and p-value), ``distinguishability`` (pairs the
log cannot tell apart with the separating manoeuvre, candidates not excited or unavailable),
``where_time`` (segments of each run where the calibrated model's residual changes level,
on the log's own time: ``[{"run", "t_start_s", "t_end_s", "excess_w"}]``, exactly these
keys), ``where_time_terrain`` (the most likely terrain of each of those segments among the
vehicle preset's terrains, in the same order; empty when the vehicle has one terrain or was
given as parameters), ``naming`` (the explanations outside the library the verdict's
effect had to beat, :mod:`ecoplan.diagnose.naming`: ``{"reason", "alternatives": [{"name",
"after", "p_value", "params", "halves_note"}], "halves"}``, ``reason`` the one line on why an
effect was not named, empty when none was overruled; ``halves_note`` why the halves of the
split do not find the same step in time (the step is then set aside), else empty;
``halves`` the named power-channel effect's parameters fitted on each half of the split,
``{"effect", "agree", "p_value", "note", "params": [{"name",
"train", "train_ci", "test", "test_ci", "agree"}]}`` with 95 % intervals, null when no such
effect was named), ``tied`` (names of an ambiguous verdict), ``log`` (runs,
duration, dropped rows, split, the readers' ``notes`` -- assumptions such as the bus voltage,
ignored columns -- and the input check's ``input_notes``) and,
with ``ecoplan diagnose --scenario``, ``ranking`` (route energies under the preset and the
corrected model, both rankings, whether the order or the best route changes).
"""

from __future__ import annotations

import json
import math
import os
from pathlib import Path
from typing import TYPE_CHECKING, Any, Literal

import numpy as np
from pydantic import BaseModel, ConfigDict, Field, ValidationError

from ecoplan.diagnose.text import watts, why_not_tried
from ecoplan.errors import InputError
from ecoplan.io.yaml import LineMap, format_validation

if TYPE_CHECKING:
    from ecoplan.diagnose.naming import HalvesCheck
    from ecoplan.diagnose.result import Diagnosis

__all__ = [
    "BASELINE_DIFF_SHARE",
    "JSON_KEYS",
    "DiagnosisJSON",
    "baseline_differs",
    "json_report",
    "refit_baseline_note",
    "save_figures",
    "save_where_time",
    "summary",
    "to_json_dict",
    "validate_json",
    "write_json",
]

#: The contract keys of the JSON report, in order.
JSON_KEYS: tuple[str, ...] = ("gap", "where", "effects", "verdict")


def _num(x: float) -> float | None:
    x = float(x)
    return x if math.isfinite(x) else None


def _halves_json(h: HalvesCheck | None) -> dict[str, Any] | None:
    if h is None:
        return None
    return {
        "effect": h.effect,
        "agree": h.agree,
        "p_value": _num(h.p_value),
        "note": h.note,
        "params": [
            {
                "name": p.name,
                "train": _num(p.train),
                "train_ci": [_num(v) for v in p.interval("train")],
                "test": _num(p.test),
                "test_ci": [_num(v) for v in p.interval("test")],
                "agree": p.agree,
            }
            for p in h.params
        ],
    }


def to_json_dict(d: Diagnosis) -> dict[str, Any]:
    """The diagnosis as a JSON-ready dictionary (see the module docstring for the shape)."""
    att = d.attribution
    effects = [
        {
            "name": s.name,
            "before": _num(s.power_before_w),
            "after": _num(s.power_after_w),
            "params": {k: _num(v) for k, v in s.params.items()},
        }
        for s in att.scores
    ]
    red = d.gap_calibrated_w - d.gap_final_w
    return {
        "gap": {"metric": "mae_w", "before": _num(d.gap_preset_w), "after": _num(d.gap_final_w)},
        "where": [
            {
                "regime": w.regime,
                "error_share": _num(w.error_share),
                "time_share": _num(w.time_share),
            }
            for w in d.where
        ],
        "effects": effects,
        "verdict": {"effect": att.verdict, "confidence": _num(att.confidence)},
        "calibration": {
            "before": _num(d.gap_preset_w),
            "after": _num(d.gap_calibrated_params_w),
            "changed": {k: [_num(a), _num(b)] for k, (a, b) in d.calibration.changed.items()},
            "refit_after": _num(d.gap_calibrated_w),
        },
        "how_far": {
            "before_w": _num(d.gap_calibrated_w),
            "after_w": _num(d.gap_final_w),
            "reduction_w": _num(red),
            "reduction_pct": _num(100.0 * red / d.gap_calibrated_w if d.gap_calibrated_w else 0.0),
            "ci95_w": [_num(d.final_ci_w[0]), _num(d.final_ci_w[1])],
            "noise_floor_w": _num(att.noise_floor_w),
            "pair": list(att.pair) if att.pair else None,
            "pair_after_w": _num(att.pair_after_w) if att.pair_after_w is not None else None,
            "ljung_box_p": _num(att.ljung_box_p),
        },
        "channels": [
            {
                "name": s.name,
                "channel": s.channel,
                "before": _num(s.before),
                "after": _num(s.after),
                "p_value": _num(s.p_value),
                "explained": _num(s.explained),
                "significant": bool(s.significant),
            }
            for s in att.scores
        ],
        "distinguishability": {
            "pairs": [
                {"names": [a, b], "correlation": _num(c), "separating_manoeuvre": m}
                for a, b, c, m in att.indistinguishable
            ],
            "not_excited": list(att.not_excited),
            "unavailable": list(att.unavailable),
        },
        "where_time": [seg.to_json() for seg in d.where_time],
        "where_time_terrain": list(d.where_time_terrain),
        "naming": {
            "reason": att.reason,
            "alternatives": [
                {
                    "name": a.name,
                    "after": _num(a.after_w),
                    "p_value": _num(a.p_value),
                    "params": {k: _num(v) for k, v in a.params.items()},
                    "halves_note": a.halves_note,
                }
                for a in att.alternatives
            ],
            "halves": _halves_json(att.halves),
        },
        "tied": list(att.tied),
        "log": {
            "runs": d.n_runs,
            "duration_s": _num(d.duration_s),
            "dropped_rows": d.dropped_rows,
            "split": d.split,
            "notes": list(d.log_notes),
            "input_notes": list(d.input_notes),
        },
    }


class _Strict(BaseModel):
    model_config = ConfigDict(extra="forbid", strict=True, allow_inf_nan=False, frozen=True)


class _Gap(_Strict):
    metric: Literal["mae_w"]
    before: float
    after: float


class _Where(_Strict):
    regime: str
    error_share: float
    time_share: float


class _Effect(_Strict):
    name: str
    before: float
    after: float
    params: dict[str, Any]


class _Verdict(_Strict):
    effect: str
    confidence: float = Field(ge=0.0, le=1.0)


class _WhereTime(_Strict):
    run: str
    t_start_s: float
    t_end_s: float
    excess_w: float


class DiagnosisJSON(BaseModel):
    """Schema of the diagnosis JSON (pydantic): the contract keys, exact, and ``where_time``.

    The four contract keys (:data:`JSON_KEYS`) and their entries have exactly the keys of the
    module docstring; numbers are finite JSON numbers (not booleans, not null).  The other
    documented top-level keys are allowed and not checked here, except ``where_time``, whose
    segments have exactly ``run``, ``t_start_s``, ``t_end_s`` and ``excess_w``.

    Examples
    --------
    >>> DiagnosisJSON.model_validate(
    ...     {"gap": {"metric": "mae_w", "before": 9.0, "after": 4.5}, "where": [],
    ...      "effects": [], "verdict": {"effect": "none", "confidence": 0.5}}
    ... ).verdict.confidence
    0.5
    """

    model_config = ConfigDict(extra="allow", strict=True, allow_inf_nan=False, frozen=True)

    gap: _Gap
    where: list[_Where]
    effects: list[_Effect]
    verdict: _Verdict
    where_time: list[_WhereTime] = []


def validate_json(obj: Any) -> None:
    """Check a diagnosis JSON object against :class:`DiagnosisJSON`.

    Parameters
    ----------
    obj : Any
        The parsed JSON (a dict).

    Raises
    ------
    InputError
        One line naming the first broken field, e.g.
        ``diagnosis JSON: verdict.confidence: expected a number <= 1.0; got 1.5``.
    """
    try:
        DiagnosisJSON.model_validate(obj)
    except ValidationError as exc:
        raise InputError(
            format_validation(exc, "diagnosis JSON", LineMap(), DiagnosisJSON)
        ) from None


def json_report(d: Diagnosis, extra: dict[str, Any] | None = None) -> dict[str, Any]:
    """:func:`to_json_dict` plus ``extra`` top-level keys, validated."""
    obj = to_json_dict(d)
    if extra:
        clash = set(extra) & set(obj)
        if clash:
            raise InputError(f"diagnosis JSON: extra keys {sorted(clash)} clash with report keys")
        obj.update(extra)
    validate_json(obj)
    return obj


def write_json(
    d: Diagnosis, path: str | os.PathLike[str], extra: dict[str, Any] | None = None
) -> Path:
    """Write :func:`json_report` to ``path``."""
    obj = json_report(d, extra)
    p = Path(path)
    p.parent.mkdir(parents=True, exist_ok=True)
    p.write_text(json.dumps(obj, indent=2))
    return p


#: The base refitted beside the effects and the calibrated parameters are reported apart
#: when their held-out gaps differ by more than this share (:func:`baseline_differs`).
BASELINE_DIFF_SHARE = 0.01


def baseline_differs(d: Diagnosis) -> bool:
    """Whether the effects' baseline and the calibrated parameters are reported apart.

    True when their held-out gaps (``gap_calibrated_w``, ``gap_calibrated_params_w``) differ
    by more than :data:`BASELINE_DIFF_SHARE` of the calibrated one; the summary's line
    (:func:`refit_baseline_note`) and ``report.md``'s row both follow it.
    """
    cal = d.gap_calibrated_params_w
    return abs(d.gap_calibrated_w - cal) > BASELINE_DIFF_SHARE * max(cal, 1e-12)


def refit_baseline_note(d: Diagnosis) -> str:
    """One line on the effects' baseline when it is not the calibrated model ('' when it is).

    Every candidate effect refits the base model's linear coefficients with its own columns, and
    is measured against the refit without an effect (``gap_calibrated_w``).  Those refits keep
    calibration's physical bounds but only a thousandth of its pull towards the preset (wheeled;
    none tracked, :func:`~ecoplan.diagnose.effects.fitting.fit_linear`), so on a log far from
    the preset's family the baseline fits better than the parameters calibration lists: on the
    BorealTC FLOORING runs (``benchmarks/real_data_diagnosis.py``) 42.0 W held out against their
    55.9 W.  Until session 22 the report called the baseline's gap "calibrated", next to
    parameters that did not reach it (and the wheeled baseline was not bounded: 36.2 W, with a
    straight-line power falling to -30 W at 0.5 m/s).  The line gives both gaps when they differ
    (:func:`baseline_differs`).
    """
    if not baseline_differs(d):
        return ""
    cal, ref = d.gap_calibrated_params_w, d.gap_calibrated_w
    return (
        f"baseline of the effects: the base model refitted beside them on the training half "
        f"(calibration's bounds, a far weaker pull towards the preset), {watts(ref)} held out "
        f"against the calibrated parameters' {watts(cal)}; 'how far' and the final gap are "
        "measured on it; the corrected model (--out) holds the calibrated parameters, or with "
        "a named effect (other than a lag) the base refitted with it"
    )


def summary(d: Diagnosis) -> str:
    """Plain-text summary: gap, calibration, where, which, how far, what the log cannot tell."""
    att = d.attribution
    lines = [
        f"Diagnosis of {d.n_runs} log(s), {d.duration_s:.0f} s, against {d.preset.name} "
        f"(held-out split by {d.split}; {d.dropped_rows} row(s) dropped by the reader)",
        f"gap (held-out MAE): preset {watts(d.gap_preset_w)} -> calibrated "
        f"{watts(d.gap_calibrated_params_w)} -> final {watts(d.gap_final_w)} "
        f"(noise floor ~{watts(att.noise_floor_w)})",
    ]
    baseline = refit_baseline_note(d)
    rp = d.replay
    parts = [
        f"energy error per run {100 * float(np.mean(np.abs(rp.run_energy_error))):.1f} % "
        "(mean |E_meas - E_model| / E_meas)"
    ]
    if rp.yaw_rate_radps is not None:
        parts.append(f"yaw rate MAE {float(np.mean(np.abs(rp.yaw_rate_radps))):.3f} rad/s")
    if rp.speed_mps is not None:
        parts.append(f"command tracking MAE {float(np.mean(np.abs(rp.speed_mps))):.3f} m/s")
    if rp.pose_m is not None:
        parts.append(f"dead-reckoned pose off by up to {float(np.max(rp.pose_m)):.2f} m")
    lines.append("replay of the preset: " + "; ".join(parts))
    if d.calibration.changed:
        ch = ", ".join(f"{k} {a:.3g}->{b:.3g}" for k, (a, b) in d.calibration.changed.items())
        closes = watts(d.gap_preset_w - d.gap_calibrated_params_w)
        lines.append(f"calibration closes {closes}: {ch}")
    if baseline:
        lines.append(baseline)
    top = sorted(d.where, key=lambda w: -(w.error_share - w.time_share))[:4]
    lines.append("where (error share vs time share, most over-represented first):")
    for w in top:
        lines.append(
            f"  {w.regime:24s} {100 * w.error_share:5.1f} % of |error| in "
            f"{100 * w.time_share:5.1f} % of time (MAE {watts(w.mae_w)})"
        )
    lines.append("which (held-out, ranked):")
    for s in att.scores[:6]:
        unit = "W" if s.channel == "power_w" else "m/s"
        star = "*" if s.significant else " "
        lines.append(
            f" {star}{s.name:28s} {s.reduction_pct:6.1f} % of {s.channel} "
            f"({s.before:.3g} -> {s.after:.3g} {unit}, p={s.p_value:.2g}) "
            f"power {watts(s.power_before_w)} -> {watts(s.power_after_w)}"
        )
    verdict = att.verdict + (f" ({' / '.join(att.tied)})" if att.tied else "")
    lines.append(f"verdict: {verdict}  confidence {att.confidence:.2f}")
    red = d.gap_calibrated_w - d.gap_final_w
    pct = 100.0 * red / d.gap_calibrated_w if d.gap_calibrated_w else 0.0
    lines.append(
        f"how far: {watts(d.gap_calibrated_w)} -> {watts(d.gap_final_w)} ({pct:.1f} %, 95 % CI "
        f"of the reduction {watts(d.final_ci_w[0])} .. {watts(d.final_ci_w[1])})"
        + (
            f"; best pair {'+'.join(att.pair)}: {watts(att.pair_after_w)}"
            if att.pair and att.pair_after_w is not None
            else ""
        )
    )
    lines.append(f"residual whiteness after the verdict (Ljung-Box): p = {att.ljung_box_p:.2g}")
    if att.reason:
        lines.append(f"not named: {att.reason}")
    held = {sc.name: sc.reduction_pct for sc in att.scores}
    for a, b, c, m in att.indistinguishable:
        line = f"look alike on this log: {a} / {b} (canonical corr {c:.2f}); to separate: {m}"
        if att.verdict in (a, b) and a in held and b in held:
            # the shapes correlate, but the fits with physical bounds (m >= 0, delay >= 0, ...)
            # did separate them held-out: say so rather than contradict the verdict
            line += f" -- held out: {a} {held[a]:.1f} %, {b} {held[b]:.1f} %"
        lines.append(line)
    if att.not_excited:
        lines.append(f"not excited by this log: {', '.join(att.not_excited)}")
    if att.unavailable:
        lines.append(
            "not tried: " + "; ".join(f"{n} -- {why_not_tried(n)}" for n in att.unavailable)
        )
    if d.where_time:
        lines.append(
            "where in time (log's own clock; residual level minus the session's, in standard "
            "errors of the stretch's mean):"
        )
        for seg in d.where_time[:12]:
            z = seg.excess_z
            lines.append(
                f"  {seg.run:24s} {seg.t_start_s:9.2f} .. {seg.t_end_s:9.2f} s  "
                f"{watts(seg.excess_w, signed=True):>10s}"
                + ("" if math.isnan(z) else f"  {z:+6.1f} SE")
            )
        if len(d.where_time) > 12:
            lines.append(f"  ... {len(d.where_time) - 12} more in where_time.csv / the JSON")
    lines.extend(f"input: {note}" for note in d.input_notes)
    lines.extend(f"log: {note}" for note in d.log_notes)
    return "\n".join(lines)


_CASE_COLOURS = ("#999999", "#1f77b4", "#2ca02c", "#ff7f0e", "#d62728")


LABEL_MIN_SHARE = 0.025
"""Narrowest segment of ``where_time.png`` that gets its text, as a share of its run's span.

Segments narrower than :data:`LABEL_ROW_SHARE` alternate between two rows of text, so that
neighbours' labels do not run into each other.
"""
LABEL_ROW_SHARE = 0.08
"""Segments narrower than this share of their run's span (a label's width on a 9 in panel)
take alternate rows of text."""


def save_where_time(d: Diagnosis, out_dir: str | os.PathLike[str]) -> list[Path]:
    """``where_time.csv`` and ``where_time.png``: the residual over each log's own time axis.

    One panel per run (at most eight: the runs with segments first), the calibrated model's
    residual averaged over 1 s bins, the change-point segments shaded (red: the robot draws
    more than the model, blue: less, grey: a level within two standard errors of the
    session's) with their excess in W and, when the preset describes several terrains, each
    segment's most likely one.  Only segments wide enough for their text are labelled (at
    least :data:`LABEL_MIN_SHARE` of the run's span, narrow neighbours on alternate rows; the
    panel's title says how many are not): an hour-long run with two hundred segments stays
    legible, and the CSV has them all.
    """
    import matplotlib

    matplotlib.use("Agg")
    import matplotlib.pyplot as plt

    from ecoplan.diagnose.where_time import write_where_time_csv

    out = Path(out_dir)
    out.mkdir(parents=True, exist_ok=True)
    paths = [write_where_time_csv(d.where_time, out / "where_time.csv")]
    if d.all_t_s.size == 0:
        return paths
    with_segs = [i for i, rid in enumerate(d.run_ids) if any(s.run == rid for s in d.where_time)]
    others = [i for i in range(len(d.run_ids)) if i not in with_segs]
    shown = (with_segs + others)[:8]
    fig, axes = plt.subplots(len(shown), 1, figsize=(9, 1.9 * len(shown) + 0.6), squeeze=False)
    for ax, i in zip(axes[:, 0], shown, strict=True):
        idx = d.all_run == i
        t, r = d.all_t_s[idx], d.all_residual_w[idx]
        k = np.floor(t - t[0]).astype(np.int64)
        cnt = np.bincount(k)
        ok = cnt > 0
        ax.plot(t, r, color="#cccccc", lw=0.5, label="residual")
        ax.plot(
            t[0] + np.arange(cnt.size)[ok] + 0.5,
            np.bincount(k, weights=r)[ok] / cnt[ok],
            color="k",
            lw=1.0,
            label="1 s mean",
        )
        rid = d.run_ids[i]
        labels = d.where_time_terrain or ("",) * len(d.where_time)
        span_s = float(t[-1] - t[0])
        min_label_s = LABEL_MIN_SHARE * span_s
        unlabelled, lower = 0, False
        for seg, lab in zip(d.where_time, labels, strict=False):
            if seg.run != rid:
                continue
            quiet = abs(seg.excess_z) < 2.0
            colour = "#999999" if quiet else ("#d62728" if seg.excess_w > 0 else "#1f77b4")
            ax.axvspan(seg.t_start_s, seg.t_end_s, color=colour, alpha=0.15)
            width = seg.t_end_s - seg.t_start_s
            if width < min_label_s:
                unlabelled += 1
                continue
            lower = width < LABEL_ROW_SHARE * span_s and not lower  # narrow: alternate rows
            excess = watts(seg.excess_w, signed=True)
            ax.text(
                0.5 * (seg.t_start_s + seg.t_end_s),
                0.76 if lower else 0.95,
                f"{excess}\n{lab}" if lab else excess,
                transform=ax.get_xaxis_transform(),
                ha="center",
                va="top",
                fontsize=7,
            )
        ax.axhline(0.0, color="k", lw=0.4)
        ax.set_ylabel("W")
        narrow = (
            f"; {unlabelled} narrow segments unlabelled, see where_time.csv" if unlabelled else ""
        )
        ax.set_title(
            f"{rid}: measured - calibrated model (grey: level within 2 SE of the session's)"
            + narrow,
            fontsize=8,
            loc="left",
        )
    axes[-1, 0].set_xlabel("time on the log's own clock [s]")
    axes[0, 0].legend(loc="lower right", fontsize=7)
    fig.tight_layout()
    fig.savefig(out / "where_time.png", dpi=110)
    plt.close(fig)
    paths.append(out / "where_time.png")
    return paths


def save_figures(d: Diagnosis, out_dir: str | os.PathLike[str]) -> list[Path]:
    """Residual over time by regime, candidates' bar chart, where chart and residual map (PNG)."""
    import matplotlib

    matplotlib.use("Agg")
    import matplotlib.pyplot as plt

    from ecoplan.models.power import MotionCase, motion_case

    out = Path(out_dir)
    out.mkdir(parents=True, exist_ok=True)
    paths: list[Path] = []
    f = d.test_frame
    r = d.residual_calibrated_w
    clock = np.cumsum(f.dt) - f.dt
    case = motion_case(f.vl, f.vr, d.calibration.params.case_tol_mps)
    fig, ax = plt.subplots(figsize=(10, 3.8))
    for c in MotionCase:
        m = case == int(c)
        if np.any(m):
            ax.plot(
                clock[m],
                r[m],
                ".",
                ms=1.5,
                color=_CASE_COLOURS[int(c)],
                label=f"case {int(c)} {c.name.lower()}",
            )
    tp = d.time_profile
    ax.plot(tp.t_s, tp.mean_w, "k-", lw=1.0, label="block mean")
    ax.axhline(0.0, color="k", lw=0.5)
    if r.size:
        lo, hi = np.quantile(r, [0.002, 0.998])
        pad = 0.25 * max(hi - lo, 1e-6)
        ax.set_ylim(lo - pad, hi + pad)  # a few outliers would flatten the rest
    ax.set_xlabel("held-out time (runs concatenated) [s]")
    ax.set_ylabel("measured - base refit (effects' baseline) [W]")
    ax.set_title("Power residual over time, coloured by motion case (Fig. 3)")
    ax.legend(loc="upper right", fontsize=7, markerscale=6, ncol=3)
    fig.tight_layout()
    paths.append(out / "residual_time.png")
    fig.savefig(paths[-1], dpi=120)
    plt.close(fig)

    att = d.attribution
    fig, ax = plt.subplots(figsize=(8, 4))
    names = [s.name for s in att.scores]
    vals = [s.reduction_pct for s in att.scores]
    err = (
        np.array(
            [
                [
                    s.reduction_pct - 100 * s.ci_low / s.before if s.before else 0.0,
                    100 * s.ci_high / s.before - s.reduction_pct if s.before else 0.0,
                ]
                for s in att.scores
            ]
        ).T
        if att.scores
        else np.zeros((2, 0))
    )
    colours = [
        "#2ca02c" if s.name == att.verdict else ("#1f77b4" if s.significant else "#bbbbbb")
        for s in att.scores
    ]
    y = np.arange(len(names))
    ax.barh(y, vals, xerr=np.abs(err), color=colours, capsize=3)
    ax.set_yticks(
        y, [f"{n} [{s.channel}]" for n, s in zip(names, att.scores, strict=True)], fontsize=8
    )
    ax.invert_yaxis()
    ax.axvline(0.0, color="k", lw=0.5)
    ax.set_xlabel("held-out reduction of the residual [%] (95 % block-bootstrap CI)")
    ax.set_title(
        f"Candidate effects — verdict: {att.verdict}\n"
        "(green: verdict, blue: significant, grey: not)",
        fontsize=10,
    )
    fig.tight_layout()
    paths.append(out / "candidates.png")
    fig.savefig(paths[-1], dpi=120)
    plt.close(fig)

    fig, ax = plt.subplots(figsize=(8, 5))
    regs = [w.regime for w in d.where]
    yy = np.arange(len(regs))
    ax.barh(yy - 0.2, [100 * w.error_share for w in d.where], 0.4, label="share of |energy error|")
    ax.barh(yy + 0.2, [100 * w.time_share for w in d.where], 0.4, label="share of time")
    ax.set_yticks(yy, regs, fontsize=7)
    ax.invert_yaxis()
    ax.set_xlabel("[%]")
    ax.set_title("Where the base refit's gap lies (held-out; the effects' baseline)")
    ax.legend(fontsize=8)
    fig.tight_layout()
    paths.append(out / "where.png")
    fig.savefig(paths[-1], dpi=120)
    plt.close(fig)

    if d.space_map is not None:
        sm = d.space_map
        # size the figure to the map's aspect ratio (long thin A->B lots stay readable)
        span_x = float(sm.x_edges[-1] - sm.x_edges[0])
        span_y = float(sm.y_edges[-1] - sm.y_edges[0])
        aspect = min(max(span_y / max(span_x, 1e-9), 0.2), 2.0)
        fig, ax = plt.subplots(figsize=(9.0, max(2.8, 7.5 * aspect + 1.2)))
        lim = float(np.nanmax(np.abs(sm.mean_w))) if np.any(np.isfinite(sm.mean_w)) else 1.0
        mesh = ax.pcolormesh(
            sm.x_edges, sm.y_edges, sm.mean_w.T, cmap="RdBu_r", vmin=-lim, vmax=lim, shading="flat"
        )
        fig.colorbar(mesh, ax=ax, label="mean residual [W]", fraction=0.04, pad=0.02)
        ax.set_aspect("equal")
        ax.set_xlabel("x [m]")
        ax.set_ylabel("y [m]")
        ax.set_title("Residual map (held-out, base refit: the effects' baseline)")
        fig.tight_layout()
        paths.append(out / "residual_map.png")
        fig.savefig(paths[-1], dpi=120)
        plt.close(fig)
    return paths
