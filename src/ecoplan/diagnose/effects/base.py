"""The base class of the candidate effects: physical parameters, generation, design and fit.

An effect is one class (:class:`Effect`) that says, once, everything the project knows about it:

* **its physical parameters** (:attr:`Effect.parameters`: a :class:`Parameter` each, with its
  unit and physical range) -- the one name per quantity that the blind-case generator, the
  diagnosis's fitted values (``params_``), the diagnosis JSON and the corrected model use.
  Every fit keeps them in range: a searched parameter is searched within it
  (:class:`ScalarSearch`), a linear one (:attr:`Parameter.column`) is a bound of the bounded
  least squares (:meth:`Effect.coef_bounds`), beside the base model's own bounds;
* **generation** (:meth:`Effect.apply`): the true electrical power ``P_T`` [W] on a motion with
  the effect, and (:meth:`Effect.drive`) the vehicle and actuator lag that produce the motion
  (only ``icr_asymmetry`` and ``actuator_lag`` change the motion); :meth:`Effect.draw` turns a
  magnitude's random draws into parameters on a session;
* **diagnosis** (:meth:`Effect.design`, :meth:`Effect.fit`, :meth:`Effect.predict`,
  :meth:`Effect.score`): its regressors for a nonlinear parameter, fitted jointly with the base
  model's linear parameters, and :meth:`Effect._name_params` which turns the fit into the
  physical parameters (``P_T = P_M / η``, tracked eq. 20: a fitted electrical coefficient is a
  mechanical quantity divided by η).

"Never below physics": an effect may add power or return it only within what physics allows;
the one that returns power, ``regeneration``, is bounded by
:func:`~ecoplan.diagnose.effects.supply.regenerated_w` in both its generation and its fit.
"""

from __future__ import annotations

import math
from collections.abc import Mapping, Sequence
from dataclasses import dataclass
from typing import Any, ClassVar, Protocol

import numpy as np
from scipy.optimize import minimize_scalar

from ecoplan._typing import ArrayLike, BoolArray, FloatArray
from ecoplan.diagnose.calibrate import CHI_BOUNDS, grid_then_bounded, kinematic_chi
from ecoplan.diagnose.effects.data import EffectData, subsample
from ecoplan.diagnose.effects.fitting import Bounds, base_bounds, fit_linear, huber_loss
from ecoplan.diagnose.replay import Frame, smooth_derivative
from ecoplan.dynamics.integrate import integrate_twist
from ecoplan.errors import InputError
from ecoplan.models.kinematics import TrackICR, tracks_to_twist
from ecoplan.models.wheeled import WheeledParams
from ecoplan.presets import VehicleParams

__all__ = [
    "Effect",
    "Motion",
    "MotionLike",
    "NoEffect",
    "Parameter",
    "Params",
    "ScalarSearch",
    "Session",
    "base_power_w",
    "eta_of",
]


def base_power_w(vehicle: VehicleParams, v_left: FloatArray, v_right: FloatArray) -> FloatArray:
    """The base model's electrical power ``P0`` at the side speeds, without any effect [W]."""
    return np.asarray(vehicle.power(v_left, v_right).total_w, dtype=np.float64)


#: An effect's parameters by name (:attr:`Effect.parameters`).
Params = Mapping[str, float]


def eta_of(vehicle: VehicleParams) -> float:
    """Electrical efficiency ``η`` of a vehicle (tracked eq. 20); 1 for the wheeled model.

    The wheeled model's powers are electrical already (Chuy et al. 2009 §III-A).
    """
    return float(getattr(vehicle, "eta", 1.0))


