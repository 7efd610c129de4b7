"""Husky A200 on five real terrains: the identified vehicle file against the static baseline.

Data: the shared BorealTC runs (``../shared/data/borealtc``: ASPHALT, FLOORING, ICE,
SANDY_LOAM, SNOW; power ``24 V x (|I_L| + |I_R|)``, the 24 V bus an assumption).  Per terrain:

* **baseline**: the static three-coefficient model of the data's ABOUT.md,
  ``P = c0 + c1 (|vL| + |vR|) + c2 |ω|`` (ω from the side speeds), least squares,
  leave-one-run-out (:func:`ecoplan.models.identify.leave_one_run_out`);
* **identified**: :func:`ecoplan.models.identify_logs.identify_vehicle` on the runs of the
  terrain (contact-friction model with the Husky's geometry and mass, acceleration power
  included), leave-one-run-out as well;
* MAE of the power over all held-out samples [W] and the energy of each held-out run,
  predicted vs measured [%] (median of the absolute errors).

Targets (issue 13): beat the baseline's MAE on every terrain; median energy error <= 10 %.
Both are missed on ASPHALT (and the energy target on SNOW); ``--explain`` prints what the
data say about why (the logged "power" behaves as a force, and on ASPHALT it falls with
speed even driving straight)::

    PYTHONPATH=src .venv/bin/python benchmarks/husky_terrains.py --explain
``--write FILE`` writes the identified vehicle file (the shipped
``src/ecoplan/models/vehicle_files/husky-a200.yaml`` is made this way)::

    PYTHONPATH=src .venv/bin/python benchmarks/husky_terrains.py [--boot 200] [--write FILE]
"""

from __future__ import annotations

import argparse
import itertools
import sys
from pathlib import Path

import numpy as np

from ecoplan.io.borealtc import HUSKY_BUS_VOLTAGE_V, data_root, list_terrains, load_runs
from ecoplan.models.identify import leave_one_run_out
from ecoplan.models.identify_logs import DriveLog, identify_vehicle
from ecoplan.models.vehicles import vehicle_from_mapping

_ASSUMED = {"source": "assumption", "ref": "starting value only; identified per terrain"}
HUSKY_BASE_MASS_KG = 70.0

#: The Husky before identification: geometry and mass (known), per-terrain values to fit.
HUSKY_BASE: dict[str, object] = {
    "name": "husky-a200",
    "kind": "wheeled",
    "power_model": "contact-friction",
    "description": (
        "Clearpath Husky A200, four-wheel skid-steer. Power model of the tracked paper "
        "(eqs. 7-20) with the four wheels as punctual contacts, identified per terrain from "
        "the BorealTC runs by benchmarks/husky_terrains.py (ecoplan identify)."
    ),
    "geometry": {
        "track_gauge_m": 0.555,
        "wheelbase_m": 0.512,
        "n_contact_points": 2,
        "wheel_radius_m": 0.165,
        "chi": 0.5333,
    },
    "inertia": {"mass_kg": HUSKY_BASE_MASS_KG},
    "limits": {"top_speed_mps": 1.0, "accel_max_mps2": 1.0},
    "drivers": {"eta": 1.0, "regen_efficiency": 0.0},
    "default_terrain": "asphalt",
    "terrains": {
        "asphalt": {
            name: {"value": 0.0, **_ASSUMED}
            for name in ("mu", "k_resistance_n", "p_powerup_w", "p_braking_w", "k_nonregen_n")
        }
    },
    "assumptions": [
        f"power = {HUSKY_BUS_VOLTAGE_V:g} V x (|I_L| + |I_R|): the 24 V bus is assumed "
        "(the logs have no voltage column)",
        "geometry from Clearpath's Husky description: wheel separation 0.555 m, wheelbase "
        "0.512 m, wheel radius 0.165 m; chi = 1 / 1.875 (wheel_separation_multiplier)",
        "mass 70 kg (BorealTC ABOUT.md: the robot with its payload); yaw inertia a uniform box",
        "eta = 1: the logged power is at the bus, the fitted terms include the drive losses",
        "top speed 1.0 m/s (Clearpath specification); acceleration 1.0 m/s^2 (assumption)",
        "held-out errors: leave-one-run-out on the runs of the terrain",
    ],
}


