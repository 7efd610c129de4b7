"""The independent plant zoo (benchmarks/plant_zoo) is right on its own terms.

Expected values are computed by hand here from the papers' equations -- Morales et al. 2009
(tracked: eqs. 3, 12, 14, 18-20, Sec. III-C values, Fig. 5 punctual pressure model) and
Chuy et al. 2009 (wheeled: eqs. 12, 14-15, Table I) -- never taken from the zoo itself.
"""

from __future__ import annotations

import ast
import csv
import math
import sys
from pathlib import Path

import numpy as np
import pytest
from hypothesis import given, settings
from hypothesis import strategies as st

BENCH = Path(__file__).resolve().parents[1] / "benchmarks"
sys.path.insert(0, str(BENCH))

import plant_zoo  # noqa: E402
from plant_zoo import plant, tracked, wheeled  # noqa: E402

speeds = st.floats(-0.86, 0.86, allow_nan=False)


def test_zoo_imports_nothing_from_ecoplan() -> None:
    files = sorted((BENCH / "plant_zoo").glob("*.py"))
    assert len(files) >= 4
    allowed = {"numpy", "scipy", "__future__", "dataclasses", "pathlib", "typing"}
    for f in files:
        tree = ast.parse(f.read_text(), filename=str(f))
        for node in ast.walk(tree):
            if isinstance(node, ast.Import):
                roots = [a.name.split(".")[0] for a in node.names]
            elif isinstance(node, ast.ImportFrom):
                if node.level > 0:  # relative: inside the zoo
                    continue
                roots = [(node.module or "").split(".")[0]]
            else:
                continue
            for r in roots:
                assert r != "ecoplan", f"{f.name} imports ecoplan"
                assert r in allowed, f"{f.name} imports {r}"


@given(v=speeds)
def test_straight_motion_draws_no_friction_power(v: float) -> None:
    for belt, terrain in plant.TRACKED_SETUPS:
        p = tracked.paper_params(belt, terrain)
        a = np.array([v])
        assert tracked.friction_power(p, a, a)[0] == 0.0
        assert tracked.friction_power(p.with_(slip_exponent=0.3), a, a)[0] == 0.0


def test_straight_total_power_is_eq_18_20_by_hand() -> None:
    # wide belts on marble, both tracks at 0.5 m/s: P_T = (K (2 v) + 58) / 0.95 (case a)
    p = tracked.paper_params("wide", "marble")
    got = tracked.total_power(p, np.array([0.5]), np.array([0.5]))[0]
    assert got == pytest.approx((342.0 * 1.0 + 58.0) / 0.95, rel=1e-12)


def test_spot_turn_equals_closed_form_of_eqs_3_12_14() -> None:
    # wide belts on marble (mu 0.63, K 342 N, chi 0.90), V_yl = -0.5, V_yr = +0.5 m/s.
    mu, k, chi, gauge, mass = 0.63, 342.0, 0.90, 0.42, 286.0
    v = 0.5
    c = gauge / (2 * chi)  # eq. (12), symmetric ICRs: C_x = +/- L / (2 chi)
    wz = (v - (-v)) / (2 * c)  # eq. (3)
    dx = c - gauge / 2  # each contact point's lateral distance to its own track ICR
    ys = (-0.36, -0.12, 0.12, 0.36)  # sprocket, 2 rollers, idler over 0.72 m (Fig. 5)
    load = mass * 9.81 / 8  # weight evenly on the eight points (Sec. III-C, assumption 2)
    p_st = mu * wz * 2 * sum(load * math.hypot(dx, y) for y in ys)  # eq. (14)
    p_r = k * 2 * v  # eq. (18)
    p_d = 58.0 + 164.0  # power-up + braking, tracks opposed (case d)
    expected = (p_st + p_r + p_d) / 0.95  # eq. (20)
    p = tracked.paper_params("wide", "marble")
    assert tracked.yaw_rate(p, np.array([-v]), np.array([v]))[0] == pytest.approx(wz)
    assert tracked.friction_power(p, np.array([-v]), np.array([v]))[0] == pytest.approx(p_st)
    assert tracked.total_power(p, np.array([-v]), np.array([v]))[0] == pytest.approx(expected)


def test_friction_share_at_top_spin_is_near_fig_11() -> None:
    # Fig. 11: dynamic friction reaches "close to 70 %" of P_T at w_z max (wide, marble)
    p = tracked.paper_params("wide", "marble")
    vl, vr = np.array([-0.86]), np.array([0.86])
    share = tracked.friction_power(p, vl, vr)[0] / p.eta / tracked.total_power(p, vl, vr)[0]
    assert 0.55 < share < 0.75


