"""Does the zoo's drive excite each effect?  A matched-filter SNR against the zoo's own noise.

A benchmark measures a diagnosis only where its logs *show* the injected effect.  For each
effect this module compares the zoo's noise-free meter power with the effect and without it
(:func:`power_snr`), on the same drive, and -- for ``icr_asymmetry`` -- the ICR offset alone
in the pose and the power (:func:`icr_offset_snr`), and expresses the difference as the
signal-to-noise ratio of the optimal (matched-filter) detector against the noise the zoo
itself adds when logging
(:mod:`plant_zoo.plant`: AR(1) noise of std 0.4 W (wheeled) / 15 W (tracked), coefficient 0.8
per 50 ms sample, on the power; std 0.02 m, coefficient 0.95 on each of ``x`` and ``y``).

**The bar** (:data:`SNR_BAR` = 5): with the effect's signature known, a detector at SNR 5
that raises a false alarm on 0.1 % of clean logs (threshold 3.09) finds the effect in
``Phi(5 - 3.09)`` = 97 % of the logs.  Below it, no diagnosis can be expected to name the
effect reliably, so a miss says more about the drive than about the diagnosis.  The bar is a
*necessary* condition only: a diagnosis must also estimate the effect's parameters and tell it
from its rivals, which costs more signal.

What the power SNR does not say: ``actuator_lag`` and ``power_saturation`` change the wheel
speeds, and the log records the changed speeds; on those speeds the plant's power is the base
power, so these two effects show in a log only against the *commands* (their power SNR
measures how much the driving changed).  And the diagnosis re-identifies the vehicle's
structure first: :func:`refit_snr` gives, for the wheeled variants, what an effect leaves
after the plant's own ``a(r)``, ``b(r)`` are re-fitted -- for ``regeneration`` almost nothing,
since a returned share of the braking power is a smaller braking torque in eq. (12).

The SNR is exact for an AR(1) noise sampled at the kept (non-dropped) log samples: the
samples are whitened with the gap-aware recursion ``e_k = (d_k - phi^g d_{k-1}) /
sqrt(1 - phi^(2 g))`` (``g`` the gap in samples), and ``SNR^2 = sum(e_k^2) / std^2``
(:func:`ar1_snr`).

Imports numpy only and the zoo's own modules, like the rest of the zoo.
"""

from __future__ import annotations

from dataclasses import dataclass, replace

import numpy as np
from numpy.typing import NDArray

from . import drive, plant, tracked, wheeled

FloatArray = NDArray[np.float64]

#: Matched-filter SNR an effect's signature must reach on every seed (see the module text).
SNR_BAR = 5.0
#: The zoo's logged power noise (plant.make_case): AR(1) std (W) by vehicle kind, coefficient.
POWER_NOISE_W = {"tracked": 15.0, "wheeled": 0.4}
POWER_NOISE_PHI = 0.8
#: The zoo's logged pose noise on x and y: AR(1) std (m) and coefficient per log sample.
POSE_NOISE_M = 0.02
POSE_NOISE_PHI = 0.95
#: Window of the pose check (s): the pose speed over non-overlapping windows of this length.
POSE_WINDOW_S = 1.0


def ar1_snr(delta: FloatArray, sample_index: FloatArray, std: float, phi: float) -> float:
    """Matched-filter SNR of a known signal in stationary AR(1) noise, with dropped samples.

    Parameters
    ----------
    delta : ndarray
        The signal (noise-free difference with and without the effect) at the kept samples.
    sample_index : ndarray
        Integer index of each kept sample on the regular log grid (increasing).
    std : float
        Stationary standard deviation of the noise (same unit as ``delta``).
    phi : float
        AR(1) coefficient per grid step, in [0, 1).

    Returns
    -------
    float
        ``sqrt(delta^T Sigma^-1 delta)`` with ``Sigma`` the AR(1) covariance at those samples.
    """
    d = np.asarray(delta, dtype=float)
    if d.size == 0:
        return 0.0
    gap = np.diff(np.asarray(sample_index, dtype=float))
    rho = phi**gap
    e = (d[1:] - rho * d[:-1]) / np.sqrt(1.0 - rho**2)
    return float(np.sqrt((d[0] ** 2 + np.sum(e**2)) / std**2))


