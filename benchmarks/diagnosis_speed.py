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
Cholesky factor of the normal equations: 22.2 s (tracked: 13.3 s).  Session 30 put the
calibration's bounded fits on that same solver (:func:`ecoplan.diagnose.lsq.bounded_lstsq`),
on a machine slower than session 23's (the test suite 600 -> 820 s on the same code): wheeled
28.3 / 31.9 s per hour before, 27.5 / 28.5 s after (two runs each); tracked 19.3 -> 18.3 s.

``--one-run`` joins the session into one continuous run on one clock (the pose columns are
left out: they jump between runs), as a robot logging for an hour without a break writes it.
The change-point search of ``where_time`` then works on one long run instead of 43 short
ones: session 25 measured 24.5 s for that hour with ``ruptures.Pelt`` in Python, 11.1 s
with the same search in C (``ruptures.KernelCPD``); 160 runs joined (3.8 h) took 68.0 s,
then 36.3 s.

``--no-pose`` leaves the pose out of every run: without it, ``slope`` searches one heading
offset per run (a plane fitted per run first, two columns each; session 26).
"""

from __future__ import annotations

import argparse
import dataclasses
import os
import time

os.environ.setdefault("OMP_NUM_THREADS", "1")
os.environ.setdefault("OPENBLAS_NUM_THREADS", "1")
os.environ.setdefault("MKL_NUM_THREADS", "1")

from ecoplan.diagnose.pipeline import diagnose
from ecoplan.dynamics.log import POSE_COLUMNS, join_runs
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
    ap.add_argument(
        "--one-run",
        action="store_true",
        help="join the session into one continuous run (one long change-point search)",
    )
    ap.add_argument(
        "--no-pose",
        action="store_true",
        help="leave the pose columns out of every run (a slope's heading offset per run searched)",
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
    logs = [join_runs(case.logs, "session")[0]] if args.one_run else list(case.logs)
    if args.no_pose:
        logs = [dataclasses.replace(lg, **dict.fromkeys(POSE_COLUMNS)) for lg in logs]
    n = sum(len(lg) for lg in logs)
    dur_h = sum(lg.duration_s for lg in logs) / 3600.0
    t0 = time.process_time()
    w0 = time.perf_counter()
    d = diagnose(logs, case.vehicle, case.terrain)
    cpu = time.process_time() - t0
    wall = time.perf_counter() - w0
    per_hour = wall / dur_h
    print(f"log: {len(logs)} runs, {n} samples, {dur_h:.2f} h at {args.rate:g} Hz")
    print(
        f"diagnosis: wall {wall:.1f} s, cpu {cpu:.1f} s -> {per_hour:.1f} s per hour of log "
        f"(target < {TARGET_S:.0f} s)  verdict={d.verdict} (truth {case.truth.effect})"
    )
    print(f"ratio to target: {per_hour / TARGET_S:.2f}")
    return 0 if per_hour < TARGET_S else 1


if __name__ == "__main__":
    raise SystemExit(main())
