"""Identify a vehicle's power model from a user's own logs of free driving, per terrain.

The papers identified their models on stationary grids (tracked §III-C: every track-speed
pair held 5 s; wheeled §III-A: ``cmd(v, r)`` held 10 s).  A user has logs of ordinary
driving instead.  For a contact-friction vehicle (tracked paper eqs. 7-20: tracks or the
wheels of a four-wheel skid-steer as punctual contacts) the logged battery power is

    P = [µ S(V_l, V_r) + K (|V_l| + |V_r|) + P_br B + k_nr N] / η + P_up + P_inertial

with ``S`` the friction power per unit µ (eq. 14, χ and the contact layout of the base
vehicle), ``B`` the indicator of cases 3-4 and ``N`` the case-2 non-regenerated speed
(§III-C), and ``P_inertial`` the mass terms (:mod:`ecoplan.models.inertial`: ``M a v + I α ω``
and the grade, through η), fixed by the base vehicle's mass.  The model is linear in
``θ = (µ, K, P_br, k_nr, P_up)``, so each terrain is one bounded linear least-squares fit
(:func:`scipy.optimize.lsq_linear`, all parameters ``>= 0``, µ ``<= 5``).

* **Intervals**: moving-block bootstrap over samples (blocks of ``block_s`` seconds keep the
  autocorrelation of a log), percentile intervals at a *joint* level (Bonferroni over the
  identified parameters).
* **Encoder noise** biases the fit (errors in the regressors: straight driving read as
  slight turning, motion cases misread near a stop).  Sides within ``speed_tol_mps`` of each
  other are taken as equal, and the remaining bias is removed by simulation-extrapolation
  (SIMEX: refit with the noise doubled, extrapolate linearly to no noise); the interval
  spans the naive and the corrected ones, widened by the size of the correction, since the
  extrapolation is itself uncertain.  With the blind benchmark's noise all parameters lie in
  their intervals in about 90 % of seeds (``benchmarks/identify_coverage.py``).
* **Not identifiable**: a parameter whose regressor is excited on fewer than
  ``min_excited`` samples (no spot turns -> no braking term; no case-2 turns -> no
  non-regenerated term; no turning -> no µ) is left at the base vehicle's value and listed.
* **Unphysical**: the same fit without bounds; when a parameter's whole interval lies
  below zero (power falling with speed gives ``K < 0``), the logs contradict the model:
  :func:`identify_vehicle` refuses (``InputError``) unless ``clamp=True``, which keeps the
  bounded fit and records the clamped parameters.
* **Held-out error**: leave-one-run-out when a terrain has several runs, else the last
  ``holdout_fraction`` of the log; mean absolute power error and energy error per run.
"""

from __future__ import annotations

import dataclasses
import math
from collections.abc import Mapping, Sequence
from dataclasses import dataclass
from typing import Any

import numpy as np
import yaml
from scipy.optimize import lsq_linear

from ecoplan._typing import FloatArray, RngLike
from ecoplan.errors import InputError
from ecoplan.models._validate import check_log_fields, check_range
from ecoplan.models.inertial import inertial_power_of_tracks
from ecoplan.models.tracked import TrackedParams, tracked_power
from ecoplan.models.vehicles import Vehicle, vehicle_from_mapping

__all__ = [
    "FREE_PARAMETERS",
    "DriveLog",
    "TerrainFit",
    "VehicleIdentification",
    "check_fit_options",
    "free_driving_log",
    "identify_vehicle",
    "model_power",
    "simex_widen",
]

#: Parameters identified per terrain, in design-matrix order.
FREE_PARAMETERS: tuple[str, ...] = (
    "mu",
    "k_resistance_n",
    "p_braking_w",
    "k_nonregen_n",
    "p_powerup_w",
)


