"""A report people can read (issue 12, item 8): report.md, ``--json -``, assumptions stated.

The logs are BorealTC-like current logs converted at an assumed bus voltage (the reader states
it in the log's notes) and a CSV with a column the log format does not know (ignored and
named); both must appear in the JSON and in ``report.md``.
"""

from __future__ import annotations

import json

import numpy as np

from ecoplan.cli import main
from ecoplan.io.logcsv import read_log_csv
from ecoplan.synth.cases import generate_case


def _logs_with_an_extra_column(tmp_path):  # type: ignore[no-untyped-def]
    case = generate_case(3, "sensor_delay", "large", n_waypoint_runs=1, rate_hz=10.0)
    paths = []
    for p in case.write(tmp_path / "logs"):
        lines = p.read_text().splitlines()
        head = next(i for i, line in enumerate(lines) if not line.startswith("#"))
        lines[head] += ",battery_temp_c"
        for i in range(head + 1, len(lines)):
            lines[i] += ",31.5"
        p.write_text("\n".join(lines) + "\n")
        paths.append(str(p))
    return case, paths


def test_json_dash_prints_only_json_on_stdout(tmp_path, capsys) -> None:  # type: ignore[no-untyped-def]
    case, paths = _logs_with_an_extra_column(tmp_path)
    code = main(
        ["diagnose", *paths, "--vehicle", case.vehicle, "--terrain", case.terrain, "--json", "-"]
    )
    cap = capsys.readouterr()
    assert code == 0
    obj = json.loads(cap.out)  # stdout is exactly one JSON document
    assert obj["verdict"]["effect"] == "sensor_delay"
    assert "verdict: sensor_delay" in cap.err  # the text went to stderr
    notes = " ".join(obj["log"]["notes"])
    assert "battery_temp_c" in notes  # the ignored column is named


def test_out_writes_a_readable_report(tmp_path, capsys) -> None:  # type: ignore[no-untyped-def]
    case, paths = _logs_with_an_extra_column(tmp_path)
    assert "battery_temp_c" in " ".join(read_log_csv(paths[0]).notes)
    out = tmp_path / "out"
    code = main(
        [
            "diagnose",
            *paths,
            "--vehicle",
            case.vehicle,
            "--terrain",
            case.terrain,
            "--out",
            str(out),
        ]
    )
    assert code == 0
    text = (out / "report.md").read_text()
    for heading in (
        "## What was found",
        "## The numbers",
        "## Where",
        "## What to do next",
        "## Input and assumptions",
    ):
        assert heading in text
    assert "`sensor_delay`" in text and "battery_temp_c" in text
    # every gap figure of the JSON is in the report, with its meaning
    obj = json.loads((out / "diagnosis.json").read_text())
    assert f"{obj['gap']['before']:.1f} W" in text and f"{obj['gap']['after']:.1f} W" in text


def test_bus_voltage_assumption_is_stated(tmp_path) -> None:  # type: ignore[no-untyped-def]
    from ecoplan.diagnose.pipeline import diagnose
    from ecoplan.diagnose.report import to_json_dict
    from ecoplan.diagnose.report_md import report_markdown

    case = generate_case(4, "none", "large", n_waypoint_runs=1, rate_hz=10.0)
    logs = [
        lg.with_notes("p_total = 24 V x (curL + curR): the bus voltage is an assumption")
        for lg in case.logs
    ]  # type: ignore[attr-defined]
    d = diagnose(logs, case.vehicle, case.terrain)
    assert "24 V" in " ".join(to_json_dict(d)["log"]["notes"])
    assert "24 V" in report_markdown(d)
    assert np.isfinite(d.gap_final_w)