#: Speed bins of the straight-driving table [m/s].
_BINS = (0.05, 0.3, 0.6, 1.0)


def _mean_around(t: np.ndarray, x: np.ndarray, at: np.ndarray, width_s: float) -> np.ndarray:
    """Mean of ``x(t)`` over ``width_s`` centred on each time of ``at``."""
    c = np.concatenate([[0.0], np.cumsum(x)])
    i0 = np.searchsorted(t, at - width_s / 2)
    i1 = np.searchsorted(t, at + width_s / 2)
    return (c[i1] - c[i0]) / np.maximum(i1 - i0, 1)


def explain() -> None:
    """Print what the logs say about the shape of the Husky's power (no fitting)."""
    print("1. straight driving (|vR - vL| < 0.03 m/s): mean 24 V x (|I_L| + |I_R|) [W] per run")
    print("   and speed bin; a power that grows with speed (K v) would rise along each row")
    head = " ".join(f"[{lo:.2f},{hi:.2f})" for lo, hi in itertools.pairwise(_BINS))
    print(f"   {'terrain':<11} run  {head}")
    for terrain in list_terrains():
        for r in load_runs(terrain):
            speed = 0.5 * (np.abs(r.v_left) + np.abs(r.v_right))
            straight = (np.abs(r.v_right - r.v_left) < 0.03) & (speed > _BINS[0])
            cells = []
            for lo, hi in itertools.pairwise(_BINS):
                m = straight & (speed >= lo) & (speed < hi)
                cells.append(f"{r.p_total[m].mean():11.0f}" if m.sum() > 30 else " " * 11)
            if any(c.strip() for c in cells):
                print(f"   {terrain.lower():<11} {r.run_id:>3}  {' '.join(cells)}")
    print("\n2. spot turns (vL = -vR): mean power against the turning speed |vR - vL| / 2")
    for terrain in list_terrains():
        pairs = []
        for r in load_runs(terrain):
            spot = (r.v_left * r.v_right < 0) & (np.abs(r.v_left + r.v_right) < 0.03)
            if spot.sum() > 100:
                turn = float(np.mean(np.abs(r.v_right - r.v_left)[spot]) / 2)
                pairs.append((turn, float(r.p_total[spot].mean())))
        if pairs:
            row = "  ".join(f"{v:.2f} m/s: {p:.0f} W" for v, p in sorted(pairs))
            print(f"   {terrain.lower():<11} {row}")
    print("\n3. grade from the IMU (pitch = (a_x - dv/dt) / g, 2 s means): power against")
    print("   M g sin(pitch) on straight driving, slope [(W) per (M g sin(pitch) in N)]:")
    for terrain in list_terrains():
        slopes = []
        for r in load_runs(terrain):
            path = data_root() / terrain / f"imu_{r.run_id}.csv"
            if not path.is_file():
                continue
            imu = np.genfromtxt(path, delimiter=",", names=True)
            ax = _mean_around(imu["time"], imu["ax"], r.t, 2.0)
            v = 0.5 * (r.v_left + r.v_right)
            a = np.gradient(_mean_around(r.t, v, r.t, 2.0), r.t)
            force = HUSKY_BASE_MASS_KG * 9.81 * np.clip((ax - a) / 9.81, -0.5, 0.5) * np.sign(v)
            straight = (np.abs(r.v_right - r.v_left) < 0.03) & (np.abs(v) > 0.05)
            if straight.sum() > 100 and np.std(force[straight]) > 1.0:
                slopes.append(float(np.polyfit(force[straight], r.p_total[straight], 1)[0]))
        if slopes:
            print(
                f"   {terrain.lower():<11} median {np.median(slopes):.2f} m/s over "
                f"{len(slopes)} runs (range {min(slopes):.2f} .. {max(slopes):.2f})"
            )
    print(
        "\nReading: on every terrain the straight-driving power is about constant in speed"
        "\n(a force, not force x speed); on ICE and SANDY_LOAM spot turns draw the same power"
        "\nat any turning speed (on SNOW it even falls with it); the grade enters as"
        "\nM g sin(pitch) times about 1 m/s, not times the driving speed (ICE: nearly flat, no"
        "\nslope to read).  The logged 24 V x |I| behaves as the motor torque (the motor"
        "\ncurrents), not as the battery power, so a model of power = force x speed misfits"
        "\nit.  On ASPHALT the straight power also falls with speed (the fast samples are"
        "\nsteady driving at the 0.79 m/s top speed), which no physical term here explains."
    )


