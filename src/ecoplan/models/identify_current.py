"""Identify the side-force model per terrain from logs of motor currents.

A robot that logs the motor current of each side (``power_log: motor_current`` in its
vehicle file; :mod:`ecoplan.models.motor_current`) measures forces, not power: the
current of a side is its no-load current plus its driving force times ``c = r / (G k_t)``.
This module fits, per terrain, the coefficients of :class:`SideForceTerrain`

    θ = (I0 [A], K [N], µ [-], λ0 [-]) and, with ``startup=True``, (K_s [N], s0 [m])

(``K_s``, ``s0``: the start-up resistance ``K_s exp(-s / s0)`` after each stop, about 0 on
ground where the robot does not settle in; ``s0`` is then poorly identified, its interval
wide)

to the logged side currents by bounded nonlinear least squares
(:func:`scipy.optimize.least_squares`, both sides' residuals), with the base vehicle's
geometry, mass and χ and the file's ``c`` held fixed (the logs scale the forces through
``c`` only: ``c`` and the winding resistance are stated assumptions, not identified).

* **Intervals**: moving-block bootstrap over samples (blocks of ``block_s`` seconds),
  percentile intervals at a joint level (Bonferroni over the fitted coefficients); the bias
  of encoder noise (errors in the regressors) is removed by SIMEX and the interval widened
  by its size, as in :mod:`ecoplan.models.identify_logs`.
* **Held-out error**: leave-one-log-out (several logs; a single log: its last
  ``holdout_fraction``), MAE of the logged signal ``V_bus (I_l + I_r)`` [W] and the
  relative error of each held-out log's integral of it.
* **Excluded samples** (:attr:`CurrentLog.excluded`, e.g. a stuck robot found by
  :func:`~ecoplan.models.identify_screen.body_at_rest`) count neither in the fit nor in
  the held-out errors.
* **Unphysical** fits cannot occur: every coefficient is bounded at 0 and the forces
  follow the sides' motion, so the signal cannot fall with a growing resistance.
"""

from __future__ import annotations

import dataclasses
import math
from collections.abc import Mapping, Sequence
from dataclasses import dataclass
from typing import Any

import numpy as np
import yaml
from scipy.optimize import least_squares, lsq_linear

from ecoplan._typing import BoolArray, FloatArray, RngLike
from ecoplan.errors import InputError
from ecoplan.models._validate import check_log_fields, check_range, finite_array
from ecoplan.models.identify_current_vehicle import (
    geometry_of,
    motor_current_spec,
    side_force_terrain,
)
from ecoplan.models.identify_logs import (
    DriveLog,
    check_fit_options,
    model_power,
    simex_widen,
)
from ecoplan.models.identify_logs import _blocks as _blocks  # the same moving blocks
from ecoplan.models.motor_current import (
    MotorCurrentLog,
    SideForceTerrain,
    battery_power_w,
    side_currents_a,
    side_forces,
    travel_since_stop_m,
    turn_slip,
)
from ecoplan.models.tracked import TrackedParams
from ecoplan.models.vehicles import Vehicle, vehicle_from_mapping

__all__ = [
    "CURRENT_PARAMETERS",
    "PLANNER_TERMS",
    "CurrentFit",
    "CurrentIdentification",
    "CurrentLog",
    "identify_from_currents",
    "planner_driver_terms",
    "predict_currents",
]

#: Coefficients identified per terrain, in fit order.
CURRENT_PARAMETERS: tuple[str, ...] = (
    "no_load_current_a",
    "k_resistance_n",
    "mu",
    "turn_slip_scale",
    "startup_force_n",
    "startup_distance_m",
)
_LOWER = np.array([0.0, 0.0, 0.0, 1e-3, 0.0, 0.05])
_UPPER = np.array([50.0, 1e4, 5.0, 10.0, 1e4, 20.0])
_START = np.array([0.5, 30.0, 0.3, 0.1, 10.0, 1.0])
#: Values of the start-up coefficients when they are not fitted (no start-up resistance).
_NO_STARTUP = np.array([0.0, 1.0])


