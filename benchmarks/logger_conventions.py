"""The zoo's logs as field loggers write them: does the diagnosis hold? (issue 12, item 3).

``plant_zoo_diagnosis.py`` diagnoses the zoo's logs as the zoo writes them: one file per
case, one world frame for the pose, every column fresh at every row.  Field logs are
seldom like that.  This benchmark rewrites each zoo case the way a logger, an export or an
operator would, with numpy on the zoo's own columns (nothing of ecoplan's is used to make
them), reads the files with the library's CSV reader (the ``bag`` ones with its ROS 2 bag
reader) and diagnoses them:

``as_logged``
    The zoo's file, unchanged (the reference).
``no_metadata``
    The zoo's file without its ``#`` lines (a user's own CSV: the ``power_sampling:
    interval_mean`` of the zoo's meter is not said).
``power_held``
    ``p_total`` repeated over 4 rows (a 5 Hz meter in the 20 Hz rows of an export that
    writes a row whenever any stream updates); the export carries no ``power_sampling`` line.
``speeds_held``
    ``v_left`` and ``v_right`` repeated over 4 rows (an encoder driver at 5 Hz), likewise.
``pose_held``
    ``x``, ``y``, ``yaw`` repeated over 4 rows (a 5 Hz GNSS or localisation in the 20 Hz rows),
    the other columns and the metadata as logged; ``pose_1hz`` over 20 rows (a 1 Hz fix).
``time_jitter``
    ``t`` moved by up to :data:`JITTER_S` either way at random, the readings kept: a logger
    that stamps rows on receipt, not at sampling.
``runs_no_pose``
    Cut into three files (runs) at 60 s and 120 s, ``x``, ``y``, ``yaw`` removed: the heading
    is known only per run, from ``wz``.
``runs_odom``
    Cut likewise, each run's pose re-expressed in the frame it started in (odometry restarted
    with every launch) and declared ``# pose_frame: run``.
``sign_flipped``
    ``p_total`` negated (a battery current signed negative when discharging): right is a
    refusal naming ``p_total``.
``yaw_degrees``, ``yaw_bearing``
    ``yaw`` in degrees, or as a compass bearing (from north, clockwise, in (-pi, pi]): right
    is a refusal naming ``yaw``.
``rotated_overlap``
    One file, the three 60 s pieces joined end to end, each after the first beginning with
    the last :data:`OVERLAP_ROWS` rows of the one before (a rotating logger's files, which
    overlap, joined with ``cat``).
``runs_one_file``
    One file, the three pieces each on its own clock from 0 (a logger that appends every
    launch to one file, its time since start): right is a refusal naming ``t`` that says to
    give each run its own file.
``rows_10hz``
    A 10 Hz logger: every other row, the power the mean of the two (still an interval mean,
    now over 0.1 s), the other columns read at the later row; a pair with a dropped row is
    lost.  The CSV reference for the bags' 10 Hz battery.
``bag``, ``bag_rates``, ``bag_battery_1hz``
    The zoo's columns as a robot's drivers publish them, in a ROS 2 bag (``zoo_bag.py``,
    with ``rosbags`` only): wheel joint rates, a ``BatteryState`` (voltage and current, the
    mean over its window), odometry and a ``cmd_vel`` twist, read with the library's bag
    reader and a topic map (the power topic's rate for the time base, as a user gets by
    default).  Every topic at the zoo's 20 Hz; the battery and ``cmd_vel`` at 10 Hz; the
    battery at 1 Hz (a battery management system's rate), ``cmd_vel`` at 10 Hz.
``bag_rates_20hz``, ``bag_battery_1hz_20hz``
    ``bag_rates`` and ``bag_battery_1hz`` read on a 20 Hz time base (the topic map's
    ``rate_hz: 20``, the wheels' rate): the battery's means interpolated between.

A verdict is right as in ``plant_zoo_diagnosis.py`` (the injected effect, ``none``, or
``unexplained`` for the out-of-library effects).  Per transform it prints the right share,
how many verdicts reached confidence 0.9 and how many of those are wrong, and how many
verdicts equal the ``as_logged`` one; per-case rows go to
``reports/logger_conventions/results.csv``, the files to ``reports/logger_conventions/logs/``.
The held-out variants (c, d, g) are refused, like ``gap_split.py``: this benchmark is for
finding what to fix.

Usage::

    PYTHONPATH=src .venv/bin/python benchmarks/logger_conventions.py --jobs 2
    PYTHONPATH=src .venv/bin/python benchmarks/logger_conventions.py --variants a,f --seeds 2
"""

from __future__ import annotations

import argparse
import csv
import dataclasses
import os
import shutil
import sys
import zlib
from collections.abc import Callable
from concurrent.futures import ProcessPoolExecutor
from pathlib import Path
from typing import Any

