"""The CSV log of a simulated case, in the diagnosis log format (so it can be diagnosed)."""

from __future__ import annotations

import io
from pathlib import Path
from typing import TYPE_CHECKING, Any

import numpy as np

from ecoplan.app.reports.tables import breakdown_components
from ecoplan.errors import InputError

if TYPE_CHECKING:
    from ecoplan.app.run import CaseResult

__all__ = ["write_log_csv"]


def write_log_csv(result: CaseResult, path: Path) -> Path:
    """Write a case's simulated steps as CSV in the diagnosis log format.

    Columns: ``t, x, y, yaw, v_left_cmd, v_right_cmd, v_left, v_right, wz, p_total,
    p_left, p_right`` (the log contract), then ``case`` (Fig. 3), the breakdown
    ``p_friction, p_resistance, ...`` [W] (``p_inertial`` too when the mass terms are
    simulated) and the ``terrain`` label.  Power columns are
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
    comps = breakdown_components(result.components_w)  # + p_inertial when simulated
    cols.update({f"p_{c.removesuffix('_w')}": result.components_w[c] for c in comps})
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
