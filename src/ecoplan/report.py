"""Reports of scenario runs: figures, CSV logs, a markdown page and JSON.

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

Output folders are never overwritten silently: see :func:`prepare_out_dir`.
"""

from __future__ import annotations

import csv
import io
import json
import math
import re
from collections.abc import Callable, Sequence
from dataclasses import dataclass, field
from datetime import UTC, datetime
from pathlib import Path
from typing import TYPE_CHECKING, Any

import numpy as np

from ecoplan.errors import InputError
from ecoplan.models.power import COMPONENTS

if TYPE_CHECKING:
    from ecoplan.app.run import CaseResult
    from ecoplan.app.scenario import Scenario

__all__ = [
    "MANIFEST",
    "TERRAIN_COLOURS",
    "OutDir",
    "plot_breakdown",
    "plot_map",
    "plot_power",
    "prepare_out_dir",
    "slug",
    "summary_table",
    "write_log_csv",
    "write_report",
]

#: Name of the file listing what ecoplan wrote into a report folder.
MANIFEST = ".ecoplan-manifest.json"

#: Fill colour of each terrain preset on the maps.
TERRAIN_COLOURS = {
    "marble": "#e4ebf5",
    "asphalt": "#d9d2c5",
    "vinyl": "#e0efdc",
    "hoisted": "#f5f0d8",
}

_COMPONENT_LABELS = {
    "friction_w": "dynamic friction",
    "resistance_w": "traction resistance",
    "powerup_w": "driver power-up",
    "braking_w": "driver braking",
    "nonregen_w": "non-regenerated",
    "elec_loss_w": "electrical loss",
}
_COMPONENT_COLOURS = {
    "friction_w": "#d62728",
    "resistance_w": "#1f77b4",
    "powerup_w": "#7f7f7f",
    "braking_w": "#9467bd",
    "nonregen_w": "#ff7f0e",
    "elec_loss_w": "#bcbd22",
}


def slug(name: str) -> str:
    """A file-name-safe version of a case name (``*`` reads as ``star``)."""
    s = re.sub(r"[^A-Za-z0-9._-]+", "-", name.replace("*", "star")).strip("-.")
    return s[:80] or "case"


def case_file_names(results: Sequence[CaseResult]) -> list[str]:
    """Names of the cases' CSV logs in a report folder (unique, file-name safe)."""
    return [f"{s}.csv" for s in _unique_slugs([r.name for r in results])]


def _unique_slugs(names: Sequence[str]) -> list[str]:
    out: list[str] = []
    for name in names:
        base = s = slug(name)
        k = 2
        while s in out:
            s = f"{base}-{k}"
            k += 1
        out.append(s)
    return out


# ----------------------------------------------------------------- output folder


@dataclass
class OutDir:
    """A report folder that records what ecoplan writes into it.

    Attributes
    ----------
    path : Path
        The folder.
    written : list of Path
        Files written so far (relative names go to the manifest).
    """

    path: Path
    written: list[Path] = field(default_factory=list)

    def file(self, name: str) -> Path:
        """Path of a file to write (recorded in the manifest)."""
        p = self.path / name
        self.written.append(p)
        return p

    def claim(self, names: Sequence[str], *, force: bool = False) -> None:
        """Refuse (InputError) to replace a file ecoplan did not write, unless ``force``."""
        _check_not_foreign(self, names, force)

    def finish(self) -> list[Path]:
        """Write the manifest; return the files written."""
        manifest = {
            "tool": "ecoplan",
            "written_utc": datetime.now(UTC).isoformat(timespec="seconds"),
            "files": sorted({p.name for p in self.written}),
        }
        (self.path / MANIFEST).write_text(json.dumps(manifest, indent=1) + "\n")
        return list(dict.fromkeys(self.written))


