"""``ecoplan diagnose``: logs in; the diagnosis, its report and its files out (nothing printed).

:func:`diagnose_logs` reads the logs (any source :func:`ecoplan.io.logs.read_logs` takes),
runs :func:`ecoplan.diagnose.pipeline.diagnose` against a preset or a vehicle file, ranks a
scenario's candidate routes under the preset and the corrected model when asked, and writes
the report folder.  The command line prints :attr:`DiagnoseRun.lines` and the JSON.
"""

from __future__ import annotations

import dataclasses
import json
import math
from collections.abc import Mapping, Sequence
from dataclasses import dataclass
from pathlib import Path
from typing import Any

from ecoplan.diagnose.corrected import corrected_model, save_corrected_model
from ecoplan.diagnose.pipeline import diagnose
from ecoplan.diagnose.ranking import Route, ranking_change
from ecoplan.diagnose.report import (
    json_report,
    save_figures,
    save_where_time,
    summary,
    write_json,
)
from ecoplan.diagnose.report_md import write_report_md
from ecoplan.diagnose.result import Diagnosis
from ecoplan.dynamics.log import check_pose_frame
from ecoplan.errors import InputError
from ecoplan.io.logs import read_logs
from ecoplan.io.rosbag import load_topic_map
from ecoplan.io.vehicles import load_vehicle

__all__ = ["DiagnoseRun", "diagnose_logs"]


@dataclass(frozen=True)
class DiagnoseRun:
    """What ``ecoplan diagnose`` found and wrote.

    Attributes
    ----------
    diagnosis : Diagnosis
        The full result.
    lines : tuple of str
        The text summary, then (with routes) the route ranking, one line each.
    report : dict
        The diagnosis JSON, validated, with the extra key ``ranking`` when routes were given.
    files : tuple of (str, Path)
        What was written to the report folder and where, in order (``"figure"``,
        ``"corrected model"``, ``"report"``, ...); empty without a folder.
    """

    diagnosis: Diagnosis
    lines: tuple[str, ...]
    report: dict[str, Any]
    files: tuple[tuple[str, Path], ...] = ()


def _ranking(d: Diagnosis, routes: Mapping[str, Route]) -> tuple[list[str], dict[str, Any]]:
    rc = ranking_change(routes, corrected_model(d))
    lines = ["route ranking under the preset and the corrected model:", *rc.summary().split("\n")]
    payload = {
        "routes": [
            {"name": n, "energy_preset_j": float(eb), "energy_corrected_j": float(ec)}
            for n, eb, ec in zip(rc.names, rc.energy_base_j, rc.energy_corrected_j, strict=True)
        ],
        "rank_preset": rc.rank_base,
        "rank_corrected": rc.rank_corrected,
        "changed": rc.changed,
        "best_changed": rc.best_changed,
    }
    return lines, payload


def _write_folder(d: Diagnosis, out: Path, extra: dict[str, Any]) -> list[tuple[str, Path]]:
    out.mkdir(parents=True, exist_ok=True)
    files = [("JSON", write_json(d, out / "diagnosis.json", extra))]
    if "ranking" in extra:
        ranking = out / "ranking.json"
        ranking.write_text(json.dumps(extra["ranking"], indent=2))
        files.append(("ranking", ranking))
    files += [("figure", p) for p in [*save_figures(d, out), *save_where_time(d, out)]]
    files.append(("corrected model", save_corrected_model(d, out / "corrected_model.json")))
    files.append(("report", write_report_md(d, out / "report.md", extra)))
    return files


def diagnose_logs(
    log_paths: Sequence[str],
    vehicle: str,
    terrain: str | None = None,
    *,
    out_dir: str | Path | None = None,
    topics_path: str | None = None,
    bus_voltage_v: float = 24.0,
    routes: Mapping[str, Route] | None = None,
    pose_frame: str | None = None,
) -> DiagnoseRun:
    """Back end of ``ecoplan diagnose LOG [LOG ...] --vehicle V [--terrain T] [--out DIR]``.

    Parameters
    ----------
    log_paths : sequence of str
        Logs: CSV files, ``borealtc:TERRAIN``, ROS 2 bags.
    vehicle : str
        A vehicle preset name or a vehicle file (``.yaml``).
    terrain : str, optional
        Terrain of the preset or file.
    out_dir : str or Path, optional
        Report folder: ``diagnosis.json``, the figures, ``where_time.csv``,
        ``corrected_model.json``, ``report.md`` (and ``ranking.json`` with routes).
    topics_path : str, optional
        Topic map of ROS 2 bags (``--topics``).
    bus_voltage_v : float
        Bus voltage assumed for BorealTC runs (``--bus-voltage``) [V].
    routes : mapping of str to route, optional
        Candidate routes of a scenario (``--scenario``): their energy ranking under the preset
        and the corrected model (:func:`ecoplan.diagnose.ranking.ranking_change`) goes into the
        lines and into the JSON as the extra key ``ranking``.
    pose_frame : {"world", "run"}, optional
        Where every log's pose is (``--pose-frame``), instead of what each log says
        (:data:`~ecoplan.dynamics.log.POSE_FRAMES`; a CSV's ``# pose_frame:`` line).

    Returns
    -------
    DiagnoseRun
        The diagnosis, its text, its JSON and the files written.

    Raises
    ------
    InputError
        No log, a bad bus voltage, an unreadable or malformed log, an unknown vehicle or
        terrain, a log the diagnosis cannot use (exit code 2 in the CLI).
    """
    if not log_paths:
        raise InputError("no log file given")
    if not (math.isfinite(bus_voltage_v) and bus_voltage_v > 0.0):
        raise InputError(f"--bus-voltage must be a positive number of volts, got {bus_voltage_v}")
    topic_map = load_topic_map(topics_path) if topics_path is not None else None
    if pose_frame is not None:
        check_pose_frame(pose_frame, "--pose-frame")
    logs = read_logs(log_paths, topic_map=topic_map, bus_voltage_v=bus_voltage_v)
    if pose_frame is not None:
        logs = [dataclasses.replace(lg, pose_frame=pose_frame) for lg in logs]
    if vehicle.endswith((".yaml", ".yml")) or Path(vehicle).is_file():  # a vehicle file
        d = diagnose(logs, load_vehicle(vehicle).params(terrain), terrain)
    else:
        d = diagnose(logs, vehicle, terrain)
    lines = summary(d).split("\n")
    extra: dict[str, Any] = {}
    if routes is not None:
        rank_lines, extra["ranking"] = _ranking(d, routes)
        lines += rank_lines
    files = _write_folder(d, Path(out_dir), extra) if out_dir is not None else []
    return DiagnoseRun(d, tuple(lines), json_report(d, extra), tuple(files))
