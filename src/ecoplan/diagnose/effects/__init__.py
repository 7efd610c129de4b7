"""Library of candidate unmodelled effects, each defined once: parameters, generation, fit.

One class per effect (:class:`~ecoplan.diagnose.effects.base.Effect`), one module per family:

=================  ==========================================================================
module             effects
=================  ==========================================================================
:mod:`.base`       the base class (physical :class:`Parameter` s with units and ranges,
                   ``apply`` for generation, the design/fit of the diagnosis), :class:`Motion`
:mod:`.data`       :class:`EffectData`: the logs as the fits see them (:func:`prepare`)
:mod:`.fitting`    the shared least squares (ridge pull, Huber IRLS)
:mod:`.motion`     ``inertia``, ``actuator_lag``, ``icr_asymmetry``
:mod:`.terrain`    ``terrain_patch``, ``terrain_change``, ``slope``, ``speed_dependent_resistance``
:mod:`.supply`     ``regeneration`` (bounded by :func:`regenerated_w`), ``power_saturation``,
                   ``efficiency_drift``
:mod:`.sensor`     ``sensor_delay``
:mod:`.outside`    out of library (generated only): ``periodic_disturbance``,
                   ``track_tension_step``, ``spike_train``
:mod:`.registry`   the effects by name (:data:`EFFECTS`, :func:`effect_class`)
=================  ==========================================================================

Every effect is fitted (STYLE.md §12: ``fit(data)`` returns the effect, fitted values end in
``_``, ``predict(data)`` gives the power it expects [W] and ``score(data)`` its mean absolute
error [W] on held-out data) **jointly with the base model's linear parameters** (the
calibration design of :mod:`ecoplan.diagnose.calibrate`), so that calibration cannot silently
absorb it and the comparison with the calibrated model alone (the :class:`NoEffect`
candidate) is like for like.  For a wheeled vehicle (Chuy et al. 2009) that joint fit keeps
the preset's braking sides (:func:`effect_base_design`), is weakly pulled towards the preset
like calibration and Huber-weighted (:func:`~ecoplan.diagnose.effects.fitting.fit_linear`),
and χ stays at the gyro's value when there is one.  Effects that need a signal the log lacks
(commands, pose) report it through :meth:`Effect.available` and are not fitted.

The fitted ``params_`` carry the same names and meanings as the generator's parameters
(:attr:`Effect.parameters`), so a blind case's truth and its diagnosis compare key by key.
"""

from ecoplan.diagnose.effects.base import (
    Effect,
    Motion,
    MotionLike,
    NoEffect,
    Parameter,
    Params,
    Session,
    base_power_w,
    eta_of,
)
from ecoplan.diagnose.effects.data import EffectData, effect_base_design, prepare, subsample
from ecoplan.diagnose.effects.fitting import huber_loss, huber_weights, robust_scale
from ecoplan.diagnose.effects.motion import ActuatorLag, IcrAsymmetry, Inertia
from ecoplan.diagnose.effects.outside import (
    PeriodicDisturbance,
    SpikeTrain,
    TimeStep,
    TimeStepOnTrend,
    TrackTensionStep,
)
from ecoplan.diagnose.effects.registry import (
    EFFECTS,
    OUTSIDE_EFFECTS,
    effect_class,
    effect_names,
    make_effect,
)
from ecoplan.diagnose.effects.sensor import SensorDelay
from ecoplan.diagnose.effects.supply import (
    EfficiencyDrift,
    PowerSaturation,
    Regeneration,
    regenerated_w,
)
from ecoplan.diagnose.effects.terrain import (
    Slope,
    SpeedDependentResistance,
    TerrainChange,
    TerrainPatch,
)

__all__ = [
    "EFFECTS",
    "OUTSIDE_EFFECTS",
    "ActuatorLag",
    "Effect",
    "EffectData",
    "EfficiencyDrift",
    "IcrAsymmetry",
    "Inertia",
    "Motion",
    "MotionLike",
    "NoEffect",
    "Parameter",
    "Params",
    "PeriodicDisturbance",
    "PowerSaturation",
    "Regeneration",
    "SensorDelay",
    "Session",
    "Slope",
    "SpeedDependentResistance",
    "SpikeTrain",
    "TerrainChange",
    "TerrainPatch",
    "TimeStep",
    "TimeStepOnTrend",
    "TrackTensionStep",
    "base_power_w",
    "effect_base_design",
    "effect_class",
    "effect_names",
    "eta_of",
    "huber_loss",
    "huber_weights",
    "make_effect",
    "prepare",
    "regenerated_w",
    "robust_scale",
    "subsample",
]
