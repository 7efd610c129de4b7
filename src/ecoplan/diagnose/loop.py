"""Closing the loop: the corrected model as a file, and whether it changes a route ranking.

:func:`save_corrected_model` writes the base preset, the calibrated parameters (refitted with the
winning effect) and the effect's fitted physical parameters to JSON (or YAML by suffix);
:func:`load_corrected_model` reads it back into a :class:`CorrectedModel` whose ``power(vl, vr)``
is a drop-in for ``params.power`` (steady state) and whose :meth:`CorrectedModel.trajectory_power`
adds the time-dependent part of the effect along a trajectory.

:func:`ranking_change` compares the energy ranking of candidate routes — each a trajectory
``(t, v_left, v_right)`` or a way-point polyline — under the preset and under the corrected
model.  It needs no planner: polylines are driven turn-on-the-spot then straight (the
tracked paper's A->B manoeuvre, §IV) through the drive's acceleration limit.

The effect is applied by its class in :mod:`ecoplan.diagnose.effects` (the same code that
generates the blind cases), with the parameter names the diagnosis reports.  Effects in the
steady-state ``power(vl, vr)`` (``Effect.steady``): ``speed_dependent_resistance``,
``regeneration``, ``power_saturation``, ``icr_asymmetry`` (in the parameters).  Only along a
trajectory: ``inertia`` (needs accelerations), ``slope`` (heading), ``terrain_patch``
(position), ``actuator_lag`` (the trajectory's speeds are then commands), ``efficiency_drift``
(time since the log's clock origin).  ``sensor_delay`` is a logging artefact and
``terrain_change`` is tied to the log's clock: neither changes the power of a new route
(``Effect.on_routes``).
"""

from __future__ import annotations

import dataclasses
import json
import math
import os
from collections.abc import Mapping, Sequence
from dataclasses import dataclass
from pathlib import Path
from typing import TYPE_CHECKING, Any

import numpy as np

from ecoplan._typing import ArrayLike, FloatArray
from ecoplan.diagnose.calibrate import base_design, with_linear_params
from ecoplan.diagnose.corrected_file import FORMAT, read_corrected_model_file
from ecoplan.diagnose.effects import Motion, effect_class
from ecoplan.dynamics.drive import follow_commands
from ecoplan.errors import InputError
from ecoplan.io.yaml import error_at
from ecoplan.models.kinematics import setpoint_to_tracks
from ecoplan.models.power import PowerBreakdown
from ecoplan.models.wheeled import SideCoefficients
from ecoplan.presets import VehicleParams, vehicle

if TYPE_CHECKING:
    from ecoplan.diagnose.result import Diagnosis

__all__ = [
    "CorrectedModel",
    "RankingChange",
    "corrected_model",
    "load_corrected_model",
    "polyline_trajectory",
    "ranking_change",
    "save_corrected_model",
]


def _param_dict(params: VehicleParams) -> dict[str, Any]:
    out: dict[str, Any] = {}
    for f in dataclasses.fields(params):
        if not f.init or f.name == "name":
            continue
        val = getattr(params, f.name)
        out[f.name] = dataclasses.asdict(val) if isinstance(val, SideCoefficients) else val
    return out


