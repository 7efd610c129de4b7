"""Blind-check cases: sessions of runs with one withheld effect, and their truth.

:func:`generate_case` draws a session (the true vehicle, the runs in random order, the
effect and its parameters), drives it, applies the effect and records the noisy logs;
:class:`SynthCase` keeps the logs and, apart, the :class:`SynthTruth`;
:func:`write_cases` writes cases to disk for ``ecoplan diagnose``; :func:`magnitude_survey`
measures the realised effect sizes.

Realism choices (documented assumptions)
----------------------------------------
* The true robot differs from its preset: by default ``base_error = 0.1`` draws µ, ``K``,
  the driver terms and the acceleration limit within ±10 % (recorded in the truth), so the
  diagnosis must calibrate before it attributes.
* Logs hold ``t, v_left, v_right, p_total, v_left_cmd, v_right_cmd, x, y, yaw, wz`` and a
  constant ``terrain`` label (patches are not labelled); no per-motor powers.
* Sensor noise is white: power 2 % + 3 W, side speeds 0.005 m/s (zero at rest: an encoder
  of a still wheel reads zero), gyro 0.01 rad/s, position 0.02 m, heading 0.005 rad;
  commands are logged exactly.
* A session: one stationary grid (6 pairs), two spirals (left and right) and
  ``n_waypoint_runs`` A->B runs in random order, starting in a 10 m x 10 m area, 5-30 s
  apart: about 5 minutes and 15 000 samples at 50 Hz.
"""

from __future__ import annotations

import dataclasses
import json
import math
import os
from collections.abc import Mapping, Sequence
from dataclasses import dataclass, field
from pathlib import Path
from typing import Any

import numpy as np

from ecoplan._typing import FloatArray, RngLike
from ecoplan.dynamics.drive import follow_commands
from ecoplan.dynamics.log import Log
from ecoplan.errors import InputError
from ecoplan.io.logcsv import write_log_csv
from ecoplan.models.kinematics import TrackICR
from ecoplan.presets import VehicleParams
from ecoplan.presets import vehicle as preset_vehicle
from ecoplan.synth.manoeuvres import (
    WaypointTask,
    spiral_commands,
    stationary_grid_commands,
    waypoint_runs,
)
from ecoplan.synth.sensors import SensorNoise, observe
from ecoplan.synth.trajectory import Trajectory, trajectory_from_commands
from ecoplan.synth.withheld import (
    IN_LIBRARY,
    MAGNITUDE_NAMES,
    OUT_OF_LIBRARY,
    choose_effect,
    drive_model,
    effect_params,
    expected_verdict,
    inject,
)

__all__ = ["SynthCase", "SynthTruth", "generate_case", "magnitude_survey", "write_cases"]


@dataclass(frozen=True, slots=True)
class SynthTruth:
    """The withheld answer of a case (never shown to the diagnosis).

    Attributes
    ----------
    effect : str
        Injected effect (one of :data:`EFFECTS`).
    label : str
        Expected verdict class: the effect name, ``none`` or ``out_of_library``.
    expected_verdict : str
        The verdict a perfect diagnosis gives: the effect, ``none`` or ``unexplained``.
    magnitude : str
        ``small``, ``moderate`` or ``large`` (``""`` for ``none``).
    params : dict
        Effect parameters as passed to :func:`~ecoplan.synth.withheld.inject`.
    base_params : dict
        The true vehicle's parameters that differ from the preset (``base_error``).
    effect_mae_w : float
        Mean absolute difference, noise-free, between the power with the effect and the
        true base model's power at the commands through the acceleration limit [W]
        (for every effect but ``actuator_lag`` these are the actual speeds; for it, the
        gap a command-driven model sees).
    effect_speed_mae_mps : float
        Mean absolute difference between the actual side speeds and the commands through
        the acceleration limit alone [m/s] (zero but for ``actuator_lag``).
    base_mean_w : float
        Mean true power of the base model on the same motion [W].
    seed_info : str
        How the case was drawn (for reproduction).
    """

    effect: str
    label: str
    expected_verdict: str
    magnitude: str
    params: dict[str, float]
    base_params: dict[str, float]
    effect_mae_w: float
    effect_speed_mae_mps: float
    base_mean_w: float
    seed_info: str = ""

    def to_json(self) -> dict[str, Any]:
        """JSON-ready dictionary."""
        return dataclasses.asdict(self)