@dataclass(frozen=True, slots=True, eq=False)
class DriveLog:
    """One log of free driving on one terrain.

    Attributes
    ----------
    t_s : ndarray
        Sample times [s], strictly increasing.
    v_left, v_right : ndarray
        Side speeds [m/s] (REP-103: positive forward).
    p_total_w : ndarray
        Measured battery power of locomotion [W].
    terrain : str
        Terrain name (lower case; e.g. ``asphalt``, ``snow``).
    run_id : str
        Name of the log, for reports.
    grade_rad : ndarray or None
        Slope along +x per sample [rad] (None: flat).
    """

    t_s: FloatArray
    v_left: FloatArray
    v_right: FloatArray
    p_total_w: FloatArray
    terrain: str
    run_id: str = "log"
    grade_rad: FloatArray | None = None

    def __post_init__(self) -> None:
        check_log_fields(self, ("t_s", "v_left", "v_right", "p_total_w", "grade_rad"))

    @property
    def n_samples(self) -> int:
        """Number of samples."""
        return int(self.t_s.size)

    def energy_j(self) -> float:
        """Measured energy (trapezoidal integral of the power) [J]."""
        return float(np.trapezoid(self.p_total_w, self.t_s))


def _unit_params(params: TrackedParams) -> list[TrackedParams]:
    """One parameter set per free parameter: that one at 1, the other four at 0, η = 1."""
    out = []
    for name in FREE_PARAMETERS:
        values: dict[str, Any] = dict.fromkeys(FREE_PARAMETERS, 0.0)
        values.update({name: 1.0, "eta": 1.0, "p_total_max_w": None})
        out.append(dataclasses.replace(params, **values))
    return out


def _snap(log: DriveLog, tol_mps: float) -> tuple[FloatArray, FloatArray]:
    """Side speeds within ``tol`` of each other set equal.

    Encoder noise must not turn straight driving into a turn; a stopped side reads exactly
    zero on an encoder, so zeros stay.
    """
    vl, vr = log.v_left.copy(), log.v_right.copy()
    equal = np.abs(vr - vl) <= tol_mps
    mean = 0.5 * (vl + vr)
    vl[equal] = mean[equal]
    vr[equal] = mean[equal]
    return vl, vr


def _design(
    log: DriveLog,
    params: TrackedParams,
    tol_mps: float,
    extra_noise_mps: float = 0.0,
    rng: np.random.Generator | None = None,
) -> FloatArray:
    """Columns of ``θ`` (battery power per unit parameter) for one log, η included.

    ``extra_noise_mps`` adds white noise to the moving sides' speeds (SIMEX step).
    """
    if extra_noise_mps > 0.0 and rng is not None:
        noisy = [
            v + rng.normal(0.0, extra_noise_mps, v.size) * (v != 0.0)
            for v in (log.v_left, log.v_right)
        ]
        log = dataclasses.replace(log, v_left=noisy[0], v_right=noisy[1])
    vl, vr = _snap(log, tol_mps)
    cols = [tracked_power(vl, vr, u).total_w for u in _unit_params(params)]
    return np.column_stack(cols) / params.eta  # P_T = (P_M + P_D) / η, eq. (20)


def _inertial(log: DriveLog, vehicle: Vehicle, params: TrackedParams) -> FloatArray:
    ip = inertial_power_of_tracks(
        log.t_s,
        log.v_left,
        log.v_right,
        params.icr.spread_m,
        0.0 if log.grade_rad is None else log.grade_rad,
        mass_kg=vehicle.mass_kg,
        yaw_inertia_kgm2=vehicle.yaw_inertia_kgm2,
    )
    return ip.battery_w(params.eta, vehicle.regen_efficiency)


def model_power(log: DriveLog, vehicle: Vehicle, terrain: str | None = None) -> FloatArray:
    """Battery power a contact-friction vehicle file predicts for a log [W].

    The static model of the terrain (tracked eq. 20) plus the mass terms (acceleration,
    yaw acceleration, grade) of :mod:`ecoplan.models.inertial`.
    """
    params = vehicle.params(terrain or log.terrain)
    if not isinstance(params, TrackedParams):
        raise InputError(f"{vehicle.name} uses the radius-fit model; expected contact-friction")
    static = tracked_power(log.v_left, log.v_right, params).total_w
    return static + _inertial(log, vehicle, params)