@dataclass(frozen=True, slots=True)
class CorrectedModel:
    """Base model with re-identified parameters plus one fitted effect.

    Attributes
    ----------
    vehicle : str
        Vehicle preset name.
    terrain : str or None
        Terrain preset name.
    params : TrackedParams or WheeledParams
        Calibrated parameters (refitted together with the effect).
    effect : str
        Effect name (``"none"`` when the verdict named no effect).
    effect_params : dict
        Fitted physical parameters of the effect.
    """

    vehicle: str
    terrain: str | None
    params: VehicleParams
    effect: str = "none"
    effect_params: Mapping[str, float] = dataclasses.field(default_factory=dict)

    @property
    def kind(self) -> str:
        """``"tracked"`` or ``"wheeled"``."""
        return self.params.kind

    def power(self, v_left: ArrayLike, v_right: ArrayLike) -> PowerBreakdown:
        """Steady-state power breakdown with the correction [W].

        The effect's steady-state power (:meth:`ecoplan.diagnose.effects.Effect.steady_power`)
        is added to ``resistance_w`` (it resists the motion or, negative, returns power); a
        supply limit clips ``total_w`` and ``elec_loss_w`` absorbs the clipped part so that the
        components still add up.
        """
        vl = np.asarray(v_left, dtype=np.float64)
        vr = np.asarray(v_right, dtype=np.float64)
        pb = self.params.power(vl, vr)
        cls = effect_class(self.effect)
        if not cls.steady:
            return pb
        total = cls.steady_power(self.effect_params, self.params, vl, vr)
        extra = total - pb.total_w
        if cls.supply_side:
            return dataclasses.replace(pb, elec_loss_w=pb.elec_loss_w + extra, total_w=total)
        return dataclasses.replace(pb, resistance_w=pb.resistance_w + extra, total_w=total)

    def trajectory_power(
        self,
        t: ArrayLike,
        v_left: ArrayLike,
        v_right: ArrayLike,
        *,
        x: ArrayLike | None = None,
        y: ArrayLike | None = None,
        yaw: ArrayLike | None = None,
    ) -> FloatArray:
        """Power along a trajectory [W], with the effect's time-dependent part.

        The effect's class applies it (:meth:`ecoplan.diagnose.effects.Effect.apply`); the
        commands go through its drive (:meth:`ecoplan.diagnose.effects.Effect.drive`: the
        lag of ``actuator_lag``) and the drive law of :mod:`ecoplan.dynamics.drive`.  An
        effect that does not carry over to routes (``sensor_delay``, ``terrain_change``)
        leaves the steady-state power.

        Parameters
        ----------
        t : array_like
            Time [s], strictly increasing.
        v_left, v_right : array_like
            Side speeds [m/s] (commands, when the effect is ``actuator_lag``).
        x, y, yaw : array_like, optional
            Pose [m, m, rad]; integrated from the speeds when absent
            (:func:`ecoplan.dynamics.integrate.integrate_twist`).
        """
        tt = np.asarray(t, dtype=np.float64)
        vl = np.asarray(v_left, dtype=np.float64)
        vr = np.asarray(v_right, dtype=np.float64)
        cls = effect_class(self.effect)
        if not cls.on_routes or cls.steady:
            return np.asarray(self.power(vl, vr).total_w, dtype=np.float64)
        tau = cls.drive(self.effect_params, self.params)[1]
        if tau > 0.0:
            vl = follow_commands(tt, vl, self.params.accel_max_mps2, tau)
            vr = follow_commands(tt, vr, self.params.accel_max_mps2, tau)
        motion = Motion.of_tracks(tt, vl, vr, self.params.icr, (x, y, yaw))
        return cls.apply(self.effect_params, self.params, motion)

    def to_dict(self) -> dict[str, Any]:
        """JSON/YAML-ready dictionary (the file format)."""
        return {
            "format": FORMAT,
            "vehicle": self.vehicle,
            "terrain": self.terrain,
            "kind": self.kind,
            "params": _param_dict(self.params),
            "effect": {
                "name": self.effect,
                "params": {
                    k: (float(v) if math.isfinite(float(v)) else None)
                    for k, v in self.effect_params.items()
                },
            },
        }


def corrected_model(d: Diagnosis) -> CorrectedModel:
    """The corrected model of a diagnosis: calibrated base refitted with the verdict's effect."""
    from ecoplan.diagnose.effects import prepare

    att = d.attribution
    name = att.tied[0] if att.verdict == "ambiguous" and att.tied else att.verdict
    eff = att.fitted.get(name)
    if eff is None or name in ("none", "unexplained"):
        return CorrectedModel(d.vehicle, d.terrain, d.calibration.params)
    eparams = {k: v for k, v in eff.params_.items() if k != "chi"}
    params = d.calibration.params
    if eff.chi_ is not None:
        params = dataclasses.replace(params, chi=eff.chi_)
    # the vehicle the effect drives (icr_asymmetry: its shifted ICRs)
    params = effect_class(name).drive(eparams, params)[0]
    if eff.coef_ is not None and eff.coef_.size and name != "actuator_lag":
        data = prepare(d.test_frame, params, prior=d.preset)
        names = base_design(data.frame, params).names
        params = with_linear_params(params, names, eff.coef_[: len(names)])
    return CorrectedModel(d.vehicle, d.terrain, params, name, eparams)


