"""End-to-end diagnosis on blind synthetic cases, the CLI back end and closing the loop (issue 6).

Every in-library effect is generated (``ecoplan.synth``, large magnitude, short
sessions at 20 Hz to keep the suite fast) and the diagnosis, not told the answer, must name it;
a ``none`` case must give ``none`` and an out-of-library effect ``unexplained``.  The blind
benchmark (benchmarks/blind_diagnosis.py) checks the moderate magnitudes on many seeds.
"""

from __future__ import annotations

import json
from functools import cache

import numpy as np
import pytest

from ecoplan.app.diagnose import diagnose_logs
from ecoplan.diagnose.corrected import CorrectedModel, load_corrected_model, save_corrected_model
from ecoplan.diagnose.pipeline import diagnose
from ecoplan.diagnose.ranking import polyline_trajectory, ranking_change
from ecoplan.diagnose.result import Diagnosis
from ecoplan.dynamics.log import Log
from ecoplan.errors import InputError
from ecoplan.presets import vehicle
from ecoplan.synth.cases import generate_case
from ecoplan.synth.withheld import IN_LIBRARY


@cache
def _diagnosed(effect: str, seed: int = 0) -> tuple[str, Diagnosis]:
    case = generate_case(seed, effect, "large", n_waypoint_runs=1, rate_hz=20.0)
    return case.truth.expected_verdict, diagnose(list(case.logs), case.vehicle, case.terrain)


@pytest.mark.parametrize("effect", IN_LIBRARY)
def test_diagnosis_names_the_withheld_effect(effect: str) -> None:
    expected, d = _diagnosed(effect)
    assert expected == effect  # every in-library effect is named, on both vehicles
    assert d.verdict == expected
    assert d.attribution.scores[0].name == expected  # ranked first
    assert 0.0 <= d.attribution.confidence <= 1.0


def test_no_effect_gives_none_and_nothing_significant() -> None:
    _, d = _diagnosed("none")
    assert d.verdict == "none"
    assert not any(s.significant for s in d.attribution.scores)
    # calibration alone closes the gap of the perturbed base parameters (synth base_error)
    assert d.gap_calibrated_w <= d.gap_preset_w


def test_out_of_library_effect_is_unexplained() -> None:
    expected, d = _diagnosed("periodic_disturbance")
    assert expected == "unexplained"
    assert d.verdict == "unexplained"
    assert d.attribution.ljung_box_p < 0.01  # the residual is not white


def test_a_found_effect_shrinks_the_held_out_gap() -> None:
    _, d = _diagnosed("speed_dependent_resistance")
    assert d.gap_final_w < 0.7 * d.gap_calibrated_w
    lo, hi = d.final_ci_w
    assert 0.0 < lo <= d.gap_calibrated_w - d.gap_final_w <= hi


def test_where_shares_add_up_per_group() -> None:
    _, d = _diagnosed("inertia")
    groups: dict[str, list[float]] = {}
    for w in d.where:
        groups.setdefault(w.regime.split(":")[0], []).append(w.error_share)
    for g, shares in groups.items():
        assert sum(shares) == pytest.approx(1.0, abs=1e-9), g
    # inertia lives where the robot accelerates: over-represented there
    acc = next(w for w in d.where if w.regime == "accel:accelerating")
    assert acc.error_share > acc.time_share


def _log(n: int = 200, **kw: object) -> Log:
    t = np.arange(n) * 0.05
    v = 0.3 + 0.1 * np.sin(t)
    cols: dict[str, object] = {"t": t, "v_left": v, "v_right": v * 0.9, "p_total": 100 + 50 * v}
    cols.update(kw)
    return Log(**cols)  # type: ignore[arg-type]


def test_too_short_log_is_an_input_error() -> None:
    with pytest.raises(InputError, match="too short"):
        diagnose(_log(30), "auriga-beta-wide")


def test_unknown_vehicle_and_effect_are_input_errors() -> None:
    with pytest.raises(InputError, match="unknown vehicle"):
        diagnose(_log(), "tank")
    with pytest.raises(InputError, match="unknown effect"):
        diagnose(_log(), "auriga-beta-wide", effects=["gremlins"])


