"""``report.md``: the diagnosis for people (issue 12, item 8).

What was found, what each number means, where in time, what the log could not tell, what to do
next (the manoeuvre that separates two look-alike effects, the signal that is missing) and the
input's stated assumptions (the bus voltage of current-only logs, ignored columns, dropped rows).
"""

from __future__ import annotations

import math
import os
from pathlib import Path
from typing import TYPE_CHECKING, Any

from ecoplan.diagnose.report import baseline_differs
from ecoplan.diagnose.text import watts, why_not_tried

if TYPE_CHECKING:
    from ecoplan.diagnose.result import Diagnosis

__all__ = ["report_markdown", "write_report_md"]

_VERDICT_MEANING = {
    "none": "the calibrated base model explains the logs down to the sensor noise; no "
    "candidate effect closes a significant part of what is left",
    "unexplained": "a gap is left that is larger than the noise and that no candidate of the "
    "library closes well enough (>= 80 % of it above the noise floor): something outside the "
    "library, or a mixture",
    "ambiguous": "two candidates close the gap equally well and this log cannot tell them apart",
}


def _f(x: float, unit: str = "", nd: int = 1) -> str:
    if unit == "W":
        return watts(x)
    return f"{x:.{nd}f}{(' ' + unit) if unit else ''}"


#: A terrain label whose model's MAE on its stretch exceeds this many times the calibrated
#: model's is said to name the least wrong of the file's models, not the ground.
LABEL_OFF_FACTOR = 2.0


def _label_ratios(d: Diagnosis) -> list[float]:
    """Per ``where_time`` segment, its label's model MAE over the calibrated model's (nan: none)."""
    pairs = zip(d.where_time_terrain_mae_w, d.where_time_calibrated_mae_w, strict=False)
    ratios = [lab / cal if cal > 0.0 else math.nan for lab, cal in pairs]
    return ratios + [math.nan] * (len(d.where_time) - len(ratios))


def _untold(d: Diagnosis) -> list[str]:
    """For a ``none``: the effects this log cannot rule out (too little excitation, below noise)."""
    if d.attribution.verdict != "none":
        return []
    untold = [n for n in d.input_notes if n.startswith(("too little excitation", "below noise"))]
    if not untold:
        return []
    return [
        "`none` does not rule out what this log cannot tell (too little excitation or below "
        "noise to tell, listed under *What to do next*); the confidence is at most 0.5.",
        "",
    ]


def _friction_law(d: Diagnosis) -> list[str]:
    """Where a friction law was identified: whether it was kept, and the two held-out MAEs."""
    law = next((a for a in d.attribution.alternatives if a.name == "friction_law"), None)
    if law is None:
        return []
    n = law.params.get("slip_exponent", float("nan"))
    coulomb = law.params.get("coulomb_after_w", float("nan"))
    kept = law.params.get("kept", 0.0) == 1.0
    choice = (
        "**kept** as base-model structure (`slip_exponent` above): the law explains the log "
        "better than any effect on Coulomb friction"
        if kept
        else "**not kept**: Coulomb friction with the best effect explains the log better, so "
        "the diagnosis stands on Coulomb friction"
    )
    refit = law.params.get("refit_exponent")
    if kept and refit is not None:
        choice += (
            f"; refitted jointly with the named effect on the training split, the exponent "
            f"is n = {refit:.2f}, which the final and corrected models carry"
        )
    under = (
        " once the strongest candidate effect is fitted with it (on the base model alone, "
        "that effect's power hid the law's shape)"
        if law.params.get("identified_under_effect", 0.0) == 1.0
        else ""
    )
    return [
        "## Friction law",
        "",
        f"The training split shows friction growing with slip speed{under}, µ (s / s_ref)^n with "
        f"n = {n:.2f}, rather than Coulomb's constant µ (Morales et al. 2009, eq. 8). Best "
        f"held-out MAE on each base: with the law {_f(law.after_w, 'W')}, with Coulomb "
        f"{_f(coulomb, 'W')}. The law was {choice}.",
        "",
    ]


def _baseline_row(d: Diagnosis) -> list[str]:
    """The row of the effects' baseline when it is not the calibrated model.

    Shown when :func:`~ecoplan.diagnose.report.baseline_differs`, as the summary's line
    (:func:`~ecoplan.diagnose.report.refit_baseline_note`) is.
    """
    if not baseline_differs(d):
        return []
    return [
        f"| gap of the effects' baseline | {_f(d.gap_calibrated_w, 'W')} | the base model "
        "refitted on the training split beside the effects, without one (calibration's "
        "physical bounds, a far weaker pull towards the preset): what the reduction and the final "
        "gap are measured on; the corrected model holds the calibrated parameters (with a "
        "named effect other than a lag, the base refitted with it) |"
    ]


