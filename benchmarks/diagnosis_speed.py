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
from typing import Any

os.environ.setdefault("OMP_NUM_THREADS", "1")
os.environ.setdefault("OPENBLAS_NUM_THREADS", "1")
os.environ.setdefault("MKL_NUM_THREADS", "1")

import numpy as np

from ecoplan.diagnose.pipeline import diagnose
from ecoplan.dynamics.log import Log
from ecoplan.synth.cases import generate_case

TARGET_S = 30.0
POSE = ("x", "y", "yaw")


def one_run(logs: list[Log]) -> Log:
    """The runs joined into one on one clock (each starts a sample period after the last).

    Columns every run has are joined; the pose columns are left out (they jump between runs).
    """
    clocks, t_next = [], 0.0
    for lg in logs:
        clocks.append(lg.t - lg.t[0] + t_next)
        t_next = float(clocks[-1][-1]) + float(np.median(np.diff(lg.t)))
    columns: dict[str, Any] = {}
    for f in dataclasses.fields(Log):
        parts = [getattr(lg, f.name) for lg in logs]
        if f.name not in ("t", *POSE) and all(isinstance(a, np.ndarray) for a in parts):
            columns[f.name] = np.concatenate(parts)
    return Log(t=np.concatenate(clocks), source="<one run>", run_id="session", **columns)


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
    logs = [one_run(list(case.logs))] if args.one_run else list(case.logs)
    if args.no_pose:
        logs = [dataclasses.replace(lg, **dict.fromkeys(POSE)) for lg in logs]
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