def _free(startup: bool) -> BoolArray:
    """Which of :data:`CURRENT_PARAMETERS` a fit adjusts (the start-up pair on request)."""
    return np.array([True] * 4 + [startup] * 2)


@dataclass(frozen=True, slots=True, eq=False)
class CurrentLog:
    """One log of side speeds and motor currents on one terrain.

    Attributes
    ----------
    t_s : ndarray
        Sample times [s], strictly increasing.
    v_left, v_right : ndarray
        Side speeds [m/s] (REP-103: positive forward).
    current_left_a, current_right_a : ndarray
        Motor current magnitude of each side [A], >= 0.
    terrain : str
        Terrain name (lower case).
    run_id : str
        Name of the log.
    grade_rad : ndarray or None
        Slope climbed along +x per sample [rad] (None: flat).
    sides_logged : bool
        False when only the sum ``I_l + I_r`` is known (:meth:`from_signal`): the fit then
        uses the sum only.
    excluded : ndarray of bool or None
        Samples left out of the fit and of the held-out scores (None: none), e.g. where the
        robot is stuck (:func:`~ecoplan.models.identify_screen.body_at_rest`); the
        derivatives still use the whole series.
    """

    t_s: FloatArray
    v_left: FloatArray
    v_right: FloatArray
    current_left_a: FloatArray
    current_right_a: FloatArray
    terrain: str
    run_id: str = "log"
    grade_rad: FloatArray | None = None
    sides_logged: bool = True
    excluded: BoolArray | None = None

    @classmethod
    def from_signal(
        cls,
        t_s: FloatArray,
        v_left: FloatArray,
        v_right: FloatArray,
        p_total_w: FloatArray,
        bus_voltage_v: float,
        terrain: str,
        run_id: str = "log",
    ) -> CurrentLog:
        """A log whose power column is the logged ``V_bus (I_l + I_r)`` (sides unknown)."""
        check_range("CurrentLog", "bus_voltage_v", bus_voltage_v, 0.0, 1e4, lo_open=True)
        half = finite_array(f"{run_id}.p_total", p_total_w) / (2.0 * bus_voltage_v)
        return cls(t_s, v_left, v_right, half, half.copy(), terrain, run_id, None, False)

    def __post_init__(self) -> None:
        names = ("t_s", "v_left", "v_right", "current_left_a", "current_right_a", "grade_rad")
        check_log_fields(self, names)
        if np.any(self.current_left_a < 0.0) or np.any(self.current_right_a < 0.0):
            raise InputError(f"{self.run_id}: motor currents are magnitudes, >= 0 A")
        if self.excluded is not None and np.shape(self.excluded) != self.t_s.shape:
            raise InputError(f"{self.run_id}: excluded must have one flag per sample")

    @property
    def used(self) -> BoolArray:
        """Samples the fit and the scores use (not :attr:`excluded`)."""
        if self.excluded is None:
            return np.ones(self.t_s.size, dtype=np.bool_)
        return ~np.asarray(self.excluded, dtype=np.bool_)

    def logged_power_w(self, bus_voltage_v: float) -> FloatArray:
        """The logged signal ``V_bus (I_l + I_r)`` [W]."""
        return bus_voltage_v * (self.current_left_a + self.current_right_a)


def predict_currents(
    log: CurrentLog, ground: SideForceTerrain, spec: MotorCurrentLog, geometry: Mapping[str, float]
) -> tuple[FloatArray, FloatArray]:
    """Side currents [A] the side-force model predicts for a log (:func:`.geometry_of`)."""
    grade = 0.0 if log.grade_rad is None else log.grade_rad
    fl, fr = side_forces(log.t_s, log.v_left, log.v_right, ground, grade_rad=grade, **geometry)
    return side_currents_a(spec, ground, log.v_left, log.v_right, fl, fr)