def prepare_out_dir(path: str | Path, *, force: bool = False) -> OutDir:
    """Create or reuse a report folder without overwriting anyone's files silently.

    Policy: a missing or empty folder is created and used.  A folder that ecoplan wrote
    before (it holds :data:`MANIFEST`) is reused, and only the files ecoplan listed there
    may be replaced.  Any other non-empty folder is refused unless ``force`` is true.

    Parameters
    ----------
    path : str or Path
        The folder (``--out``).
    force : bool
        Write into a non-empty folder that ecoplan did not create (``--force``).

    Returns
    -------
    OutDir
        The folder, ready for writing.

    Raises
    ------
    InputError
        The path is a file, or a non-empty foreign folder without ``force``.
    """
    p = Path(path)
    if p.exists() and not p.is_dir():
        raise InputError(f"--out {p}: exists and is not a folder")
    if p.is_dir() and not force:
        entries = {e.name for e in p.iterdir()}
        if entries:
            if _manifest_files(p / MANIFEST) is None:
                raise InputError(
                    f"--out {p}: folder exists and holds files ecoplan did not write; "
                    "choose another folder or pass --force"
                )
    try:
        p.mkdir(parents=True, exist_ok=True)
    except OSError as exc:
        raise InputError(f"--out {p}: cannot create folder: {exc.strerror or exc}") from None
    return OutDir(p)


def _manifest_files(path: Path) -> set[str] | None:
    try:
        data = json.loads(path.read_text())
    except (OSError, ValueError):
        return None
    if not isinstance(data, dict) or data.get("tool") != "ecoplan":
        return None
    files = data.get("files", [])
    return {str(f) for f in files} if isinstance(files, list) else None


def _check_not_foreign(out: OutDir, names: Sequence[str], force: bool) -> None:
    if force:
        return
    ours = _manifest_files(out.path / MANIFEST) or set()
    for name in names:
        if (out.path / name).exists() and name not in ours:
            raise InputError(
                f"--out {out.path}: would overwrite {name}, which ecoplan did not write; "
                "move it or pass --force"
            )


# ------------------------------------------------------------------------- CSV


def write_log_csv(result: CaseResult, path: Path) -> Path:
    """Write a case's simulated steps as CSV in the diagnosis log format.

    Columns: ``t, x, y, yaw, v_left_cmd, v_right_cmd, v_left, v_right, wz, p_total,
    p_left, p_right`` (the log contract), then ``case`` (Fig. 3), the breakdown
    ``p_friction, p_resistance, ...`` [W] and the ``terrain`` label.  Power columns are
    terrain-aware.
    """
    sim = result.sim
    if sim is None:
        raise InputError("this case was not simulated; nothing to write")
    cols: dict[str, Any] = {
        "t": sim.t,
        "x": sim.x,
        "y": sim.y,
        "yaw": sim.yaw,
        "v_left_cmd": sim.v_left_cmd,
        "v_right_cmd": sim.v_right_cmd,
        "v_left": sim.v_left,
        "v_right": sim.v_right,
        "wz": sim.wz,
        "p_total": result.p_total_w,
        "p_left": result.p_left_w,
        "p_right": result.p_right_w,
        "case": sim.case,
    }
    cols.update({f"p_{c.removesuffix('_w')}": result.components_w[c] for c in COMPONENTS})
    data = np.column_stack([np.asarray(v, dtype=np.float64) for v in cols.values()])
    fmt = ["%.10g"] * len(cols)
    fmt[list(cols).index("case")] = "%d"
    buf = io.StringIO()
    np.savetxt(buf, data, fmt=fmt, delimiter=",")
    rows = buf.getvalue().splitlines()
    with path.open("w", newline="") as fh:
        fh.write(",".join([*cols, "terrain"]) + "\n")
        fh.writelines(f"{row},{terr}\n" for row, terr in zip(rows, result.terrain, strict=True))
    return path


_SUMMARY_COLUMNS = (
    "case",
    "planner",
    "waypoints",
    "planned_length_m",
    "speed_mps",
    "planning_time_s",
    "estimate_energy_j",
    "energy_j",
    "time_s",
    "length_m",
    "psi_rad",
    "peak_power_w",
    "mean_power_w",
    "completed",
    "battery_completes",
    "battery_margin_j",
)


