"""Speed of the diagnosis: one hour of 100 Hz log diagnosed on one core (issue 6, item 5).

Generates a session of about one hour at 100 Hz with :func:`ecoplan.synth.cases.generate_case`
(inertia at moderate magnitude, 40 A->B runs plus the grid and spirals), then times
:func:`ecoplan.diagnose.pipeline.diagnose` on it.  Target: under 30 s.  Run with one BLAS thread::

    OMP_NUM_THREADS=1 OPENBLAS_NUM_THREADS=1 .venv/bin/python benchmarks/diagnosis_speed.py

``--vehicle pioneer-3at`` times the wheeled path on the same kind of session (the small-radius
shape search of the naming rule's structural alternative dominates it; session 16 measured
273 s per hour, then 58 s with the search on at most 8 000 samples; session 17 27 s, with the
search on 4 000, the calibration's bounded fits on the QR factor and fewer sign passes).
Session 22 bounded the effects' wheeled refits and took it to 37.7 s per hour (their bounded
least squares on the whole design, 3 100 times); session 23 solves those on the k x k
Cholesky factor of the normal equations: 22.2 s (tracked: 13.3 s).
"""

from __future__ import annotations

import argparse
import os
import time

os.environ.setdefault("OMP_NUM_THREADS", "1")
os.environ.setdefault("OPENBLAS_NUM_THREADS", "1")
os.environ.setdefault("MKL_NUM_THREADS", "1")

from ecoplan.diagnose.pipeline import diagnose
from ecoplan.synth.cases import generate_case

TARGET_S = 30.0


def main() -> int:
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--runs", type=int, default=40, help="A->B runs in the session")
    ap.add_argument("--rate", type=float, default=100.0, help="sample rate [Hz]")
    ap.add_argument("--seed", type=int, default=0)
    ap.add_argument(
        "--vehicle",
        default="auriga-beta-narrow",
        help="preset the session is generated for (pioneer-3at: the wheeled path, on asphalt)",
    )
    args = ap.parse_args()
    case = generate_case(
        args.seed,
        "inertia",
        "moderate",
        vehicle=args.vehicle,
        terrain="asphalt",
        n_waypoint_runs=args.runs,
        rate_hz=args.rate,
    )
    n = sum(len(lg) for lg in case.logs)
    dur_h = sum(lg.duration_s for lg in case.logs) / 3600.0
    t0 = time.process_time()
    w0 = time.perf_counter()
    d = diagnose(list(case.logs), case.vehicle, case.terrain)
    cpu = time.process_time() - t0
    wall = time.perf_counter() - w0
    per_hour = wall / dur_h
    print(f"log: {len(case.logs)} runs, {n} samples, {dur_h:.2f} h at {args.rate:g} Hz")
    print(
        f"diagnosis: wall {wall:.1f} s, cpu {cpu:.1f} s -> {per_hour:.1f} s per hour of log "
        f"(target < {TARGET_S:.0f} s)  verdict={d.verdict} (truth {case.truth.effect})"
    )
    print(f"ratio to target: {per_hour / TARGET_S:.2f}")
    return 0 if per_hour < TARGET_S else 1


if __name__ == "__main__":
    raise SystemExit(main())