@dataclass(frozen=True, slots=True, eq=False)
class SynthCase:
    """A blind-check case: logs for the diagnosis, the truth kept apart.

    Attributes
    ----------
    logs : tuple of Log
        One log per run (session clock).
    vehicle : str
        Vehicle preset the diagnosis is told.
    terrain : str
        Terrain preset the diagnosis is told.
    truth : SynthTruth
        The withheld answer.
    trajectories : tuple of Trajectory
        True motion of every run (hidden, for checks).
    true_power : tuple of ndarray
        Noise-free power of every run with the effect [W] (hidden).
    base_power : tuple of ndarray
        Noise-free power of the true base vehicle at the rate-limited commands [W]
        (hidden; the actual speeds but for ``actuator_lag``).
    """

    logs: tuple[Log, ...]
    vehicle: str
    terrain: str
    truth: SynthTruth = field(repr=False)
    trajectories: tuple[Trajectory, ...] = field(repr=False, default=())
    true_power: tuple[FloatArray, ...] = field(repr=False, default=())
    base_power: tuple[FloatArray, ...] = field(repr=False, default=())

    def write(self, directory: str | os.PathLike[str], *, overwrite: bool = False) -> list[Path]:
        """Write the logs as ``<run_id>.csv`` and the truth as ``truth.json`` beside them.

        Returns
        -------
        list of Path
            The log files (the truth file is not in the list).
        """
        d = Path(directory)
        d.mkdir(parents=True, exist_ok=True)
        paths = [write_log_csv(lg, d / f"{lg.run_id}.csv", overwrite=overwrite) for lg in self.logs]
        truth = d / "truth.json"
        if truth.exists() and not overwrite:
            raise InputError(f"{truth}: file exists; pass overwrite=True to replace it")
        payload = {"vehicle": self.vehicle, "terrain": self.terrain, **self.truth.to_json()}
        truth.write_text(json.dumps(payload, indent=2, sort_keys=True))
        return paths


_BASE_ERROR_FIELDS = {
    "tracked": ("mu", "k_resistance_n", "p_powerup_w", "p_braking_w", "k_nonregen_n"),
    "wheeled": ("p_powerup_w",),
}


def _true_vehicle(
    nominal: VehicleParams, g: np.random.Generator, base_error: float
) -> tuple[VehicleParams, dict[str, float]]:
    if base_error <= 0.0:
        return nominal, {}
    changes: dict[str, float] = {}
    for name in _BASE_ERROR_FIELDS[nominal.kind]:
        val = float(getattr(nominal, name))
        if val > 0.0:
            changes[name] = val * (1.0 + g.uniform(-base_error, base_error))
    changes["accel_max_mps2"] = nominal.accel_max_mps2 * (1.0 + g.uniform(-base_error, base_error))
    true_vehicle: Any = dataclasses.replace(nominal, **changes)  # type: ignore[arg-type]
    return true_vehicle, changes


@dataclass(frozen=True, slots=True, eq=False)
class _RunPlan:
    """One run of a session, drawn once and replayed with or without the effect.

    Open loop: ``t`` (from 0) and the commands; closed loop: ``task``.
    """

    kind: str
    pose0: tuple[float, float, float]
    t: FloatArray | None = None
    cmd_left: FloatArray | None = None
    cmd_right: FloatArray | None = None
    task: WaypointTask | None = None


def _session_plan(
    g: np.random.Generator, vehicle: VehicleParams, dt_s: float, n_waypoint_runs: int
) -> list[_RunPlan]:
    """The runs of a session in random order: a stationary grid, two spirals, A->B runs."""
    area = 10.0

    def start() -> tuple[float, float, float]:
        return (
            float(g.uniform(-area / 2, area / 2)),
            float(g.uniform(-area / 2, area / 2)),
            float(g.uniform(-math.pi, math.pi)),
        )

    t, cl, cr = stationary_grid_commands(vehicle, g, n_pairs=6, dt_s=dt_s)
    plans = [_RunPlan("grid", start(), t, cl, cr)]
    for left in (True, False):
        t, cl, cr = spiral_commands(vehicle, g, left_turn=left, dt_s=dt_s)
        plans.append(_RunPlan("spiral", start(), t, cl, cr))
    for _ in range(n_waypoint_runs):
        pose0 = start()
        wps = tuple(
            (float(g.uniform(-area, area)), float(g.uniform(-area, area)))
            for _ in range(int(g.integers(3, 6)))
        )
        speed = float(g.uniform(0.35, 0.75)) * vehicle.top_track_speed_mps
        task = WaypointTask(wps, pose0, speed, float(g.uniform(0.4, 1.2)))
        plans.append(_RunPlan("waypoints", pose0, task=task))
    order = g.permutation(len(plans))
    return [plans[i] for i in order]


