"""Ground elevation of a scenario (``terrain: {elevation: ...}``) as a vectorised ``z(x, y)``.

The planners' energy cost and the route estimate take it as ``elevation=``
(:class:`ecoplan.energy.objective.EnergyCost`, :func:`ecoplan.energy.path.path_cost`);
:func:`climb_power_w` gives the simulated power of the climbs along a trajectory.

>>> from ecoplan.app.scenario.schema import ElevationSection
>>> z = ground_elevation(ElevationSection(grade=[0.1, 0.0], z0_m=2.0))
>>> float(z(np.array([10.0]), np.array([3.0]))[0])
3.0
"""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np
import numpy.typing as npt

from ecoplan._typing import FloatArray
from ecoplan.app.scenario.schema import ElevationSection
from ecoplan.models.tracked import GRAVITY_MPS2

__all__ = ["GroundElevation", "climb_power_w", "ground_elevation"]


@dataclass(frozen=True, slots=True, eq=False)
class GroundElevation:
    """``z(x, y) = z0 + gx x + gy y + Σ h_i exp(-|p - c_i|^2 / (2 r_i^2))`` [m].

    Attributes
    ----------
    z0_m : float
        Height at the origin [m].
    grade : ndarray, shape (2,)
        Rise per metre along +x and +y [-].
    hills : ndarray, shape (n, 4)
        Rows ``x_m, y_m, height_m, radius_m`` of the round hills.
    """

    z0_m: float
    grade: FloatArray
    hills: FloatArray

    def __call__(self, x: npt.ArrayLike, y: npt.ArrayLike) -> FloatArray:
        """Elevation at the points ``(x, y)`` [m], broadcast."""
        xa = np.asarray(x, dtype=np.float64)
        ya = np.asarray(y, dtype=np.float64)
        z = self.z0_m + self.grade[0] * xa + self.grade[1] * ya
        for cx, cy, h, r in self.hills:
            z = z + h * np.exp(-((xa - cx) ** 2 + (ya - cy) ** 2) / (2.0 * r * r))
        return np.asarray(z, dtype=np.float64)


def ground_elevation(section: ElevationSection) -> GroundElevation:
    """The elevation function of a validated ``terrain.elevation`` section.

    Parameters
    ----------
    section : ElevationSection
        The scenario's section.

    Returns
    -------
    GroundElevation
    """
    hills = np.array(
        [[h.x, h.y, h.height_m, h.radius_m] for h in section.hills], dtype=np.float64
    ).reshape(-1, 4)
    return GroundElevation(float(section.z0_m), np.asarray(section.grade, dtype=np.float64), hills)


def climb_power_w(
    elevation: GroundElevation,
    x: FloatArray,
    y: FloatArray,
    dt_s: float,
    mass_kg: float,
    eta: float,
) -> FloatArray:
    """Battery power of the climbs along a sampled trajectory, ``M g max(Δz, 0) / (η dt)`` [W].

    Step ``k`` carries the rise from sample ``k`` to ``k + 1`` (the last sample draws 0), so
    ``sum(P) dt`` is ``M g Σ max(Δz, 0) / η``, the climb energy the planner's cost charges
    (:func:`ecoplan.models.inertial.climb_energy_along_j`); descents are not credited.

    Parameters
    ----------
    elevation : GroundElevation
        The ground.
    x, y : ndarray
        Positions of the samples [m].
    dt_s : float
        Sample period [s].
    mass_kg : float
        Vehicle mass [kg].
    eta : float
        Drive efficiency in (0, 1].

    Returns
    -------
    ndarray
        Power per sample [W], the shape of ``x``.
    """
    z = elevation(x, y)
    rise = np.maximum(np.diff(z), 0.0)
    return np.append(rise, 0.0) * (mass_kg * GRAVITY_MPS2 / (eta * dt_s))