def _summary_row(r: CaseResult) -> dict[str, Any]:
    s = r.summary()
    b = s.get("battery") or {}
    return {
        "case": r.name,
        "planner": r.plan.planner,
        "waypoints": len(r.plan.waypoints),
        "planned_length_m": round(r.plan.length_m, 3),
        "speed_mps": r.plan.speed_mps,
        "planning_time_s": round(r.plan.planning_time_s, 4),
        "estimate_energy_j": s.get("estimate_energy_j"),
        "energy_j": s.get("energy_j"),
        "time_s": s.get("time_s"),
        "length_m": s.get("length_m"),
        "psi_rad": s.get("psi_rad"),
        "peak_power_w": s.get("peak_power_w"),
        "mean_power_w": s.get("mean_power_w"),
        "completed": s.get("completed"),
        "battery_completes": b.get("completes"),
        "battery_margin_j": b.get("margin_j"),
    }


def summary_table(results: Sequence[CaseResult]) -> str:
    """Side-by-side markdown table of cases, cheapest first is NOT imposed (case order)."""
    best = min((r.energy_j for r in results if r.sim is not None), default=math.nan)
    head = (
        "| case | planner | waypoints | v_sp [m/s] | length [m] | time [s] | ψ [rad] "
        "| energy [kJ] | vs best | peak [W] | limits |"
    )
    lines = [head, "|" + "---|" * 11]
    for r in results:
        if r.sim is None:
            lines.append(
                f"| {r.name} | {r.plan.planner} | – | – | – | – | – | – | – | – | "
                f"no route: {r.error or 'not simulated'} |"
            )
            continue
        rel = 100.0 * (r.energy_j / best - 1.0) if best > 0 else math.nan
        lines.append(
            f"| {r.name} | {r.plan.planner} | {len(r.plan.waypoints)} | {_speed_cell(r)} | "
            f"{r.sim.length_m:.1f} | {r.sim.time_s:.1f} | {r.sim.psi_rad:.2f} | "
            f"{r.energy_j / 1e3:.2f} | {'best' if rel == 0 else f'+{rel:.1f} %'} | "
            f"{r.peak_power_w:.0f} | {_limits_cell(r)} |"
        )
    return "\n".join(lines)


def _panel_note(r: CaseResult) -> str:
    if r.sim is None:
        est = r.plan.estimate_energy_j
        text = f"planned {r.plan.length_m:.1f} m"
        return text + (f", analytic {est / 1e3:.1f} kJ" if est is not None else "")
    text = f"{r.energy_j / 1e3:.1f} kJ in {r.sim.time_s:.0f} s, ψ {r.sim.psi_rad:.2f} rad"
    if r.battery is not None:
        b = r.battery
        if b.completes:
            text += f"\nbattery: completes, margin {b.margin_j / 3600:.1f} Wh"
        elif b.empty_at is not None:
            text += f"\nbattery: empty after {b.empty_at[0]:.0f} s"
        else:
            text += "\nbattery: goal not reached"
    if r.violation_s:
        text += "\nover limit " + ", ".join(f"{v:.1f} s" for v in r.violation_s.values())
    return text


def _speed_cell(r: CaseResult) -> str:
    v = f"{r.plan.speed_mps:.2f}"
    return f"{v} (optimal)" if r.plan.speed_policy == "optimal" else v


def _limits_cell(r: CaseResult) -> str:
    parts = [f"{name} {sec:.1f} s" for name, sec in r.violation_s.items()]
    if r.clearance_violation_s > 0:
        parts.append(f"clearance {r.clearance_violation_s:.1f} s")
    if r.sim is not None and not r.sim.completed:
        parts.append("time limit")
    return ", ".join(parts) or "ok"


# --------------------------------------------------------------------- figures