@dataclass(frozen=True, slots=True)
class TerrainFit:
    """Identified parameters of one terrain.

    Attributes
    ----------
    terrain : str
        Terrain name.
    values : mapping of str to float
        Value of every parameter of :data:`FREE_PARAMETERS` (identified or from the base).
    intervals : mapping of str to (float, float)
        Joint bootstrap interval of each identified parameter.
    identified : tuple of str
        Parameters the logs identified.
    unidentified : tuple of str
        Parameters the logs did not excite, left at the base vehicle's value.
    clamped : mapping of str to float
        Parameters held at their bound 0 whose unconstrained estimate was negative, with
        that estimate (only with ``clamp=True``).
    run_ids : tuple of str
        Logs used.
    n_samples : int
        Samples used.
    heldout_mae_w : float
        Held-out mean absolute power error over all held-out samples [W].
    heldout_energy_error : tuple of float
        Relative error of the predicted energy of each held-out log (signed, -0.05 = 5 % low).
    mean_power_w : float
        Mean measured power [W].
    """

    terrain: str
    values: Mapping[str, float]
    intervals: Mapping[str, tuple[float, float]]
    identified: tuple[str, ...]
    unidentified: tuple[str, ...]
    clamped: Mapping[str, float]
    run_ids: tuple[str, ...]
    n_samples: int
    heldout_mae_w: float
    heldout_energy_error: tuple[float, ...]
    mean_power_w: float

    @property
    def median_energy_error(self) -> float:
        """Median of the absolute held-out energy errors [-]."""
        return float(np.median(np.abs(self.heldout_energy_error)))


@dataclass(frozen=True, slots=True)
class VehicleIdentification:
    """Result of :func:`identify_vehicle`: per-terrain fits and the identified vehicle.

    Attributes
    ----------
    base : Vehicle
        The vehicle the fit started from (geometry, mass, χ, η; unidentified values).
    fits : mapping of str to TerrainFit
        One fit per terrain of the logs.
    level : float
        Joint confidence level of the intervals.
    name : str
        Name of the identified vehicle.
    """

    base: Vehicle
    fits: Mapping[str, TerrainFit]
    level: float
    name: str

    def vehicle(self) -> Vehicle:
        """The identified vehicle: the base file with the terrain table of the fits."""
        return vehicle_from_mapping(self.document(), f"identified:{self.name}")

    def document(self) -> dict[str, object]:
        """The identified vehicle file as a plain mapping (see :meth:`to_yaml`)."""
        doc = self.base.spec.model_dump(mode="json", exclude_none=True)
        doc["name"] = self.name
        terrains: dict[str, object] = {}
        pct = f"{100 * self.level:g} %"
        for terrain, fit in sorted(self.fits.items()):
            base_entry = self._base_entry(terrain)
            entry: dict[str, object] = {}
            for name in FREE_PARAMETERS:
                if name in fit.identified:
                    lo, hi = fit.intervals[name]
                    note = f"free-driving fit on {len(fit.run_ids)} log(s), {fit.n_samples} samples"
                    if name in fit.clamped:
                        note += f"; clamped at 0 (unconstrained {fit.clamped[name]:.4g})"
                    entry[name] = {
                        "value": _round(fit.values[name]),
                        "source": "identified",
                        "ref": note + f"; {pct} joint bootstrap interval",
                        "interval": [_round(lo), _round(hi)],
                    }
                elif name in base_entry:
                    entry[name] = base_entry[name]
                else:
                    entry[name] = {
                        "value": _round(fit.values[name]),
                        "source": "assumption",
                        "ref": f"not excited by the logs; base vehicle {self.base.name}",
                    }
            if "chi" in base_entry:
                entry["chi"] = base_entry["chi"]
            entry["heldout_mae_w"] = _round(fit.heldout_mae_w)
            terrains[terrain] = entry
        doc["terrains"] = terrains
        if doc.get("default_terrain") not in terrains:
            doc["default_terrain"] = sorted(terrains)[0]
        return doc

    def _base_entry(self, terrain: str) -> dict[str, object]:
        key = terrain if terrain in self.base.spec.terrains else self.base.default_terrain
        entry = self.base.spec.terrains[key].model_dump(mode="json", exclude_none=True)
        entry.pop("heldout_mae_w", None)
        entry.pop("rolling_resistance", None)
        return entry

    def to_yaml(self, header: str = "") -> str:
        """The identified vehicle file as YAML text (readable by the vehicle loader).

        Parameters
        ----------
        header : str
            Comment lines written above the document (without ``#``).
        """
        lines = [f"# {line}" if line else "#" for line in header.splitlines()]
        body = yaml.safe_dump(self.document(), sort_keys=False, allow_unicode=True, width=100)
        return "\n".join([*lines, body]) if lines else body


