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
``--write FILE`` writes the identified vehicle file (the shipped
``src/ecoplan/models/vehicle_files/husky-a200.yaml`` is made this way)::

    PYTHONPATH=src .venv/bin/python benchmarks/husky_terrains.py [--boot 200] [--write FILE]
"""

from __future__ import annotations

import argparse
import sys
from pathlib import Path

import numpy as np

from ecoplan.io.borealtc import HUSKY_BUS_VOLTAGE_V, list_terrains, load_runs
from ecoplan.models.identify import leave_one_run_out
from ecoplan.models.identify_logs import DriveLog, identify_vehicle
from ecoplan.models.vehicles import vehicle_from_mapping

_ASSUMED = {"source": "assumption", "ref": "starting value only; identified per terrain"}

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
    "inertia": {"mass_kg": 70.0},
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


def main() -> int:
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--boot", type=int, default=200, help="bootstrap resamples per terrain")
    ap.add_argument("--write", type=Path, default=None, help="write the identified vehicle file")
    args = ap.parse_args()
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
