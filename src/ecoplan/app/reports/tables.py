"""Tables of scenario runs: the side-by-side markdown table and the summary CSV rows."""

from __future__ import annotations

import math
from collections.abc import Iterable, Sequence
from typing import TYPE_CHECKING, Any

from ecoplan.models.power import COMPONENTS

if TYPE_CHECKING:
    from ecoplan.app.run import CaseResult, PlanOutcome

__all__ = [
    "COMPONENT_LABELS",
    "SUMMARY_COLUMNS",
    "breakdown_components",
    "case_lines",
    "plan_lines",
    "summary_row",
    "summary_table",
]

#: Readable name of each power component (tracked paper eqs. 14-20).
COMPONENT_LABELS = {
    "friction_w": "dynamic friction",
    "resistance_w": "traction resistance",
    "powerup_w": "driver power-up",
    "braking_w": "driver braking",
    "nonregen_w": "non-regenerated",
    "elec_loss_w": "electrical loss",
    "inertial_w": "inertia",
    "grade_w": "climbing",
}


def breakdown_components(components: Iterable[str]) -> list[str]:
    """The components a report shows, in report order.

    The static model's six (:data:`ecoplan.models.power.COMPONENTS`) first, then the
    mass terms: ``inertial_w`` (``M a v + I α ω``, present when a scenario sets
    ``simulation: {inertial: true}``) and ``grade_w`` (the climbs of
    ``terrain: {elevation: ...}``), then any other key of ``components``.

    Parameters
    ----------
    components : iterable of str
        Keys of a breakdown (``CaseResult.breakdown_j`` or ``components_w``).

    Returns
    -------
    list of str

    Examples
    --------
    >>> breakdown_components(["inertial_w", "friction_w", "resistance_w"])[:2]
    ['friction_w', 'resistance_w']
    >>> breakdown_components(["inertial_w", *COMPONENTS])[-1]
    'inertial_w'
    """
    keys = set(components)
    order = [*COMPONENTS, "inertial_w", "grade_w"]
    return [k for k in order if k in keys] + sorted(keys - set(order))


#: Columns of ``summary.csv``, one row per case.
SUMMARY_COLUMNS = (
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


def summary_row(r: CaseResult) -> dict[str, Any]:
    """One row of ``summary.csv`` (:data:`SUMMARY_COLUMNS`) for a case."""
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


def case_lines(r: CaseResult) -> list[str]:
    """Terminal lines for one case: the route, the analytic estimate, the run, the battery.

    Parameters
    ----------
    r : CaseResult
        The case.

    Returns
    -------
    list of str
        A header line, then indented details (``NO ROUTE`` and why when it failed).
    """
    if r.error is not None:
        return [f"{r.name}: NO ROUTE ({r.error})"]
    p = r.plan
    lines = [f"{r.name}: route from {p.planner}, {len(p.waypoints)} points, {p.length_m:.1f} m"]
    if p.estimate_energy_j is not None:
        lines.append(f"  analytic estimate: {p.estimate_energy_j / 1e3:.2f} kJ")
    if r.sim is not None:
        s = r.sim
        state = "goal reached" if s.completed else "TIME LIMIT before the goal"
        lines.append(
            f"  simulated: {r.energy_j / 1e3:.2f} kJ in {s.time_s:.1f} s over {s.length_m:.1f} m, "
            f"psi {s.psi_rad:.2f} rad, peak {r.peak_power_w:.0f} W ({state})"
        )
    if r.battery is not None:
        lines.append(f"  battery: {r.battery.sentence()}")
    return lines


def plan_lines(scenario: str, plan: PlanOutcome) -> list[str]:
    """Terminal lines for a planned route: planner, length, speed, waypoints, estimate.

    Parameters
    ----------
    scenario : str
        Scenario name.
    plan : PlanOutcome
        The route.

    Returns
    -------
    list of str
        A header line, one line per waypoint ``x y`` [m], and the analytic estimate.
    """
    lines = [
        f"{scenario}: route from {plan.planner}, {plan.length_m:.1f} m, v_sp {plan.speed_mps} m/s"
    ]
    lines += [f"  {x:9.3f} {y:9.3f}" for x, y in plan.waypoints]
    if plan.estimate_energy_j is not None:
        lines.append(f"  analytic estimate: {plan.estimate_energy_j / 1e3:.2f} kJ")
    return lines
