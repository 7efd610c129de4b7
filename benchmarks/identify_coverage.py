"""Coverage of ``identify_vehicle``'s intervals on simulated free driving (issue 13).

For a wheeled robot (the 50 kg, 0.55 m-gauge example ``scenarios/vehicles/robot50.yaml``)
and a tracked one (the shipped ``auriga-beta-wide``), each seed simulates three 200 s logs
of free driving (:func:`ecoplan.models.identify_logs.free_driving_log`: straight driving,
arcs, pivot and spot turns; noise as in the blind benchmark: power 2 % + 3 W, side speeds
0.005 m/s), identifies the vehicle and checks whether *every* identified parameter lies in
its reported (joint 95 %) interval.  Target: >= 90 % of seeds::

    PYTHONPATH=src .venv/bin/python benchmarks/identify_coverage.py [--seeds 100] [--boot 100]
"""

from __future__ import annotations

import argparse
import sys
import time
from pathlib import Path

import yaml

from ecoplan.models.identify_logs import free_driving_log, identify_vehicle
from ecoplan.models.vehicles import Vehicle, shipped_vehicle, vehicle_from_mapping

ROBOT50 = Path(__file__).resolve().parents[1] / "scenarios" / "vehicles" / "robot50.yaml"


def covered(vehicle: Vehicle, seed: int, n_boot: int) -> tuple[bool, list[str]]:
    logs = [
        free_driving_log(vehicle, rng=seed * 10 + k, run_id=f"r{k}", duration_s=200)
        for k in range(3)
    ]
    fit = identify_vehicle(logs, vehicle, rng=seed, n_boot=n_boot).fits[vehicle.default_terrain]
    truth = vehicle.params()
    missed = [
        name for name, (lo, hi) in fit.intervals.items() if not lo <= getattr(truth, name) <= hi
    ]
    return not missed, missed


def main() -> int:
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--seeds", type=int, default=100)
    ap.add_argument("--boot", type=int, default=100)
    args = ap.parse_args()
    robot = vehicle_from_mapping(yaml.safe_load(ROBOT50.read_text()), str(ROBOT50))
    auriga = shipped_vehicle("auriga-beta-wide")
    ok_all = True
    vehicles = (("wheeled robot50", robot), ("tracked auriga-beta-wide", auriga))
    for label, vehicle in vehicles:
        t0 = time.perf_counter()
        hits, misses = 0, {}
        for seed in range(args.seeds):
            ok, missed = covered(vehicle, seed, args.boot)
            hits += ok
            for name in missed:
                misses[name] = misses.get(name, 0) + 1
        share = hits / args.seeds
        ok_all &= share >= 0.9
        print(
            f"{label:<26} all parameters inside their intervals in {hits}/{args.seeds} seeds "
            f"({100 * share:.0f} %, target >= 90 %); misses by parameter: {misses or '-'} "
            f"[{time.perf_counter() - t0:.0f} s]"
        )
    print("target met" if ok_all else "target NOT met")
    return 0


if __name__ == "__main__":
    sys.exit(main())
