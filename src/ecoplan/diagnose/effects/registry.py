"""The effects by name: the diagnosis's candidate library and the generator's outside effects.

Adding an effect: write its class (an :class:`~ecoplan.diagnose.effects.base.Effect` subclass)
in the module of its family and list it here.
"""

from __future__ import annotations

from ecoplan.diagnose.effects.base import Effect, NoEffect
from ecoplan.diagnose.effects.motion import ActuatorLag, IcrAsymmetry, Inertia
from ecoplan.diagnose.effects.outside import PeriodicDisturbance, SpikeTrain, TrackTensionStep
from ecoplan.diagnose.effects.sensor import SensorDelay
from ecoplan.diagnose.effects.supply import EfficiencyDrift, PowerSaturation, Regeneration
from ecoplan.diagnose.effects.terrain import (
    Slope,
    SpeedDependentResistance,
    TerrainChange,
    TerrainPatch,
)
from ecoplan.errors import InputError

__all__ = ["EFFECTS", "OUTSIDE_EFFECTS", "effect_class", "effect_names", "make_effect"]

#: The candidate library, by stable name (the blind check's names).
EFFECTS: dict[str, type[Effect]] = {
    cls.name: cls
    for cls in (
        Inertia,
        ActuatorLag,
        IcrAsymmetry,
        TerrainPatch,
        TerrainChange,
        Slope,
        SpeedDependentResistance,
        Regeneration,
        PowerSaturation,
        SensorDelay,
        EfficiencyDrift,
    )
}

#: Effects outside the library, generated to check that the diagnosis calls them unexplained.
OUTSIDE_EFFECTS: dict[str, type[Effect]] = {
    cls.name: cls for cls in (PeriodicDisturbance, TrackTensionStep, SpikeTrain)
}


def effect_names() -> list[str]:
    """Stable names of the candidate effects."""
    return list(EFFECTS)


def effect_class(name: str) -> type[Effect]:
    """The class of an effect by name: ``none``, a candidate or an outside effect.

    Raises
    ------
    InputError
        Unknown name.
    """
    if name == "none":
        return NoEffect
    cls = EFFECTS.get(name) or OUTSIDE_EFFECTS.get(name)
    if cls is None:
        accepted = ", ".join(["none", *EFFECTS, *OUTSIDE_EFFECTS])
        raise InputError(f"unknown effect {name!r}; accepted: {accepted}")
    return cls


def make_effect(name: str) -> Effect:
    """A fresh, unfitted candidate effect by name (``"none"`` gives :class:`NoEffect`).

    Raises
    ------
    InputError
        Not a candidate of the library.
    """
    if name == "none":
        return NoEffect()
    try:
        return EFFECTS[name]()
    except KeyError:
        raise InputError(
            f"unknown effect {name!r}; accepted: none, {', '.join(effect_names())}"
        ) from None