def check_fit_options(
    owner: str,
    level: float,
    n_boot: int,
    block_s: float,
    holdout_fraction: float,
    speed_noise_mps: float,
    n_simex: int,
) -> None:
    """Range checks of the options the log identifications share (one-line InputError)."""
    check_range(owner, "level", level, 0.0, 1.0, lo_open=True, hi_open=True)
    check_range(owner, "n_boot", n_boot, 10, 100_000)
    check_range(owner, "block_s", block_s, 0.0, lo_open=True)
    check_range(owner, "holdout_fraction", holdout_fraction, 0.05, 0.5)
    check_range(owner, "speed_noise_mps", speed_noise_mps, 0.0, 0.5)
    check_range(owner, "n_simex", n_simex, 1, 1000)


def simex_widen(
    lo: FloatArray, hi: FloatArray, shift: FloatArray, floor: float
) -> tuple[FloatArray, FloatArray]:
    """Bootstrap interval after a SIMEX correction ``shift`` of the estimate.

    The linear extrapolation is itself uncertain: the interval spans the naive and the
    shifted ones, widened by the size of the correction on both sides (lower end >= floor).
    """
    pad = np.abs(shift)
    return np.maximum(np.minimum(lo, lo + shift) - pad, floor), np.maximum(hi, hi + shift) + pad


def _round(x: float) -> float:
    return float(f"{x:.5g}")


def _blocks(t: FloatArray, block_s: float) -> list[FloatArray]:
    edges = np.flatnonzero(np.diff(np.floor((t - t[0]) / block_s)) > 0) + 1
    return [np.asarray(b) for b in np.split(np.arange(t.size), edges)]


#: Upper bounds of the parameters in a bounded fit (µ: the range ``TrackedParams`` accepts).
_UPPER = np.array([5.0, np.inf, np.inf, np.inf, np.inf])


def _fit(x: FloatArray, y: FloatArray, free: list[int], bounded: bool) -> FloatArray:
    if not bounded:
        res = lsq_linear(x[:, free], y, method="bvls")
    else:
        res = lsq_linear(x[:, free], y, bounds=(0.0, _UPPER[free]), method="bvls")
    return np.asarray(res.x, dtype=np.float64)


def _excited(x: FloatArray, min_excited: int) -> list[bool]:
    out = []
    for j in range(x.shape[1]):
        col = np.abs(x[:, j])
        scale = float(col.max()) if col.size else 0.0
        out.append(scale > 0.0 and int(np.sum(col > 0.05 * scale)) >= min_excited)
    return out