def _heading_origin(d: Diagnosis) -> list[str]:
    """Where a slope's uphill heading is counted from, when not from one world frame."""
    halves = d.attribution.halves
    f = d.test_frame
    if halves is None or halves.effect != "slope" or not f.heading_per_run:
        return []
    first = d.run_ids[0] if d.run_ids else "the first run"
    searched = (
        "; every other run's was searched as an offset, from a plane fitted to each run alone"
    )
    if f.yaw is not None:
        if d.n_runs < 2:
            return []
        return [
            f"Each run's pose in its own frame: `uphill_heading_rad` is counted from the x axis "
            f"of run `{first}`'s frame (counter-clockwise){searched}.",
            "",
        ]
    if d.n_runs > 1:
        return [
            f"No pose: `uphill_heading_rad` is counted from the heading run `{first}` started "
            f"in (counter-clockwise){searched}.",
            "",
        ]
    return [
        "No pose: `uphill_heading_rad` is counted from the heading the run started in "
        "(counter-clockwise).",
        "",
    ]


def report_markdown(d: Diagnosis, extra: dict[str, Any] | None = None) -> str:
    """The Markdown text of ``report.md`` for a diagnosis."""
    att = d.attribution
    verdict = att.verdict + (f" ({' / '.join(att.tied)})" if att.tied else "")
    red = d.gap_calibrated_w - d.gap_final_w
    pct = 100.0 * red / d.gap_calibrated_w if d.gap_calibrated_w else 0.0
    out: list[str] = [f"# Diagnosis: {d.preset.name}", ""]
    out += [
        "## What was found",
        "",
        f"**Verdict: `{verdict}`**, confidence {att.confidence:.2f}.",
        "",
        _VERDICT_MEANING.get(
            att.verdict,
            f"the effect `{att.verdict}` closes the gap the calibrated model leaves, better than "
            "every other candidate and significantly on held-out data",
        )
        + ".",
        "",
        "Confidence is one minus the (Bonferroni-corrected) p-value of the deciding test: for an "
        "effect, that its held-out reduction of the gap is not chance; for `unexplained`, that "
        "the residual is not white noise.",
        "",
    ]
    if att.reason:
        out += [f"Not named: {att.reason}.", ""]
    if att.halves is not None and att.halves.params:
        out += [
            f"`{att.halves.effect}` fitted on each half of the split (95 % intervals; the "
            "name stands only if they overlap):",
            "",
            "| parameter | training half | held-out half | agree |",
            "|---|---|---|---|",
        ]
        for p in att.halves.params:
            (a0, a1), (b0, b1) = p.interval("train"), p.interval("test")
            out.append(
                f"| `{p.name}` | {p.train:.4g} [{a0:.4g}, {a1:.4g}] | "
                f"{p.test:.4g} [{b0:.4g}, {b1:.4g}] | {'yes' if p.agree else 'no'} |"
            )
        out += ["", *_heading_origin(d)]
    out += [
        *_untold(d),
        "## The numbers",
        "",
        "| quantity | value | meaning |",
        "|---|---|---|",
        f"| gap of the preset | {_f(d.gap_preset_w, 'W')} | held-out mean absolute error of the "
        "preset's power model on the measured side speeds |",
        f"| gap after calibration | {_f(d.gap_calibrated_params_w, 'W')} | the same after "
        "re-identifying the base model's own parameters on the training split (the table "
        "under *Calibration*) |",
        *_baseline_row(d),
        f"| gap of the final model | {_f(d.gap_final_w, 'W')} | the base model refitted with "
        "the verdict's effect (without one, or for a lag, which changes no power at the measured "
        "speeds: the base refitted alone) |",
        f"| reduction by the effect | {_f(red, 'W')} ({pct:.1f} %) | 95 % block-bootstrap "
        f"interval {_f(d.final_ci_w[0], 'W')} .. {_f(d.final_ci_w[1], 'W')} |",
        f"| noise floor | {_f(att.noise_floor_w, 'W')} | the error the power sensor's noise alone "
        "would leave (coloured, from lag-1 and lag-2 differences; at most the gap) |",
        f"| residual whiteness | p = {att.ljung_box_p:.2g} | Ljung-Box test after the verdict "
        "(small: structure is left) |",
        "",
        f"Data: {d.n_runs} run(s), {d.duration_s:.0f} s; held out by {d.split}; "
        f"{d.dropped_rows} row(s) dropped by the reader.",
        "",
    ]
    if d.calibration.changed:
        out += ["## Calibration (base-model parameters re-identified)", ""]
        out += ["| parameter | preset | calibrated |", "|---|---|---|"]
        for k, (a, b) in d.calibration.changed.items():
            out.append(f"| `{k}` | {a:.4g} | {b:.4g} |")
        out += [
            "",
            "Calibration is constrained to physics (resistance >= 0, straight power "
            "non-decreasing with speed, a(r), b(r) monotone as in the wheeled paper).",
            "",
        ]
    out += _friction_law(d)
    out += ["## Where", "", "Regimes where the error share exceeds the time share:", ""]
    top = sorted(d.where, key=lambda w: -(w.error_share - w.time_share))[:5]
    out += ["| regime | share of error | share of time | MAE |", "|---|---|---|---|"]
    for w in top:
        out.append(
            f"| {w.regime} | {100 * w.error_share:.1f} % | {100 * w.time_share:.1f} % | "
            f"{_f(w.mae_w, 'W')} |"
        )
    out += [""]
    if d.where_time:
        out += [
            "In each log's own time (`where_time.csv`, `where_time.png`): stretches where the "
            "calibrated residual changes level or ripple, or (with a vehicle file's terrains) "
            "where the power moves between the known terrains' levels; excess = the stretch's "
            "mean residual minus the session's (positive: the robot draws more than the "
            "model), and the same in standard errors of that mean (the scatter of the run's "
            "1 s means).",
            "",
            "| run | from [s] | to [s] | excess | excess / SE | likely terrain | its model's "
            "MAE / calibrated |",
            "|---|---|---|---|---|---|---|",
        ]
        labels = d.where_time_terrain or ("-",) * len(d.where_time)
        ratios = _label_ratios(d)
        for seg, lab, ratio in zip(d.where_time[:30], labels, ratios, strict=False):
            z = seg.excess_z
            out.append(
                f"| {seg.run} | {seg.t_start_s:.2f} | {seg.t_end_s:.2f} "
                f"| {watts(seg.excess_w, signed=True)} | {'-' if math.isnan(z) else f'{z:+.1f}'} "
                f"| {lab} | {'-' if math.isnan(ratio) else f'{ratio:.2f}'} |"
            )
        off = sum(r > LABEL_OFF_FACTOR for r in ratios)  # nan compares false
        if off:
            out += [
                "",
                f"{off} of these labels come from a terrain model that misses its stretch by "
                f"more than {LABEL_OFF_FACTOR:g} times what the calibrated model misses: the "
                "vehicle file's models do not describe this robot there, so such a label names "
                "the least wrong of them, not the ground.",
            ]
        quiet = sum(abs(s.excess_z) < 2.0 for s in d.where_time)
        if quiet:
            out += [
                "",
                f"{quiet} of these {len(d.where_time)} stretches have a level within two "
                "standard errors of the session's: their level does not depart significantly "
                "(they were cut where the ripple, a known terrain's level or a neighbour's "
                "level changed).",
            ]
        out += [""]
    out += ["## Candidates (held out, best first)", ""]
    out += ["| effect | reduction | significant | parameters |", "|---|---|---|---|"]
    for s in att.scores[:8]:
        shown = ", ".join(f"{k} = {v:.3g}" for k, v in list(s.params.items())[:5])
        out.append(
            f"| {s.name} | {s.reduction_pct:.1f} % of {s.channel} | "
            f"{'yes' if s.significant else 'no'} | {shown} |"
        )
    out += ["", "## What to do next", ""]
    todo: list[str] = []
    for e1, e2, c, m in att.indistinguishable:
        todo.append(f"`{e1}` and `{e2}` look alike on this log (correlation {c:.2f}): drive {m}.")
    if att.verdict == "terrain_change":
        # friction and resistance both scale with the weight: a load added or removed is the
        # same step in power (only the inertia of the accelerations differs), and so, nearly,
        # is a power meter whose gain changed
        todo.append(
            "Before reading `terrain_change` as ground: a load added or removed at the "
            "segments' boundaries (`where_time.csv`) steps friction and resistance alike, "
            "and a power meter whose gain changed looks nearly the same; check what changed "
            "at those times."
        )
    for note in d.input_notes:
        todo.append(note[0].upper() + note[1:] + ".")
    if att.not_excited:
        todo.append(
            "Not excited by this log (cannot be confirmed or ruled out): "
            + ", ".join(f"`{n}`" for n in att.not_excited)
            + "."
        )
    for n in att.unavailable:
        todo.append(f"`{n}` could not be tried: {why_not_tried(n)}.")
    if att.verdict == "unexplained":
        todo.append(
            "Look at `where_time.png`: a stretch with a large excess is where to look for the "
            "cause (a terrain, a payload, a fault)."
        )
    if not todo:
        todo.append("Nothing: the log separates every candidate it excites.")
    out += [f"- {t}" for t in todo]
    out += ["", "## Input and assumptions", ""]
    notes = list(d.log_notes) or ["no reader notes"]
    out += [f"- {n}" for n in notes]
    if extra and "ranking" in extra:
        rk = extra["ranking"]
        out += ["", "## Route ranking", ""]
        out.append(
            f"Preset order {rk['rank_preset']}, corrected-model order {rk['rank_corrected']}; "
            f"best route changed: {rk['best_changed']}."
        )
    return "\n".join(out) + "\n"


def write_report_md(
    d: Diagnosis, path: str | os.PathLike[str], extra: dict[str, Any] | None = None
) -> Path:
    """Write :func:`report_markdown` to ``path``; returns the path."""
    p = Path(path)
    p.parent.mkdir(parents=True, exist_ok=True)
    p.write_text(report_markdown(d, extra))
    return p