def _draw_world(ax: Any, sc: Scenario) -> None:
    from matplotlib.patches import Patch
    from matplotlib.patches import Polygon as MplPolygon

    x0, y0, x1, y1 = sc.bounds.bounds
    default = sc.default_terrain
    ax.set_facecolor(TERRAIN_COLOURS.get(default, "#eeeeee"))
    handles = [Patch(facecolor=TERRAIN_COLOURS.get(default, "#eeeeee"), label=f"{default}")]
    seen = {default}
    for _name, terrain, poly in sc.regions:
        colour = TERRAIN_COLOURS.get(terrain, "#cccccc")
        ax.add_patch(
            MplPolygon(np.asarray(poly.exterior.coords), facecolor=colour, edgecolor="#8c8c8c")
        )
        if terrain not in seen:
            handles.append(Patch(facecolor=colour, edgecolor="#8c8c8c", label=terrain))
            seen.add(terrain)
    for infl in sc.world.inflated_obstacles:
        for part in getattr(infl, "geoms", [infl]):
            ax.add_patch(
                MplPolygon(
                    np.asarray(part.exterior.coords),
                    facecolor="none",
                    edgecolor="#555555",
                    linestyle=":",
                    linewidth=0.8,
                )
            )
    for obs in sc.obstacles:
        ax.add_patch(
            MplPolygon(np.asarray(obs.exterior.coords), facecolor="#3b3b3b", edgecolor="black")
        )
    handles.append(Patch(facecolor="#3b3b3b", label="obstacle"))
    ax.plot([x0, x1, x1, x0, x0], [y0, y0, y1, y1, y0], color="black", linewidth=1.0)
    ax.set_xlim(x0, x1)
    ax.set_ylim(y0, y1)
    ax.set_aspect("equal")
    ax.set_xlabel("x [m]")
    ax.set_ylabel("y [m]")
    ax._ecoplan_handles = handles


