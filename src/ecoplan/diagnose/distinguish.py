"""Can the log tell two candidates apart, and a pair of effects fitted in sequence.

* :func:`distinguishability`, *before* fitting: each candidate's regressors at nominal values
  (linearised for the nonlinear ones -- a lag or a delay ``d`` changes the power by about
  ``-d dP/dt``), with the base model's columns projected out.  A candidate whose regressors
  vanish is *not excited* by the log; two candidates whose regressor spaces have a canonical
  correlation above 0.95 *cannot be told apart*, and the report names the manoeuvre that would
  separate them (:data:`SEPARATING_MANOEUVRES`).
* :class:`PairEffect`: two effects fitted in sequence, the second on what the first leaves.
"""

from __future__ import annotations

import dataclasses
from collections.abc import Sequence

import numpy as np

from ecoplan._typing import FloatArray
from ecoplan.diagnose.effects import Effect, EffectData, make_effect
from ecoplan.diagnose.replay import smooth_derivative
from ecoplan.models.wheeled import WheeledParams

__all__ = ["SEPARATING_MANOEUVRES", "PairEffect", "distinguishability"]

#: Manoeuvre that separates two candidates that look alike on a log.
SEPARATING_MANOEUVRES: dict[frozenset[str], str] = {
    frozenset({"inertia", "actuator_lag"}): "speed steps of several amplitudes at constant speed "
    "levels (a lag delays the power, inertia scales with v·a)",
    frozenset({"inertia", "sensor_delay"}): "accelerations from rest and at cruise speed (inertia "
    "grows with speed, a delay does not)",
    frozenset({"actuator_lag", "sensor_delay"}): "a log with commanded and measured speeds (a lag "
    "delays the speeds, a sensor delay only the power)",
    frozenset({"inertia", "regeneration"}): "accelerations and decelerations of equal size",
    frozenset({"slope", "speed_dependent_resistance"}): "runs out and back along one line",
    frozenset({"slope", "efficiency_drift"}): "runs out and back along one line, repeated",
    frozenset({"slope", "terrain_patch"}): "crossing the region in both directions",
    frozenset({"efficiency_drift", "terrain_patch"}): "revisiting the same place early and late",
    frozenset({"speed_dependent_resistance", "power_saturation"}): "sustained runs at top speed "
    "on the spot and straight (saturation caps power, resistance grows with speed only)",
    frozenset({"icr_asymmetry", "regeneration"}): "turns of both directions at several radii",
    frozenset({"icr_asymmetry", "slope"}): "turns of both directions on the spot",
}
_DEFAULT_MANOEUVRE = "a richer log: speed steps, turns of both directions, out-and-back runs"


class PairEffect(Effect):
    """Two effects fitted in sequence: the second on what the first leaves."""

    name = "pair"

    def __init__(self, first: Effect, second: Effect) -> None:
        super().__init__()
        self.first = first
        self.second = second

    def fit(self, data: EffectData) -> Effect:  # noqa: D102
        self.first.fit(data)
        rest = data.p - self.first.effect_w(data)
        shifted = dataclasses.replace(data, frame=dataclasses.replace(data.frame, p=rest))
        self.second.fit(shifted)
        self.coef_ = np.zeros(0)
        self.chi_ = self.second.chi_
        self.params_ = {
            **{f"{self.first.name}.{k}": v for k, v in self.first.params_.items()},
            **{f"{self.second.name}.{k}": v for k, v in self.second.params_.items()},
        }
        return self

    def predict(self, data: EffectData) -> FloatArray:  # noqa: D102
        return np.asarray(self.second.predict(data) + self.first.effect_w(data), dtype=np.float64)


def _signatures(data: EffectData, names: Sequence[str]) -> dict[str, FloatArray]:
    """Regressors of each candidate at nominal values (linearised where nonlinear)."""
    f = data.frame
    dbase = np.empty(f.n)
    for r in np.unique(f.run):
        idx = f.run == r
        dbase[idx] = smooth_derivative(f.t[idx], data.base_w[idx])
    sig: dict[str, FloatArray] = {}
    for name in names:
        eff = make_effect(name)
        if name in ("sensor_delay", "actuator_lag"):
            sig[name] = dbase[:, None]
        elif name == "icr_asymmetry":
            from ecoplan.diagnose.calibrate import base_design

            h = 0.02 * data.params.track_gauge_m
            plus = base_design(f, dataclasses.replace(data.params, icr_offset_m=h)).X
            minus = base_design(f, dataclasses.replace(data.params, icr_offset_m=-h)).X
            sig[name] = (plus - minus) / (2 * h)
        elif name == "power_saturation":
            cap = float(np.quantile(data.base_w, 0.9))
            sig[name] = np.minimum(cap - data.base_w, 0.0)[:, None]
        elif name in ("terrain_patch", "terrain_change"):
            continue
        elif name == "regeneration" and not isinstance(data.params, WheeledParams):
            # a share of the k_nr column: told apart from the base model by the floor the
            # refits keep k_nr above (effects.fitting.NONREGEN_FLOOR_SHARE), not by its shape
            continue
        else:
            sig[name] = eff.columns(data, None)
    return sig


def _orth(A: FloatArray, Q0: FloatArray) -> FloatArray:
    A = A - Q0 @ (Q0.T @ A)
    return A


def distinguishability(
    data: EffectData, names: Sequence[str], threshold: float = 0.95
) -> tuple[list[tuple[str, str, float, str]], list[str]]:
    """Pairs of candidates this log cannot tell apart, and candidates it does not excite.

    Returns
    -------
    pairs : list of (name, name, canonical correlation, separating manoeuvre)
        Pairs whose base-residualised regressor spaces correlate above ``threshold``.
    not_excited : list of str
        Candidates whose regressors lie (99 %) in the base model's column space.
    """
    sig = _signatures(data, names)
    xs = data.X / np.maximum(np.sqrt(np.mean(data.X**2, axis=0)), 1e-12)
    Q0, _ = np.linalg.qr(xs)
    q: dict[str, FloatArray] = {}
    not_excited: list[str] = []
    for name, A in sig.items():
        scale = np.sqrt(np.mean(A**2, axis=0))
        ok = scale > 1e-12
        if not np.any(ok):
            not_excited.append(name)
            continue
        A = A[:, ok] / scale[ok]
        R = _orth(A, Q0)
        frac = np.sqrt(np.sum(R**2) / max(np.sum(A**2), 1e-300))
        if frac < 0.02:
            not_excited.append(name)
            continue
        Qa, _ = np.linalg.qr(R)
        q[name] = Qa
    pairs = []
    keys = list(q)
    for i, a in enumerate(keys):
        for b in keys[i + 1 :]:
            s = np.linalg.svd(q[a].T @ q[b], compute_uv=False)
            cc = float(s[0]) if s.size else 0.0
            if cc > threshold:
                man = SEPARATING_MANOEUVRES.get(frozenset({a, b}), _DEFAULT_MANOEUVRE)
                pairs.append((a, b, cc, man))
    return pairs, not_excited