def save_corrected_model(d: Diagnosis | CorrectedModel, path: str | os.PathLike[str]) -> Path:
    """Write the corrected model to JSON (``.json``) or YAML (``.yaml``/``.yml``)."""
    model = d if isinstance(d, CorrectedModel) else corrected_model(d)
    p = Path(path)
    p.parent.mkdir(parents=True, exist_ok=True)
    obj = model.to_dict()
    if p.suffix.lower() in (".yaml", ".yml"):
        import yaml

        p.write_text(yaml.safe_dump(obj, sort_keys=False))
    else:
        p.write_text(json.dumps(obj, indent=2))
    return p


def load_corrected_model(path: str | os.PathLike[str]) -> CorrectedModel:
    """Load a file written by :func:`save_corrected_model`.

    The file is checked against :class:`~ecoplan.diagnose.corrected_file.CorrectedModelFile`,
    then the parameters by the vehicle's parameter class, the effect's name against the
    library and its parameters against the effect's declared ones
    (:attr:`ecoplan.diagnose.effects.Effect.parameters`): a required one missing is reported
    here rather than when the model is used.

    Parameters
    ----------
    path : str or path
        A ``.json``, ``.yaml`` or ``.yml`` file.

    Returns
    -------
    CorrectedModel
        The model.

    Raises
    ------
    InputError
        One line naming the file, the line and the field: unreadable file, wrong format tag,
        unknown key, vehicle, terrain, parameter or effect, a value of the wrong type or range,
        a missing effect parameter.
    """
    from ecoplan.diagnose.effects import make_effect

    spec, lines = read_corrected_model_file(path)
    source = os.fspath(path)
    try:
        params = vehicle(spec.vehicle, spec.terrain)
    except InputError as exc:
        field = "terrain" if spec.terrain is not None and "terrain" in str(exc) else "vehicle"
        raise error_at(source, lines, (field,), str(exc)) from None
    if spec.kind is not None and spec.kind != params.kind:
        raise error_at(
            source, lines, ("kind",), f"{spec.vehicle!r} is {params.kind}, not {spec.kind}"
        )
    try:
        params = vehicle(spec.vehicle, spec.terrain, spec.params)
    except InputError as exc:
        raise error_at(source, lines, ("params",), str(exc)) from None
    name = spec.effect.name
    eparams = {k: (math.inf if v is None else v) for k, v in spec.effect.params.items()}
    try:
        effect = make_effect(name)
    except InputError as exc:
        raise error_at(source, lines, ("effect", "name"), str(exc)) from None
    try:
        type(effect).values(eparams)  # every required parameter is given
    except InputError as exc:
        raise error_at(source, lines, ("effect", "params"), str(exc)) from None
    return CorrectedModel(spec.vehicle, spec.terrain, params, name, eparams)


def polyline_trajectory(
    points: Sequence[Sequence[float]],
    params: VehicleParams,
    *,
    speed_mps: float | None = None,
    yaw_rate_radps: float | None = None,
    dt_s: float = 0.05,
) -> tuple[FloatArray, FloatArray, FloatArray]:
    """Drive a polyline turn-on-the-spot then straight, through the acceleration limit.

    Parameters
    ----------
    points : sequence of (x, y)
        Way points [m]; the robot starts at the first, heading to the second.
    params : TrackedParams or WheeledParams
        Vehicle (ICRs, top speed, acceleration limit).
    speed_mps : float, optional
        Cruise speed (default half the top track speed).
    yaw_rate_radps : float, optional
        On-the-spot turning rate (default: side speeds at half the top speed).
    dt_s : float
        Time step [s].

    Returns
    -------
    tuple of ndarray
        ``(t, v_left, v_right)`` [s, m/s, m/s].
    """
    pts = np.asarray(points, dtype=np.float64)
    if pts.ndim != 2 or pts.shape[1] != 2 or pts.shape[0] < 2:
        raise InputError("a route polyline needs at least two (x, y) points")
    icr = params.icr
    v = 0.5 * params.top_track_speed_mps if speed_mps is None else float(speed_mps)
    w = (params.top_track_speed_mps / icr.spread_m) if yaw_rate_radps is None else yaw_rate_radps
    a = params.accel_max_mps2
    lever = max(icr.y_left_m, -icr.y_right_m)
    cl: list[FloatArray] = []
    cr: list[FloatArray] = []

    def pulse(left: float, right: float, duration: float) -> None:
        # a command pulse then a stop as long as the ramp down: the rate-limited response
        # covers exactly speed x duration when the pulse is longer than the ramp
        n = max(round(duration / dt_s), 1)
        stop = int(np.ceil(max(abs(left), abs(right)) / a / dt_s)) + 1
        cl.extend([np.full(n, left), np.zeros(stop)])
        cr.extend([np.full(n, right), np.zeros(stop)])

    seg = np.diff(pts, axis=0)
    heading = math.atan2(seg[0, 1], seg[0, 0])
    for dx, dy in seg:
        target = math.atan2(dy, dx)
        turn = (target - heading + math.pi) % (2 * math.pi) - math.pi
        if abs(turn) > 1e-6:
            wt = min(w, math.sqrt(abs(turn) * a / lever))  # the pulse outlasts the ramp
            l_, r_ = setpoint_to_tracks(0.0, math.copysign(wt, turn), icr)
            pulse(float(l_), float(r_), abs(turn) / wt)
        heading = target
        d = math.hypot(dx, dy)
        if d > 0.0:
            vs = min(v, math.sqrt(d * a))
            pulse(vs, vs, d / vs)
    cmd_l, cmd_r = np.concatenate(cl), np.concatenate(cr)
    t = np.arange(cmd_l.size, dtype=np.float64) * dt_s
    return (
        t,
        follow_commands(t, cmd_l, params.accel_max_mps2),
        follow_commands(t, cmd_r, params.accel_max_mps2),
    )


