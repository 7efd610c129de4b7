"""The planned route for other tools: a nav_msgs/Path bag, GeoJSON and CSV in the report folder.

``ecoplan plan --out DIR`` writes them next to the plan's report with
:func:`ecoplan.io.route_export.write_route`; the folder's manifest lists them, so the next run
may replace them and nothing else.
"""

from __future__ import annotations

from pathlib import Path
from typing import TYPE_CHECKING

from ecoplan.app.outdir import OutDir
from ecoplan.io.route_export import write_route

if TYPE_CHECKING:
    from ecoplan.app.run import PlanOutcome

__all__ = ["ROUTE_FILES", "write_route_files"]

#: What :func:`write_route` creates in the folder (the bag is a directory).
ROUTE_FILES = ("route_bag", "route.geojson", "route.csv")


def write_route_files(folder: OutDir, plan: PlanOutcome, *, force: bool = False) -> list[Path]:
    """Write the route of ``plan`` into ``folder`` and list it in the folder's manifest.

    Parameters
    ----------
    folder : OutDir
        The report folder.
    plan : PlanOutcome
        The planned route and its speed.
    force : bool
        Replace files ecoplan did not write.

    Returns
    -------
    list of Path
        The bag directory, the GeoJSON and the CSV.

    Raises
    ------
    InputError
        One of :data:`ROUTE_FILES` exists and ecoplan did not write it (without ``force``).
    """
    folder.claim(list(ROUTE_FILES), force=force)
    files = write_route(folder.path, plan.waypoints, plan.speed_mps, planner=plan.planner)
    folder.written.extend(files)
    folder.finish()
    return files
