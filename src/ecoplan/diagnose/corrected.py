"""The corrected model: the calibrated base plus the verdict's effect, as an object and a file.

:func:`save_corrected_model` writes the base preset, the calibrated parameters (refitted with the
winning effect) and the effect's fitted physical parameters to JSON (or YAML by suffix);
:func:`load_corrected_model` reads it back into a :class:`CorrectedModel` whose ``power(vl, vr)``
is a drop-in for ``params.power`` (steady state) and whose :meth:`CorrectedModel.trajectory_power`
adds the time-dependent part of the effect along a trajectory.  Whether it changes a route
ranking is :mod:`ecoplan.diagnose.ranking`.
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
from collections.abc import Mapping
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
from ecoplan.models.power import PowerBreakdown
from ecoplan.models.tracked import TrackedParams
from ecoplan.models.wheeled import SideCoefficients
from ecoplan.presets import VehicleParams, vehicle

if TYPE_CHECKING:
    from ecoplan.diagnose.result import Diagnosis

__all__ = [
    "CorrectedModel",
    "corrected_model",
    "load_corrected_model",
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
    refit = d.calibration.changed.get("slip_exponent_with_effect")
    # the kept friction law's exponent refitted with the effect (law_rival.refit_with_effect)
    if refit is not None and isinstance(params, TrackedParams):
        params = dataclasses.replace(params, slip_exponent=refit[1])
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
        values = type(effect).values(eparams)  # every required parameter is given
    except InputError as exc:
        raise error_at(source, lines, ("effect", "params"), str(exc)) from None
    for par, value in zip(type(effect).parameters, values, strict=True):
        if not par.admits(value):  # a null (infinite) mass or rate gave a nan simulation
            shown = "null (infinite)" if value == math.inf else repr(value)
            raise error_at(
                source,
                lines,
                ("effect", "params", par.name),
                f"{name}: {par.name} = {shown} [{par.unit}] is outside its physical range; "
                f"accepted: {par.accepted()}",
            )
    return CorrectedModel(spec.vehicle, spec.terrain, params, name, eparams)
