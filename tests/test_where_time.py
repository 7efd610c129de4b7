"""Where in the log's own time (issue 12, item 4): change points of the residual, JSON, CSV, plot.

Expected switch times are the ones the test builds into the data (a level step of the residual,
or a power gain switched on half-way through each run), never the detector's output.
"""

from __future__ import annotations

import csv
import dataclasses
import json
import math
from functools import cache

import numpy as np
import pytest
from hypothesis import given, settings
from hypothesis import strategies as st

from ecoplan.app.diagnose import diagnose_logs
from ecoplan.diagnose.pipeline import diagnose
from ecoplan.diagnose.report import summary, to_json_dict
from ecoplan.diagnose.result import Diagnosis
from ecoplan.diagnose.where_time import TimeSegment, where_time, write_where_time_csv
from ecoplan.dynamics.log import Log
from ecoplan.synth.cases import generate_case


@settings(max_examples=20, deadline=None)
@given(
    t_switch=st.floats(30.0, 150.0),
    step_w=st.sampled_from([-80.0, -40.0, 40.0, 80.0]),
    t0=st.floats(0.0, 1e5),
    seed=st.integers(0, 1000),
)
def test_a_level_step_is_found_on_the_logs_own_clock(
    t_switch: float, step_w: float, t0: float, seed: int
) -> None:
    g = np.random.default_rng(seed)
    t = t0 + np.arange(0.0, 180.0, 0.05)
    r = np.where(t - t0 < t_switch, 0.0, step_w) + g.normal(0.0, 15.0, t.size)
    segs = where_time(t, r, np.zeros(t.size, dtype=int), ["A"])
    bounds = [s.t_end_s for s in segs[:-1]]
    assert min(abs(b - (t0 + t_switch)) for b in bounds) <= 1.5  # within the 1 s bins
    before = float(np.mean(r[t - t0 < t_switch]) - np.mean(r))
    after = float(np.mean(r[t - t0 >= t_switch]) - np.mean(r))
    for s in segs:  # any extra split is a noise split: its level is that of its side
        side = before if s.t_end_s <= t0 + t_switch + 1.5 else after
        assert s.excess_w == pytest.approx(side, abs=12.0)


def test_a_flat_residual_gives_no_segment() -> None:
    g = np.random.default_rng(3)
    t = np.arange(0.0, 300.0, 0.1)
    run = (t > 150.0).astype(int)
    segs = where_time(t, g.normal(0.0, 10.0, t.size), run, ["a", "b"])
    assert segs == []


@pytest.mark.parametrize(("stop_s", "seed"), [(60.0, 5), (100.0, 1), (180.0, 2)])
def test_a_stop_does_not_hide_a_switch_between_known_terrains(stop_s: float, seed: int) -> None:
    # The robot stands for 30 s, where every model says 0 W (motors off), then drives on a
    # known softer ground from 150 s on: the same manoeuvre draws 40 % more.  The stop must
    # not outweigh the switch (a relative level over a model at rest was a level over nothing).
    g = np.random.default_rng(seed)
    t = np.arange(0.0, 240.0, 0.1)
    moving = (t < stop_s) | (t >= stop_s + 30.0)
    drive_w = np.where(moving, 120.0 + 60.0 * np.sin(2.0 * np.pi * t / 17.0), 0.0)
    soft_w = 1.4 * drive_w
    p = np.where(t < 150.0, drive_w, soft_w) + g.normal(0.0, 6.0, t.size)
    run = np.zeros(t.size, dtype=int)
    segs = where_time(t, p - drive_w, run, ["A"], model_w=drive_w, known_w=[drive_w, soft_w])
    bounds = [s.t_end_s for s in segs[:-1]]
    assert bounds
    assert min(abs(b - 150.0) for b in bounds) <= 5.0


@cache
def _gain_case() -> tuple[list[float], Diagnosis]:
    # power multiplied by 1.15 on the second half of every run (the "flat yard")
    case = generate_case(0, "none", "large", n_waypoint_runs=1, rate_hz=10.0)
    logs, switches = [], []
    for lg in case.logs:
        assert isinstance(lg, Log)
        p = lg.p_total.copy()
        h = len(p) // 2
        p[h:] *= 1.15
        switches.append(float(lg.t[h]))
        logs.append(dataclasses.replace(lg, p_total=p))
    return switches, diagnose(logs, case.vehicle, case.terrain)


def test_a_gain_switched_on_mid_run_is_located_in_each_run() -> None:
    switches, d = _gain_case()
    assert d.verdict != "slope"  # the symptom: "slope, confidence 1.00" on a flat yard
    for rid, t_sw in zip(d.run_ids, switches, strict=True):
        bounds = [s.t_end_s for s in d.where_time if s.run == rid]
        assert bounds, rid
        assert min(abs(b - t_sw) for b in bounds) <= 5.0, (rid, t_sw, bounds)