@dataclass(frozen=True, slots=True)
class CurrentFit:
    """Side-force coefficients identified on one terrain.

    Attributes
    ----------
    terrain : str
        Terrain name.
    values : mapping of str to float
        The coefficients of :data:`CURRENT_PARAMETERS` (units as in :class:`SideForceTerrain`).
    intervals : mapping of str to (float, float)
        Joint bootstrap interval of each coefficient.
    run_ids : tuple of str
        Logs used.
    n_samples : int
        Samples used.
    heldout_mae_w : float
        Held-out MAE of the logged signal ``V_bus (I_l + I_r)`` [W].
    heldout_energy_error : tuple of float
        Relative error of each held-out log's integral of the logged signal (signed).
    mean_power_w : float
        Mean logged signal [W].
    n_excluded : int
        Samples the logs mark :attr:`CurrentLog.excluded`; they count in none of the above.
    fitted : tuple of str
        Coefficients the fit adjusted (the others hold the values of "no start-up term").
    """

    terrain: str
    values: Mapping[str, float]
    intervals: Mapping[str, tuple[float, float]]
    run_ids: tuple[str, ...]
    n_samples: int
    heldout_mae_w: float
    heldout_energy_error: tuple[float, ...]
    mean_power_w: float
    n_excluded: int = 0
    fitted: tuple[str, ...] = CURRENT_PARAMETERS

    @property
    def median_energy_error(self) -> float:
        """Median of the absolute held-out energy errors [-]."""
        return float(np.median(np.abs(self.heldout_energy_error)))

    @property
    def identified(self) -> tuple[str, ...]:
        """Coefficients identified (:attr:`fitted`)."""
        return self.fitted

    @property
    def unidentified(self) -> tuple[str, ...]:
        """Coefficients not fitted (the start-up pair unless asked for: no start-up term)."""
        return tuple(n for n in CURRENT_PARAMETERS if n not in self.fitted)

    @property
    def clamped(self) -> dict[str, float]:
        """Coefficients held at a bound against the logs (none: the model cannot need it)."""
        return {}

    def ground(self) -> SideForceTerrain:
        """The identified coefficients as a :class:`SideForceTerrain`."""
        return SideForceTerrain(**{k: float(self.values[k]) for k in CURRENT_PARAMETERS})


@dataclass(frozen=True, slots=True)
class CurrentIdentification:
    """Result of :func:`identify_from_currents`.

    Attributes
    ----------
    base : Vehicle
        Vehicle giving geometry, mass and χ.
    spec : MotorCurrentLog
        What the logs measure (bus voltage, ``c``, winding resistance).
    fits : mapping of str to CurrentFit
        One fit per terrain.
    level : float
        Joint confidence level of the intervals.
    logs : tuple of CurrentLog
        The logs (their motions also fit the planners' driver terms, :meth:`document`).
    name : str
        Name of the identified vehicle.
    """

    base: Vehicle
    spec: MotorCurrentLog
    fits: Mapping[str, CurrentFit]
    level: float
    logs: tuple[CurrentLog, ...] = ()
    name: str = ""

    def document(self) -> dict[str, Any]:
        """The identified vehicle file (``power_log`` of the base) as a plain mapping.

        Each terrain holds the side-force fit and the planners' driver terms fitted to its
        battery power on the logs' motions (:func:`planner_driver_terms`).

        Raises
        ------
        InputError
            The base vehicle's ``power_log`` is not ``motor_current``.
        """
        motor_current_spec(self.base)
        doc: dict[str, Any] = self.base.spec.model_dump(mode="json", exclude_none=True)
        doc["name"] = self.name or self.base.name
        doc["terrains"] = self.terrain_entries()
        if doc.get("default_terrain") not in doc["terrains"]:
            doc["default_terrain"] = sorted(doc["terrains"])[0]
        forces = vehicle_from_mapping(doc, f"identified:{doc['name']}")
        for terrain, fit in self.fits.items():
            group = [log for log in self.logs if log.terrain == terrain]
            note = (
                "least squares (>= 0) of the battery power of the identified side forces "
                "(copper loss with the file's winding resistance) not covered by mu and "
                f"K + I0 / c, on the motions of the {len(fit.run_ids)} logs"
            )
            for key, value in planner_driver_terms(forces, group, terrain).items():
                doc["terrains"][terrain][key] = {
                    "value": float(f"{value:.5g}"),
                    "source": "identified",
                    "ref": note,
                }
        return doc

    def vehicle(self) -> Vehicle:
        """The identified vehicle (see :meth:`document`)."""
        return vehicle_from_mapping(self.document(), f"identified:{self.name}")

    def to_yaml(self, header: str = "") -> str:
        """The identified vehicle file as YAML text, ``header`` as comment lines above it."""
        lines = [f"# {line}" if line else "#" for line in header.splitlines()]
        body = yaml.safe_dump(self.document(), sort_keys=False, allow_unicode=True, width=100)
        return "\n".join([*lines, body]) if lines else body

    def terrain_entries(self) -> dict[str, dict[str, object]]:
        """Terrain table of a vehicle file (``power_log: motor_current``) with the fits."""
        pct = f"{100 * self.level:g} %"
        out: dict[str, dict[str, object]] = {}
        for terrain, fit in sorted(self.fits.items()):
            left_out = f" ({fit.n_excluded} left out: stuck)" if fit.n_excluded else ""
            note = (
                f"side-force fit to the motor currents of {len(fit.run_ids)} log(s), "
                f"{fit.n_samples} samples{left_out}; {pct} joint bootstrap interval"
            )
            entry: dict[str, object] = {
                name: {
                    "value": float(f"{fit.values[name]:.5g}"),
                    "source": "identified",
                    "ref": note,
                    "interval": [float(f"{x:.5g}") for x in fit.intervals[name]],
                }
                for name in fit.fitted
            }
            kept = self.base.spec.terrains.get(terrain)
            for name in fit.unidentified:  # the base's values, if it has them
                value = None if kept is None else getattr(kept, name)
                if value is not None:
                    entry[name] = value.model_dump(mode="json", exclude_none=True)
            entry["heldout_mae_w"] = float(f"{fit.heldout_mae_w:.5g}")
            out[terrain] = entry
        return out


