"""The report of ``ecoplan identify``: per terrain, what was identified and how well it predicts.

Text lines for the terminal and JSON-ready rows, from a
:class:`~ecoplan.models.identify_logs.VehicleIdentification`.
"""

from __future__ import annotations

from typing import TYPE_CHECKING, Any

if TYPE_CHECKING:
    from collections.abc import Mapping

    from ecoplan.models.identify_current import CurrentFit, CurrentIdentification
    from ecoplan.models.identify_logs import TerrainFit, VehicleIdentification

__all__ = ["identification_lines", "identification_rows"]


def _fits(
    res: VehicleIdentification | CurrentIdentification,
) -> Mapping[str, TerrainFit | CurrentFit]:
    return res.fits


def identification_lines(res: VehicleIdentification | CurrentIdentification) -> list[str]:
    """Human-readable lines: per terrain, the held-out error, the values and their intervals.

    Parameters
    ----------
    res : VehicleIdentification or CurrentIdentification
        The identification (battery-power or motor-current logs).

    Returns
    -------
    list of str
        One header line per terrain, then one line per identified value, the values the
        logs could not identify and those held at 0.
    """
    lines = []
    for terrain, fit in sorted(_fits(res).items()):
        lines.append(
            f"{terrain}: {len(fit.run_ids)} log(s), {fit.n_samples} samples, held-out MAE "
            f"{fit.heldout_mae_w:.1f} W (mean power {fit.mean_power_w:.0f} W), median energy "
            f"error {100 * fit.median_energy_error:.1f} %"
        )
        for key in fit.identified:
            lo, hi = fit.intervals[key]
            lines.append(f"  {key} = {fit.values[key]:.4g}  [{lo:.4g}, {hi:.4g}]")
        if fit.unidentified:
            lines.append(f"  not identified (base values kept): {', '.join(fit.unidentified)}")
        for key, val in fit.clamped.items():
            lines.append(f"  clamped at 0: {key} (the logs give {val:.4g})")
    return lines


def identification_rows(
    res: VehicleIdentification | CurrentIdentification,
) -> list[dict[str, Any]]:
    """JSON-ready rows, one per terrain (values, intervals, held-out errors; SI units).

    Parameters
    ----------
    res : VehicleIdentification or CurrentIdentification
        The identification (battery-power or motor-current logs).

    Returns
    -------
    list of dict
        ``terrain, values, intervals, unidentified, clamped, heldout_mae_w,
        heldout_energy_error`` per terrain, sorted by terrain.
    """
    return [
        {
            "terrain": terrain,
            "values": dict(fit.values),
            "intervals": {k: list(v) for k, v in fit.intervals.items()},
            "unidentified": list(fit.unidentified),
            "clamped": dict(fit.clamped),
            "heldout_mae_w": fit.heldout_mae_w,
            "heldout_energy_error": list(fit.heldout_energy_error),
        }
        for terrain, fit in sorted(_fits(res).items())
    ]