def test_cli_back_end_writes_json_figures_and_a_loadable_model(tmp_path) -> None:  # type: ignore[no-untyped-def]
    case = generate_case(5, "sensor_delay", "large", n_waypoint_runs=1, rate_hz=20.0)
    paths = [str(p) for p in case.write(tmp_path / "logs")]
    out = tmp_path / "out"
    run = diagnose_logs(paths, case.vehicle, case.terrain, out_dir=out)
    assert any(line.startswith("verdict: sensor_delay") for line in run.lines)
    obj = json.loads((out / "diagnosis.json").read_text())
    assert obj["verdict"]["effect"] == "sensor_delay" == run.report["verdict"]["effect"]
    assert ("corrected model", out / "corrected_model.json") in run.files
    for name in ("residual_time.png", "candidates.png", "where.png", "residual_map.png"):
        assert (out / name).stat().st_size > 1000
    model = load_corrected_model(out / "corrected_model.json")
    assert model.effect == "sensor_delay"
    assert model.effect_params["delay_s"] == pytest.approx(case.truth.params["delay_s"], abs=0.1)


def test_cli_back_end_rejects_a_bad_log(tmp_path) -> None:  # type: ignore[no-untyped-def]
    bad = tmp_path / "bad.csv"
    bad.write_text("t,v_left,v_right\n0,0,0\n1,0,0\n")
    with pytest.raises(InputError, match="p_total"):
        diagnose_logs([str(bad)], "auriga-beta-wide")


def test_corrected_model_round_trips_through_yaml_and_json(tmp_path) -> None:  # type: ignore[no-untyped-def]
    base = vehicle("auriga-beta-wide", "asphalt")
    m = CorrectedModel(
        "auriga-beta-wide", "asphalt", base, "speed_dependent_resistance", {"c_n_s_per_m": 200.0}
    )
    for suffix in (".json", ".yaml"):
        back = load_corrected_model(save_corrected_model(m, tmp_path / f"m{suffix}"))
        assert back.effect == m.effect and back.params == base
        # independent: preset power plus c (vl² + vr²) drawn through eta (eq. 20)
        want = float(base.power(0.5, 0.3).total_w) + 200.0 * (0.5**2 + 0.3**2) / base.eta
        assert float(back.power(0.5, 0.3).total_w) == pytest.approx(want)
        pb = back.power(0.5, 0.3)
        assert float(sum(pb.components().values())) == pytest.approx(float(pb.total_w))


def test_bad_corrected_model_file_is_an_input_error(tmp_path) -> None:  # type: ignore[no-untyped-def]
    p = tmp_path / "m.json"
    p.write_text(json.dumps({"format": "something-else"}))
    with pytest.raises(InputError, match="format"):
        load_corrected_model(p)


def test_speed_dependent_resistance_reverses_a_fast_short_vs_slow_long_ranking() -> None:
    # Route A: 10 m at 0.8 m/s; route B: 12 m at 0.3 m/s (straight).  Preset: energy per metre
    # is (2K v + P_pu)/eta / v, so the faster, shorter route wins.  With c (vl²+vr²) / eta of
    # c = 2000 N s/m, A costs 2 c v² t / eta = 2c v d / eta = 33.7 kJ more and B only 15.2 kJ:
    # B wins (a resistance force, drawn through eta like every mechanical power, eq. 20).
    base = vehicle("auriga-beta-wide", "asphalt")
    dt = 0.01

    def straight(d: float, v: float) -> tuple[np.ndarray, np.ndarray, np.ndarray]:
        t = np.arange(0.0, d / v, dt)
        return t, np.full(t.size, v), np.full(t.size, v)

    routes = {"A": straight(10.0, 0.8), "B": straight(12.0, 0.3)}
    m = CorrectedModel(
        "auriga-beta-wide", "asphalt", base, "speed_dependent_resistance", {"c_n_s_per_m": 2000.0}
    )
    rc = ranking_change(routes, m)
    assert rc.rank_base == ["A", "B"]
    assert rc.rank_corrected == ["B", "A"]
    assert rc.changed and rc.best_changed
    extra_a = 2000.0 * 2 * 0.8**2 * (10.0 / 0.8) / base.eta
    assert rc.energy_corrected_j[0] - rc.energy_base_j[0] == pytest.approx(extra_a, rel=0.01)


def test_polyline_routes_turn_on_the_spot_then_drive() -> None:
    base = vehicle("auriga-beta-wide", "asphalt")
    t, vl, vr = polyline_trajectory([(0, 0), (4, 0), (4, 4)], base)
    assert t.size == vl.size == vr.size
    assert np.any((vl < 0) & (vr > 0))  # a left turn on the spot (case 4 of Fig. 3)
    dist = float(np.sum(0.5 * (vl + vr)) * (t[1] - t[0]))
    assert dist == pytest.approx(8.0, rel=0.05)
