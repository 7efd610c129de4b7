"""Where the held-out gap left by the final model comes from, on zoo cases (issue 12).

``plant_zoo_diagnosis.py`` measures the held-out gap reduction ``1 - MAE(true - final) /
MAE(true - calibrated)`` against the zoo's noise-free meter power.  This splits what the final
model leaves, ``MAE(true - final)``, on the same held-out samples, by diagnosing variants of
the same case (the same drive; ``rng`` the seed, as the benchmark)::

    fin        the case as logged (the benchmark's figure);
    fam        the same log with the power column replaced by the noise-free truth, the named
               effect the only candidate: what the model family (base + effect) cannot
               represent, with the logged speeds;
    base       the ``none`` case of the same seed and drive, noise-free power, no candidate:
               what the base family alone cannot represent (law family, driver-term steps,
               averaging), with the logged speeds;
    base_v     the same with noise-free speeds too (every ``_ar1`` noise of the zoo's logger
               set to zero): the base family's own misfit; ``base - base_v`` is what the
               speed noise costs through the regressors (errors in variables).

``fin - fam`` is the noise-limited estimation (power noise), ``fam - base`` the effect's misfit
(its family and its interaction with the base).  Per seed the ``base`` figures are shared by
every effect.  The held-out variants (c, d, g) are refused::

    PYTHONPATH=src nice .venv/bin/python benchmarks/gap_split.py --cases h:inertia:0,a:inertia:0

Measured on main 7b5225b (session 12), W held out: the base floor dominates, on the Coulomb
plant a as much as on h, and the law family is not most of it::

    case        fin    fam   base  base_v      case        fin    fam   base  base_v
    h inert s0 12.27  12.06  11.86  9.11       a inert s0 11.40  10.57  10.09  7.35
    h inert s1 10.45   9.66   9.77  8.37       a eff.dr s1 12.26  11.45   9.79  6.32
    h eff.dr s1 13.38 12.14   9.77  8.37       a sdr s3    9.90   9.41   9.60  5.05
    h sdr s3    9.54   8.95   8.64  6.17       a regen s0  8.39  10.81* 10.09  7.35
    h sdr s0   12.42  12.69  11.86  9.11       (* noise-free verdict unexplained)
    h regen s0  9.26   9.12  11.86  9.11

The law family's own cost (h's ``base_v`` over a's, same drive and belt) is 1.1-2.1 W; the
speed noise 1.4-4.6 W; the noise 0.1-1.2 W; the effects 0-2.4 W.  Of a's ``base_v`` (seed 0,
7.36 W) about 2.1 W is the logger's 50 ms power averaging against speeds sampled at the
window's end: the calibrated model evaluated at the speeds 12.5 / 25 / 37.5 ms earlier leaves
5.49 / 5.26 / 6.94 W (h: 9.12 -> 7.41 / 7.15 / 8.48 W), without refitting anything.
"""

from __future__ import annotations

import argparse
import dataclasses
import os
import sys
import tempfile
from collections.abc import Callable
from pathlib import Path
from typing import Any

for _var in ("OMP_NUM_THREADS", "OPENBLAS_NUM_THREADS", "MKL_NUM_THREADS"):
    os.environ.setdefault(_var, "1")

import numpy as np  # noqa: E402

sys.path.insert(0, str(Path(__file__).resolve().parent))

from plant_zoo import plant  # noqa: E402

#: Variants never run here (held out from development, see the zoo's README).
HELD_OUT = frozenset({"c", "d", "g"})


def _held_mae(case: plant.Case, d: Any) -> float:
    """Held-out MAE of the final model against the case's noise-free meter power [W]."""
    rows = np.searchsorted(case.columns["t"], d.test_frame.t)
    return float(np.mean(np.abs(case.true_power_w[rows] - d.prediction_final_w)))


def _diagnose(case: plant.Case, noise_free_power: bool, effects: list[str] | None) -> Any:
    from ecoplan.diagnose.pipeline import diagnose
    from ecoplan.io.logcsv import read_log_csv

    with tempfile.TemporaryDirectory() as tmp:
        log = read_log_csv(plant.write_log(case, Path(tmp) / "case.csv"))
    if noise_free_power:
        log = dataclasses.replace(log, p_total=np.asarray(case.true_power_w, dtype=float))
    return diagnose([log], case.vehicle, case.terrain, rng=case.seed, effects=effects)


def _case(variant: str, effect: str, seed: int, quiet: bool = False) -> plant.Case:
    """The zoo case; ``quiet``: with every logging noise of the zoo set to zero."""
    if not quiet:
        return plant.make_case(variant, effect, seed)
    orig: Callable[..., Any] = plant._ar1
    plant._ar1 = lambda rng, n, std, phi: orig(rng, n, std, phi) * 0.0  # same draws
    try:
        return plant.make_case(variant, effect, seed)
    finally:
        plant._ar1 = orig


def split(variant: str, effect: str, seed: int, base: dict[tuple[str, int], Any]) -> dict[str, Any]:
    """The split of one case (module docstring); ``base`` caches the per-seed base figures."""
    case = _case(variant, effect, seed)
    d = _diagnose(case, False, None)
    rows = np.searchsorted(case.columns["t"], d.test_frame.t)
    p_true = case.true_power_w[rows]
    cal = float(np.mean(np.abs(p_true - (d.test_frame.p - d.residual_calibrated_w))))
    out: dict[str, Any] = {"case": f"{variant} {effect} s{seed}", "verdict": d.verdict}
    out["cal"], out["fin"] = cal, _held_mae(case, d)
    out["n"] = float(getattr(d.calibration.params, "slip_exponent", 0.0))
    fam = _diagnose(case, True, [effect])
    out["fam"] = _held_mae(case, fam)
    if (variant, seed) not in base:
        none = _case(variant, "none", seed)
        clean = _case(variant, "none", seed, quiet=True)
        base[(variant, seed)] = (
            _held_mae(none, _diagnose(none, True, [])),
            _held_mae(clean, _diagnose(clean, True, [])),
        )
    out["base"], out["base_v"] = base[(variant, seed)]
    return out


def main() -> int:
    """Print the split for the cases given (``variant:effect:seed``, comma-separated)."""
    ap = argparse.ArgumentParser(description="split the final model's held-out gap (zoo)")
    ap.add_argument("--cases", required=True, help="variant:effect:seed,... (not c, d, g)")
    args = ap.parse_args()
    cases = []
    for spec in (s for s in args.cases.split(",") if s):
        parts = spec.split(":")
        if len(parts) != 3 or not parts[2].isdigit():
            ap.error(f"case {spec!r}: expected variant:effect:seed")
        v, e, s = parts
        if v in HELD_OUT or v not in plant.VARIANTS:
            ap.error(f"variant {v!r}: one of {sorted(set(plant.VARIANTS) - HELD_OUT)}")
        if e not in plant.EFFECTS:
            ap.error(f"effect {e!r}: one of {','.join(plant.EFFECTS)}")
        cases.append((v, e, int(s)))
    base: dict[tuple[str, int], Any] = {}
    cols = ("cal", "fin", "fam", "base", "base_v")
    print(f"{'case':42s} {'verdict':28s} {'n':>5s} " + " ".join(f"{c:>7s}" for c in cols))
    for v, e, s in cases:
        r = split(v, e, s, base)
        figs = " ".join(f"{r[c]:7.2f}" for c in cols)
        print(f"{r['case']:42s} {r['verdict']:28s} {r['n']:5.2f} {figs}", flush=True)
    return 0


if __name__ == "__main__":
    sys.exit(main())