def plot_map(sc: Scenario, results: Sequence[CaseResult], *, vmax_w: float | None = None) -> Any:
    """The map with obstacles, terrain regions and each case's paths coloured by power.

    One panel per case (at most 6; more cases are overlaid in one panel).  Returns the
    matplotlib figure.
    """
    import matplotlib.pyplot as plt
    from matplotlib.collections import LineCollection
    from matplotlib.colors import Normalize
    from matplotlib.lines import Line2D

    sims = [r for r in results if r.sim is not None]
    n = len(results) if 1 <= len(results) <= 6 else 1
    ncols = 1 if n == 1 else 2
    nrows = math.ceil(n / ncols)
    x0, y0, x1, y1 = sc.bounds.bounds
    aspect = (y1 - y0) / max(x1 - x0, 1e-9)
    width = 9.0 if ncols == 1 else 13.0
    panel_h = min(8.0, (width / ncols - 1.2) * aspect) + 0.9
    fig, axes = plt.subplots(
        nrows, ncols, figsize=(width, panel_h * nrows + 0.4), layout="constrained", squeeze=False
    )
    flat = list(axes.ravel())
    for ax in flat[n:]:
        ax.set_visible(False)
    moving = [r.p_total_w[:-1] for r in sims if len(r.p_total_w) > 1]
    # colour scale from the cruise power (5th percentile) to the peaks: turns stand out
    vmin = min((float(np.percentile(p, 5)) for p in moving), default=0.0)
    # ... up to the 99.5th percentile: short spikes (limit violations) saturate
    vmax = vmax_w or max((float(np.percentile(p, 99.5)) for p in moving), default=1.0)
    vmin = min(vmin, vmax - 1.0)
    norm = Normalize(vmin=vmin, vmax=vmax)
    mappable = None
    for i, r in enumerate(results):
        ax = flat[i if n > 1 else 0]
        if i == 0 or n > 1:
            _draw_world(ax, sc)
            title = r.name if n > 1 else sc.name + (f": {r.name}" if r.name != sc.name else "")
            ax.set_title(title, fontsize=10)
        if r.error is not None:
            ax.set_title(f"{r.name}: no route", fontsize=10, color="darkred")
            ax.plot(*sc.spec.start.xy, marker="s", color="tab:green", mec="black", ms=8)
            ax.plot(*sc.goal_xy, marker="*", color="gold", mec="black", ms=13)
            continue
        for alt in r.plan.alternatives:  # further waypoint sets the planner returned
            ax.plot(alt[:, 0], alt[:, 1], "--", color="grey", linewidth=0.8, zorder=2)
        wp = r.plan.waypoints
        ax.plot(wp[:, 0], wp[:, 1], "--", color="black", linewidth=1.0, zorder=3)
        ax.plot(wp[1:-1, 0], wp[1:-1, 1], "o", color="white", mec="black", ms=5, zorder=4)
        ax.plot(*wp[0], marker="s", color="tab:green", mec="black", ms=8, zorder=5)
        ax.plot(*wp[-1], marker="*", color="gold", mec="black", ms=13, zorder=5)
        if r.sim is not None and len(r.sim.x) > 1:
            # at most ~1500 drawn segments per path; each shows the peak power it covers
            stride = max(1, math.ceil((len(r.sim.x) - 1) / 1500))
            idx = np.unique(np.append(np.arange(0, len(r.sim.x), stride), len(r.sim.x) - 1))
            pts = np.column_stack([r.sim.x[idx], r.sim.y[idx]])
            segs = np.stack([pts[:-1], pts[1:]], axis=1)
            seg_power = np.maximum.reduceat(r.p_total_w[:-1], idx[:-1])
            lc = LineCollection(
                list(segs), cmap="plasma", norm=norm, capstyle="round", linewidths=3.0, zorder=4
            )
            lc.set_array(seg_power)
            lc.set_in_layout(False)  # the axes limits are the map's: skip costly bboxes
            ax.add_collection(lc)
            mappable = lc
        if r.sim is not None and np.any(r.over_limit):
            bad = np.flatnonzero(r.over_limit)
            ax.plot(r.sim.x[bad], r.sim.y[bad], "o", ms=4, mfc="none", mec="red", mew=0.8, zorder=5)
        if n > 1 or len(results) == 1:  # one panel per case
            ax.text(
                0.01, 0.99, _panel_note(r), transform=ax.transAxes, va="top", ha="left",
                fontsize=8, zorder=7,
                bbox={"boxstyle": "round", "facecolor": "white", "alpha": 0.85, "lw": 0.5},
            )  # fmt: skip
        if r.battery is not None and r.battery.empty_at is not None:
            _, bx, by, _ = r.battery.empty_at
            ax.plot(bx, by, marker="X", color="red", mec="black", ms=14, zorder=6)
            ax.annotate(
                "battery empty",
                (bx, by),
                xytext=(6, 8),
                textcoords="offset points",
                color="darkred",
                fontsize=9,
                weight="bold",
                zorder=6,
            )
    handles = list(getattr(flat[0], "_ecoplan_handles", []))
    handles.append(
        Line2D([], [], linestyle="--", color="black", marker="o", mfc="white", label="planned")
    )
    if any(len(r.plan.alternatives) for r in results):
        handles.append(Line2D([], [], linestyle="--", color="grey", label="alternatives"))
    if sims:
        cmap = plt.get_cmap("plasma")
        handles.append(Line2D([], [], color=cmap(0.6), linewidth=3, label="simulated"))
    if any(np.any(r.over_limit) for r in sims):
        handles.append(
            Line2D([], [], linestyle="", marker="o", mfc="none", mec="red", label="over a limit")
        )
    handles += [
        Line2D([], [], linestyle="", marker="s", color="tab:green", mec="black", label="start"),
        Line2D([], [], linestyle="", marker="*", color="gold", mec="black", ms=12, label="goal"),
    ]
    fig.legend(
        handles=handles,
        loc="outside lower center",
        ncols=min(len(handles), 8),
        fontsize=8,
        frameon=False,
    )
    if mappable is not None:
        fig.colorbar(
            mappable, ax=flat[:n], label="electrical power $P_T$ [W]", shrink=0.9, extend="max"
        )
    return fig