@dataclass(frozen=True, slots=True)
class Parameter:
    """One physical parameter of an effect.

    Attributes
    ----------
    name : str
        The parameter's one name (generator, diagnosis, JSON, corrected model).
    unit : str
        Its unit (``"-"`` when dimensionless).
    low, high : float
        The physically admissible range (inclusive); generation rejects values outside.
    doc : str
        What it is.
    default : float or None
        Value when absent (None: required).
    column : int or None
        When the parameter is a linear coefficient of the diagnosis's fit: the index of its
        column among the effect's own (:meth:`Effect.columns`), whose fitted coefficient ``g``
        gives the parameter as ``offset + scale g``; the range then bounds ``g`` in every fit
        (:meth:`Effect.coef_bounds`).  None: found otherwise (a search, or derived).
    offset : float
        ``offset`` of that map (1 for a factor fitted as ``1 + η g``).
    scale : float or None
        ``scale`` of that map; None: the vehicle's η (a fitted electrical coefficient is a
        mechanical quantity divided by η, tracked eq. 20).
    infinite_ok : bool
        An infinite value means something (``p_max_w``: a supply without cap).  Otherwise an
        infinite ``high`` only says the range is open: the value itself must be finite.
    """

    name: str
    unit: str
    low: float
    high: float
    doc: str
    default: float | None = None
    column: int | None = None
    offset: float = 0.0
    scale: float | None = None
    infinite_ok: bool = False

    def admits(self, value: float) -> bool:
        """Whether ``value`` is within the range (finite unless :attr:`infinite_ok`)."""
        return (math.isfinite(value) or (self.infinite_ok and not math.isnan(value))) and (
            self.low <= value <= self.high
        )

    def accepted(self) -> str:
        """The values :meth:`admits`, in words (for error messages)."""
        if self.infinite_ok:
            return f"[{self.low:g}, {self.high:g}] (null: no limit)"
        return f"finite values in [{self.low:g}, {self.high:g}]"

    def map_of(self, data: EffectData) -> tuple[float, float]:
        """``(offset, scale)`` of the coefficient-to-parameter map on ``data`` (:attr:`column`)."""
        scale = eta_of(data.params) if self.scale is None else self.scale
        return self.offset, scale

    def coef_range(self, data: EffectData) -> tuple[float, float]:
        """The range of the fitted coefficient ``g`` that keeps the parameter in its range."""
        off, scale = self.map_of(data)
        a, b = (self.low - off) / scale, (self.high - off) / scale
        return (a, b) if a <= b else (b, a)


class MotionLike(Protocol):
    """A motion the effects apply to: time, side speeds, body twist, its derivatives, pose.

    :class:`Motion` and the blind-case generator's trajectories have these attributes.
    """

    @property
    def t(self) -> FloatArray: ...  # noqa: D102

    @property
    def v_left(self) -> FloatArray: ...  # noqa: D102

    @property
    def v_right(self) -> FloatArray: ...  # noqa: D102

    @property
    def vx(self) -> FloatArray: ...  # noqa: D102

    @property
    def vy(self) -> FloatArray: ...  # noqa: D102

    @property
    def wz(self) -> FloatArray: ...  # noqa: D102

    @property
    def ax(self) -> FloatArray: ...  # noqa: D102

    @property
    def alpha(self) -> FloatArray: ...  # noqa: D102

    @property
    def x(self) -> FloatArray: ...  # noqa: D102

    @property
    def y(self) -> FloatArray: ...  # noqa: D102

    @property
    def yaw(self) -> FloatArray: ...  # noqa: D102


