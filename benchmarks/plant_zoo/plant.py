"""Run a zoo plant with one injected effect and log it like a real robot.

Pipeline of :func:`make_case` (internal step 0.01 s):

1. operator commands (:mod:`plant_zoo.drive`), quantised to 0.01 m/s;
2. side speeds follow the commands through a first-order drive lag (0.1 s);
3. ICR kinematics and pose (paper frame, then REP-103: x forward, y left, yaw CCW);
4. electrical power of the variant's plant with the effect injected *physically* (a terrain
   patch changes mu and K under the robot, a slope adds ``m g sin(alpha)`` times the uphill
   speed, a saturated supply slows the tracks, ...);
5. logging at 20 Hz: power averaged over each 50 ms sample (a watt-hour meter), the other
   columns sampled at the sample's end, coloured (AR(1)) noise on power, speeds, yaw rate and
   pose, dropped samples.  The log states how its power was taken, as a logger's driver
   would (``# power_sampling: interval_mean``, the log format's metadata line).

The effect names are the diagnosis's ten candidates, ``none``, and three effects outside its
library (``ripple``, ``payload``, ``power_gain``).  The truth never enters the log file.
"""

from __future__ import annotations

from dataclasses import dataclass, field, replace
from pathlib import Path

import numpy as np
from numpy.typing import NDArray
from scipy.signal import lfilter

from . import drive, tracked, wheeled

FloatArray = NDArray[np.float64]

#: Internal simulation step (s).
DT_S = 0.01
#: Logging period (s): 20 Hz.
LOG_DT_S = 0.05
#: Nominal drive lag (s): the speed loop of a real drive; the paper models no dynamics.
DRIVE_LAG_S = 0.1

IN_LIBRARY: tuple[str, ...] = (
    "inertia",
    "actuator_lag",
    "icr_asymmetry",
    "terrain_patch",
    "slope",
    "speed_dependent_resistance",
    "regeneration",
    "power_saturation",
    "sensor_delay",
    "efficiency_drift",
)
OUT_OF_LIBRARY: tuple[str, ...] = ("ripple", "payload", "power_gain")
EFFECTS: tuple[str, ...] = ("none", *IN_LIBRARY, *OUT_OF_LIBRARY)

#: Variant -> (vehicle kind, description).
VARIANTS: dict[str, tuple[str, str]] = {
    "a": ("tracked", "tracked paper literally: non-regen and braking as steps"),
    "b": ("tracked", "non-regenerated power ramped in over 0.1 m/s"),
    "c": ("tracked", "friction coefficient grows with slip speed (mu (s/0.4)^0.3)"),
    "d": ("tracked", "centre of gravity off the track centre (uneven contact pressure)"),
    "e": ("tracked", "mu, K, chi and driver terms 15-25 % off the paper"),
    "f": ("wheeled", "wheeled a(r), b(r) of another smooth family (r^-2 decay)"),
    "g": ("wheeled", "wheeled paper literally (Table I, eqs. 12-15)"),
    # c's development sibling: friction grows with slip by another law, so that work on the
    # slip law can be measured without looking at c (held out); after "g" in sorted order,
    # so the seeds of a-g (``vi``) are unchanged
    "h": (
        "tracked",
        "friction grows with slip, Coulomb plus viscous (mu (1 + s/0.4) / 2); c's dev sibling",
    ),
    # g's development sibling: the wheeled paper literally on its other terrain, so that work
    # on the wheeled diagnosis can be measured without looking at g (held out); after "h" in
    # sorted order, so the seeds of a-h are unchanged
    "i": ("wheeled", "wheeled paper literally on vinyl (Table II, eqs. 12-15); g's dev sibling"),
}

#: Tracked (belt, terrain) per seed, cycled.
TRACKED_SETUPS: tuple[tuple[str, str], ...] = (
    ("wide", "marble"),
    ("narrow", "marble"),
    ("wide", "asphalt"),
    ("narrow", "asphalt"),
)