def _terrain_fit(
    logs: Sequence[DriveLog],
    base: Vehicle,
    terrain: str,
    *,
    level: float,
    n_boot: int,
    block_s: float,
    min_excited: int,
    clamp: bool,
    holdout_fraction: float,
    speed_tol_mps: float,
    speed_noise_mps: float,
    n_simex: int,
    rng: np.random.Generator,
) -> TerrainFit:
    key = terrain if terrain in base.spec.terrains else base.default_terrain
    params = base.params(key)
    if not isinstance(params, TrackedParams):
        raise InputError(
            f"identify: base vehicle {base.name} uses the radius-fit model; free-driving "
            "identification needs a contact-friction vehicle (use WheeledIdentifier on "
            "cmd(v, r) experiments for the radius-fit model)"
        )
    base_theta = np.array([float(getattr(params, n)) for n in FREE_PARAMETERS])
    xs = [_design(log, params, speed_tol_mps) for log in logs]
    ys = [log.p_total_w - _inertial(log, base, params) for log in logs]
    x, y = np.vstack(xs), np.concatenate(ys)
    excited = _excited(x, min_excited)
    free = [j for j in range(len(FREE_PARAMETERS)) if excited[j]]
    fixed = [j for j in range(len(FREE_PARAMETERS)) if not excited[j]]
    if not free:
        raise InputError(f"identify: the logs on {terrain} excite no parameter of the model")

    def solve(xx: FloatArray, yy: FloatArray, bounded: bool) -> FloatArray:
        theta = base_theta.copy()
        theta[free] = _fit(xx, yy - xx[:, fixed] @ base_theta[fixed], free, bounded)
        return theta

    t_all = np.concatenate([log.t_s - log.t_s[0] + 1e6 * i for i, log in enumerate(logs)])
    blocks = _blocks(t_all, block_s)
    boot_b, boot_u = [], []
    for _ in range(n_boot):
        pick = rng.integers(0, len(blocks), len(blocks))
        idx = np.concatenate([blocks[k] for k in pick])
        boot_b.append(solve(x[idx], y[idx], True))
        boot_u.append(solve(x[idx], y[idx], False))
    alpha = (1.0 - level) / len(free)  # Bonferroni: joint coverage >= level
    q = (100 * alpha / 2, 100 * (1 - alpha / 2))
    theta = solve(x, y, True)
    theta_u = solve(x, y, False)
    lo_u, hi_u = np.percentile(np.array(boot_u), q, axis=0)
    lo_b, hi_b = np.percentile(np.array(boot_b), q, axis=0)
    if speed_noise_mps > 0.0:  # SIMEX: bias of the speed noise, extrapolated to no noise
        sims = []
        for _ in range(n_simex):
            xn = np.vstack(
                [_design(log, params, speed_tol_mps, speed_noise_mps, rng) for log in logs]
            )
            sims.append(solve(xn, y, True))
        shift = theta - np.mean(sims, axis=0)
        shift[fixed] = 0.0
        theta = np.clip(theta + shift, 0.0, _UPPER)
        # the linear extrapolation is itself uncertain: the interval spans the naive and the
        # corrected ones, widened by the size of the correction on both sides
        lo_b, hi_b = simex_widen(lo_b, hi_b, shift, 0.0)
        lo_u, hi_u = simex_widen(lo_u, hi_u, shift, -np.inf)
    clamped: dict[str, float] = {}
    for j in free:
        if hi_u[j] < 0.0:
            name = FREE_PARAMETERS[j]
            if not clamp:
                what = "power falling with speed" if name == "k_resistance_n" else "a negative term"
                raise InputError(
                    f"identify: on {terrain} the logs give {name} = {theta_u[j]:.4g} "
                    f"(interval [{lo_u[j]:.4g}, {hi_u[j]:.4g}]): {what}, an unphysical model; "
                    "refused (clamp=True / --clamp fits with the parameter held at 0)"
                )
            clamped[name] = float(theta_u[j])
    values = dict(zip(FREE_PARAMETERS, (float(v) for v in theta), strict=True))
    intervals = {FREE_PARAMETERS[j]: (float(lo_b[j]), float(hi_b[j])) for j in free}
    mae, energy = _holdout(logs, xs, ys, solve, holdout_fraction)
    return TerrainFit(
        terrain=terrain,
        values=values,
        intervals=intervals,
        identified=tuple(FREE_PARAMETERS[j] for j in free),
        unidentified=tuple(FREE_PARAMETERS[j] for j in fixed),
        clamped=clamped,
        run_ids=tuple(log.run_id for log in logs),
        n_samples=int(y.size),
        heldout_mae_w=mae,
        heldout_energy_error=energy,
        mean_power_w=float(np.mean(np.concatenate([log.p_total_w for log in logs]))),
    )