def power_snr(variant: str, effect: str, seed: int, duration_s: float = 180.0) -> float:
    """SNR of an effect in the zoo's noise-free meter power, against the logged power noise.

    The case with the effect and the clean case share the drive (the operator depends on the
    seed and the vehicle only); their ``true_power_w`` (sensor-side effects in, noise out) are
    compared at the samples both logs kept.

    Parameters
    ----------
    variant, effect : str
        Zoo variant and effect (:data:`plant_zoo.plant.EFFECTS`, not ``none``).
    seed : int
        Case seed.
    duration_s : float
        Run length (s).

    Returns
    -------
    float
        :func:`ar1_snr` of the power difference (W) against :data:`POWER_NOISE_W`.
    """
    kind = plant.VARIANTS[variant][0]
    with_fx = plant.make_case(variant, effect, seed, duration_s)
    clean = plant.make_case(variant, "none", seed, duration_s)
    t_a, t_b = with_fx.columns["t"], clean.columns["t"]
    common, ia, ib = np.intersect1d(t_a, t_b, assume_unique=True, return_indices=True)
    delta = with_fx.true_power_w[ia] - clean.true_power_w[ib]
    index = np.round(common / plant.LOG_DT_S)
    return ar1_snr(delta, index, POWER_NOISE_W[kind], POWER_NOISE_PHI)


@dataclass(frozen=True)
class IcrOffsetExcitation:
    """What the ICR offset alone does to the pose and the power over one run.

    Attributes
    ----------
    offset_m : float
        The plant's lateral ICR offset ``(C_l + C_r) / 2`` (m) of the drawn asymmetry.
    pose_snr : float
        SNR of the offset in the pose: the displacement over non-overlapping
        :data:`POSE_WINDOW_S` windows, asymmetric plant minus the symmetric plant with the same
        ICR span (same yaw rate), against the window displacement noise of the logged pose.
    power_snr : float
        :func:`ar1_snr` of the noise-free power (50 ms means), asymmetric minus symmetric plant
        of the same span, against the logged power noise.
    snr : float
        Both channels together, ``hypot(pose_snr, power_snr)`` (their noises are independent).
    turning_share : float
        Share of the run with a yaw rate above 0.05 rad/s (-).
    max_yaw_rate : float
        Largest yaw rate of the run (rad/s).
    """

    offset_m: float
    pose_snr: float
    power_snr: float
    snr: float
    turning_share: float
    max_yaw_rate: float