def main() -> int:
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--boot", type=int, default=200, help="bootstrap resamples per terrain")
    ap.add_argument("--write", type=Path, default=None, help="write the identified vehicle file")
    ap.add_argument("--explain", action="store_true", help="print what the data say, no fit")
    args = ap.parse_args()
    if args.explain:
        explain()
        return 0
    base = vehicle_from_mapping(HUSKY_BASE, "husky_terrains.py")
    logs, baselines = [], {}
    for terrain in list_terrains():
        runs = load_runs(terrain)
        baselines[terrain.lower()] = leave_one_run_out(runs)
        logs += [DriveLog(r.t, r.v_left, r.v_right, r.p_total, terrain, r.run_id) for r in runs]
    res = identify_vehicle(logs, base, rng=0, n_boot=args.boot, clamp=True)
    print(
        f"{'terrain':<11} {'runs':>4} {'mean P':>7} {'baseline MAE':>12} {'identified MAE':>14}"
        f" {'beats':>5} {'median |dE|':>11} {'<=10 %':>6}  clamped (unconstrained value)"
    )
    all_ok = True
    for terrain, fit in sorted(res.fits.items()):
        b = baselines[terrain]
        beats = fit.heldout_mae_w < b.pooled_mae_w
        e_ok = fit.median_energy_error <= 0.10
        all_ok &= beats and e_ok
        clamped = ", ".join(f"{k} ({v:.3g})" for k, v in fit.clamped.items()) or "-"
        print(
            f"{terrain:<11} {len(fit.run_ids):>4} {fit.mean_power_w:>6.0f}W"
            f" {b.pooled_mae_w:>11.1f}W {fit.heldout_mae_w:>13.1f}W {'yes' if beats else 'NO':>5}"
            f" {100 * fit.median_energy_error:>10.1f}% {'yes' if e_ok else 'NO':>6}  {clamped}"
        )
    print("\nper-run held-out energy error [%] (predicted / measured - 1):")
    for terrain, fit in sorted(res.fits.items()):
        errs = " ".join(f"{100 * e:+.0f}" for e in fit.heldout_energy_error)
        print(f"  {terrain:<11} {errs}")
    print("\nidentified values (interval):")
    for terrain, fit in sorted(res.fits.items()):
        vals = ", ".join(
            f"{k} {fit.values[k]:.3g} [{fit.intervals[k][0]:.3g}, {fit.intervals[k][1]:.3g}]"
            for k in fit.identified
        )
        print(f"  {terrain:<11} {vals}")
    if args.write is not None:
        header = (
            "Clearpath Husky A200 identified on the BorealTC runs (five terrains).\n"
            "Written by: PYTHONPATH=src python benchmarks/husky_terrains.py "
            f"--boot {args.boot} --write <this file>\n"
            "Power = 24 V x (|I_L| + |I_R|): the 24 V bus is an assumption."
        )
        args.write.write_text(res.to_yaml(header), encoding="utf-8")
        print(f"\nwrote {args.write}")
    print("\nall targets met" if all_ok else "\nsome targets NOT met (see the table)")
    return 0


if __name__ == "__main__":
    np.seterr(all="ignore")
    sys.exit(main())