@dataclass(frozen=True, slots=True, eq=False)
class Motion:
    """A motion built from time-stamped side speeds (and the pose, when known).

    Attributes
    ----------
    t : ndarray
        Time [s].
    v_left, v_right : ndarray
        Side speeds [m/s].
    vx, vy, wz : ndarray
        Body twist (tracked eqs. 1-3) [m/s, m/s, rad/s].
    ax, alpha : ndarray
        Time derivatives of ``vx`` [m/s²] and ``wz`` [rad/s²].
    x, y, yaw : ndarray
        Pose [m, m, rad] in the world frame (REP-103: x forward, y left, yaw counter-clockwise).
    """

    t: FloatArray
    v_left: FloatArray
    v_right: FloatArray
    vx: FloatArray
    vy: FloatArray
    wz: FloatArray
    ax: FloatArray
    alpha: FloatArray
    x: FloatArray
    y: FloatArray
    yaw: FloatArray

    @classmethod
    def of_tracks(
        cls,
        t: FloatArray,
        v_left: FloatArray,
        v_right: FloatArray,
        icr: TrackICR,
        pose: tuple[ArrayLike | None, ArrayLike | None, ArrayLike | None] = (None, None, None),
    ) -> Motion:
        """The motion of side speeds: twist by the ICR kinematics, smoothed derivatives.

        Parameters
        ----------
        t : ndarray
            Time [s], strictly increasing.
        v_left, v_right : ndarray
            Side speeds [m/s].
        icr : TrackICR
            The vehicle's track ICRs.
        pose : tuple
            ``(x, y, yaw)`` [m, m, rad], each None to integrate it from the twist
            (:func:`ecoplan.dynamics.integrate.integrate_twist`, exact arcs).

        Returns
        -------
        Motion
            The motion.
        """
        tw = tracks_to_twist(v_left, v_right, icr)
        vx, vy, wz = (np.asarray(a, dtype=np.float64) for a in (tw.vx, tw.vy, tw.wz))
        own = integrate_twist(t, vx, vy, wz)
        x, y, yaw = (
            own[i] if given is None else np.asarray(given, dtype=np.float64)
            for i, given in enumerate(pose)
        )
        ax, alpha = smooth_derivative(t, vx), smooth_derivative(t, wz)
        return cls(t, v_left, v_right, vx, vy, wz, ax, alpha, x, y, yaw)


@dataclass(frozen=True, slots=True, eq=False)
class Session:
    """What an effect's parameters may depend on in a generated session (:meth:`Effect.draw`).

    Attributes
    ----------
    vehicle : TrackedParams or WheeledParams
        The true base vehicle.
    trajectories : sequence of MotionLike
        The session's runs without the effect.
    t_start_s, t_end_s : float
        First and last time of the session clock [s].
    p_base_w : ndarray
        The base model's power on all samples [W].
    moving : ndarray of bool
        Samples where a side moves faster than 1 mm/s.
    sign : float
        A random sign (+1 or -1) drawn for the case.
    rng : Generator
        The case's random source, for draws that depend on the session.
    """

    vehicle: VehicleParams
    trajectories: Sequence[MotionLike]
    t_start_s: float
    t_end_s: float
    p_base_w: FloatArray
    moving: BoolArray
    sign: float
    rng: np.random.Generator

    @classmethod
    def of(
        cls,
        vehicle: VehicleParams,
        trajectories: Sequence[MotionLike],
        sign: float,
        rng: np.random.Generator,
    ) -> Session:
        """The session of base trajectories on a vehicle."""
        t_all = np.concatenate([tr.t for tr in trajectories])
        p_base = np.concatenate(
            [base_power_w(vehicle, tr.v_left, tr.v_right) for tr in trajectories]
        )
        moving = np.concatenate(
            [(np.abs(tr.v_left) + np.abs(tr.v_right)) > 1e-3 for tr in trajectories]
        )
        t0, t1 = float(t_all[0]), float(t_all[-1])
        return cls(vehicle, trajectories, t0, t1, p_base, moving, sign, rng)

    @property
    def mean_p_w(self) -> float:
        """Mean base power of the session [W]."""
        return float(np.mean(self.p_base_w))