def icr_offset_snr(variant: str, seed: int, duration_s: float = 180.0) -> IcrOffsetExcitation:
    """SNR of the ``icr_asymmetry`` case's ICR *offset* in the logged pose and power.

    The drawn asymmetry both widens the ICR span and shifts its centre.  The span is the
    efficiency index, a structural parameter that calibration identifies from the yaw rate;
    what only the effect explains is the shift ``d``, which changes the forward speed by
    ``w_z d`` at the same yaw rate.  The check therefore compares the asymmetric plant with
    the symmetric plant of the same span, on the zoo's own drive (same seeds as
    :func:`plant_zoo.plant.make_case`).  Pose: the squared window displacements are summed
    over the window noise ``std sqrt(2 (1 - phi^L))`` (``L`` samples per window); windows are
    treated as independent, so the accumulated position, which a wrong efficiency index or
    odometry drift also moves, is not counted as evidence.  Power: the plant's power with
    either ICR pair (the shift changes the forward speed and so the turning radius).

    Parameters
    ----------
    variant : str
        Zoo variant.
    seed : int
        Case seed.
    duration_s : float
        Run length (s).

    Returns
    -------
    IcrOffsetExcitation
        The offset, its pose and power SNR and how much the run turns.
    """
    kind = plant.VARIANTS[variant][0]
    vi = sorted(plant.VARIANTS).index(variant)
    ei = plant.EFFECTS.index("icr_asymmetry")
    fx = plant._draw_effect("icr_asymmetry", np.random.default_rng([seed, vi, ei, 11]), kind)
    rng_drive = np.random.default_rng([seed, 0 if kind == "tracked" else 1])
    sl, sr = fx["scale_left"], fx["scale_right"]
    sym = (sl + sr) / 2  # same span C_r - C_l, centred
    if kind == "tracked":
        belt, terrain = plant.TRACKED_SETUPS[seed % len(plant.TRACKED_SETUPS)]
        tp = tracked.paper_params(belt, terrain)
        cmd_l, cmd_r = drive.operator_commands(
            rng_drive, kind, duration_s, plant.DT_S, v_top_mps=tp.v_max_mps
        )
        asym_p = tp.with_(icr_scale_left=sl, icr_scale_right=sr)
        sym_p = tp.with_(icr_scale_left=sym, icr_scale_right=sym)
        vl, vr = plant._lag(cmd_l, plant.DRIVE_LAG_S), plant._lag(cmd_r, plant.DRIVE_LAG_S)
        v_a, w = tracked.forward_speed(asym_p, vl, vr), tracked.yaw_rate(asym_p, vl, vr)
        v_s = tracked.forward_speed(sym_p, vl, vr)
        half = asym_p.icr_x_m
        dp = tracked.total_power(asym_p, vl, vr) - tracked.total_power(sym_p, vl, vr)
    else:
        wp = plant.wheeled_plant(variant)[0]
        cmd_l, cmd_r = drive.operator_commands(
            rng_drive, kind, duration_s, plant.DT_S, wheeled_params=wp
        )
        asym_w = replace(wp, icr_scale_left=sl, icr_scale_right=sr)
        sym_w = replace(wp, icr_scale_left=sym, icr_scale_right=sym)
        vl, vr = plant._lag(cmd_l, plant.DRIVE_LAG_S), plant._lag(cmd_r, plant.DRIVE_LAG_S)
        v_a, w = wheeled.forward_speed(asym_w, vl, vr), wheeled.yaw_rate(asym_w, vl, vr)
        v_s = wheeled.forward_speed(sym_w, vl, vr)
        half = asym_w.icr_y_m
        dp = wheeled.total_power(asym_w, vl, vr) - wheeled.total_power(sym_w, vl, vr)
    _, _, yaw = plant._pose(v_a, w)
    dv = v_a - v_s
    per = round(POSE_WINDOW_S / plant.DT_S)
    m = len(dv) // per
    dx = (dv * np.cos(yaw))[: m * per].reshape(m, per).sum(axis=1) * plant.DT_S
    dy = (dv * np.sin(yaw))[: m * per].reshape(m, per).sum(axis=1) * plant.DT_S
    samples = round(POSE_WINDOW_S / plant.LOG_DT_S)
    noise = POSE_NOISE_M * np.sqrt(2.0 * (1.0 - POSE_NOISE_PHI**samples))
    pose = float(np.sqrt(np.sum(dx**2 + dy**2)) / noise)
    step = round(plant.LOG_DT_S / plant.DT_S)
    k = len(dp) // step
    dp_log = np.asarray(dp, dtype=float)[: k * step].reshape(k, step).mean(axis=1)
    power = ar1_snr(dp_log, np.arange(k), POWER_NOISE_W[kind], POWER_NOISE_PHI)
    return IcrOffsetExcitation(
        offset_m=float(sum(half) / 2),
        pose_snr=pose,
        power_snr=power,
        snr=float(np.hypot(pose, power)),
        turning_share=float(np.mean(np.abs(w) > 0.05)),
        max_yaw_rate=float(np.max(np.abs(w))),
    )