class _Design:
    """Parameter-free parts of the model for a set of logs (so a fit only redoes tanh/max)."""

    def __init__(self, logs: Sequence[CurrentLog], geometry: Mapping[str, float]) -> None:
        zero = SideForceTerrain(0.0, 0.0, 1.0)
        unit_k = SideForceTerrain(1.0, 0.0, 1.0)
        cols: dict[str, list[FloatArray]] = {k: [] for k in ("m0l", "m0r", "kl", "kr", "lam", "s")}
        cols.update(turn=[], sl=[], sr=[], il=[], ir=[], known=[], used=[])
        for log in logs:
            grade = 0.0 if log.grade_rad is None else log.grade_rad
            m0 = side_forces(log.t_s, log.v_left, log.v_right, zero, grade_rad=grade, **geometry)
            k1 = side_forces(log.t_s, log.v_left, log.v_right, unit_k, grade_rad=grade, **geometry)
            cols["m0l"].append(m0[0])
            cols["m0r"].append(m0[1])
            cols["kl"].append(k1[0] - m0[0])
            cols["kr"].append(k1[1] - m0[1])
            cols["s"].append(travel_since_stop_m(log.t_s, log.v_left, log.v_right))
            dv = log.v_right - log.v_left
            cols["turn"].append(np.sign(dv) * (np.abs(dv) > 0.01))
            cols["lam"].append(
                turn_slip(
                    log.v_left, log.v_right, geometry["half_wheelbase_m"], geometry["spread_m"]
                )
            )
            cols["sl"].append(np.where(log.v_left < 0.0, -1.0, 1.0))
            cols["sr"].append(np.where(log.v_right < 0.0, -1.0, 1.0))
            cols["il"].append(log.current_left_a)
            cols["ir"].append(log.current_right_a)
            cols["known"].append(np.full(log.t_s.size, log.sides_logged))
            cols["used"].append(log.used.astype(np.float64))
        self.x = {k: np.concatenate(v) for k, v in cols.items()}
        self.cs = float(geometry["friction_n_per_mu"])

    def currents(
        self, theta: FloatArray, c: float, idx: FloatArray | slice
    ) -> tuple[FloatArray, FloatArray]:
        x = {k: v[idx] for k, v in self.x.items()}
        i0, k0, mu, lam0, k_s, s0 = theta
        k = k0 + k_s * np.exp(-x["s"] / s0)
        f_turn = mu * self.cs * np.tanh(x["lam"] / lam0) * x["turn"]
        fl = x["m0l"] + k * x["kl"] - f_turn
        fr = x["m0r"] + k * x["kr"] + f_turn
        il = i0 + c * np.maximum(fl * x["sl"], 0.0)
        ir = i0 + c * np.maximum(fr * x["sr"], 0.0)
        return il, ir

    def fit(
        self, c: float, idx: FloatArray | slice, start: FloatArray, free: BoolArray
    ) -> FloatArray:
        meas_l, meas_r = self.x["il"][idx], self.x["ir"][idx]
        known = self.x["known"][idx].astype(bool)
        used = self.x["used"][idx].astype(np.float64)

        full = np.where(free, start, np.concatenate([start[:4], _NO_STARTUP]))

        def residual(theta: FloatArray) -> FloatArray:
            # each side where the sides are logged, else the sum (and a zero)
            full[free] = theta
            il, ir = self.currents(full, c, idx)
            first = np.where(known, il - meas_l, il + ir - meas_l - meas_r)
            return np.concatenate([first * used, (ir - meas_r) * known * used])

        x0 = np.clip(start, _LOWER + 1e-9, _UPPER - 1e-9)[free]
        bounds = (_LOWER[free], _UPPER[free])
        res = least_squares(residual, x0, bounds=bounds, x_scale=_START[free])
        full[free] = res.x
        return full.copy()


