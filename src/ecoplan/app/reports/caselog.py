"""The log of a simulated case, with the power re-evaluated on the terrain under the robot."""

from __future__ import annotations

import dataclasses
from typing import TYPE_CHECKING

from ecoplan.app.reports.tables import breakdown_components
from ecoplan.dynamics.log import Log
from ecoplan.errors import InputError

if TYPE_CHECKING:
    from ecoplan.app.run import CaseResult

__all__ = ["case_log"]


def case_log(result: CaseResult) -> Log:
    """A case's simulated steps as a :class:`~ecoplan.dynamics.log.Log`.

    The simulator's log (:meth:`ecoplan.sim.SimResult.to_log`) with terrain-aware power
    columns (``p_total``, ``p_left``, ``p_right`` and the breakdown ``p_friction``, ...,
    ``p_inertial`` / ``p_grade`` when the mass terms are simulated)
    and the ``terrain`` label of every step; write it with
    :func:`ecoplan.io.logcsv.write_log_csv`.

    Parameters
    ----------
    result : CaseResult
        A simulated case.

    Returns
    -------
    Log
        The case's log (no ``run_id``: the file starts with its header row, as plain
        CSV tools expect).

    Raises
    ------
    InputError
        The case was not simulated.
    """
    sim = result.sim
    if sim is None:
        raise InputError("this case was not simulated; nothing to write")
    return dataclasses.replace(
        sim.to_log(terrain=result.terrain),
        p_total=result.p_total_w,
        p_left=result.p_left_w,
        p_right=result.p_right_w,
        extra={
            "case": sim.case,
            **{
                f"p_{c.removesuffix('_w')}": result.components_w[c]
                for c in breakdown_components(result.components_w)  # + p_inertial, p_grade
            },
        },
    )