class Effect:
    """Base class of the effects: parameters, generation (``apply``) and the diagnosis's fit.

    A subclass names its :attr:`parameters`, gives its power on a motion (:meth:`apply`), the
    extra linear regressors of the diagnosis (:meth:`columns`) for a nonlinear parameter
    ``theta`` found by :meth:`_search`, and turns the fit into its parameters
    (:meth:`_name_params`).  The base model's linear parameters are refitted with the effect
    and χ (tracked eq. 12) is searched again with the effect in place, since calibration
    without the effect may have bent χ to mimic it.  The fit follows STYLE.md §12:
    ``fit(data)`` returns the effect, fitted values end in ``_``.

    Parameters
    ----------
    theta : object, optional
        Nonlinear parameter to use instead of searching it (e.g. an ICR offset measured on
        the pose).

    Attributes
    ----------
    theta_ : object
        Fitted nonlinear parameter (None for purely linear effects).
    chi_ : float
        χ refitted with the effect.
    coef_ : ndarray
        Linear coefficients: base columns, then the effect's.
    params_ : dict
        Fitted physical parameters by name (:attr:`parameters`), plus ``chi``.
    """

    name: ClassVar[str] = "effect"
    #: Whether the diagnosis offers it (False: generated only, to check ``unexplained``).
    in_library: ClassVar[bool] = True
    #: The effect's physical parameters.
    parameters: ClassVar[tuple[Parameter, ...]] = ()
    #: What the log must contain for the effect to be fitted.
    needs: ClassVar[tuple[str, ...]] = ()
    #: Acts on the steady-state power ``P(v_l, v_r)`` alone (:meth:`steady_power`).
    steady: ClassVar[bool] = False
    #: Acts on the supply (its power goes to the electrical loss, not the resistance).
    supply_side: ClassVar[bool] = False
    #: Whether the corrected model carries it over to new routes (False: a logging artefact
    #: or a fit tied to the log's own clock).
    on_routes: ClassVar[bool] = True
    #: Fitted as levels over segments of the log's time, so a step in time is one of its
    #: own cases, not a rival explanation (:mod:`ecoplan.diagnose.naming`).
    segments_in_time: ClassVar[bool] = False
    #: A steady trend in time (a drift of the whole power with the log's clock): a step in
    #: time is its rival only where the step adds to the trend (:mod:`ecoplan.diagnose.naming`).
    trend_in_time: ClassVar[bool] = False
    #: The searched ``theta`` is a nuisance (e.g. a heading offset per run), not a shape: the
    #: two halves of the split still compare the effect's parameters
    #: (:func:`~ecoplan.diagnose.naming.halves_check`).
    nuisance_theta: ClassVar[bool] = False

    def __init__(self, theta: Any = None) -> None:
        self.theta = theta
        self.theta_: Any = None
        self.chi_: float | None = None
        self.coef_: FloatArray | None = None
        self.params_: dict[str, float] = {}

    # -- generation --------------------------------------------------------------------
    @classmethod
    def values(cls, params: Params) -> list[float]:
        """The parameters in :attr:`parameters` order (defaults filled in).

        Raises
        ------
        InputError
            A required parameter is missing.
        """
        missing = [p.name for p in cls.parameters if p.name not in params and p.default is None]
        if missing:
            raise InputError(
                f"effect {cls.name!r} needs parameter(s) {', '.join(missing)}; got {sorted(params)}"
            )
        return [float(params.get(p.name, p.default)) for p in cls.parameters]  # type: ignore[arg-type]

    @classmethod
    def check(cls, params: Params, vehicle: VehicleParams, motion: MotionLike) -> None:
        """Reject parameters outside their physical range on this motion.

        Raises
        ------
        InputError
            A missing parameter or one out of range.
        """
        for p, v in zip(cls.parameters, cls.values(params), strict=True):
            if not p.admits(v):
                raise InputError(
                    f"{cls.name}: {p.name} = {v} is out of range; accepted: {p.accepted()}"
                )

    @classmethod
    def drive(cls, params: Params, vehicle: VehicleParams) -> tuple[VehicleParams, float]:
        """The vehicle and actuator lag ``τ`` [s] that produce the motion under the effect.

        Default: the vehicle unchanged and no lag (the effect acts on power alone).
        """
        return vehicle, 0.0

    @classmethod
    def steady_power(
        cls,
        params: Params,
        vehicle: VehicleParams,
        v_left: FloatArray,
        v_right: FloatArray,
    ) -> FloatArray:
        """Steady-state power ``P(v_l, v_r)`` with the effect [W] (:attr:`steady` effects)."""
        return base_power_w(vehicle, v_left, v_right)

    @classmethod
    def apply(cls, params: Params, vehicle: VehicleParams, motion: MotionLike) -> FloatArray:
        """True electrical power ``P_T`` [W] on a motion with the effect (no noise).

        Parameters
        ----------
        params : mapping of str to float
            The effect's :attr:`parameters`.
        vehicle : TrackedParams or WheeledParams
            The vehicle *without* the effect.
        motion : MotionLike
            The true motion (from :meth:`drive`'s vehicle and lag).

        Returns
        -------
        ndarray
            ``P_T`` per sample [W].
        """
        return cls.steady_power(params, vehicle, motion.v_left, motion.v_right)

    @classmethod
    def draw(cls, draws: Params, session: Session) -> dict[str, float]:
        """The effect's parameters from a magnitude's uniform draws on a session.

        Parameters
        ----------
        draws : mapping of str to float
            The magnitude's uniform draws (e.g. a mass as a multiple of the vehicle's).
        session : Session
            The session's base motion, vehicle and random source (further draws).

        Returns
        -------
        dict
            The effect's :attr:`parameters`.  Default: the draws are the parameters.
        """
        return {k: float(v) for k, v in draws.items()}

    # -- diagnosis: to be specialised --------------------------------------------------
    @classmethod
    def available(cls, frame: Frame) -> bool:
        """Whether the log carries the signals this effect needs."""
        have = {
            "commands": frame.vl_cmd is not None and frame.vr_cmd is not None,
            "pose": frame.on_one_map,
        }
        return all(have[k] for k in cls.needs)

    def columns(self, data: EffectData, theta: Any) -> FloatArray:
        """Extra regressors of the effect, shape (n, m) (m may be 0)."""
        return np.zeros((data.frame.n, 0))

    def design(self, data: EffectData, theta: Any) -> FloatArray:
        """Full design: base columns then the effect's columns."""
        return np.column_stack([data.X, self.columns(data, theta)])

    def _search(self, data: EffectData) -> Any:
        return None

    def coef_bounds(self, data: EffectData, n_cols: int) -> Bounds:
        """Physical bounds of the fit's coefficients: base columns, then the effect's.

        The base model's from its design (:func:`~ecoplan.diagnose.effects.fitting.base_bounds`,
        with the floor under a tracked ``k_nr``); the effect's from the ranges of its
        :attr:`parameters` that are linear coefficients (:attr:`Parameter.column`).

        Parameters
        ----------
        data : EffectData
            The samples.
        n_cols : int
            Columns of the design.

        Returns
        -------
        (ndarray, ndarray)
            Lower and upper bounds, one each per column.
        """
        lo, hi = base_bounds(data, n_cols)
        k = data.X.shape[1]
        for p in self.parameters:
            if p.column is not None and k + p.column < n_cols:
                lo[k + p.column], hi[k + p.column] = p.coef_range(data)
        return lo, hi

    def _fit_coef(self, data: EffectData, theta: Any) -> FloatArray:
        D = self.design(data, theta)
        return fit_linear(data, D, bounds=self.coef_bounds(data, D.shape[1]))

    def _predict(self, data: EffectData, theta: Any, coef: FloatArray) -> FloatArray:
        return np.asarray(self.design(data, theta) @ coef, dtype=np.float64)

    def _name_params(self, data: EffectData, theta: Any, coef: FloatArray) -> dict[str, float]:
        """The parameters that are linear coefficients (:attr:`Parameter.column`)."""
        k = data.X.shape[1]
        out: dict[str, float] = {}
        for p in self.parameters:
            if p.column is not None and k + p.column < coef.size:
                off, scale = p.map_of(data)
                out[p.name] = off + scale * float(coef[k + p.column])
        return out

    def _sse(self, data: EffectData, theta: Any) -> float:
        pred = self._predict(data, theta, self._fit_coef(data, theta))
        if isinstance(data.params, WheeledParams):
            return huber_loss(data.p - pred)
        return float(np.sum((data.p - pred) ** 2))

    # -- diagnosis: the contract ---------------------------------------------------------
    def fit(self, data: EffectData) -> Effect:
        """Fit the effect (with the base linear parameters and χ) on training data; returns self."""
        sub = subsample(data)
        search = self._search if self.theta is None else (lambda _d: self.theta)
        theta = search(sub)
        chi0 = float(data.params.chi)
        chi = chi0
        if kinematic_chi(data.frame, data.params) is None:  # else χ was measured, not fitted
            chi = grid_then_bounded(lambda c: self._sse(sub.at_chi(c), theta), *CHI_BOUNDS)
            if self._sse(sub.at_chi(chi), theta) >= self._sse(sub, theta):
                chi = chi0
        if chi != chi0:
            theta = search(sub.at_chi(chi))
        full = data.at_chi(chi)
        self.theta_, self.chi_ = theta, chi
        self.coef_ = self._fit_coef(full, theta)
        self.params_ = {**self._name_params(full, theta, self.coef_), "chi": chi}
        return self

    def _ready(self, data: EffectData) -> tuple[EffectData, FloatArray]:
        if self.coef_ is None or self.chi_ is None:
            raise InputError(f"effect {self.name!r} is not fitted")
        return data.at_chi(self.chi_), self.coef_

    def predict(self, data: EffectData) -> FloatArray:
        """Power predicted with the effect [W]."""
        d, coef = self._ready(data)
        return self._predict(d, self.theta_, coef)

    def refit_residual(self, data: EffectData) -> FloatArray:
        """Power residual on ``data`` with the linear terms refitted [W].

        The fitted nonlinear parameter is held; the base model's linear terms and the
        effect's are fitted again on ``data`` as prepared (its own χ and base parameters), as
        the last step of :meth:`fit` does.  What a structural search of the base (e.g. the
        friction law's exponent) minimises with the effect held.
        """
        if self.coef_ is None:
            raise InputError(f"effect {self.name!r} is not fitted")
        coef = self._fit_coef(data, self.theta_)
        return np.asarray(data.p - self._predict(data, self.theta_, coef), dtype=np.float64)

    def base_part(self, data: EffectData) -> FloatArray:
        """The refitted base model's part of :meth:`predict` [W]."""
        d, coef = self._ready(data)
        return np.asarray(d.X @ coef[: d.X.shape[1]], dtype=np.float64)

    def score(self, data: EffectData) -> float:
        """Mean absolute error of :meth:`predict` on ``data`` [W]."""
        return float(np.mean(np.abs(data.p - self.predict(data))))

    def effect_w(self, data: EffectData) -> FloatArray:
        """The effect's own contribution: prediction minus the refitted base part [W]."""
        return np.asarray(self.predict(data) - self.base_part(data), dtype=np.float64)