def test_driver_cases_of_fig_3() -> None:
    p = tracked.paper_params("wide", "marble")
    vl = np.array([0.5, 0.3, 0.0, -0.2, 0.0, 0.5])
    vr = np.array([0.5, 0.5, 0.5, 0.5, 0.0, 0.49])
    assert list(tracked.motion_case(vl, vr)) == [1, 2, 3, 4, 0, 2]
    pd = tracked.driver_power(p, vl, vr)
    expected = [58.0, 58.0 + 162.0 * 0.8, 58.0 + 164.0, 58.0 + 164.0, 58.0, 58.0 + 162.0 * 0.99]
    np.testing.assert_allclose(pd, expected)
    # ramped over 0.1 m/s: 0.01 m/s of difference gives a tenth of the step
    ramped = tracked.driver_power(p.with_(nonregen_ramp_mps=0.1), vl, vr)
    assert ramped[5] == pytest.approx(58.0 + 162.0 * 0.99 * 0.1)
    assert ramped[1] == pytest.approx(expected[1])


@settings(max_examples=60)
@given(vl=speeds, vr=speeds)
def test_tracked_power_positive_and_mirror_symmetric(vl: float, vr: float) -> None:
    for variant in ("a", "b", "c"):
        p, _ = plant._tracked_params(variant, "narrow", "asphalt", np.random.default_rng(0))
        a, b = np.array([vl]), np.array([vr])
        pt = tracked.total_power(p, a, b)[0]
        assert pt >= p.power_up_w / p.eta - 1e-9
        # mirror (left <-> right) and reverse (both signs flipped) give the same power
        assert tracked.total_power(p, b, a)[0] == pytest.approx(pt, rel=1e-9, abs=1e-9)
        assert tracked.total_power(p, -a, -b)[0] == pytest.approx(pt, rel=1e-9, abs=1e-9)


@given(v1=st.floats(0.0, 0.86), v2=st.floats(0.0, 0.86))
def test_straight_power_non_decreasing_with_speed(v1: float, v2: float) -> None:
    lo, hi = sorted((v1, v2))
    p = tracked.paper_params("wide", "asphalt")
    p_lo = tracked.total_power(p, np.array([lo]), np.array([lo]))[0]
    p_hi = tracked.total_power(p, np.array([hi]), np.array([hi]))[0]
    assert p_hi >= p_lo - 1e-9


def test_slip_law_grows_faster_than_coulomb() -> None:
    # variant (c): mu (s / 0.4)^0.3 -- a faster spin costs more than in proportion to |w_z|
    p = tracked.paper_params("wide", "marble").with_(slip_exponent=0.3)
    slow = tracked.friction_power(p, np.array([-0.2]), np.array([0.2]))[0]
    fast = tracked.friction_power(p, np.array([-0.4]), np.array([0.4]))[0]
    assert fast / slow == pytest.approx(2.0**1.3, rel=1e-9)


def test_off_centre_gravity_balances_moment_and_keeps_icrs_symmetric() -> None:
    p = tracked.paper_params("wide", "marble").with_(cg_x_m=0.05, cg_y_m=-0.1)
    xy, load = tracked.contact_points(p)
    w = 286.0 * 9.81
    assert load.sum() == pytest.approx(w)
    assert (load * xy[:, :, 0]).sum() == pytest.approx(w * 0.05)
    assert (load * xy[:, :, 1]).sum() == pytest.approx(w * -0.1)
    cxl, cxr = p.icr_x_m
    assert cxl == pytest.approx(-cxr)
    # the heavier (right) track carries more of the load-dependent resistance:
    # turning left (right track faster) costs more than the mirrored right turn
    left = tracked.resistance_power(p, np.array([0.2]), np.array([0.6]))[0]
    right = tracked.resistance_power(p, np.array([0.6]), np.array([0.2]))[0]
    assert left > right


def _chuy(inf: float, alpha: float, beta: float, r: float) -> float:
    return inf + alpha * math.exp(-beta * math.log(r + 1.0))  # eqs. (14)-(15)