def _holdout(
    logs: Sequence[DriveLog],
    xs: list[FloatArray],
    ys: list[FloatArray],
    solve: object,
    holdout_fraction: float,
) -> tuple[float, tuple[float, ...]]:
    """Leave-one-log-out (several logs) or a final time split (one log)."""
    assert callable(solve)
    errs: list[FloatArray] = []
    energy: list[float] = []
    splits: list[tuple[FloatArray, FloatArray, FloatArray, FloatArray, DriveLog, slice]] = []
    if len(logs) > 1:
        for i, log in enumerate(logs):
            xt = np.vstack([xx for j, xx in enumerate(xs) if j != i])
            yt = np.concatenate([yy for j, yy in enumerate(ys) if j != i])
            splits.append((xt, yt, xs[i], ys[i], log, slice(None)))
    else:
        cut = max(2, round(xs[0].shape[0] * (1.0 - holdout_fraction)))
        cut = min(cut, xs[0].shape[0] - 2)
        splits.append(
            (xs[0][:cut], ys[0][:cut], xs[0][cut:], ys[0][cut:], logs[0], slice(cut, None))
        )
    for xt, yt, xh, yh, log, part in splits:
        theta = solve(xt, yt, True)
        pred = xh @ theta + (log.p_total_w[part] - yh)  # add back the fixed inertial power
        meas = log.p_total_w[part]
        errs.append(np.abs(pred - meas))
        t = log.t_s[part]
        e_meas = float(np.trapezoid(meas, t))
        energy.append(float(np.trapezoid(pred, t)) / e_meas - 1.0 if e_meas > 0 else math.nan)
    return float(np.mean(np.concatenate(errs))), tuple(energy)


def identify_vehicle(
    logs: Sequence[DriveLog],
    base: Vehicle,
    *,
    name: str | None = None,
    level: float = 0.95,
    n_boot: int = 200,
    block_s: float = 5.0,
    min_excited: int = 20,
    clamp: bool = False,
    holdout_fraction: float = 0.2,
    speed_tol_mps: float = 0.01,
    speed_noise_mps: float = 0.005,
    n_simex: int = 10,
    rng: RngLike = None,
) -> VehicleIdentification:
    """Identify a contact-friction vehicle's power model per terrain from free-driving logs.

    Parameters
    ----------
    logs : sequence of DriveLog
        Logs of the vehicle; each carries its terrain.
    base : Vehicle
        Vehicle file giving geometry, mass, χ, η and the values of parameters the logs
        cannot identify (its terrain of the same name, else its default terrain).
    name : str, optional
        Name of the identified vehicle (default: the base's).
    level : float
        Joint confidence level of the intervals, in (0, 1).
    n_boot : int
        Bootstrap resamples.
    block_s : float
        Length of the bootstrap blocks [s] (longer than the correlation of the noise).
    min_excited : int
        Samples a regressor must be excited on for its parameter to be identified.
    clamp : bool
        Fit parameters the logs drive negative at 0 instead of refusing.
    holdout_fraction : float
        Share of a terrain's single log held out for the error (several logs: leave one out).
    speed_tol_mps : float
        Side speeds this close to each other (to zero) are taken as equal (as zero) when the
        model's motion cases are evaluated: about twice the encoder noise.
    speed_noise_mps : float
        Standard deviation of the side-speed (encoder) noise of the logs [m/s]; the bias it
        causes (errors in the regressors) is removed by simulation-extrapolation (SIMEX:
        refit with the noise doubled, extrapolate linearly to no noise).  0 = no correction.
    n_simex : int
        Refits averaged in the SIMEX step.
    rng : Generator, int or None
        Randomness of the bootstrap.

    Returns
    -------
    VehicleIdentification

    Raises
    ------
    InputError
        No logs, a radius-fit base vehicle, or an unphysical fit without ``clamp``.
    """
    if not logs:
        raise InputError("identify: no logs given")
    check_fit_options(
        "identify_vehicle", level, n_boot, block_s, holdout_fraction, speed_noise_mps, n_simex
    )
    check_range("identify_vehicle", "speed_tol_mps", speed_tol_mps, 0.0, 0.5)
    gen = rng if isinstance(rng, np.random.Generator) else np.random.default_rng(rng)
    by_terrain: dict[str, list[DriveLog]] = {}
    for log in logs:
        by_terrain.setdefault(log.terrain, []).append(log)
    fits = {
        terrain: _terrain_fit(
            group,
            base,
            terrain,
            level=level,
            n_boot=n_boot,
            block_s=block_s,
            min_excited=min_excited,
            clamp=clamp,
            holdout_fraction=holdout_fraction,
            speed_tol_mps=speed_tol_mps,
            speed_noise_mps=speed_noise_mps,
            n_simex=n_simex,
            rng=gen,
        )
        for terrain, group in sorted(by_terrain.items())
    }
    return VehicleIdentification(base, fits, level, name or base.name)