@dataclass(frozen=True)
class Case:
    """One zoo log and its hidden truth.

    Attributes
    ----------
    variant, effect : str
        Plant variant and injected effect.
    seed : int
        Seed of the case.
    vehicle, terrain : str
        Matching library preset name and terrain.
    expected : str
        The right verdict: the effect for in-library effects, ``none``, or ``unexplained``.
    columns : dict of str to ndarray
        Logged columns (log format of the README), 20 Hz with dropped rows.
    meta : dict of str to str
        ``# key: value`` metadata lines.
    true_power_w : ndarray
        Noise-free power as the meter reports it (W): the plant's power after the sensor-side
        effects (delay, gain, ripple) and the 50 ms averaging, before noise; the reference of
        the held-out gap reduction.
    plant_power_w : ndarray
        Noise-free electrical power the plant really draws (W), averaged over each sample.
    effect_params : dict of str to float
        Drawn parameters of the effect (for the record).
    """

    variant: str
    effect: str
    seed: int
    vehicle: str
    terrain: str
    expected: str
    columns: dict[str, FloatArray]
    meta: dict[str, str]
    true_power_w: FloatArray
    plant_power_w: FloatArray
    effect_params: dict[str, float] = field(default_factory=dict)


def expected_verdict(effect: str) -> str:
    """The right verdict for an injected effect.

    Parameters
    ----------
    effect : str
        Injected effect name.

    Returns
    -------
    str
        ``effect`` itself for the ten in-library effects, ``none``, or ``unexplained``.
    """
    if effect in OUT_OF_LIBRARY:
        return "unexplained"
    return effect


def _ar1(rng: np.random.Generator, n: int, std: float, phi: float) -> FloatArray:
    """Stationary AR(1) (coloured) noise of standard deviation ``std``."""
    e = rng.normal(0.0, std * np.sqrt(1.0 - phi**2), n)
    zi = np.array([rng.normal(0.0, std) * phi])
    out, _ = lfilter([1.0], [1.0, -phi], e, zi=zi)
    return np.asarray(out, dtype=float)


def _lag(x: FloatArray, tau_s: float) -> FloatArray:
    """First-order lag with time constant ``tau_s`` at step :data:`DT_S`, starting at rest."""
    a = DT_S / (tau_s + DT_S)
    return np.asarray(lfilter([a], [1.0, a - 1.0], x), dtype=float)


def wheeled_plant(variant: str) -> tuple[wheeled.WheeledParams, str]:
    """The wheeled variant's plant and the terrain name of its table.

    f: Table I (asphalt) in another smooth family; g: the paper literally, Table I
    (asphalt); i: the paper literally, Table II (vinyl floor).
    """
    if variant == "i":
        inner, outer = wheeled.TABLE_II_INNER, wheeled.TABLE_II_OUTER
        return wheeled.WheeledParams(inner=inner, outer=outer), "vinyl"
    return wheeled.WheeledParams(family="rational" if variant == "f" else "chuy"), "asphalt"


def _tracked_params(
    variant: str, belt: str, terrain: str, rng: np.random.Generator
) -> tuple[tracked.TrackedParams, dict[str, float]]:
    """The variant's tracked plant (and what was drawn for it)."""
    p = tracked.paper_params(belt, terrain)
    info: dict[str, float] = {}
    if variant == "b":
        p = p.with_(nonregen_ramp_mps=0.1)
    elif variant == "c":
        p = p.with_(slip_exponent=0.3, slip_ref_mps=0.4)
    elif variant == "h":
        p = p.with_(slip_viscous_mps=0.4, slip_ref_mps=0.4)
    elif variant == "d":
        cx = float(rng.uniform(0.04, 0.06) * rng.choice([-1, 1]))
        cy = float(rng.uniform(0.08, 0.12) * rng.choice([-1, 1]))
        p = p.with_(cg_x_m=cx, cg_y_m=cy)
        info = {"cg_x_m": cx, "cg_y_m": cy}
    elif variant == "e":
        changes: dict[str, float] = {}
        for name in ("mu", "k_n", "chi", "power_up_w", "braking_w", "nonregen_n"):
            f = float(rng.uniform(0.15, 0.25)) * float(rng.choice([-1.0, 1.0]))
            value = getattr(p, name) * (1.0 + f)
            if name == "chi" and value >= 0.99:
                value = getattr(p, name) * (1.0 - abs(f))
            changes[name] = value
        changes["k_hoisted_n"] = min(p.k_hoisted_n, 0.8 * changes["k_n"])
        p = p.with_(**changes)
        info = changes
    return p, info