@pytest.mark.parametrize(("r", "v"), [(5.0, 0.4), (2.0, 0.3), (20.0, 0.6), (1.0, 0.2)])
def test_wheeled_plant_reproduces_table_i(r: float, v: float) -> None:
    # Table I (asphalt), per wheel side: (a_inf, a_alpha, a_beta, b_inf, b_alpha, b_beta)
    inner = (7.5313, -170.0, 2.5507, 0.006, 500.0, 7.7136)
    outer = (10.2208, 250.0, 2.2187, 0.03397, 300.0, 4.818)
    p_in = _chuy(*inner[:3], r) * v + _chuy(*inner[3:], r)  # eq. (12)
    p_out = _chuy(*outer[:3], r) * v + _chuy(*outer[3:], r)
    wp = wheeled.WheeledParams()
    half = wp.track_m / (2 * wp.chi)  # side speeds of a left turn of radius r at speed v
    vl, vr = np.array([v * (1 - half / r)]), np.array([v * (1 + half / r)])
    pl, pr = wheeled.side_powers(wp, vl, vr)
    assert pl[0] == pytest.approx(p_in, rel=1e-9)  # left is the inner side
    assert pr[0] == pytest.approx(p_out, rel=1e-9)
    assert wheeled.total_power(wp, vl, vr)[0] == pytest.approx(abs(p_in) + abs(p_out))


def test_wheeled_straight_is_the_r_to_infinity_limit() -> None:
    wp = wheeled.WheeledParams()
    v = np.array([0.5])
    expected = (7.5313 + 10.2208) * 0.5 + 0.006 + 0.03397  # a_inf v + b_inf, both sides
    assert wheeled.total_power(wp, v, v)[0] == pytest.approx(expected)


def test_variant_f_family_differs_but_matches_at_0_1_inf() -> None:
    c = wheeled.TABLE_I_OUTER
    for r in (0.0, 1.0, 1e9):
        assert wheeled.rational_family(np.array([r]), *c[:3])[0] == pytest.approx(
            _chuy(*c[:3], r), rel=1e-6, abs=1e-6
        )
    r = np.linspace(0, 50, 501)
    fam = wheeled.rational_family(r, *c[:3])
    assert np.all(np.diff(fam) <= 0)  # a(r) decreasing in r, as the paper assumes after (12)
    assert abs(wheeled.rational_family(np.array([4.0]), *c[:3])[0] - _chuy(*c[:3], 4.0)) > 1.0


def test_pose_is_rep_103() -> None:
    # a left turn (right track faster) has w_z > 0 (eq. 3) and moves the robot to +y
    p = tracked.paper_params("wide", "marble")
    n = 300
    vl, vr = np.full(n, 0.3), np.full(n, 0.5)
    x, y, yaw = plant._pose(tracked.forward_speed(p, vl, vr), tracked.yaw_rate(p, vl, vr))
    assert yaw[-1] > 0 and y[-1] > 0 and x[-1] > 0


def test_case_log_is_in_the_readme_format(tmp_path: Path) -> None:
    case = plant_zoo.make_case("a", "none", 3, duration_s=60.0)
    path = plant_zoo.write_log(case, tmp_path / "run.csv")
    lines = path.read_text().splitlines()
    meta = [ln for ln in lines if ln.startswith("#")]
    assert meta == lines[: len(meta)]
    assert "# run_id: zoo-a-none-s3" in meta
    rows = list(csv.reader(lines[len(meta) :]))
    header = rows[0]
    for col in ("t", "v_left", "v_right", "p_total", "v_left_cmd", "v_right_cmd", "wz", "yaw"):
        assert col in header
    data = np.array(rows[1:], dtype=float)
    t = data[:, header.index("t")]
    assert np.all(np.diff(t) > 0)
    assert np.median(np.diff(t)) == pytest.approx(0.05)  # 20 Hz
    dropped = 1 - len(t) / 1200
    assert 0.005 < dropped < 0.08  # some samples are lost, as on a real logger
    cmd = data[:, header.index("v_left_cmd")]
    np.testing.assert_allclose(cmd, np.round(cmd / 0.01) * 0.01, atol=1e-6)  # 0.01 m/s quantum
    assert np.all(np.isfinite(data))


def test_speeds_within_limits_and_manoeuvres_varied() -> None:
    c = plant_zoo.make_case("a", "none", 0)
    vl, vr = c.columns["v_left_cmd"], c.columns["v_right_cmd"]
    assert max(np.abs(vl).max(), np.abs(vr).max()) <= 0.86
    cases = set(tracked.motion_case(vl, vr).tolist())
    assert {0, 1, 2, 4} <= cases  # stops, straights, arcs, spot turns / pivots
    w = plant_zoo.make_case("g", "none", 0)
    assert w.plant_power_w.max() < 2 * 12.0  # two sides, each under the Pioneer side limit
    assert np.abs(w.columns["v_left_cmd"]).max() <= 0.9