def _noisier(log: CurrentLog, sigma: float, rng: np.random.Generator) -> CurrentLog:
    """The log with white noise added to the moving sides' speeds (SIMEX step)."""
    vl, vr = (v + rng.normal(0.0, sigma, v.size) * (v != 0.0) for v in (log.v_left, log.v_right))
    return dataclasses.replace(log, v_left=vl, v_right=vr)


def _terrain_fit(
    logs: Sequence[CurrentLog],
    geometry: Mapping[str, float],
    spec: MotorCurrentLog,
    *,
    level: float,
    n_boot: int,
    block_s: float,
    holdout_fraction: float,
    speed_noise_mps: float,
    n_simex: int,
    rng: np.random.Generator,
    startup: bool,
) -> CurrentFit:
    design = _Design(logs, geometry)
    c = spec.amps_per_newton
    free = _free(startup)
    theta = design.fit(c, slice(None), _START, free)
    t_all = np.concatenate([log.t_s - log.t_s[0] + 1e6 * i for i, log in enumerate(logs)])
    blocks = _blocks(t_all, block_s)
    boots = []
    for _ in range(n_boot):
        pick = rng.integers(0, len(blocks), len(blocks))
        boots.append(design.fit(c, np.concatenate([blocks[k] for k in pick]), theta, free))
    alpha = (1.0 - level) / int(free.sum())  # Bonferroni: joint coverage >= level
    lo, hi = np.percentile(np.array(boots), (100 * alpha / 2, 100 * (1 - alpha / 2)), axis=0)
    if speed_noise_mps > 0.0:  # SIMEX: bias of the encoder noise, extrapolated to no noise
        sims = [
            _Design([_noisier(log, speed_noise_mps, rng) for log in logs], geometry).fit(
                c, slice(None), theta, free
            )
            for _ in range(n_simex)
        ]
        shift = theta - np.mean(sims, axis=0)
        theta = np.clip(theta + shift, _LOWER, _UPPER)
        lo, hi = simex_widen(lo, hi, shift, 0.0)
    mae, energy = _holdout(logs, geometry, spec, holdout_fraction, theta, free)
    signal = np.concatenate([log.logged_power_w(spec.bus_voltage_v)[log.used] for log in logs])
    return CurrentFit(
        terrain=logs[0].terrain,
        values=dict(zip(CURRENT_PARAMETERS, (float(v) for v in theta), strict=True)),
        intervals={n: (float(lo[j]), float(hi[j])) for j, n in enumerate(CURRENT_PARAMETERS)},
        run_ids=tuple(log.run_id for log in logs),
        n_samples=int(signal.size),
        heldout_mae_w=mae,
        heldout_energy_error=energy,
        mean_power_w=float(signal.mean()),
        n_excluded=int(sum(int(np.sum(~log.used)) for log in logs)),
        fitted=tuple(n for n, f in zip(CURRENT_PARAMETERS, free, strict=True) if f),
    )