def excitation_table(
    variant: str, seeds: range | list[int], duration_s: float = 180.0
) -> dict[str, list[float]]:
    """Power SNR of every effect (and the ICR pose SNR) on each seed.

    Parameters
    ----------
    variant : str
        Zoo variant.
    seeds : iterable of int
        Case seeds.
    duration_s : float
        Run length (s).

    Returns
    -------
    dict of str to list of float
        Effect name -> SNR per seed; ``"icr_asymmetry (offset)"`` holds the offset's combined
        pose and power SNR, :func:`icr_offset_snr`.
    """
    effects = [e for e in plant.EFFECTS if e != "none"]
    table = {e: [power_snr(variant, e, s, duration_s) for s in seeds] for e in effects}
    table["icr_asymmetry (offset)"] = [icr_offset_snr(variant, s, duration_s).snr for s in seeds]
    return table


def refit_snr(variant: str, effect: str, seed: int, duration_s: float = 180.0) -> float:
    """SNR of what a wheeled effect leaves after the plant's own ``a(r)``, ``b(r)`` are re-fitted.

    A stronger necessary condition than :func:`power_snr`: the diagnosis re-identifies the
    vehicle's structure before it names an effect (issue 12, items 1-2), so only the part of
    the effect's signature that no re-fit of the 12 coefficients of eqs. (14)-(15) (Table I's
    inner and outer ``a_inf, a_alpha, a_beta, b_inf, b_alpha, b_beta``, in the plant's own
    family) can absorb is evidence for it.  The noise-free meter power of the case is fitted
    by least squares (scipy) on the drive's noise-free side speeds (the commands through the
    case's drive lag) from Table I as the start, and the residual's :func:`ar1_snr` against the
    logged power noise is returned.

    Parameters
    ----------
    variant : str
        A wheeled zoo variant (``f`` or ``g``).
    effect : str
        Any effect of :data:`plant_zoo.plant.EFFECTS` except ``power_saturation``, whose
        slowed side speeds the zoo does not return.
    seed : int
        Case seed.
    duration_s : float
        Run length (s).

    Returns
    -------
    float
        SNR of the residual after the re-fit.

    Raises
    ------
    ValueError
        A tracked variant or ``power_saturation``.
    """
    from scipy.optimize import least_squares

    if plant.VARIANTS[variant][0] != "wheeled" or effect == "power_saturation":
        raise ValueError(f"refit_snr: wheeled variants, not {variant!r} / {effect!r}")
    case = plant.make_case(variant, effect, seed, duration_s)
    wp = plant.wheeled_plant(variant)[0]
    cmd_l, cmd_r = drive.operator_commands(
        np.random.default_rng([seed, 1]), "wheeled", duration_s, plant.DT_S, wheeled_params=wp
    )
    tau = case.effect_params.get("tau_s", plant.DRIVE_LAG_S)
    vl, vr = plant._lag(cmd_l, tau), plant._lag(cmd_r, tau)
    step = round(plant.LOG_DT_S / plant.DT_S)
    m = len(vl) // step
    index = np.round((case.columns["t"] - (step - 1) * plant.DT_S) / plant.LOG_DT_S)
    kept = index.astype(int)

    def residual(x: FloatArray) -> FloatArray:
        p = replace(
            wp,
            inner=(x[0], x[1], x[2], x[3], x[4], x[5]),
            outer=(x[6], x[7], x[8], x[9], x[10], x[11]),
        )
        pw = wheeled.total_power(p, vl, vr)[: m * step].reshape(m, step).mean(axis=1)
        return np.asarray(pw[kept] - case.true_power_w, dtype=float)

    x0 = np.array(wp.inner + wp.outer, dtype=float)
    lower = np.full(12, -np.inf)
    lower[[2, 5, 8, 11]] = 0.05  # decay exponents stay positive: a(r), b(r) decay with r
    fit = least_squares(
        residual, x0, x_scale=np.abs(x0) + 0.1, bounds=(lower, np.inf), max_nfev=400
    )
    return ar1_snr(fit.fun, index, POWER_NOISE_W["wheeled"], POWER_NOISE_PHI)