def test_effects_act_where_they_physically_should() -> None:
    base = plant_zoo.make_case("b", "none", 1)
    t = base.columns["t"]
    # a payload switched on mid-run changes nothing before it, raises power after
    pay = plant_zoo.make_case("b", "payload", 1)
    t_on = pay.effect_params["t_on_frac"] * 180.0
    same = np.intersect1d(t, pay.columns["t"])
    pb = base.plant_power_w[np.isin(t, same)]
    pp = pay.plant_power_w[np.isin(pay.columns["t"], same)]
    before, after = same < t_on - 0.1, same > t_on + 0.1
    np.testing.assert_allclose(pp[before], pb[before])
    assert np.all(pp[after] >= pb[after] - 1e-9) and pp[after].mean() > pb[after].mean()
    # sensor-side effects leave the plant's true power alone
    for e in ("sensor_delay", "power_gain", "ripple"):
        c = plant_zoo.make_case("b", e, 1)
        common = np.intersect1d(t, c.columns["t"])
        np.testing.assert_allclose(
            c.plant_power_w[np.isin(c.columns["t"], common)],
            base.plant_power_w[np.isin(t, common)],
        )


def test_deterministic_and_checked() -> None:
    a = plant_zoo.make_case("e", "slope", 2, duration_s=30.0)
    b = plant_zoo.make_case("e", "slope", 2, duration_s=30.0)
    for k in a.columns:
        np.testing.assert_array_equal(a.columns[k], b.columns[k])
    with pytest.raises(ValueError, match="unknown variant"):
        plant_zoo.make_case("z", "none", 0)
    with pytest.raises(ValueError, match="unknown effect"):
        plant_zoo.make_case("a", "gremlins", 0)
    assert len(plant_zoo.VARIANTS) >= 6
    assert {k for k, _ in plant_zoo.VARIANTS.values()} == {"tracked", "wheeled"}
    assert len(plant_zoo.IN_LIBRARY) == 10 and len(plant_zoo.OUT_OF_LIBRARY) >= 3


def test_power_saturation_slows_the_drive_instead_of_exceeding_the_supply() -> None:
    for variant in ("a", "g"):
        c = plant_zoo.make_case(variant, "power_saturation", 2, duration_s=90.0)
        cap = c.effect_params["cap_w"]
        eta = 0.95 if variant == "a" else 1.0
        # the supply limit is on the drive demand (P_M + P_D); the meter sees it over eta
        assert c.plant_power_w.max() <= cap / eta * (1 + 1e-6)
        free = plant_zoo.make_case(variant, "none", 2, duration_s=90.0)
        assert free.plant_power_w.max() > cap / eta  # the limit did bind


@pytest.mark.parametrize("variant", ["a", "g"])
def test_the_library_reads_a_zoo_log_whole(tmp_path: Path, variant: str) -> None:
    # the README log format is the contract: ecoplan's reader takes every row and column
    from ecoplan.io.logcsv import read_log_csv

    case = plant_zoo.make_case(variant, "none", 1, duration_s=30.0)
    log = read_log_csv(plant_zoo.write_log(case, tmp_path / "zoo.csv"))
    assert log.dropped_rows == 0
    assert log.run_id == f"zoo-{variant}-none-s1"
    for col in ("t", "v_left", "v_right", "p_total", "v_left_cmd", "x", "y", "yaw", "wz"):
        got = getattr(log, col)
        assert got is not None
        np.testing.assert_allclose(got, case.columns[col], rtol=1e-5, atol=1e-5)


def test_meter_power_carries_the_sensor_effects_but_no_noise() -> None:
    c = plant_zoo.make_case("a", "power_gain", 0, duration_s=120.0)
    t, g = c.columns["t"], c.effect_params["gain"]
    t_on = c.effect_params["t_on_frac"] * 120.0
    late, early = t > t_on + 0.05, t < t_on - 0.05
    np.testing.assert_allclose(c.true_power_w[late], g * c.plant_power_w[late])
    np.testing.assert_allclose(c.true_power_w[early], c.plant_power_w[early])
    noise = c.columns["p_total"] - c.true_power_w
    assert 5.0 < np.std(noise) < 30.0  # the 15 W coloured meter noise is only in the log
