"""The logs as the candidate effects see them: :class:`EffectData` and its preparation.

:func:`prepare` turns a :class:`~ecoplan.diagnose.replay.Frame` and calibrated parameters into
the base model's linear design, its power breakdown and the heading; every effect's
design and fit (:mod:`ecoplan.diagnose.effects.base`) work on it.
"""

from __future__ import annotations

import dataclasses
import itertools
from dataclasses import dataclass

import numpy as np

from ecoplan._typing import BoolArray, FloatArray, IntArray
from ecoplan.diagnose.calibrate import (
    BaseDesign,
    base_design,
    wheeled_bounds,
    wheeled_prior,
    with_linear_params,
)
from ecoplan.diagnose.replay import Frame
from ecoplan.models.power import PowerBreakdown
from ecoplan.models.wheeled import WheeledParams
from ecoplan.presets import VehicleParams

__all__ = [
    "MAX_SEARCH_SAMPLES",
    "EffectData",
    "effect_base_design",
    "prepare",
    "segments",
    "subsample",
]


@dataclass(frozen=True, slots=True)
class EffectData:
    """A split of the logs prepared for the effects: frame, base design and model breakdown.

    Attributes
    ----------
    frame : Frame
        The samples.
    params : TrackedParams or WheeledParams
        Calibrated base parameters.
    X : ndarray, shape (n, k)
        Linear design of the base model (:func:`ecoplan.diagnose.calibrate.base_design`).
    base_w : ndarray
        Calibrated model power [W].
    friction_w, resistance_w : ndarray
        Friction and resistance components of the calibrated model [W].
    side_neg_w : ndarray
        ``min(P_left, 0) + min(P_right, 0)``: negative side power of the calibrated model [W].
    yaw : ndarray
        Heading [rad]: the frame's (:attr:`~ecoplan.diagnose.replay.Frame.heading`, logged or
        integrated over each whole run).
    t_rel : ndarray
        Time on the logs' clock [s] (a session clock when runs follow each other).
    prior : TrackedParams or WheeledParams or None
        The parameters calibration started from (the preset), which the wheeled refits are
        pulled towards (:func:`~ecoplan.diagnose.calibrate.wheeled_prior`); None: ``params``.
    breakdown : PowerBreakdown or None
        The calibrated model's power breakdown on the samples.
    lower, upper : ndarray or None
        Physical bounds of the base design's coefficients (:func:`effect_base_design`; wheeled,
        the prior's :func:`~ecoplan.diagnose.calibrate.wheeled_bounds`), which every refit
        keeps (:func:`~ecoplan.diagnose.effects.fitting.base_bounds`).
    """

    frame: Frame
    params: VehicleParams
    X: FloatArray
    base_w: FloatArray
    friction_w: FloatArray
    resistance_w: FloatArray
    side_neg_w: FloatArray
    yaw: FloatArray
    t_rel: FloatArray
    prior: VehicleParams | None = None
    breakdown: PowerBreakdown | None = None
    lower: FloatArray | None = None
    upper: FloatArray | None = None

    @property
    def p(self) -> FloatArray:
        """Measured power [W]."""
        return self.frame.p

    def at_chi(self, chi: float) -> EffectData:
        """The same samples prepared with the base parameters at another χ (eq. 12)."""
        if chi == self.params.chi:
            return self
        return prepare(
            self.frame, dataclasses.replace(self.params, chi=chi), self.t_rel, prior=self.prior
        )

    def subset(self, mask: BoolArray) -> EffectData:
        """The samples where ``mask`` is true."""
        return EffectData(
            self.frame.subset(mask),
            self.params,
            self.X[mask],
            self.base_w[mask],
            self.friction_w[mask],
            self.resistance_w[mask],
            self.side_neg_w[mask],
            self.yaw[mask],
            self.t_rel[mask],
            self.prior,
            None if self.breakdown is None else _subset_breakdown(self.breakdown, mask),
            self.lower,
            self.upper,
        )


def _subset_breakdown(pb: PowerBreakdown, mask: BoolArray) -> PowerBreakdown:
    return PowerBreakdown(**{f.name: getattr(pb, f.name)[mask] for f in dataclasses.fields(pb)})