def plot_power(sc: Scenario, results: Sequence[CaseResult]) -> Any:
    """Power and cumulative energy over time for each case (one line per case)."""
    import matplotlib.pyplot as plt

    fig, (ax_p, ax_e) = plt.subplots(2, 1, figsize=(9, 6), sharex=True, layout="constrained")
    for r in results:
        if r.sim is None:
            continue
        n = r.sim.n_steps
        step = max(1, n // 3000)  # enough points for the figure's width
        t = r.sim.t
        (line,) = ax_p.plot(t[:n:step], r.p_total_w[:n:step], linewidth=1.0, label=r.name)
        (cum,) = ax_e.plot(
            t[::step],
            r.cumulative_energy_j[::step] / 1e3,
            color=line.get_color(),
            label=f"{r.name}: {r.energy_j / 1e3:.1f} kJ",
        )
        line.set_in_layout(False)
        cum.set_in_layout(False)
        if r.battery is not None and r.battery.empty_at is not None:
            ax_e.axvline(r.battery.empty_at[0], color=line.get_color(), linestyle=":")
    if sc.spec.battery is not None:
        usable = sc.spec.battery.usable_j / 1e3
        ax_e.axhline(
            usable,
            color="red",
            linestyle="--",
            linewidth=1.2,
            label=f"battery usable {usable:.1f} kJ",
        )
    ax_p.set_ylabel("electrical power $P_T$ [W]")
    ax_p.set_title(f"{sc.name}: power and energy over time", fontsize=10)
    ax_e.set_ylabel("cumulative energy [kJ]")
    ax_e.set_xlabel("time [s]")
    ax_e.legend(fontsize=8, loc="upper left")
    if len(results) > 1:
        ax_p.legend(fontsize=8, loc="upper right")
    for ax in (ax_p, ax_e):
        ax.grid(alpha=0.3)
    return fig


def plot_breakdown(sc: Scenario, results: Sequence[CaseResult]) -> Any:
    """Energy by component, one stacked horizontal bar per case [kJ]."""
    import matplotlib.pyplot as plt

    rs = [r for r in results if r.sim is not None]
    fig, ax = plt.subplots(figsize=(9, 1.4 + 0.6 * len(rs)), layout="constrained")
    names = [r.name for r in rs]
    left = np.zeros(len(rs))
    for comp in COMPONENTS:
        vals = np.array([r.breakdown_j[comp] / 1e3 for r in rs])
        if not np.any(vals > 0):
            continue
        ax.barh(
            names, vals, left=left, color=_COMPONENT_COLOURS[comp], label=_COMPONENT_LABELS[comp]
        )
        for i, v in enumerate(vals):
            total = rs[i].energy_j / 1e3
            if total > 0 and v / total > 0.06:
                ax.text(
                    left[i] + v / 2,
                    i,
                    f"{100 * v / total:.0f} %",
                    ha="center",
                    va="center",
                    fontsize=8,
                    color="white",
                )
        left += vals
    for i, r in enumerate(rs):
        ax.text(left[i], i, f" {r.energy_j / 1e3:.1f} kJ", va="center", fontsize=9)
    ax.invert_yaxis()
    ax.set_xlabel("energy [kJ]")
    ax.set_xlim(0, max(left.max(initial=1.0) * 1.15, 1e-3))
    ax.set_title(f"{sc.name}: energy by component", fontsize=10)
    fig.legend(fontsize=8, ncols=3, loc="outside lower center", frameon=False)
    return fig


# ---------------------------------------------------------------------- report


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
        Folder from :func:`prepare_out_dir`.
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
    csv_names = dict(zip((id(r) for r in results), case_file_names(results), strict=True))
    if opts.csv:
        names += [csv_names[id(r)] for r in simulated]
    if opts.markdown:
        names.append("report.md")
    _check_not_foreign(out, names, force)

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
        w = csv.DictWriter(fh, fieldnames=list(_SUMMARY_COLUMNS))
        w.writeheader()
        for r in results:
            w.writerow(_summary_row(r))
    if opts.csv:
        for r in simulated:
            write_log_csv(r, out.file(csv_names[id(r)]))
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
        f"- vehicle: `{sc.params.name}` ({sc.params.kind})",
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
            f"Analytic energy of the route (ecoplan.cost.path_cost): "
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
    for comp in COMPONENTS:
        e = r.breakdown_j[comp]
        share = 100.0 * e / r.energy_j if r.energy_j else 0.0
        lines.append(f"| {_COMPONENT_LABELS[comp]} | {e / 1e3:.2f} | {share:.1f} % |")
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