class NoEffect(Effect):
    """The calibrated base model alone (the reference every effect is compared with)."""

    name = "none"
    steady = True


class ScalarSearch(Effect):
    """An effect with one nonlinear parameter found by a grid then a bounded scalar search.

    The parameter is the first of :attr:`parameters`; the search stays within its range.
    """

    n_grid: ClassVar[int] = 9

    def _bounds(self, data: EffectData) -> tuple[float, float]:
        raise NotImplementedError

    def _search(self, data: EffectData) -> Any:
        lo, hi = self._bounds(data)
        if self.parameters:  # the search stays within the parameter's physical range
            p = self.parameters[0]
            lo, hi = min(max(lo, p.low), p.high), max(min(hi, p.high), p.low)
        if hi <= lo:
            return float(lo)
        grid = np.linspace(lo, hi, self.n_grid)
        sse = [self._sse(data, float(g)) for g in grid]
        i = int(np.argmin(sse))
        a, b = grid[max(i - 1, 0)], grid[min(i + 1, grid.size - 1)]
        res = minimize_scalar(
            lambda th: self._sse(data, float(th)),
            bounds=(a, b),
            method="bounded",
            options={"xatol": (hi - lo) * 2e-3},
        )
        return float(res.x) if res.fun < sse[i] else float(grid[i])