def _draw_effect(effect: str, rng: np.random.Generator, kind: str) -> dict[str, float]:
    """Physical parameters of the effect, drawn per case."""
    tr = kind == "tracked"
    if effect == "inertia":
        return {"mass_factor": float(rng.uniform(1.0, 1.3))}
    if effect == "actuator_lag":
        return {"tau_s": float(rng.uniform(0.5, 0.8))}
    if effect == "icr_asymmetry":
        d = float(rng.uniform(0.15, 0.3)) * float(rng.choice([-1.0, 1.0]))
        return {"scale_left": 1.0 + d, "scale_right": 1.0 - d / 2}
    if effect == "terrain_patch":
        return {"factor": float(rng.uniform(1.3, 1.6)), "radius_m": float(rng.uniform(3, 5))}
    if effect == "slope":
        return {
            "angle_rad": float(np.radians(rng.uniform(2.0, 4.0))),
            "direction_rad": float(rng.uniform(-np.pi, np.pi)),
        }
    if effect == "speed_dependent_resistance":
        return {"coef_per_mps": float(rng.uniform(0.6, 1.0))}
    if effect == "regeneration":
        return {"fraction": float(rng.uniform(0.5, 0.9))}
    if effect == "power_saturation":
        return {"quantile": float(rng.uniform(0.8, 0.9))}
    if effect == "sensor_delay":
        return {"delay_s": float(rng.uniform(0.3, 0.6))}
    if effect == "efficiency_drift":
        return {"drop": float(rng.uniform(0.1, 0.18))}
    if effect == "ripple":
        return {
            "rel": float(rng.uniform(0.05, 0.08)),
            "abs_w": 30.0 if tr else 1.0,
            "period_s": float(rng.uniform(3.0, 6.0)),
            "phase": float(rng.uniform(0, 2 * np.pi)),
        }
    if effect == "payload":
        return {
            "mass_kg": float(rng.uniform(60, 90) if tr else rng.uniform(8, 12)),
            "t_on_frac": float(rng.uniform(0.35, 0.65)),
        }
    if effect == "power_gain":
        return {"gain": float(rng.uniform(1.12, 1.2)), "t_on_frac": float(rng.uniform(0.35, 0.65))}
    return {}


def _pose(v_fwd: FloatArray, wz: FloatArray) -> tuple[FloatArray, FloatArray, FloatArray]:
    """Integrate REP-103 pose from forward speed and yaw rate (trapezoid in yaw)."""
    yaw = np.concatenate([[0.0], np.cumsum((wz[1:] + wz[:-1]) / 2) * DT_S])
    x = np.concatenate([[0.0], np.cumsum(v_fwd[:-1] * np.cos(yaw[:-1])) * DT_S])
    y = np.concatenate([[0.0], np.cumsum(v_fwd[:-1] * np.sin(yaw[:-1])) * DT_S])
    return x, y, yaw