def _holdout(
    logs: Sequence[CurrentLog],
    geometry: Mapping[str, float],
    spec: MotorCurrentLog,
    holdout_fraction: float,
    start: FloatArray,
    free: BoolArray,
) -> tuple[float, tuple[float, ...]]:
    """Leave-one-log-out (several logs) or a final time split (one log)."""
    splits: list[tuple[list[CurrentLog], CurrentLog]] = []
    if len(logs) > 1:
        splits = [([g for j, g in enumerate(logs) if j != i], h) for i, h in enumerate(logs)]
    else:
        log = logs[0]
        cut = min(max(2, round(log.t_s.size * (1.0 - holdout_fraction))), log.t_s.size - 3)

        def piece(sl: slice) -> CurrentLog:
            grade = None if log.grade_rad is None else log.grade_rad[sl]
            return CurrentLog(
                log.t_s[sl], log.v_left[sl], log.v_right[sl], log.current_left_a[sl],
                log.current_right_a[sl], log.terrain, log.run_id, grade, log.sides_logged,
                ~log.used[sl],
            )  # fmt: skip

        splits = [([piece(slice(None, cut))], piece(slice(cut, None)))]
    errs: list[FloatArray] = []
    energy: list[float] = []
    v_bus = spec.bus_voltage_v
    for train, held in splits:
        theta = _Design(train, geometry).fit(spec.amps_per_newton, slice(None), start, free)
        ground = SideForceTerrain(
            **{n: float(x) for n, x in zip(CURRENT_PARAMETERS, theta, strict=True)}
        )
        il, ir = predict_currents(held, ground, spec, geometry)
        use = held.used
        pred, meas = v_bus * (il + ir) * use, held.logged_power_w(v_bus) * use
        errs.append(np.abs(pred - meas)[use])
        e_meas = float(np.trapezoid(meas, held.t_s))
        ratio = float(np.trapezoid(pred, held.t_s)) / e_meas - 1.0 if e_meas > 0 else math.nan
        energy.append(ratio)
    return float(np.mean(np.concatenate(errs))), tuple(energy)


def identify_from_currents(
    logs: Sequence[CurrentLog],
    base: Vehicle,
    spec: MotorCurrentLog,
    *,
    name: str | None = None,
    level: float = 0.95,
    n_boot: int = 100,
    block_s: float = 5.0,
    holdout_fraction: float = 0.2,
    speed_noise_mps: float = 0.005,
    n_simex: int = 10,
    rng: RngLike = None,
    startup: bool = False,
) -> CurrentIdentification:
    """Identify the side-force model of each terrain from motor-current logs.

    Parameters
    ----------
    logs : sequence of CurrentLog
        Logs; each carries its terrain.
    base : Vehicle
        Contact-friction vehicle giving geometry, mass and χ (its terrain of the same name,
        else its default terrain, for χ).
    spec : MotorCurrentLog
        What the logs measure: bus voltage and ``c`` (held fixed, not identified).
    name : str, optional
        Name of the identified vehicle (default: the base's).
    level : float
        Joint confidence level of the intervals, in (0, 1).
    n_boot : int
        Bootstrap resamples per terrain.
    block_s : float
        Length of the bootstrap blocks [s].
    holdout_fraction : float
        Share of a terrain's single log held out (several logs: leave one out).
    speed_noise_mps : float
        Standard deviation of the side-speed (encoder) noise [m/s]; its bias (errors in the
        regressors) is removed by simulation-extrapolation (SIMEX: refit with the noise
        doubled, extrapolate linearly to no noise).  0 = no correction.
    n_simex : int
        Refits averaged in the SIMEX step.
    rng : Generator, int or None
        Randomness of the bootstrap.
    startup : bool
        Also fit the start-up resistance ``K_s exp(-s / s0)`` after each stop (ground where
        a robot at rest settles in: snow, soft soil); False: no start-up term (``K_s = 0``,
        the pair reported as not identified).

    Returns
    -------
    CurrentIdentification

    Raises
    ------
    InputError
        No logs, a radius-fit base vehicle, or a bad option.
    """
    if not logs:
        raise InputError("identify: no logs given")
    check_fit_options(
        "identify_from_currents", level, n_boot, block_s, holdout_fraction, speed_noise_mps,
        n_simex,
    )  # fmt: skip
    gen = rng if isinstance(rng, np.random.Generator) else np.random.default_rng(rng)
    by_terrain: dict[str, list[CurrentLog]] = {}
    for log in logs:
        by_terrain.setdefault(log.terrain, []).append(log)
    fits = {
        terrain: _terrain_fit(
            group,
            geometry_of(base, terrain),
            spec,
            level=level,
            n_boot=n_boot,
            block_s=block_s,
            holdout_fraction=holdout_fraction,
            speed_noise_mps=speed_noise_mps,
            n_simex=n_simex,
            rng=gen,
            startup=startup,
        )
        for terrain, group in sorted(by_terrain.items())
    }
    return CurrentIdentification(base, spec, fits, level, tuple(logs), name or base.name)