def free_driving_log(
    vehicle: Vehicle,
    terrain: str | None = None,
    *,
    duration_s: float = 300.0,
    rate_hz: float = 10.0,
    power_noise: tuple[float, float] = (0.02, 3.0),
    speed_noise_mps: float = 0.005,
    mix: tuple[float, float, float, float] = (0.35, 0.35, 0.15, 0.15),
    rng: RngLike = None,
    run_id: str = "sim",
) -> DriveLog:
    """A simulated log of free driving with white sensor noise.

    Random side-speed targets under the speed and acceleration limits, the power of
    :func:`model_power`.  Segments of 2-8 s each hold a random target chosen among
    straight driving, arcs, pivot turns (one side stopped) and spot turns, so every term of
    the model is excited.  Noise
    as in the blind benchmark (``ecoplan.synth.sensors.SensorNoise``): power
    ``2 % P + 3 W``, side speeds 0.005 m/s while moving.

    Parameters
    ----------
    vehicle : Vehicle
        A contact-friction vehicle file.
    terrain : str, optional
        Terrain (default: the vehicle's default).
    duration_s, rate_hz : float
        Length and sample rate of the log.
    power_noise : (float, float)
        Relative and absolute standard deviation of the power noise [-, W].
    speed_noise_mps : float
        Standard deviation of the side-speed noise [m/s].
    mix : (float, float, float, float)
        Weights of straight segments, arcs, pivot turns and spot turns.
    rng : Generator, int or None
        Randomness.
    run_id : str
        Name of the log.
    """
    gen = rng if isinstance(rng, np.random.Generator) else np.random.default_rng(rng)
    weights = np.asarray(mix, dtype=np.float64)
    if weights.shape != (4,) or np.any(weights < 0.0) or weights.sum() <= 0.0:
        raise InputError(f"mix = {mix!r}; expected 4 weights >= 0 with a positive sum")
    weights = weights / weights.sum()
    terrain = (terrain or vehicle.default_terrain).lower()
    params = vehicle.params(terrain)
    vmax = 0.9 * params.top_track_speed_mps
    amax = params.accel_max_mps2
    n = int(duration_s * rate_hz)
    t = np.arange(n) / rate_hz
    targets = np.empty((n, 2))
    i = 0
    while i < n:
        seg = int(gen.uniform(2.0, 8.0) * rate_hz)
        kind = gen.choice(4, p=weights)
        s = gen.uniform(0.2, 1.0) * vmax * gen.choice([-1.0, 1.0], p=[0.2, 0.8])
        if kind == 0:
            pair = (s, s)
        elif kind == 1:
            pair = (s, s * gen.uniform(0.2, 0.9))
        elif kind == 2:
            pair = (s, 0.0)
        else:
            pair = (s, -s)
        if gen.random() < 0.5:
            pair = pair[::-1]
        targets[i : i + seg] = pair
        i += seg
    v = np.zeros((n, 2))
    dv = amax / rate_hz
    for k in range(1, n):
        v[k] = v[k - 1] + np.clip(targets[k] - v[k - 1], -dv, dv)
    truth = DriveLog(t, v[:, 0], v[:, 1], np.zeros(n), terrain, run_id)
    p = model_power(truth, vehicle, terrain)
    rel, floor = power_noise
    p_meas = p + gen.normal(0.0, 1.0, n) * (rel * np.abs(p) + floor)
    moving = np.abs(v) > 1e-9
    v_meas = v + gen.normal(0.0, speed_noise_mps, v.shape) * moving
    return DriveLog(t, v_meas[:, 0], v_meas[:, 1], p_meas, terrain, run_id)