def segments(frame: Frame, max_gap_s: float | None = None) -> list[IntArray]:
    """Contiguous pieces of a (possibly split) frame.

    A new piece starts at every run change and at every time gap longer than 1.5 sample
    periods, or than ``max_gap_s`` [s] when given (a clock that bridges dropped rows).
    """
    if frame.n == 0:
        return []
    dt = np.diff(frame.t)
    if max_gap_s is None:
        same = np.diff(frame.run) == 0
        step = float(np.median(dt[same & (dt > 0)])) if np.any(same & (dt > 0)) else 1.0
        max_gap_s = 1.5 * step
    brk = (np.diff(frame.run) != 0) | (dt > max_gap_s) | (dt <= 0)
    edges = np.concatenate([[0], np.flatnonzero(brk) + 1, [frame.n]])
    return [np.arange(a, b) for a, b in itertools.pairwise(edges) if b > a]


def effect_base_design(
    frame: Frame, params: VehicleParams, prior: VehicleParams | None = None
) -> BaseDesign:
    """The base model's linear design as the candidate effects use it.

    Tracked: :func:`~ecoplan.diagnose.calibrate.base_design`.  Wheeled: the same unit columns
    (at ``params``' χ and decay exponents), each side's sign -- battery draw ``|P|`` (wheeled
    §III-A) -- taken from the coefficients calibration was pulled towards (the preset's,
    :func:`~ecoplan.diagnose.calibrate.wheeled_prior`), not from the calibrated ones.  Which
    side brakes in which turn is the vehicle's physics (the inner side below r ≈ 2.4 m,
    wheeled Fig. 6); a calibration that absorbed an effect may bend it: one that absorbed a
    speed-dependent resistance had a negative straight-line offset, called both sides
    "braking" in slow straight motion and so flipped the columns' sign there (0.06 W of
    error everywhere on a Pioneer log, whatever the effect).  The coefficients' bounds are
    the prior's :func:`~ecoplan.diagnose.calibrate.wheeled_bounds` for the same reason: an
    alpha calibrated to 0 must not let a refit flip ``a(r)``'s direction.
    """
    if not isinstance(params, WheeledParams):
        return base_design(frame, params)
    theta, _ = wheeled_prior(params, prior)
    # the unit columns depend on χ, the ICRs and the decay exponents, not on the linear
    # coefficients: only the sides' signs come from the prior coefficients
    design = base_design(frame, with_linear_params(params, (), theta))
    lower, upper = wheeled_bounds(prior if isinstance(prior, WheeledParams) else params)
    return dataclasses.replace(design, lower=lower, upper=upper)


def prepare(
    frame: Frame,
    params: VehicleParams,
    t_rel: FloatArray | None = None,
    *,
    prior: VehicleParams | None = None,
) -> EffectData:
    """Build :class:`EffectData` for a frame and calibrated parameters.

    ``prior`` is the model calibration started from (the preset): the wheeled refits are pulled
    towards it like calibration was, and take the sides' braking signs from it.
    """
    pb = params.power(frame.vl, frame.vr)
    design = effect_base_design(frame, params, prior)
    return EffectData(
        frame=frame,
        params=params,
        X=design.X,
        base_w=pb.total_w,
        friction_w=pb.friction_w,
        resistance_w=pb.resistance_w,
        side_neg_w=np.minimum(pb.left_w, 0.0) + np.minimum(pb.right_w, 0.0),
        yaw=frame.heading,
        t_rel=frame.t if t_rel is None else t_rel,
        prior=prior,
        breakdown=pb,
        lower=design.lower,
        upper=design.upper,
    )


#: Nonlinear searches run on at most this many samples (a strided subsample).
MAX_SEARCH_SAMPLES = 20_000


def subsample(data: EffectData, max_n: int = MAX_SEARCH_SAMPLES) -> EffectData:
    """A strided subsample of at most ``max_n`` samples (searches only; final fits use all)."""
    n = data.frame.n
    if n <= max_n:
        return data
    mask = np.zeros(n, dtype=bool)
    mask[:: int(np.ceil(n / max_n))] = True
    return data.subset(mask)