#: Driver terms of the planners' contact-friction model fitted to the forces' battery power.
PLANNER_TERMS: tuple[str, ...] = ("p_braking_w", "k_nonregen_n", "p_powerup_w")


def planner_driver_terms(
    vehicle: Vehicle, logs: Sequence[CurrentLog], terrain: str
) -> dict[str, float]:
    """Driver terms that carry the side forces' battery power into the planners' model.

    The planners cost motion with the contact-friction model (tracked eq. 20) of the file:
    µ and ``K + I0 / c`` cover the forces' output and the no-load torque; what is left of
    :func:`~ecoplan.models.motor_current.battery_power_w` on the logs' motions (the braked
    inner side's lost power, the copper loss of turning currents) is fitted, bounded at 0,
    to the model's driver terms: braking (cases 3-4), non-regenerated (case 2), power-up.
    The file's η divides the planners' mechanical terms on top of these explicit motor
    losses: keep it 1 unless the drivers themselves lose power (husky-a200: 1).

    Parameters
    ----------
    vehicle : Vehicle
        A ``motor_current`` vehicle file whose terrain entry has the side-force fit.
    logs : sequence of CurrentLog
        Motions to fit on (the identification logs of the terrain).
    terrain : str
        Terrain name.

    Returns
    -------
    dict
        ``p_braking_w`` [W], ``k_nonregen_n`` [N], ``p_powerup_w`` [W].
    """
    spec, ground = motor_current_spec(vehicle), side_force_terrain(vehicle, terrain)
    geom = geometry_of(vehicle, terrain)
    full = vehicle.params(terrain)
    assert isinstance(full, TrackedParams)  # geometry_of refuses radius-fit files
    params = dataclasses.replace(full, p_braking_w=0.0, k_nonregen_n=0.0, p_powerup_w=0.0)
    rows, target = [], []
    for log in logs:
        fl, fr = side_forces(log.t_s, log.v_left, log.v_right, ground, **geom)
        p_batt = battery_power_w(spec, ground, log.v_left, log.v_right, fl, fr)
        drive = DriveLog(log.t_s, log.v_left, log.v_right, p_batt, terrain, log.run_id)
        mass_terms = (
            model_power(drive, vehicle, terrain) - full.power(log.v_left, log.v_right).total_w
        )
        base = mass_terms + params.power(log.v_left, log.v_right).total_w
        cols = []
        flat = dataclasses.replace(params, mu=0.0, k_resistance_n=0.0)
        for unit in (
            dataclasses.replace(flat, p_braking_w=1.0),
            dataclasses.replace(flat, k_nonregen_n=1.0),
            dataclasses.replace(flat, p_powerup_w=1.0),
        ):
            cols.append(unit.power(log.v_left, log.v_right).total_w)
        rows.append(np.column_stack(cols)[log.used])
        target.append((p_batt - base)[log.used])
    res = lsq_linear(np.vstack(rows), np.concatenate(target), bounds=(0.0, np.inf))
    return {n: float(v) for n, v in zip(PLANNER_TERMS, res.x, strict=True)}