def _run_session(
    plans: Sequence[_RunPlan],
    vehicle: VehicleParams,
    tau_s: float,
    pauses: Sequence[float],
    dt_s: float,
    ctrl_icr: TrackICR,
) -> list[Trajectory]:
    """Every run of a session on one clock; the closed-loop runs rolled out in one batch."""
    tasks = [plan.task for plan in plans if plan.task is not None]
    closed = iter(waypoint_runs(vehicle, tasks, dt_s=dt_s, controller_icr=ctrl_icr, tau_s=tau_s))
    out: list[Trajectory] = []
    t0 = 0.0
    for plan, pause in zip(plans, pauses, strict=True):
        if plan.t is not None and plan.cmd_left is not None and plan.cmd_right is not None:
            traj = trajectory_from_commands(
                t0 + plan.t,
                plan.cmd_left,
                plan.cmd_right,
                vehicle,
                tau_s=tau_s,
                pose0=plan.pose0,
                manoeuvre=plan.kind,
            )
        else:
            traj = next(closed).shifted(t0)
        out.append(traj)
        t0 = float(traj.t[-1]) + pause
    return out


def generate_case(
    rng: RngLike,
    effect: str | None = "random",
    magnitude: str = "moderate",
    vehicle: str = "auriga-beta-narrow",
    terrain: str = "asphalt",
    *,
    n_waypoint_runs: int = 2,
    rate_hz: float = 50.0,
    noise: SensorNoise | None = None,
    base_error: float = 0.1,
    params: Mapping[str, float] | None = None,
) -> SynthCase:
    """Generate a blind-check case: a session of runs with one withheld effect.

    Parameters
    ----------
    rng : Generator, int or None
        Random source (an int seed makes the case reproducible).
    effect : str or None
        An effect of :data:`EFFECTS`, ``"random"`` (uniform over ``none``, the ten library
        effects and ``out_of_library``), ``"out_of_library"`` (one of
        :data:`OUT_OF_LIBRARY`) or None (= ``"none"``).
    magnitude : str
        ``small``, ``moderate`` or ``large`` (:data:`MAGNITUDES`).
    vehicle, terrain : str
        Presets of the nominal vehicle (what the diagnosis is told).
    n_waypoint_runs : int
        A->B runs in the session (besides one stationary grid and two spirals).
    rate_hz : float
        Sample rate [Hz].
    noise : SensorNoise, optional
        Sensor noise (default :meth:`SensorNoise.for_vehicle` of the preset).
    base_error : float
        Relative spread of the true base parameters around the preset (0 = exact).
    params : mapping, optional
        Effect parameters to use instead of drawing them for ``magnitude``.

    Returns
    -------
    SynthCase
        Logs, presets and the withheld truth.
    """
    g = np.random.default_rng(rng)
    if not (math.isfinite(rate_hz) and 5.0 <= rate_hz <= 1000.0):
        raise InputError(f"rate_hz = {rate_hz!r} is out of range; accepted: [5, 1000]")
    if not (0.0 <= base_error < 0.5):
        raise InputError(f"base_error = {base_error!r} is out of range; accepted: [0, 0.5)")
    if magnitude not in MAGNITUDE_NAMES:
        raise InputError(f"unknown magnitude {magnitude!r}; accepted: {', '.join(MAGNITUDE_NAMES)}")
    name = choose_effect(g, effect)
    nominal = preset_vehicle(vehicle, terrain)
    true_vehicle, base_changes = _true_vehicle(nominal, g, base_error)
    dt = 1.0 / rate_hz
    plans = _session_plan(g, true_vehicle, dt, n_waypoint_runs)
    pauses = [float(g.uniform(5.0, 30.0)) for _ in plans]
    base_trajs = _run_session(plans, true_vehicle, 0.0, pauses, dt, nominal.icr)
    p = (
        dict(params)
        if params is not None
        else effect_params(name, magnitude, true_vehicle, base_trajs, g)
    )
    drive_vehicle, tau = drive_model(name, p, true_vehicle)
    if drive_vehicle is true_vehicle and tau == 0.0:
        trajs = base_trajs
    else:
        trajs = _run_session(plans, drive_vehicle, tau, pauses, dt, nominal.icr)
    powers = [inject(name, p, true_vehicle, tr) for tr in trajs]
    bases = [_base_power_from_commands(true_vehicle, tr) for tr in trajs]
    noise_rng = np.random.default_rng(g.integers(0, 2**63 - 1))
    logs = tuple(
        observe(
            tr,
            pw,
            noise_rng,
            SensorNoise.for_vehicle(nominal) if noise is None else noise,
            terrain=terrain,
            run_id=f"run{i:02d}-{tr.manoeuvre}",
            source=f"<synth run{i:02d}>",
        )
        for i, (tr, pw) in enumerate(zip(trajs, powers, strict=True))
    )
    p_all = np.concatenate(powers)
    b_all = np.concatenate(bases)
    speed_mae = _tracking_error(trajs, true_vehicle.accel_max_mps2)
    truth = SynthTruth(
        effect=name,
        label=name if name in IN_LIBRARY or name == "none" else "out_of_library",
        expected_verdict=expected_verdict(name, nominal),
        magnitude="" if name == "none" else magnitude,
        params=p,
        base_params=base_changes,
        effect_mae_w=float(np.mean(np.abs(p_all - b_all))),
        effect_speed_mae_mps=speed_mae,
        base_mean_w=float(np.mean(b_all)),
        seed_info=f"effect={effect!r} magnitude={magnitude!r} vehicle={vehicle!r}",
    )
    return SynthCase(
        logs=logs,
        vehicle=vehicle,
        terrain=terrain,
        truth=truth,
        trajectories=tuple(trajs),
        true_power=tuple(powers),
        base_power=tuple(bases),
    )


