"""Figures of scenario runs: the map with paths coloured by power, power over time, breakdown."""

from __future__ import annotations

import math
from collections.abc import Sequence
from typing import TYPE_CHECKING, Any

import numpy as np

from ecoplan.app.reports.tables import COMPONENT_LABELS, breakdown_components
from ecoplan.geometry.maps import GridMap

if TYPE_CHECKING:
    from ecoplan.app.run import CaseResult
    from ecoplan.app.scenario import Scenario

__all__ = ["TERRAIN_COLOURS", "plot_breakdown", "plot_map", "plot_power"]

#: Fill colour of each terrain preset on the maps.
TERRAIN_COLOURS = {
    "marble": "#e4ebf5",
    "asphalt": "#d9d2c5",
    "vinyl": "#e0efdc",
    "hoisted": "#f5f0d8",
}

_COMPONENT_COLOURS = {
    "friction_w": "#d62728",
    "resistance_w": "#1f77b4",
    "powerup_w": "#7f7f7f",
    "braking_w": "#9467bd",
    "nonregen_w": "#ff7f0e",
    "elec_loss_w": "#bcbd22",
    "inertial_w": "#17becf",
    "grade_w": "#8c564b",
}


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


def _flat(colour: str) -> Any:
    from matplotlib.colors import ListedColormap

    return ListedColormap([colour])


def _draw_contours(ax: Any, sc: Scenario, handles: list[Any]) -> None:
    """Contour lines of the scenario's ground elevation, labelled in metres."""
    from matplotlib.lines import Line2D

    assert sc.elevation is not None
    x0, y0, x1, y1 = sc.bounds.bounds
    xs, ys = np.meshgrid(np.linspace(x0, x1, 200), np.linspace(y0, y1, 200))
    z = sc.elevation(xs, ys)
    span = float(np.ptp(z))
    if span < 1e-6:
        return
    step = float(10.0 ** np.floor(np.log10(span / 4.0)))  # about 4-40 lines
    levels = np.arange(np.ceil(z.min() / step) * step, z.max() + 1e-9, step)
    cs = ax.contour(xs, ys, z, levels=levels, colors="#6b4f2a", linewidths=0.7, zorder=1.5)
    ax.clabel(cs, fontsize=7, fmt="%g m")
    handles.append(Line2D([], [], color="#6b4f2a", linewidth=0.7, label="elevation [m]"))


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
    if isinstance(sc.world, GridMap):  # a ROS map: terrain layer and inflated cells
        grid = sc.world
        ext = (x0, x1, y0, y1)
        for label, layer_terrain in enumerate(grid.terrain_names):
            name = str(layer_terrain or default)
            mask = np.where(grid.labels == label, 1.0, np.nan)
            colour = TERRAIN_COLOURS.get(name, "#cccccc")
            if label and name not in seen:
                handles.append(Patch(facecolor=colour, label=name))
                seen.add(name)
            ax.imshow(mask, origin="lower", extent=ext, cmap=_flat(colour), interpolation="none")
        blocked = np.where(grid.blocked & ~grid.obstacle, 1.0, np.nan)
        ax.imshow(blocked, origin="lower", extent=ext, cmap=_flat("#9a9a9a"), interpolation="none")
        occ = np.where(grid.obstacle, 1.0, np.nan)
        ax.imshow(occ, origin="lower", extent=ext, cmap=_flat("#3b3b3b"), interpolation="none")
    for infl in () if isinstance(sc.world, GridMap) else sc.world.inflated_obstacles:
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
    if sc.elevation is not None:  # terrain.elevation: contour lines every metre or so
        _draw_contours(ax, sc, handles)
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
    """Energy by component, one stacked horizontal bar per case [kJ].

    The static model's components, then the mass terms when the scenario simulates them
    (``inertial_w``: accelerating, :mod:`ecoplan.models.inertial`; ``grade_w``: climbing).  A
    component is drawn where it is positive (net energy regained while braking or
    descending shortens the total printed at the bar's end, not the bar).
    """
    import matplotlib.pyplot as plt

    rs = [r for r in results if r.sim is not None]
    fig, ax = plt.subplots(figsize=(9, 1.4 + 0.6 * len(rs)), layout="constrained")
    names = [r.name for r in rs]
    left = np.zeros(len(rs))
    comps = breakdown_components({k for r in rs for k in r.breakdown_j})
    for comp in comps:
        vals = np.array([max(r.breakdown_j.get(comp, 0.0), 0.0) / 1e3 for r in rs])
        if not np.any(vals > 0):
            continue
        ax.barh(
            names,
            vals,
            left=left,
            color=_COMPONENT_COLOURS.get(comp, "#e377c2"),
            label=COMPONENT_LABELS.get(comp, comp),
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
