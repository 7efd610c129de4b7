"""The report of a scenario run: figures, CSV logs, a markdown page and JSON.

Used by ``ecoplan run``, ``simulate`` and ``compare``.  Every report folder holds

* ``map.png`` -- bounds, obstacles (with their footprint inflation), terrain regions,
  the planned route (dashed, waypoints marked) and the simulated path coloured by the
  electrical power ``P_T`` (one panel per case when comparing, one colour scale);
* ``power.png`` -- ``P_T`` and the cumulative energy over time (with the battery's
  usable energy when the scenario has a budget);
* ``breakdown.png`` -- energy by component (tracked paper eqs. 14-20: friction,
  resistance, power-up, braking, non-regenerated, electrical loss);
* ``<case>.csv`` -- every simulated step in the diagnosis log format (plus ``terrain``
  and the breakdown), ``summary.csv`` -- one row per case;
* ``report.md`` -- the numbers and the figures, with a side-by-side table when comparing.

Output folders are never overwritten silently: see :mod:`ecoplan.app.outdir`.
"""

from __future__ import annotations

import csv
import json
from collections.abc import Callable, Sequence
from pathlib import Path
from typing import TYPE_CHECKING, Any

from ecoplan.app.outdir import OutDir, case_file_names
from ecoplan.app.reports.caselog import case_log
from ecoplan.app.reports.figures import plot_breakdown, plot_map, plot_power
from ecoplan.app.reports.tables import (
    COMPONENT_LABELS,
    SUMMARY_COLUMNS,
    breakdown_components,
    summary_row,
    summary_table,
)
from ecoplan.io.logcsv import write_log_csv

if TYPE_CHECKING:
    from ecoplan.app.run import CaseResult
    from ecoplan.app.scenario import Scenario

__all__ = ["write_report"]


#: The power model behind a vehicle's parameters (a wheeled robot may use the contact model).
_MODEL = {
    "tracked": "contact-friction power model, tracked paper",
    "wheeled": "radius-fit power model, wheeled paper",
}


def write_report(
    sc: Scenario,
    results: Sequence[CaseResult],
    out: OutDir,
    *,
    force: bool = False,
    title: str | None = None,
    executor: str | None = None,
) -> list[Path]:
    """Write figures, CSV, JSON and ``report.md`` of one or more cases into ``out``.

    Parameters
    ----------
    sc : Scenario
        The scenario the cases come from.
    results : sequence of CaseResult
        The cases, in the order to show.
    out : OutDir
        Folder from :func:`ecoplan.app.outdir.prepare_out_dir`.
    force : bool
        Overwrite files ecoplan did not write.
    title : str, optional
        Heading of the markdown page.
    executor : str, optional
        Where the cases ran (for the page).

    Returns
    -------
    list of Path
        Every file written (the manifest excluded).
    """
    import matplotlib

    matplotlib.use("Agg")
    import matplotlib.pyplot as plt

    opts = sc.spec.outputs
    simulated = [r for r in results if r.sim is not None]
    fig_names = [f"{stem}.{ext}" for stem in ("map", "power", "breakdown") for ext in opts.figures]
    names = ["summary.json", "summary.csv", *fig_names]
    csv_names = dict(
        zip((id(r) for r in results), case_file_names([r.name for r in results]), strict=True)
    )
    if opts.csv:
        names += [csv_names[id(r)] for r in simulated]
    if opts.markdown:
        names.append("report.md")
    out.claim(names, force=force)

    figures: dict[str, list[Path]] = {}
    makers: dict[str, Callable[[], Any]] = {"map": lambda: plot_map(sc, results)}
    if simulated:
        makers["power"] = lambda: plot_power(sc, simulated)
        makers["breakdown"] = lambda: plot_breakdown(sc, simulated)
    for stem, make in makers.items():
        fig = make()
        try:
            for ext in opts.figures:
                path = out.file(f"{stem}.{ext}")
                fig.savefig(path, dpi=130)
                figures.setdefault(stem, []).append(path)
        finally:
            plt.close(fig)
    summaries = [
        {**r.summary(), "log_file": csv_names[id(r)] if opts.csv and r.sim else None}
        for r in results
    ]
    payload = {"scenario": sc.name, "source": sc.source, "cases": summaries}
    out.file("summary.json").write_text(json.dumps(payload, indent=1, default=float) + "\n")
    with out.file("summary.csv").open("w", newline="") as fh:
        w = csv.DictWriter(fh, fieldnames=list(SUMMARY_COLUMNS))
        w.writeheader()
        for r in results:
            w.writerow(summary_row(r))
    if opts.csv:
        for r in simulated:
            write_log_csv(case_log(r), out.file(csv_names[id(r)]), overwrite=True)
    if opts.markdown:
        md = _markdown(sc, results, figures, title=title, executor=executor)
        out.file("report.md").write_text(md)
    return out.finish()