for _var in ("OMP_NUM_THREADS", "OPENBLAS_NUM_THREADS", "MKL_NUM_THREADS"):
    os.environ.setdefault(_var, "1")

import numpy as np  # noqa: E402

sys.path.insert(0, str(Path(__file__).resolve().parent))

import plant_zoo  # noqa: E402
import zoo_bag  # noqa: E402

ROOT = Path(__file__).resolve().parents[1]
HELD_OUT = {"c", "d", "g"}
#: Rows a held stream repeats each reading over (5 Hz readings in the zoo's 20 Hz rows).
HOLD_ROWS = 4
#: Where the zoo's 180 s runs are cut into three files [s].
CUTS_S = (60.0, 120.0)
#: Largest shift of a jittered time stamp [s] (the zoo's rows are 50 ms apart).
JITTER_S = 0.01
#: Rows a rotated file repeats from the end of the one before it.
OVERLAP_ROWS = 3

Columns = dict[str, np.ndarray]
Meta = dict[str, str]
Files = list[tuple[Columns, Meta]]


def _hold(cols: Columns, names: tuple[str, ...], rows: int = HOLD_ROWS) -> Columns:
    idx = (np.arange(cols["t"].size) // rows) * rows
    return {k: (v[idx] if k in names else v) for k, v in cols.items()}


def _no_sampling(meta: Meta) -> Meta:
    return {k: v for k, v in meta.items() if k != "power_sampling"}


def _cut(cols: Columns, meta: Meta) -> Files:
    edges = (-np.inf, *CUTS_S, np.inf)
    out: Files = []
    for k in range(len(edges) - 1):
        m = (cols["t"] >= edges[k]) & (cols["t"] < edges[k + 1])
        run_meta = {**meta, "run_id": f"{meta.get('run_id', 'run')}-r{k}"}
        out.append(({c: v[m] for c, v in cols.items()}, run_meta))
    return out


def _own_frame(cols: Columns) -> Columns:
    """The pose rotated and moved into the frame of the run's first sample."""
    x, y, yaw = cols["x"], cols["y"], cols["yaw"]
    c, s = np.cos(yaw[0]), np.sin(yaw[0])
    dx, dy = x - x[0], y - y[0]
    yaw_r = np.arctan2(np.sin(yaw - yaw[0]), np.cos(yaw - yaw[0]))
    return {**cols, "x": c * dx + s * dy, "y": -s * dx + c * dy, "yaw": yaw_r}


def _as_logged(cols: Columns, meta: Meta) -> Files:
    return [(cols, meta)]


def _no_metadata(cols: Columns, meta: Meta) -> Files:
    return [(cols, {})]


def _power_held(cols: Columns, meta: Meta) -> Files:
    return [(_hold(cols, ("p_total",)), _no_sampling(meta))]


def _speeds_held(cols: Columns, meta: Meta) -> Files:
    return [(_hold(cols, ("v_left", "v_right")), _no_sampling(meta))]


def _pose_held(cols: Columns, meta: Meta) -> Files:
    return [(_hold(cols, ("x", "y", "yaw")), meta)]


def _pose_1hz(cols: Columns, meta: Meta) -> Files:
    return [(_hold(cols, ("x", "y", "yaw"), rows=20), meta)]


def _time_jitter(cols: Columns, meta: Meta) -> Files:
    rng = np.random.default_rng(zlib.crc32(meta.get("run_id", "").encode()))
    shift = rng.uniform(-JITTER_S, JITTER_S, cols["t"].size)
    return [({**cols, "t": cols["t"] + shift}, meta)]


def _runs_no_pose(cols: Columns, meta: Meta) -> Files:
    bare = {k: v for k, v in cols.items() if k not in ("x", "y", "yaw")}
    return _cut(bare, meta)


def _runs_odom(cols: Columns, meta: Meta) -> Files:
    return [(_own_frame(c), {**m, "pose_frame": "run"}) for c, m in _cut(cols, meta)]


def _sign_flipped(cols: Columns, meta: Meta) -> Files:
    return [({**cols, "p_total": -cols["p_total"]}, meta)]


def _yaw_degrees(cols: Columns, meta: Meta) -> Files:
    return [({**cols, "yaw": np.degrees(cols["yaw"])}, meta)]


def _yaw_bearing(cols: Columns, meta: Meta) -> Files:
    b = np.pi / 2 - cols["yaw"]
    return [({**cols, "yaw": np.arctan2(np.sin(b), np.cos(b))}, meta)]


def _rows_10hz(cols: Columns, meta: Meta) -> Files:
    pairs = [idx for idx, _ in zoo_bag.windows(cols["t"], 2)]
    out = {
        c: np.array([v[idx].mean() if c == "p_total" else v[idx[-1]] for idx in pairs])
        for c, v in cols.items()
    }
    return [(out, meta)]


def _joined(pieces: list[Columns], meta: Meta) -> Files:
    cols = {c: np.concatenate([p[c] for p in pieces]) for c in pieces[0]}
    return [(cols, meta)]


def _rotated_overlap(cols: Columns, meta: Meta) -> Files:
    pieces = [c for c, _ in _cut(cols, meta)]
    for k in range(1, len(pieces)):
        prev = pieces[k - 1]
        pieces[k] = {c: np.concatenate([prev[c][-OVERLAP_ROWS:], v]) for c, v in pieces[k].items()}
    return _joined(pieces, meta)


def _runs_one_file(cols: Columns, meta: Meta) -> Files:
    pieces = [{**c, "t": c["t"] - c["t"][0]} for c, _ in _cut(cols, meta)]
    return _joined(pieces, meta)


TRANSFORMS: dict[str, Callable[[Columns, Meta], Files]] = {
    "as_logged": _as_logged,
    "no_metadata": _no_metadata,
    "power_held": _power_held,
    "speeds_held": _speeds_held,
    "pose_held": _pose_held,
    "pose_1hz": _pose_1hz,
    "time_jitter": _time_jitter,
    "runs_no_pose": _runs_no_pose,
    "runs_odom": _runs_odom,
    "sign_flipped": _sign_flipped,
    "yaw_degrees": _yaw_degrees,
    "yaw_bearing": _yaw_bearing,
    "rotated_overlap": _rotated_overlap,
    "runs_one_file": _runs_one_file,
    "rows_10hz": _rows_10hz,
    "bag": _as_logged,
    "bag_rates": _as_logged,
    "bag_battery_1hz": _as_logged,
    "bag_rates_20hz": _as_logged,
    "bag_battery_1hz_20hz": _as_logged,
}
#: Transforms written as a ROS 2 bag (``zoo_bag.py``) and read with the library's bag reader:
#: the keyword arguments of :func:`zoo_bag.write_bag`.
BAGS: dict[str, dict[str, int]] = {
    "bag": {},
    "bag_rates": {"battery_every": 2, "cmd_every": 2},
    "bag_battery_1hz": {"battery_every": 20, "cmd_every": 2},
    "bag_rates_20hz": {"battery_every": 2, "cmd_every": 2},
    "bag_battery_1hz_20hz": {"battery_every": 20, "cmd_every": 2},
}
#: The topic map's ``rate_hz`` per bag transform (default: the power topic's rate).
BAG_RATE_HZ = {"bag_rates_20hz": 20.0, "bag_battery_1hz_20hz": 20.0}
#: Transforms whose right answer is a refusal, and what its one line must contain.
REFUSALS = {
    "sign_flipped": ("'p_total'",),
    "yaw_degrees": ("'yaw'", "degrees"),
    "yaw_bearing": ("'yaw'", "clockwise"),
    "runs_one_file": ("'t'", "own file"),
}


def run_case(args: tuple[str, str, int, str, str]) -> dict[str, Any]:
    """Diagnose one zoo case rewritten by one transform; the row of the results table."""
    variant, effect, seed, transform, out = args
    from ecoplan.diagnose.pipeline import diagnose
    from ecoplan.errors import EcoplanError
    from ecoplan.io.logcsv import read_log_csv
    from ecoplan.io.rosbag import TopicMap, read_rosbag

    case = plant_zoo.make_case(variant, effect, seed)
    files = TRANSFORMS[transform](dict(case.columns), dict(case.meta))
    folder = Path(out) / "logs" / transform
    if transform in BAGS:
        bags = []
        for k, (c, _) in enumerate(files):
            bag = folder / f"{variant}-{effect}-s{seed}-r{k}"
            shutil.rmtree(bag, ignore_errors=True)
            bags.append(zoo_bag.write_bag(c, bag, **BAGS[transform]))
        topics = TopicMap.joint_states(
            "/joint_states",
            "left_wheel_joint",
            "right_wheel_joint",
            zoo_bag.WHEEL_RADIUS_M,
            rate_hz=BAG_RATE_HZ.get(transform),
            **zoo_bag.topic_map_kwargs(),
        )

        def read_all() -> list[Any]:
            return [read_rosbag(b, topics) for b in bags]
    else:
        paths = [
            plant_zoo.write_log(
                dataclasses.replace(case, columns=c, meta=m),
                folder / f"{variant}-{effect}-s{seed}-r{k}.csv",
            )
            for k, (c, m) in enumerate(files)
        ]

        def read_all() -> list[Any]:
            return [read_log_csv(p) for p in paths]

    row: dict[str, Any] = {
        "variant": variant,
        "effect": effect,
        "seed": seed,
        "transform": transform,
        "expected": "refused" if transform in REFUSALS else case.expected,
        "verdict": "",
        "confidence": float("nan"),
        "error": "",
    }
    one_line = True
    try:
        d = diagnose(read_all(), case.vehicle, case.terrain, rng=seed)
    except EcoplanError as exc:
        row["verdict"] = "refused"
        row["error"] = str(exc).splitlines()[0]
        one_line = "\n" not in str(exc).strip()
    except Exception as exc:  # counted and listed, never hidden
        row["verdict"] = "crash"
        row["error"] = f"{type(exc).__name__}: {exc}"
    else:
        row["verdict"] = d.verdict
        row["confidence"] = float(d.attribution.confidence)
    right = row["verdict"] == row["expected"]
    if transform in REFUSALS:
        said = all(frag in row["error"] for frag in REFUSALS[transform])
        right = right and said and one_line
    row["right"] = right
    return row


def summarise(rows: list[dict[str, Any]]) -> None:
    """Per transform: right, confident verdicts and confident wrong ones, same as as_logged."""
    ref = {(r["variant"], r["effect"], r["seed"]): r["verdict"] for r in rows
           if r["transform"] == "as_logged"}  # fmt: skip
    print(
        f"{'transform':20s} {'right':>12s}  {'conf >= 0.9: verdicts / wrong':>30s}  "
        f"{'same verdict as as_logged':>26s}  crashes"
    )
    for name in TRANSFORMS:
        sub = [r for r in rows if r["transform"] == name]
        if not sub:
            continue
        right = sum(bool(r["right"]) for r in sub)
        conf = [r for r in sub if r["confidence"] >= 0.9]
        wrong = sum(not r["right"] for r in conf)
        keyed = [r for r in sub if (r["variant"], r["effect"], r["seed"]) in ref]
        same = sum(r["verdict"] == ref[(r["variant"], r["effect"], r["seed"])] for r in keyed)
        crashes = sum(r["verdict"] == "crash" for r in sub)
        same_s = f"{same}/{len(keyed)}" if keyed and name != "as_logged" else "-"
        print(
            f"{name:20s} {right:5d}/{len(sub):<3d} {100 * right / len(sub):5.1f}%  "
            f"{len(conf):>21d} / {wrong:<6d}  {same_s:>26s}  {crashes}"
        )
    for r in rows:
        if r["verdict"] == "crash":
            print(
                f"  crash: {r['variant']} {r['effect']} s{r['seed']} {r['transform']}: {r['error']}"
            )


def main() -> int:
    """Run the transforms over the chosen zoo cases and print the table."""
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--variants", default="a,e,f,i", help="zoo variants (not c, d, g)")
    ap.add_argument("--effects", default=",".join(plant_zoo.EFFECTS), help="zoo effects")
    ap.add_argument("--seeds", type=int, default=1, help="seeds 0..N-1 per case")
    ap.add_argument("--transforms", default=",".join(TRANSFORMS), help="which rewrites")
    ap.add_argument("--jobs", type=int, default=1, help="worker processes")
    ap.add_argument("--out", default=str(ROOT / "reports" / "logger_conventions"))
    args = ap.parse_args()
    variants = args.variants.split(",")
    if HELD_OUT & set(variants):
        ap.error(f"variants {', '.join(sorted(HELD_OUT))} are held out; not for finding fixes")
    unknown = set(variants) - set(plant_zoo.VARIANTS)
    if unknown:
        ap.error(f"unknown variant(s) {', '.join(sorted(unknown))}")
    transforms = args.transforms.split(",")
    if set(transforms) - set(TRANSFORMS):
        ap.error(f"transforms are {', '.join(TRANSFORMS)}")
    effects = args.effects.split(",")
    if set(effects) - set(plant_zoo.EFFECTS):
        ap.error(f"effects are {', '.join(plant_zoo.EFFECTS)}")
    jobs = [
        (v, e, s, t, args.out)
        for t in transforms
        for v in variants
        for e in effects
        for s in range(args.seeds)
    ]
    with ProcessPoolExecutor(max_workers=args.jobs) as ex:
        rows = list(ex.map(run_case, jobs))
    out = Path(args.out)
    out.mkdir(parents=True, exist_ok=True)
    with open(out / "results.csv", "w", newline="") as fh:
        w = csv.DictWriter(fh, fieldnames=list(rows[0]))
        w.writeheader()
        w.writerows(rows)
    print(f"{len(rows)} diagnoses: variants {args.variants}, seeds 0-{args.seeds - 1}")
    summarise(rows)
    return 0


if __name__ == "__main__":
    raise SystemExit(main())
