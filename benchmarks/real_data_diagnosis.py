"""Diagnosis of real data: BorealTC FLOORING and ASPHALT runs (Husky A200) — issue 6, item 4.

For each terrain, all runs are loaded through :func:`ecoplan.io.borealtc.load_borealtc`
(``p_total = 24 V x (|I_left| + |I_right|)``: the bus voltage is an assumption, the data have no
voltage column) and diagnosed against a wheeled skid-steer model (wheeled paper eqs. 12-15)
whose coefficients the calibration step re-identifies on the training runs ("fit the static
model first").  Odd-numbered runs are held out.

Vehicle (assumptions, there is no Husky preset): the ``pioneer-3at`` structure with the Husky's
mass (70 kg, BorealTC ABOUT), track width 0.555 m (Clearpath spec), top side speed 1.0 m/s and no
per-side power limit.

For reference the script also computes the plain static least-squares fit of BorealTC's ABOUT
note, ``P = c0 + c1 (|vL| + |vR|) + c2 |ω|`` with ω from the side speeds, leave-one-run-out
(≈ 47 W MAE on FLOORING, ≈ 74 W on ASPHALT)::

    .venv/bin/python benchmarks/real_data_diagnosis.py [--out reports/borealtc]
"""

from __future__ import annotations

import argparse
import sys
from pathlib import Path

import numpy as np

from ecoplan.diagnose.pipeline import diagnose
from ecoplan.diagnose.report import save_figures, summary, write_json
from ecoplan.io.borealtc import load_borealtc_runs
from ecoplan.presets import vehicle

HUSKY = {"mass_kg": 70.0, "track_gauge_m": 0.555, "top_track_speed_mps": 1.0, "p_side_max_w": None}


def static_lsq_loro(logs: list) -> float:
    """Leave-one-run-out MAE of P = c0 + c1(|vL|+|vR|) + c2|ω| [W] (ω = (vR - vL)/0.555)."""

    def design(lg):  # type: ignore[no-untyped-def]
        vl, vr = np.asarray(lg.v_left), np.asarray(lg.v_right)
        return np.column_stack(
            [np.ones(vl.size), np.abs(vl) + np.abs(vr), np.abs(vr - vl) / HUSKY["track_gauge_m"]]
        )

    errs = []
    for i, lg in enumerate(logs):
        X = np.vstack([design(o) for j, o in enumerate(logs) if j != i])
        y = np.concatenate([np.asarray(o.p_total) for j, o in enumerate(logs) if j != i])
        c, *_ = np.linalg.lstsq(X, y, rcond=None)
        errs.append(np.abs(np.asarray(lg.p_total) - design(lg) @ c))
    return float(np.mean(np.concatenate(errs)))


def main() -> int:
    ap = argparse.ArgumentParser(description="diagnose the BorealTC hard-ground runs")
    ap.add_argument("--out", default=None, help="write JSON and figures per terrain here")
    args = ap.parse_args()
    params = vehicle("pioneer-3at", "asphalt", HUSKY)
    for terrain in ("FLOORING", "ASPHALT"):
        logs = load_borealtc_runs(terrain)
        mean_p = float(np.mean(np.concatenate([np.asarray(lg.p_total) for lg in logs])))
        ref = static_lsq_loro(logs)
        d = diagnose(logs, params, rng=0)
        print(
            f"===== BorealTC {terrain}: {len(logs)} runs, mean power {mean_p:.0f} W "
            f"(24 V assumed); static LSQ leave-one-run-out MAE {ref:.1f} W"
        )
        print(summary(d))
        if args.out:
            out = Path(args.out) / terrain.lower()
            write_json(d, out / "diagnosis.json")
            for p in save_figures(d, out):
                print(f"figure: {p}")
        print()
    return 0


if __name__ == "__main__":
    sys.exit(main())