def _markdown(
    sc: Scenario,
    results: Sequence[CaseResult],
    figures: dict[str, list[Path]],
    *,
    title: str | None,
    executor: str | None,
) -> str:
    spec = sc.spec
    lines = [f"# {title or sc.name}", ""]
    if spec.description:
        lines += [spec.description.strip(), ""]
    regions = ", ".join(f"{name} ({terr})" for name, terr, _ in sc.regions) or "none"
    lines += [
        f"- scenario file: `{sc.source}`",
        f"- vehicle: `{sc.params.name}` ({_MODEL[sc.params.kind]})",
        f"- terrain: {sc.default_terrain}; regions: {regions}",
        f"- obstacles: {len(sc.obstacles)} (inflated by {spec.map.inflation_m:g} m)",
        f"- controller: G = {spec.controller.gain:g} 1/s, d_th = {spec.controller.d_th_m:g} m; "
        f"simulation step {spec.simulation.dt_s:g} s",
    ]
    if executor:
        lines.append(f"- cases ran on: {executor}")
    lines.append("")
    single = len(results) == 1
    if not single:  # the comparison first, the details of each case after the figures
        lines += ["## Side by side", "", summary_table(results), ""]
    else:
        lines += _case_markdown(results[0], single=True)
    for stem, caption in (
        ("map", "Map: planned routes (dashed) and simulated paths coloured by power"),
        ("power", "Power and cumulative energy over time"),
        ("breakdown", "Energy by component"),
    ):
        if stem in figures:
            lines += [f"![{caption}]({figures[stem][0].name})", "", f"*{caption}.*", ""]
    if not single:
        for r in results:
            lines += _case_markdown(r, single=False)
    return "\n".join(lines)


def _case_markdown(r: CaseResult, *, single: bool) -> list[str]:
    lines = [f"## {r.name}" if not single else "## Result", ""]
    if r.error is not None:
        return [*lines, f"No route: {r.error}", ""]
    lines.append(
        f"Route from `{r.plan.planner}` with {len(r.plan.waypoints)} points "
        f"({r.plan.length_m:.1f} m planned) at v_sp = {r.plan.speed_mps:g} m/s"
        + (f", planned in {r.plan.planning_time_s:.2f} s." if r.plan.planning_time_s else ".")
    )
    if r.plan.estimate_energy_j is not None:
        lines.append(
            f"Analytic energy of the route (ecoplan.energy.path.path_cost): "
            f"{r.plan.estimate_energy_j / 1e3:.2f} kJ."
        )
    if r.sim is None:
        return [*lines, ""]
    s = r.sim
    status = "reached the goal" if s.completed else "hit the time limit before the goal"
    lines += [
        "",
        f"Simulated: the vehicle {status} after **{s.time_s:.1f} s** and {s.length_m:.1f} m, "
        f"turning ψ = {s.psi_rad:.2f} rad, using **{r.energy_j / 1e3:.2f} kJ** "
        f"({r.energy_j / 3600:.2f} Wh; mean {r.energy_j / max(s.time_s, 1e-9):.0f} W, "
        f"peak {r.peak_power_w:.0f} W).",
        "",
        "| component | energy [kJ] | share |",
        "|---|---|---|",
    ]
    for comp in breakdown_components(r.breakdown_j):
        e = r.breakdown_j[comp]
        share = 100.0 * e / r.energy_j if r.energy_j else 0.0
        lines.append(f"| {COMPONENT_LABELS.get(comp, comp)} | {e / 1e3:.2f} | {share:.1f} % |")
    if r.violation_s:
        what = ", ".join(f"{k} for {v:.2f} s" for k, v in r.violation_s.items())
        lines += ["", f"**Limits.** The simulated commands violate {what}."]
    else:
        lines += ["", "**Limits.** Every simulated command respects the vehicle's limits."]
    if r.clearance_violation_s > 0:
        lines.append(
            f"The path comes closer than the footprint inflation to an obstacle or the map "
            f"edge for {r.clearance_violation_s:.1f} s."
        )
    if r.plan.violations:
        lines.append(f"Analytic plan: {'; '.join(r.plan.violations[:3])}.")
    if r.battery is not None:
        lines += ["", f"**Battery.** {r.battery.sentence()}"]
    return [*lines, ""]
