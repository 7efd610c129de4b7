"""Structured power results shared by the tracked and the wheeled models."""

from __future__ import annotations

from dataclasses import dataclass
from enum import IntEnum

import numpy as np
import numpy.typing as npt

from ecoplan._typing import FloatArray, IntArray

__all__ = [
    "CASE_TABLE",
    "COMPONENTS",
    "MotionCase",
    "PowerBreakdown",
    "motion_case",
    "motion_case_index",
    "motion_case_into",
]

#: Names of the additive components of :class:`PowerBreakdown`, in report order.
COMPONENTS: tuple[str, ...] = (
    "friction_w",
    "resistance_w",
    "powerup_w",
    "braking_w",
    "nonregen_w",
    "elec_loss_w",
)


class MotionCase(IntEnum):
    """Dynamic-friction cases of the tracked paper's Fig. 3 (plus standstill)."""

    STOPPED = 0
    STRAIGHT = 1  # (a) equal track speeds
    SAME_SIGN = 2  # (b) different speeds of the same sign: the slower track is dragged
    ONE_ZERO = 3  # (c) one track speed null
    OPPOSITE = 4  # (d) opposite track speeds


def motion_case(v_left: FloatArray, v_right: FloatArray, tol_mps: float = 1e-3) -> IntArray:
    """Classify track-speed pairs into the cases of Fig. 3 (tracked paper §II-B).

    Speeds within ``tol_mps`` of zero count as zero and pairs within ``tol_mps``
    of each other count as equal.

    Examples
    --------
    >>> import numpy as np
    >>> vl, vr = np.array([0.0, 0.5, 0.5, 0.2, -0.3]), np.array([0.0, 0.5, 0.3, 0.0, 0.3])
    >>> [MotionCase(c).name for c in motion_case(vl, vr)]
    ['STOPPED', 'STRAIGHT', 'SAME_SIGN', 'ONE_ZERO', 'OPPOSITE']
    """
    vl, vr = np.broadcast_arrays(np.asarray(v_left, np.float64), np.asarray(v_right, np.float64))
    case = np.empty(vl.shape, dtype=np.int64)
    motion_case_into(vl, vr, np.abs(vl), np.abs(vr), np.abs(vr - vl), tol_mps, case)
    return case


def _case_table() -> IntArray:
    """Case of every 4-bit pattern (zero left, zero right, equal, opposite signs)."""
    table = np.empty(16, dtype=np.int64)
    for idx in range(16):
        zl, zr, eq, opp = (bool(idx >> bit & 1) for bit in range(4))
        if zl and zr:
            table[idx] = MotionCase.STOPPED
        elif eq:
            table[idx] = MotionCase.STRAIGHT
        elif zl or zr:
            table[idx] = MotionCase.ONE_ZERO
        else:
            table[idx] = MotionCase.OPPOSITE if opp else MotionCase.SAME_SIGN
    return table


#: :class:`MotionCase` of each pattern index of :func:`motion_case_index`.
CASE_TABLE: IntArray = _case_table()


def motion_case_index(
    v_left: FloatArray,
    v_right: FloatArray,
    abs_left: FloatArray,
    abs_right: FloatArray,
    abs_diff: FloatArray,
    tol_mps: float,
) -> npt.NDArray[np.uint8]:
    """Pattern index ``zl + 2 zr + 4 equal + 8 opposite`` of track-speed pairs.

    ``CASE_TABLE[index]`` is the :class:`MotionCase`; gathering from small tables
    avoids data-dependent branches (``np.where`` on random masks is slow).  Priority:
    stopped (both zero) > straight (equal) > one zero > opposite > same sign.
    """
    idx = (abs_left <= tol_mps).view(np.uint8).copy()
    idx |= (abs_right <= tol_mps).view(np.uint8) << 1
    idx |= (abs_diff <= tol_mps).view(np.uint8) << 2
    idx |= (np.signbit(v_left) ^ np.signbit(v_right)).view(np.uint8) << 3
    return idx


def motion_case_into(
    v_left: FloatArray,
    v_right: FloatArray,
    abs_left: FloatArray,
    abs_right: FloatArray,
    abs_diff: FloatArray,
    tol_mps: float,
    out: IntArray,
) -> None:
    """:func:`motion_case` into ``out``, reusing ``|V_l|``, ``|V_r|`` and ``|V_r - V_l|``."""
    idx = motion_case_index(v_left, v_right, abs_left, abs_right, abs_diff, tol_mps)
    np.take(CASE_TABLE, idx, out=out)


@dataclass(frozen=True, slots=True)
class PowerBreakdown:
    """Electrical power of locomotion with its breakdown, vectorised over samples [W].

    The six components in :data:`COMPONENTS` add up to ``total_w``.

    Attributes
    ----------
    friction_w : ndarray
        Dynamic-friction (skid) power, tracked eq. (14) / wheeled turning part.
    resistance_w : ndarray
        Traction resistance, tracked eq. (18) / wheeled straight-line part.
    powerup_w : ndarray
        Driver power-up (tracked §III-C).
    braking_w : ndarray
        Driver braking effort (tracked cases 3 and 4) / wheeled braking side.
    nonregen_w : ndarray
        Non-regenerated power of the dragged motor (tracked case 2).
    elec_loss_w : ndarray
        Electrical dissipation ``P_T (1 - eta)`` (tracked eq. 20).
    total_w : ndarray
        Total electrical power ``P_T`` drawn by locomotion.
    left_w, right_w : ndarray
        Mechanical power of the left and right motors (signed: negative when dragged
        or braking).
    case : ndarray of int
        :class:`MotionCase` of every sample.
    """

    friction_w: FloatArray
    resistance_w: FloatArray
    powerup_w: FloatArray
    braking_w: FloatArray
    nonregen_w: FloatArray
    elec_loss_w: FloatArray
    total_w: FloatArray
    left_w: FloatArray
    right_w: FloatArray
    case: IntArray

    @property
    def mechanical_w(self) -> FloatArray:
        """Mechanical power of locomotion ``P_M`` (tracked eq. 19) [W]."""
        return self.friction_w + self.resistance_w

    def components(self) -> dict[str, FloatArray]:
        """The additive components as a name -> array mapping (sums to ``total_w``)."""
        return {name: getattr(self, name) for name in COMPONENTS}