@dataclass(frozen=True, slots=True)
class RankingChange:
    """Energy of candidate routes under the preset and the corrected model.

    Attributes
    ----------
    names : list of str
        Route names.
    energy_base_j, energy_corrected_j : ndarray
        Energy of every route [J].
    rank_base, rank_corrected : list of str
        Route names from the least to the most energy.
    changed : bool
        Whether the order differs.
    best_changed : bool
        Whether the least-energy route differs.
    """

    names: list[str]
    energy_base_j: FloatArray
    energy_corrected_j: FloatArray
    rank_base: list[str]
    rank_corrected: list[str]
    changed: bool
    best_changed: bool

    def summary(self) -> str:
        """One line per route and the conclusion."""
        lines = [
            f"{n:16s} preset {eb / 1e3:8.2f} kJ   corrected {ec / 1e3:8.2f} kJ"
            for n, eb, ec in zip(
                self.names, self.energy_base_j, self.energy_corrected_j, strict=True
            )
        ]
        lines.append(
            f"ranking preset: {' < '.join(self.rank_base)}; corrected: "
            f"{' < '.join(self.rank_corrected)} -> "
            + ("CHANGED" if self.changed else "unchanged")
            + (" (best route changes)" if self.best_changed else "")
        )
        return "\n".join(lines)


Route = tuple[ArrayLike, ArrayLike, ArrayLike] | Sequence[Sequence[float]]


def ranking_change(
    routes: Mapping[str, Route],
    corrected: CorrectedModel,
    base: VehicleParams | None = None,
) -> RankingChange:
    """Whether the correction changes the energy ranking of candidate routes.

    Parameters
    ----------
    routes : mapping of name -> route
        Either a trajectory ``(t, v_left, v_right)`` (three equal-length arrays) or a polyline
        ``[(x, y), ...]`` of way points (driven by :func:`polyline_trajectory`).
    corrected : CorrectedModel
        The corrected model.
    base : TrackedParams or WheeledParams, optional
        The model to compare with (default: the corrected model's preset).

    Returns
    -------
    RankingChange
        Energies and rankings.
    """
    if not routes:
        raise InputError("no routes to rank")
    base_p = base if base is not None else vehicle(corrected.vehicle, corrected.terrain)
    names = list(routes)
    eb, ec = [], []
    for name in names:
        r = routes[name]
        arr = [np.asarray(a, dtype=np.float64) for a in r]
        if (
            len(arr) == 3
            and arr[0].ndim == 1
            and arr[0].size > 2
            and all(a.shape == arr[0].shape for a in arr)
        ):
            t, vl, vr = arr
        else:
            t, vl, vr = polyline_trajectory(r, base_p)  # type: ignore[arg-type]
        dt = np.diff(t, append=t[-1])
        eb.append(float(np.sum(base_p.power(vl, vr).total_w * dt)))
        ec.append(float(np.sum(corrected.trajectory_power(t, vl, vr) * dt)))
    ebase, ecorr = np.array(eb), np.array(ec)
    rb = [names[i] for i in np.argsort(ebase, kind="stable")]
    rc = [names[i] for i in np.argsort(ecorr, kind="stable")]
    return RankingChange(names, ebase, ecorr, rb, rc, rb != rc, rb[0] != rc[0])