def test_where_time_json_csv_and_figure(tmp_path) -> None:  # type: ignore[no-untyped-def]
    _, d = _gain_case()
    obj = to_json_dict(d)
    assert obj["where_time"]
    for seg in obj["where_time"]:
        assert list(seg) == ["run", "t_start_s", "t_end_s", "excess_w"]
        assert seg["t_start_s"] < seg["t_end_s"]
    path = write_where_time_csv(d.where_time, tmp_path / "w.csv")
    with path.open() as fh:
        rows = list(csv.reader(fh))
    assert rows[0] == ["run", "t_start_s", "t_end_s", "excess_w", "excess_se_w"]
    assert len(rows) == len(d.where_time) + 1
    json.dumps(obj)


def test_cli_out_writes_where_time_files(tmp_path) -> None:  # type: ignore[no-untyped-def]
    case = generate_case(1, "none", "large", n_waypoint_runs=1, rate_hz=10.0)
    paths = [str(p) for p in case.write(tmp_path / "logs")]
    out = tmp_path / "out"
    diagnose_logs(paths, case.vehicle, case.terrain, out_dir=out)
    assert (
        (out / "where_time.csv")
        .read_text()
        .startswith("run,t_start_s,t_end_s,excess_w,excess_se_w")
    )
    assert (out / "where_time.png").stat().st_size > 1000


def _terrain_switch_logs() -> tuple[list[Log], str, str]:
    # no pose; friction and resistance x1.6 on the middle third of every run (a softer
    # terrain crossed in time), from the preset's own breakdown (tracked eqs. 14, 18)
    from ecoplan.presets import vehicle

    case = generate_case(2, "none", "large", n_waypoint_runs=1, rate_hz=10.0)
    params = vehicle(case.vehicle, case.terrain)
    logs = []
    for lg in case.logs:
        assert isinstance(lg, Log)
        pb = params.power(lg.v_left, lg.v_right)
        n = len(lg)
        mid = (np.arange(n) >= n // 3) & (np.arange(n) < 2 * n // 3)
        extra = np.where(mid, 0.6 * (pb.friction_w + pb.resistance_w) / params.eta, 0.0)
        logs.append(
            Log(
                t=lg.t,
                v_left=lg.v_left,
                v_right=lg.v_right,
                p_total=lg.p_total + extra,
                run_id=lg.run_id,
            )
        )
    return logs, case.vehicle, case.terrain


def test_terrain_change_finds_the_switches_and_reduces_the_gap() -> None:
    # where_time finds each run's terrain switches (n/3 and 2n/3, built in above) and the
    # terrain_change candidate lowers the held-out gap.  Its verdict is not required: on
    # these logs it closes 15-40 % of the gap, short of the 80 % the naming rule asks
    # (the segmentation also splits the manoeuvres; see benchmarks/borealtc_mixes.py).
    logs, veh, ter = _terrain_switch_logs()
    d = diagnose(logs, veh, ter)
    for lg in logs:
        n = len(lg)
        bounds = [s.t_end_s for s in d.where_time if s.run == lg.run_id]
        for t_sw in (float(lg.t[n // 3]), float(lg.t[2 * n // 3])):
            assert min(abs(b - t_sw) for b in bounds) <= 5.0, (lg.run_id, t_sw, bounds)
    score = next(s for s in d.attribution.scores if s.name == "terrain_change")
    assert score.reduction_pct > 5.0
    assert d.verdict in ("terrain_change", "unexplained")


def test_terrain_change_needs_no_pose_and_leaves_logs_with_pose_to_terrain_patch() -> None:
    from ecoplan.diagnose.effects import TerrainChange

    case = generate_case(0, "none", "large", n_waypoint_runs=1, rate_hz=10.0)
    d = diagnose(list(case.logs), case.vehicle, case.terrain)
    assert "terrain_change" in d.attribution.unavailable
    assert TerrainChange.available(d.test_frame) is False
    # the summary says why it was not tried, not that the log lacks a signal (it has a pose)
    text = summary(d)
    assert "terrain_change -- (offered only without a pose on one map" in text
    assert "lacks" not in text


def test_segment_standard_error_is_the_noise_over_root_samples() -> None:
    # white noise of 10 W at 10 Hz around a 50 W step at 60 s: each half holds 600 samples,
    # so its mean is known to 10 / sqrt(600) = 0.41 W (by hand), and the step is ~60 of them
    rng = np.random.default_rng(3)
    t = np.arange(0.0, 120.0, 0.1)
    r = np.where(t < 60.0, 0.0, 50.0) + rng.normal(0.0, 10.0, t.size)
    segs = where_time(t, r, np.zeros(t.size, dtype=int), ["run0"])
    assert len(segs) == 2
    for seg in segs:
        n = int(np.sum((t >= seg.t_start_s) & (t <= seg.t_end_s)))
        assert seg.excess_se_w is not None
        assert seg.excess_se_w == pytest.approx(10.0 / np.sqrt(n), rel=0.3)
        assert abs(seg.excess_z) > 30.0
    # a stretch cut on noise alone sits within its scatter
    quiet = TimeSegment("run0", 0.0, 1.0, 0.5, 1.0)
    assert quiet.excess_z == pytest.approx(0.5)
    assert math.isnan(TimeSegment("run0", 0.0, 1.0, 0.5).excess_z)
