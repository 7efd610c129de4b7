"""Parameters that follow the terrain: from one terrain's parameters back to the vehicle file.

:meth:`ecoplan.models.vehicles.Vehicle.params` (and so :func:`ecoplan.presets.vehicle`)
returns the parameters of one terrain that remember the file and the overrides they
came from, so ``p.on("grass")`` gives the same vehicle (same overrides) on grass.  This
is what lets one vehicle value be planned on a map with terrain regions.
"""

from __future__ import annotations

from collections.abc import Mapping
from typing import Any, Protocol, Self

from ecoplan.errors import InputError

__all__ = ["FollowsTerrain", "TerrainSource", "terrain_params"]


class TerrainSource(Protocol):
    """Where parameters come from: a vehicle file (:class:`ecoplan.models.vehicles.Vehicle`)."""

    @property
    def name(self) -> str:
        """The vehicle's stable name."""
        ...

    def params(self, terrain: str | None = None, overrides: Mapping[str, Any] | None = None) -> Any:
        """Parameters on ``terrain`` with ``overrides``."""
        ...


def terrain_params(p: Any, terrain: str | None) -> Any:
    """The parameters ``p`` (of one terrain) moved to ``terrain``.

    Parameters
    ----------
    p : TrackedParams or WheeledParams
        Parameters with their ``terrain``, ``source`` and ``overrides``.
    terrain : str or None
        Target terrain (case-insensitive); None or ``p``'s own terrain returns ``p``.

    Returns
    -------
    TrackedParams or WheeledParams
        The same vehicle and overrides on ``terrain``.

    Raises
    ------
    InputError
        ``p`` was built by hand or changed with ``dataclasses.replace`` (no vehicle file
        behind it: a change would silently not follow the terrain), or the vehicle has no
        such terrain.
    """
    if terrain is None or (p.terrain is not None and terrain.lower() == p.terrain):
        return p
    src: TerrainSource | None = p.source
    if src is None:
        raise InputError(
            f"{p.name}: parameters built by hand (or changed with dataclasses.replace) hold "
            "one terrain; build them with ecoplan.presets.vehicle(name or vehicle file, "
            f"terrain, overrides=...) to evaluate them on {terrain!r}"
        )
    return src.params(terrain, dict(p.overrides))


class FollowsTerrain:
    """Mixin of the parameter classes: :meth:`on` moves them to another terrain."""

    __slots__ = ()

    def on(self, terrain: str | None = None) -> Self:
        """The same vehicle (and overrides) on ``terrain``; None: these parameters.

        Raises
        ------
        InputError
            Built by hand (or with ``dataclasses.replace``), or an unknown terrain
            (:func:`terrain_params`).
        """
        out: Self = terrain_params(self, terrain)
        return out