def make_case(variant: str, effect: str, seed: int, duration_s: float = 180.0) -> Case:
    """Simulate one zoo case.

    Parameters
    ----------
    variant : str
        Key of :data:`VARIANTS`.
    effect : str
        One of :data:`EFFECTS`.
    seed : int
        Seed; the operator's manoeuvres depend on the seed and the vehicle only.
    duration_s : float
        Run length (s).

    Returns
    -------
    Case
        The log and its truth.

    Raises
    ------
    ValueError
        Unknown variant or effect.
    """
    if variant not in VARIANTS:
        raise ValueError(f"unknown variant {variant!r}; one of {sorted(VARIANTS)}")
    if effect not in EFFECTS:
        raise ValueError(f"unknown effect {effect!r}; one of {list(EFFECTS)}")
    kind = VARIANTS[variant][0]
    vi = sorted(VARIANTS).index(variant)
    ei = EFFECTS.index(effect)
    rng_drive = np.random.default_rng([seed, 0 if kind == "tracked" else 1])
    rng_plant = np.random.default_rng([seed, vi, 7])
    rng_fx = np.random.default_rng([seed, vi, ei, 11])
    rng_log = np.random.default_rng([seed, vi, ei, 13])
    n = round(duration_s / DT_S)
    t = np.arange(n) * DT_S
    fx = _draw_effect(effect, rng_fx, kind)

    if kind == "tracked":
        belt, terrain = TRACKED_SETUPS[seed % len(TRACKED_SETUPS)]
        tp, plant_info = _tracked_params(variant, belt, terrain, rng_plant)
        wp = wheeled.WheeledParams()
        vehicle, v_top, mass = f"auriga-beta-{belt}", tp.v_max_mps, tp.mass_kg
        inertia_z = mass * (0.7**2 + 1.2**2) / 12.0
    else:
        tp = tracked.TrackedParams()
        wp, terrain = wheeled_plant(variant)
        plant_info = {}
        vehicle, v_top, mass = "pioneer-3at", wp.v_max_mps, wp.mass_kg
        inertia_z = mass * (0.5**2 + 0.5**2) / 12.0

    cmd_l, cmd_r = drive.operator_commands(
        rng_drive, kind, duration_s, DT_S, v_top_mps=v_top, wheeled_params=wp
    )
    tau = fx.get("tau_s", DRIVE_LAG_S)
    vl, vr = _lag(cmd_l, tau), _lag(cmd_r, tau)
    if effect == "icr_asymmetry":
        tp = tp.with_(icr_scale_left=fx["scale_left"], icr_scale_right=fx["scale_right"])
        wp = replace(wp, icr_scale_left=fx["scale_left"], icr_scale_right=fx["scale_right"])

    def base_power(
        vl_: FloatArray,
        vr_: FloatArray,
        x_: FloatArray | None = None,
        y_: FloatArray | None = None,
    ) -> tuple[FloatArray, FloatArray]:
        """Mechanical and driver power with the effects that act inside the power law."""
        scale: FloatArray | float = 1.0
        extra_m: FloatArray | float = 0.0
        if effect == "terrain_patch" and x_ is not None and y_ is not None:
            inside = np.hypot(x_ - fx["cx"], y_ - fx["cy"]) < fx["radius_m"]
            scale = np.where(inside, fx["factor"], 1.0)
        if effect == "payload":
            extra_m = np.where(t >= fx["t_on_frac"] * duration_s, fx["mass_kg"], 0.0)
        if kind == "tracked":
            pm = tracked.friction_power(tp, vl_, vr_, mu_scale=scale, extra_mass_kg=extra_m)
            pm = pm + tracked.resistance_power(
                tp,
                vl_,
                vr_,
                k_scale=scale,
                extra_mass_kg=extra_m,
                speed_coef_per_mps=fx.get("coef_per_mps", 0.0),
            )
            pd = tracked.driver_power(tp, vl_, vr_, regen_fraction=fx.get("fraction", 0.0))
            return np.asarray(pm, dtype=float), np.asarray(pd, dtype=float)
        pl, pr = wheeled.side_powers(wp, vl_, vr_)
        mult = np.asarray(scale, dtype=float) * (1.0 + np.asarray(extra_m) / mass)
        if effect == "speed_dependent_resistance":
            c = fx["coef_per_mps"]
            pl = pl * (1 + c * np.abs(vl_))
            pr = pr * (1 + c * np.abs(vr_))
        if effect == "regeneration":  # the braking (negative) side gives back a share
            pl = np.where(pl < 0, pl * (1 - fx["fraction"]), pl)
            pr = np.where(pr < 0, pr * (1 - fx["fraction"]), pr)
        return np.asarray((np.abs(pl) + np.abs(pr)) * mult, dtype=float), np.zeros_like(vl_)

    def kinematics(vl_: FloatArray, vr_: FloatArray) -> tuple[FloatArray, FloatArray]:
        if kind == "tracked":
            return tracked.forward_speed(tp, vl_, vr_), tracked.yaw_rate(tp, vl_, vr_)
        return wheeled.forward_speed(wp, vl_, vr_), wheeled.yaw_rate(wp, vl_, vr_)

    if effect == "power_saturation":
        pm, pd = base_power(vl, vr)
        demand = pm + pd
        cap = float(np.quantile(demand[np.abs(vl) + np.abs(vr) > 0.05], fx["quantile"]))
        fx["cap_w"] = cap
        over = demand > cap
        lo, hi = np.zeros(int(over.sum())), np.ones(int(over.sum()))
        for _ in range(30):  # the drive slows down until the supply suffices
            mid = (lo + hi) / 2
            pm_m, pd_m = base_power(vl[over] * mid, vr[over] * mid)
            ok = pm_m + pd_m <= cap
            lo = np.where(ok, mid, lo)
            hi = np.where(ok, hi, mid)
        vl, vr = vl.copy(), vr.copy()
        vl[over] *= lo
        vr[over] *= lo

    v_fwd, wz = kinematics(vl, vr)
    x, y, yaw = _pose(v_fwd, wz)
    if effect == "terrain_patch":  # a patch centred on where the robot is mid-run
        k = int(rng_fx.uniform(0.3, 0.7) * n)
        fx["cx"], fx["cy"] = float(x[k]), float(y[k])
    pm, pd = base_power(vl, vr, x, y)
    if effect == "inertia":
        m_eff = mass * fx["mass_factor"]
        acc = np.gradient(v_fwd, DT_S)
        wdot = np.gradient(wz, DT_S)
        pm = pm + m_eff * v_fwd * acc + inertia_z * fx["mass_factor"] * wz * wdot
    if effect == "slope":
        uphill = v_fwd * np.cos(yaw - fx["direction_rad"])
        pm = pm + mass * tracked.G_MPS2 * np.sin(fx["angle_rad"]) * uphill
    pm = np.maximum(pm, 0.0)  # drivers do not regenerate: no negative drive power
    eta = tp.eta if kind == "tracked" else 1.0
    if effect == "efficiency_drift":
        eta = eta * (1.0 - fx["drop"] * t / duration_s)
    p_true = (pm + pd) / eta

    # ---- logging -------------------------------------------------------------------------
    p_meas = p_true
    if effect == "sensor_delay":
        shift = round(fx["delay_s"] / DT_S)
        p_meas = np.concatenate([np.full(shift, p_meas[0]), p_meas[:-shift]])
    if effect == "ripple":
        p_meas = p_meas + (fx["rel"] * p_meas + fx["abs_w"]) * np.sin(
            2 * np.pi * t / fx["period_s"] + fx["phase"]
        )
    if effect == "power_gain":
        p_meas = np.where(t >= fx["t_on_frac"] * duration_s, p_meas * fx["gain"], p_meas)
    step = round(LOG_DT_S / DT_S)
    m = n // step
    idx = np.arange(m) * step + step - 1  # sample at the end of each 50 ms window
    p_avg = p_meas[: m * step].reshape(m, step).mean(axis=1)
    true_avg = p_true[: m * step].reshape(m, step).mean(axis=1)
    p_noise = 15.0 if kind == "tracked" else 0.4
    # resolvers read 0 at rest, otherwise the speed with a little coloured noise
    vl_meas = np.where(np.abs(vl[idx]) < 2e-3, 0.0, vl[idx] + _ar1(rng_log, m, 0.004, 0.7))
    vr_meas = np.where(np.abs(vr[idx]) < 2e-3, 0.0, vr[idx] + _ar1(rng_log, m, 0.004, 0.7))
    cols: dict[str, FloatArray] = {
        "t": t[idx],
        "v_left": vl_meas,
        "v_right": vr_meas,
        "p_total": p_avg + _ar1(rng_log, m, p_noise, 0.8),
        "v_left_cmd": cmd_l[idx],
        "v_right_cmd": cmd_r[idx],
        "x": x[idx] + _ar1(rng_log, m, 0.02, 0.95),
        "y": y[idx] + _ar1(rng_log, m, 0.02, 0.95),
        "yaw": np.angle(np.exp(1j * (yaw[idx] + _ar1(rng_log, m, 0.01, 0.9)))),
        "wz": wz[idx] + _ar1(rng_log, m, 0.01, 0.5) + 0.002,
    }
    keep = rng_log.random(m) > 0.015  # scattered drops
    b0 = int(rng_log.integers(m // 5, 4 * m // 5))
    keep[b0 : b0 + int(rng_log.integers(10, 40))] = False  # one burst
    keep[0] = keep[-1] = True
    cols = {k: np.asarray(v[keep], dtype=float) for k, v in cols.items()}
    run_id = f"zoo-{variant}-{effect}-s{seed}"
    # the logger's power is each window's mean: a log states it (ecoplan's `power_sampling`)
    meta = {
        "run_id": run_id,
        "source": "benchmarks/plant_zoo",
        "vehicle": vehicle,
        "power_sampling": "interval_mean",
    }
    fx_all = {**plant_info, **fx}
    return Case(
        variant=variant,
        effect=effect,
        seed=seed,
        vehicle=vehicle,
        terrain=terrain,
        expected=expected_verdict(effect),
        columns=cols,
        meta=meta,
        true_power_w=np.asarray(p_avg[keep], dtype=float),
        plant_power_w=np.asarray(true_avg[keep], dtype=float),
        effect_params=fx_all,
    )


def write_log(case: Case, path: Path) -> Path:
    """Write a case in the README's CSV log format.

    Parameters
    ----------
    case : Case
        The case.
    path : pathlib.Path
        Output file (its folder is created).

    Returns
    -------
    pathlib.Path
        ``path``.
    """
    path.parent.mkdir(parents=True, exist_ok=True)
    names = list(case.columns)
    data = np.column_stack([case.columns[k] for k in names])
    header = "".join(f"# {k}: {v}\n" for k, v in case.meta.items()) + ",".join(names)
    np.savetxt(path, data, delimiter=",", header=header, comments="", fmt="%.6g")
    return path