def _base_power_from_commands(vehicle: VehicleParams, traj: Trajectory) -> FloatArray:
    """Base model's power at the commands through the acceleration limit alone [W].

    Equal to the power at the actual speeds for every effect but ``actuator_lag``, for
    which it is what a model driven by the commands predicts.
    """
    a = vehicle.accel_max_mps2
    vl = follow_commands(traj.t, traj.cmd_left, a)
    vr = follow_commands(traj.t, traj.cmd_right, a)
    return np.asarray(vehicle.power(vl, vr).total_w, dtype=np.float64)


def _tracking_error(trajs: Sequence[Trajectory], accel_max_mps2: float) -> float:
    """Mean |actual side speed - rate-limited command| over a session [m/s]."""
    err = [
        np.abs(v - follow_commands(tr.t, c, accel_max_mps2))
        for tr in trajs
        for v, c in ((tr.v_left, tr.cmd_left), (tr.v_right, tr.cmd_right))
    ]
    return float(np.mean(np.concatenate(err)))


def magnitude_survey(
    magnitude: str = "moderate",
    seeds: Sequence[int] = tuple(range(12)),
    effects: Sequence[str] = (*IN_LIBRARY, *OUT_OF_LIBRARY),
    **case_kwargs: Any,
) -> dict[str, tuple[float, float, float]]:
    """Realised effect sizes: min, median and max of ``effect_mae_w`` over seeds [W].

    The key ``"noise"`` holds the same statistics of the mean absolute power-sensor noise
    of the ``none`` cases, for comparison.

    Parameters
    ----------
    magnitude : str
        ``small``, ``moderate`` or ``large``.
    seeds : sequence of int
        Seeds of the cases.
    effects : sequence of str
        Effects to survey.
    **case_kwargs
        Passed to :func:`generate_case` (vehicle, terrain, rate, ...).

    Returns
    -------
    dict
        ``effect -> (min, median, max)`` [W].
    """
    out: dict[str, tuple[float, float, float]] = {}

    def stats(values: list[float]) -> tuple[float, float, float]:
        return float(np.min(values)), float(np.median(values)), float(np.max(values))

    for eff in effects:
        out[eff] = stats(
            [generate_case(s, eff, magnitude, **case_kwargs).truth.effect_mae_w for s in seeds]
        )
    noise = []
    for s in seeds:
        case = generate_case(s, "none", magnitude, **case_kwargs)
        diffs = [np.abs(lg.p_total - p) for lg, p in zip(case.logs, case.true_power, strict=True)]
        noise.append(float(np.mean(np.concatenate(diffs))))
    out["noise"] = stats(noise)
    return out


def write_cases(
    directory: str | os.PathLike[str],
    seeds: Sequence[int],
    effect: str | None = "random",
    magnitude: str = "moderate",
    vehicle: str = "auriga-beta-narrow",
    terrain: str = "asphalt",
    *,
    overwrite: bool = False,
    **case_kwargs: Any,
) -> list[Path]:
    """Write blind-check cases to ``directory/case_<seed>/`` (logs + ``truth.json``).

    Back end for a command line ``ecoplan synth``: the logs can then be diagnosed with
    ``ecoplan diagnose directory/case_<seed>/run*.csv`` and the verdict compared with the
    truth file, which the diagnosis never reads.

    Parameters
    ----------
    directory : path-like
        Output directory (created).
    seeds : sequence of int
        One case per seed.
    effect, magnitude, vehicle, terrain
        As :func:`generate_case`.
    overwrite : bool
        Replace existing files.
    **case_kwargs
        Passed to :func:`generate_case`.

    Returns
    -------
    list of Path
        The case directories.
    """
    root = Path(directory)
    out = []
    for seed in seeds:
        case = generate_case(seed, effect, magnitude, vehicle, terrain, **case_kwargs)
        d = root / f"case_{seed}"
        case.write(d, overwrite=overwrite)
        out.append(d)
    return out
