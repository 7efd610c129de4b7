"""Throughput of the power models, cost and accuracy of identification, Husky static fit.

Run: ``.venv/bin/python benchmarks/model_throughput.py [--pairs 1000000] [--seeds 10]``

Prints

1. ``P_T`` evaluations per second of :func:`ecoplan.models.tracked_power` over random
   track-speed pairs on one core (BLAS/OpenMP threads pinned to 1; NumPy's element-wise
   loops are single-threaded anyway), for the total only
   (:func:`~ecoplan.models.tracked_total_power`) and for the full breakdown, timed
   interleaved with one ``numpy.add`` pass over the same arrays whose ratio can be
   compared across machines and loads;
2. the time and the recovered-parameter errors of the identification round trips
   (tracked §III-C by Nelder-Mead, wheeled §III-A by least squares);
3. the leave-one-run-out error of the static model on the BorealTC Husky runs.
"""

from __future__ import annotations

import os

for _var in ("OMP_NUM_THREADS", "OPENBLAS_NUM_THREADS", "MKL_NUM_THREADS"):
    os.environ.setdefault(_var, "1")

import argparse  # noqa: E402
import time  # noqa: E402
from collections.abc import Callable  # noqa: E402

import numpy as np  # noqa: E402

from ecoplan.errors import InputError  # noqa: E402
from ecoplan.io.borealtc import data_root, list_terrains, load_runs  # noqa: E402
from ecoplan.models import TrackedParams, WheeledParams, tracked_total_power  # noqa: E402
from ecoplan.models.identify import (  # noqa: E402
    TrackedIdentifier,
    WheeledIdentifier,
    cmd_experiments,
    leave_one_run_out,
    stationary_experiments,
)
from ecoplan.presets import vehicle  # noqa: E402


def throughput(pairs: int, repeats: int) -> None:
    """Evaluations per second, timed interleaved with a numpy-add pass (same conditions)."""
    rng = np.random.default_rng(0)
    tracked = vehicle("auriga-beta-wide", "marble")
    wheeled = vehicle("pioneer-3at", "asphalt")
    assert isinstance(tracked, TrackedParams)
    vl = rng.uniform(-0.86, 0.86, pairs)
    vr = rng.uniform(-0.86, 0.86, pairs)
    calls: dict[str, Callable[[], object]] = {
        "numpy add (reference)": lambda: np.add(vl, vr),
        "tracked P_T only": lambda: tracked_total_power(vl, vr, tracked),
        "tracked breakdown": lambda: tracked.power(vl, vr),
        "wheeled breakdown": lambda: wheeled.power(vl, vr),
    }
    times: dict[str, list[float]] = {name: [] for name in calls}
    for _ in range(repeats):  # interleaved: every call sees the same machine load
        for name, fn in calls.items():
            t0 = time.perf_counter()
            fn()
            times[name].append(time.perf_counter() - t0)
    ref = float(np.median(times["numpy add (reference)"]))
    print(f"== throughput over {pairs:,} random track-speed pairs, one core, {repeats} runs")
    print(f"   load average {os.getloadavg()[0]:.1f} on {os.cpu_count()} cores")
    for name, ts in times.items():
        best, median = min(ts), float(np.median(ts))
        print(
            f"{name:22s} best {pairs / best / 1e6:7.1f} M/s  median {pairs / median / 1e6:7.1f} M/s"
            f"  = {median / ref:5.1f} numpy-add passes"
        )


def _tracked_identification(seeds: int) -> None:
    print(f"== tracked identification (§III-C), {seeds} noise seeds per preset, 20 W/sample")
    names = ("mu", "k_resistance_n", "p_powerup_w", "p_braking_w", "k_nonregen_n")
    print(f"{'preset':28s} {'time/fit':>9s} " + " ".join(f"{n:>15s}" for n in names))
    for preset in (
        ("auriga-beta-wide", "marble"),
        ("auriga-beta-narrow", "marble"),
        ("auriga-beta-wide", "asphalt"),
        ("auriga-beta-narrow", "asphalt"),
    ):
        truth = vehicle(*preset)
        assert isinstance(truth, TrackedParams)
        errs: dict[str, list[float]] = {n: [] for n in names}
        t0 = time.perf_counter()
        for seed in range(seeds):
            fit = TrackedIdentifier(truth).fit(stationary_experiments(truth, rng=seed))
            for key, val in fit.relative_errors(truth).items():
                errs[key].append(val)
        per_fit = (time.perf_counter() - t0) / seeds
        cells = " ".join(
            f"{100 * np.mean(errs[n]):5.2f}/{100 * np.max(errs[n]):5.2f} %" for n in names
        )
        print(f"{'/'.join(preset):28s} {per_fit * 1e3:7.1f}ms {cells}")
    print("  (cells: mean/max relative error over seeds; time includes generating the data)")


def _wheeled_identification(seeds: int) -> None:
    print(f"== wheeled identification (§III-A), {seeds} noise seeds, 0.5 W/sample")
    for terrain in ("asphalt", "vinyl"):
        truth = vehicle("pioneer-3at", terrain)
        assert isinstance(truth, WheeledParams)
        rel: list[float] = []
        b_inf: list[float] = []
        t0 = time.perf_counter()
        for seed in range(seeds):
            fit = WheeledIdentifier(truth).fit(cmd_experiments(truth, rng=seed))
            for got, want in ((fit.inner_, truth.inner), (fit.outer_, truth.outer)):
                g, w = got.as_array(), want.as_array()
                rel.append(
                    float(np.max(np.abs(g - w)[[0, 1, 2, 4, 5]] / np.abs(w[[0, 1, 2, 4, 5]])))
                )
                b_inf.append(float(abs(g[3] - w[3])))
        per_fit = (time.perf_counter() - t0) / seeds
        print(
            f"pioneer-3at/{terrain:8s} {per_fit * 1e3:7.1f} ms/fit   worst relative error of "
            f"a_inf, alphas, betas: mean {100 * np.mean(rel):.2f} %, max {100 * np.max(rel):.2f} %"
            f"   |b_inf error| max {max(b_inf):.3f} W"
        )


def _husky() -> None:
    print("== Husky (BorealTC) static fit P = c0 + c1(|vL|+|vR|) + c2|w|, leave one run out")
    try:
        terrains = list_terrains()
    except InputError as exc:
        print(f"skipped: {exc}")
        return
    print(f"data: {data_root()}  (P = 24 V x (curL + curR): bus voltage assumed)")
    for terrain in terrains:
        runs = load_runs(terrain)
        for yaw in ("sides", "imu"):
            t0 = time.perf_counter()
            loo = leave_one_run_out(runs, yaw=yaw)
            dt = time.perf_counter() - t0
            print(
                f"{terrain:9s} w from {yaw:5s}: MAE mean over {len(loo.mae_w):2d} runs "
                f"{loo.mean_mae_w:5.1f} W, pooled {loo.pooled_mae_w:5.1f} W, "
                f"mean power {loo.mean_power_w:5.1f} W  ({dt * 1e3:.0f} ms)"
            )


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--pairs", type=int, default=1_000_000)
    parser.add_argument("--repeats", type=int, default=7)
    parser.add_argument("--seeds", type=int, default=10)
    args = parser.parse_args()
    throughput(args.pairs, args.repeats)
    _tracked_identification(args.seeds)
    _wheeled_identification(args.seeds)
    _husky()


if __name__ == "__main__":
    main()
