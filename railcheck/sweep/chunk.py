"""One chunk of a sweep: settings (bar lengths) -> table rows, one per setting and speed.

For the whole chunk at once (arrays settings x steps): the configuration checks, the
kinematics and inverse dynamics in closed form at the sweep's first speed, the peak
reactions, motor torque and power and the joints' bearing lives at every speed, and,
for the settings that pass the checks, each part's cycle peak, fatigue factor and tip
deflection by superposition, its utilisation, and the setting's safe speed.

Speed scaling. At constant crank speed every acceleration scales with omega^2, so the
loads are ``C(s) = C_g + s C_i`` with ``s = (omega / omega_0)^2``: ``C_g`` the constant
part (gravity, explicit loads), ``C_i`` the inertial part at the first speed. Without
gravity every stress and deflection scales with ``s`` and every fatigue factor with
``1 / s``, so each speed's results and the safe speed (the ``s`` at which the largest
utilisation reaches 1) follow in closed form; with gravity each speed is evaluated and
the safe speed is found by bisection on ``s``.

Units: SI inside; the table's column names carry their units (mm, Hz, N, N m, W, MPa, h).
"""

from __future__ import annotations

import math

import numpy as np

from railcheck.fea.dynamic import modal_correction
from railcheck.fea.screening import hull_steps, peak_and_fatigue, tip_peak, von_mises_peak
from railcheck.kinematics import batch
from railcheck.kinematics.checks import fourbar_checks_batch, slidercrank_checks_batch
from railcheck.kinematics.dynamics import STANDARD_GRAVITY
from railcheck.kinematics.motion import crank_angles
from railcheck.loads.bearings import bearing_life_of_magnitude, relative_speeds, with_weight_couple
from railcheck.model.kinematics_stage import joints_on_rails_flags
from railcheck.model.loading import free_body_coefficients, source_coefficients, weight_cases_names, weight_columns
from railcheck.model.utilisation import quasi_static_share
from railcheck.parts import BAR_INDEX
from railcheck.sweep.columns import fe_columns
from railcheck.sweep.components import (
    components_of_settings,
    no_part_results,
    swept_components,
    weight_of_settings,
    with_components,
)
from railcheck.sweep.context import Loads, SweepContext, reactions_at, setting_lengths
from railcheck.sweep.motor import (
    MOTOR_CURVE_KEY,
    demand_at_safe,
    motor_columns,
    motor_curve_speeds,
    motor_demand,
    torque_parts,
)
from railcheck.sweep.validity import (
    Spectra,
    certified_safe_ratio_sq,
    certifying,
    margin_governs,
    safe_ratio_sq_with_margin,
    with_estimates,
    with_margin,
)
from railcheck.sweep.verdicts import (
    SAFE_SPEED_SCAN,
    governing_of,
    safe_ratio_sq_bisect,
    safe_ratio_sq_closed,
    safe_ratio_sq_convex,
    scaled_results,
    utilisation,
    worst_utilisation,
)

REVOLVE_MARGIN = 1e-7  # rad: closer to a toggle is singular (kinematics.motion)


def configuration_flags(ctx: SweepContext, lengths: dict) -> dict:
    """check name -> (S,) pass flags, plus ``mu_min``/``mu_max`` (rad)."""

    if ctx.kind == "four-bar":
        flags = fourbar_checks_batch(lengths["crank"], lengths["coupler"], lengths["rocker"], lengths["ground"])
    else:
        flags = slidercrank_checks_batch(lengths["crank"], lengths["coupler"], lengths["offset"])
    flags["joints_on_rails"] = joints_on_rails_flags(lengths, ctx.rail)
    return flags


def checks_of(flags: dict) -> dict:
    """check name -> (S,) pass flags: :func:`configuration_flags` without the transmission
    angles ``mu_min``/``mu_max`` (rad), which are not checks."""
    return {k: v for k, v in flags.items() if k not in ("mu_min", "mu_max")}


def passes_checks(flags: dict) -> np.ndarray:
    """(S,) True where a setting passes every configuration check of ``flags``
    (:func:`configuration_flags`, :func:`checks_of`)."""
    return np.logical_and.reduce(list(checks_of(flags).values()))


def checked_settings(ctx: SweepContext, lengths: dict) -> np.ndarray:
    """(S,) True where a setting's parts are checked by FE when the scene has parts to
    check: it revolves and passes every configuration check."""
    flags = configuration_flags(ctx, lengths)
    return passes_checks(flags) & revolvable(ctx, lengths, flags)


def revolvable(ctx: SweepContext, lengths: dict, flags: dict) -> np.ndarray:
    """(S,) True where the crank makes a full revolution away from a toggle."""
    if ctx.kind == "four-bar":
        with np.errstate(invalid="ignore"):
            return (
                (flags["mu_min"] > REVOLVE_MARGIN)
                & (math.pi - flags["mu_max"] > REVOLVE_MARGIN)
                & np.isfinite(flags["mu_min"])
                & np.isfinite(flags["mu_max"])
            )
    reach = lengths["crank"] + np.abs(lengths["offset"])
    return lengths["coupler"] - reach >= REVOLVE_MARGIN * lengths["coupler"]


def motion_of(ctx: SweepContext, lengths: dict, speed: float):

    sign = 1.0 if ctx.inputs.sweep.assembly == "open" else -1.0
    th = crank_angles(ctx.steps)
    if ctx.kind == "four-bar":
        return batch.fourbar_motion(
            lengths["crank"], lengths["coupler"], lengths["rocker"], lengths["ground"], sign, speed, th
        )
    return batch.slidercrank_motion(lengths["crank"], lengths["coupler"], lengths["offset"], sign, speed, th)


def dynamics_of(ctx: SweepContext, motion, gravity: float):
    """The settings' inverse dynamics with the check's one mass model (a free-body check
    places the rails as they are meshed: :func:`railcheck.parts.mass_model`)."""
    masses = ctx.inputs.masses
    if ctx.inputs.formulation == "seed-2013":
        return batch.seed_2013(motion, masses)
    return batch.newton_euler(motion, masses, gravity=gravity)


def loads_of(ctx: SweepContext, lengths: dict) -> Loads:

    motion = motion_of(ctx, lengths, ctx.speeds[0])
    inertial = dynamics_of(ctx, motion, 0.0) if "inertia" in ctx.effects else None
    static = constant = None
    if "gravity" in ctx.effects:
        static = motion_of(ctx, lengths, 0.0)
        constant = dynamics_of(ctx, static, STANDARD_GRAVITY)
    return Loads(motion, static, inertial, constant)


def motor_and_bearings(ctx: SweepContext, loads: Loads, speed: float) -> dict:
    """Peak reactions, motor torque (peak, RMS), peak power and the joints' bearing
    equivalent loads and L10 lives at ``speed`` rad/s (on a table-top rig, O2 and O4 also
    carry their cantilevered bar's weight moment as a couple over the bearings): columns (S,)."""

    s = (speed / ctx.speeds[0]) ** 2
    R, torque = reactions_at(loads, s)
    ratio = speed / ctx.speeds[0]
    w = loads.motion.omega * ratio  # (3, S, T) rad/s
    # |R| once per joint for the peak and the bearings: sqrt(x^2 + y^2), not np.hypot (3x
    # slower; no overflow: forces are bounded by the scene's lengths and speeds)
    size = {j: np.sqrt(r[..., 0] * r[..., 0] + r[..., 1] * r[..., 1]) for j, r in R.items()}
    out = {f"peak_{j}_N": m.max(axis=1) for j, m in size.items()}
    out["torque_peak_Nm"] = np.abs(torque).max(axis=1)
    out["torque_rms_Nm"] = np.sqrt(np.mean(torque**2, axis=1))
    out["power_peak_W"] = np.abs(torque * speed).max(axis=1)
    relative = relative_speeds(w[0], w[1], w[2], ctx.kind)
    lives, statics = [], []
    moments = weight_of_settings(ctx, loads.motion, np.arange(torque.shape[0]))["moments"]
    for joint in ("O2", "A", "B", "O4"):
        if joint not in R:
            continue
        load = with_weight_couple(size[joint], moments.get(joint, 0.0), ctx.inputs.component_spec.bearing_spacing)
        life = bearing_life_of_magnitude(load, relative[joint])
        out[f"bearing_{joint}_load_N"] = life.equivalent_load
        out[f"bearing_{joint}_peak_N"] = life.peak_load
        lives.append(life.l10_hours)
        statics.append(life.static_safety)
    out["bearing_life_h"] = np.min(lives, axis=0)
    out["bearing_static_safety"] = np.min(statics, axis=0)
    return out


def kinematic_columns(ctx: SweepContext) -> list[str]:
    """The columns :func:`motor_and_bearings` gives, in order (NaN where a setting does not revolve)."""
    joints = ("O2", "A", "B", "O4") if ctx.kind == "four-bar" else ("O2", "A", "B", "slider")
    bearings = ("O2", "A", "B", "O4") if ctx.kind == "four-bar" else ("O2", "A", "B")
    return (
        [f"peak_{j}_N" for j in joints]
        + ["torque_peak_Nm", "torque_rms_Nm", "power_peak_W"]
        + [f"bearing_{j}_{q}_N" for j in bearings for q in ("load", "peak")]
        + ["bearing_life_h", "bearing_static_safety"]
    )


def coefficients(ctx: SweepContext, name: str, loads: Loads, sel: np.ndarray) -> list[tuple]:
    """Per load source of part ``name``: (C_g or None, C_i) (S_sel, T, k) for the settings
    ``sel``: the constant part (gravity at rest) and the inertial part at the first speed
    (the total there minus the constant part)."""

    def coeffs(src, reactions: dict, motion):
        by_bar = lambda a: {bar: a[i][sel] for bar, i in BAR_INDEX.items()}  # noqa: E731
        return source_coefficients(
            loads_model,
            src,
            {j: r[sel] for j, r in reactions.items()},
            by_bar(motion.theta),
            {j: a[sel] for j, a in motion.accelerations.items()},
            by_bar(motion.omega),
            by_bar(motion.alpha),
        )

    loads_model = ctx.models[name].loads
    total, torque = reactions_at(loads, 1.0)
    if loads_model.is_free_body:  # one history: both joints' forces, the motor's torque, the rail's own inertia
        Ct = free_coeffs(loads_model, total, torque, loads.motion, sel)
        if loads.constant is not None:
            C_gravity = free_coeffs(loads_model, loads.constant.reactions, loads.constant.torque, loads.static, sel)
            return [(C_gravity, Ct - C_gravity)]
        if loads_model.weight is None:
            return [(None, Ct)]
        Cw = weight_part(loads_model, loads.motion, sel, Ct.shape)  # the table-top rig's weight: constant
        return [(Cw, Ct - Cw)]
    out = []
    for src in loads_model.sources:
        if src.joint not in total:
            continue
        Ct = coeffs(src, total, loads.motion)
        if loads.constant is None:
            out.append((None, Ct))
        else:
            C_gravity = coeffs(src, loads.constant.reactions, loads.static)
            out.append((C_gravity, Ct - C_gravity))
    return out


def free_coeffs(model, reactions: dict, torque: np.ndarray, motion, sel: np.ndarray) -> np.ndarray:
    """(S_sel, T, k): a free rail's coefficients (:func:`railcheck.model.loading.free_body_coefficients`)
    for the settings ``sel`` from reactions (N), torque (N m) and the motion they come from."""
    by_bar = lambda a: {bar: a[i][sel] for bar, i in BAR_INDEX.items()}  # noqa: E731
    return free_body_coefficients(
        model,
        {j: r[sel] for j, r in reactions.items()},
        torque[sel],
        by_bar(motion.theta),
        {j: a[sel] for j, a in motion.accelerations.items()},
        by_bar(motion.omega),
        by_bar(motion.alpha),
        setting_lengths(motion, sel),
    )


def weight_part(model, motion, sel: np.ndarray, shape: tuple) -> np.ndarray:
    """(S_sel, T, k): a free rail's coefficients of the table-top rig's weight alone (every
    other column zero), constant over steps and speeds."""
    out = np.zeros(shape)
    out[..., shape[-1] - len(weight_cases_names(model)) :] = weight_columns(model, setting_lengths(motion, sel), shape[:-1])
    return out


def evaluate_part(
    model, history: list[tuple], bar_lengths: np.ndarray | None, s, speed0: float = 0.0, decide: bool = False
) -> tuple[np.ndarray, ...]:
    """(von Mises peak Pa, fatigue factor, tip m, dynamic amplification) of one part for
    every setting of the history at speed ratio squared ``s`` (scalar or (S,)), each (S,).
    With a dynamic response (``model.dynamic``) the peak, factor and tip are those of the
    quasi-static history plus the mode-acceleration correction at crank speed
    ``speed0 sqrt(s)`` rad/s, and the amplification is that peak over the quasi-static
    one (the largest over the load sources); without, the amplification is 1. ``decide``:
    only whether each criterion passes matters beyond its limit (a safe-speed search), so
    a fatigue factor above the required one is not refined (:func:`fatigue_min` ``enough``)."""

    n_set = history[0][1].shape[0]
    s = np.broadcast_to(np.asarray(s, float), (n_set,))
    # amplification: the largest over the load sources, as the check's (below 1 where the modes lower the peak)
    vm, fat, tip, amp = np.zeros(n_set), np.full(n_set, np.inf), np.zeros(n_set), np.full(n_set, -np.inf)
    if model.bar is None:
        groups = [(np.arange(n_set), model.screens[None], model.modes_for(0.0))]
    else:
        assert bar_lengths is not None  # a part on a bar: its hole pair follows the bar's length
        keys, inverse = np.unique(np.round(bar_lengths * 1e6).astype(np.int64), return_inverse=True)
        groups = [
            (np.flatnonzero(inverse == i), model.screen_for(key / 1e6), model.modes_for(key / 1e6))
            for i, key in enumerate(keys)
        ]
    args = (model.endurance, model.ultimate, model.criterion, model.yield_strength, model.required if decide else None)
    for idx, screen, modes in groups:
        length = None if bar_lengths is None else bar_lengths[idx[0]]
        if modes is None:  # every load source's histories in one call: they share the part's box
            C = hull_steps(np.concatenate([_source_history(model, length, s, idx, *h) for h in history]))
            sets = np.tile(np.arange(idx.size), len(history))  # a setting's load sources: one set
            peak, factor = (r.reshape(len(history), idx.size) for r in peak_and_fatigue(screen, C, *args, sets=sets))
            vm[idx] = np.maximum(vm[idx], peak.max(axis=0))
            fat[idx] = np.minimum(fat[idx], factor.min(axis=0))
            tip[idx] = np.maximum(tip[idx], tip_peak(screen, C).reshape(len(history), idx.size).max(axis=0))
            amp[idx] = np.maximum(amp[idx], 1.0)  # quasi-static: the peak is its own
            continue
        for C_gravity, C_inertia in history:  # with modes: each source's correction read on the modes' screen
            C = _source_history(model, length, s, idx, C_gravity, C_inertia)
            quasi = von_mises_peak(screen, hull_steps(C))
            dq = modal_correction(modes.modal_loads, modes.hz, C, speed0 * np.sqrt(s[idx]), model.damping)
            C = hull_steps(np.concatenate([C, dq], axis=2))
            peak, factor = peak_and_fatigue(modes.screen, C, *args)
            with np.errstate(invalid="ignore", divide="ignore"):
                amp[idx] = np.maximum(amp[idx], np.where(quasi > 0, peak / quasi, 1.0))
            vm[idx] = np.maximum(vm[idx], peak)
            fat[idx] = np.minimum(fat[idx], factor)
            tip[idx] = np.maximum(tip[idx], tip_peak(modes.screen, C))
    return vm, fat, tip, np.where(np.isfinite(amp), amp, 1.0)


def _source_history(model, length, s: np.ndarray, idx: np.ndarray, C_gravity, C_inertia: np.ndarray) -> np.ndarray:
    """(len(idx), T, k): one load source's coefficients for the settings ``idx`` at speed
    ratio squared ``s`` (gravity ``C_gravity`` or None, inertia ``C_inertia``), with the pin pressures
    of the hole pair a bar of ``length`` m uses."""
    return model.with_pin_pressure(
        length, s[idx, None, None] * C_inertia[idx] + (C_gravity[idx] if C_gravity is not None else 0.0)
    )


def fe_histories(ctx: SweepContext, loads: Loads, sel: np.ndarray) -> dict[str, list[tuple]]:
    """part -> :func:`coefficients` of the settings ``sel`` (every part not of constant result)."""
    return {name: coefficients(ctx, name, loads, sel) for name, m in ctx.models.items() if m.constant is None}


def joined_histories(parts: list[dict[str, list[tuple]]]) -> dict[str, list[tuple]]:
    """:func:`fe_histories` of several groups of settings as one: each part's load
    sources' arrays joined along the settings (a constant part None stays None)."""
    return {
        name: [
            tuple(None if arrays[0] is None else np.concatenate(arrays) for arrays in zip(*sources))
            for sources in zip(*(p[name] for p in parts))
        ]
        for name in parts[0]
    }


def fe_results(ctx: SweepContext, histories: dict, lengths: dict, speeds_s: list) -> dict:
    """part -> list over speeds of (vm, fatigue, tip, amplification, utilisation) (S,)
    arrays of the settings whose histories are ``histories`` (:func:`fe_histories`) and
    bar lengths ``lengths`` (bar -> (S,) m), and ``safe_s``: the speed ratio squared at
    which the largest utilisation reaches 1 (closed form when every result scales with
    ``s``; searched with gravity or a dynamic response)."""
    bar_len = lambda m: lengths[m.bar] if m.bar else None  # noqa: E731
    n_sel = next(iter(lengths.values())).size
    scaling = homogeneous_parts(ctx, histories)
    first: dict = {}  # part -> its results at s = 1, once known (scaling's parts)

    def at(s, decide: bool = False, idx=None) -> dict:
        """The parts' results at ``s``: of every setting, or of the settings ``idx`` only."""
        k = n_sel if idx is None else idx.size
        out = {}
        for name, m in ctx.models.items():
            if m.constant is not None:
                vm, fat, tip = (np.full(k, v) for v in m.constant)
                amp = np.ones(k)
            elif name in first:
                vm, fat, tip, amp = scaled_part(first[name], s, idx)
            else:
                hist, lens = histories[name], bar_len(m)
                if idx is not None:
                    hist = [(None if C_gravity is None else C_gravity[idx], C_inertia[idx]) for C_gravity, C_inertia in hist]
                    lens = None if lens is None else lens[idx]
                vm, fat, tip, amp = evaluate_part(m, hist, lens, s, ctx.speeds[0], decide)
            out[name] = (vm, fat, tip, amp, utilisation(m, vm, fat, tip, amp))
        return out

    dynamic = any(m.dynamic is not None for m in ctx.models.values())
    weight = any(m.loads.weight is not None for m in ctx.models.values())
    exact = "gravity" in ctx.effects or dynamic or weight
    base = at(1.0)
    first.update({name: base[name][:4] for name in scaling})
    per_speed = [base if s == 1.0 else (at(s) if exact else scaled_results(ctx, base, s)) for s in speeds_s]
    convex = exact and not dynamic  # a constant part (gravity, the table-top weight): convex in s
    if dynamic:
        safe = safe_ratio_sq_bisect(ctx, lambda s: at(s, decide=True), n_sel, scan=SAFE_SPEED_SCAN)
    elif convex and not certifying(ctx):
        safe = safe_ratio_sq_convex(lambda s, idx: at(s, True, idx), n_sel, worst_utilisation(base))
    elif not exact:
        safe = safe_ratio_sq_closed(ctx, base, n_sel)
    if certifying(ctx):  # each speed's rows carry the estimate; the safe speed takes it as a margin
        spectra = Spectra(ctx, histories, lengths)
        per_speed = [with_estimates(ctx, r, spectra.at(s)) for r, s in zip(per_speed, speeds_s)]
        results = (lambda s: at(s)) if exact else (lambda s: scaled_results(ctx, base, s))
        safe, governs = _margin_safe(ctx, spectra, at, results, base, safe if not convex else None)
    else:
        finite = np.where(np.isfinite(safe), safe, 1.0)  # unlimited: what governs at the reference speed
        governs = governing_of(ctx, at(finite) if exact else scaled_results(ctx, base, finite))
    return {"per_speed": per_speed, "safe_s": safe, "safe_governs": governs}


def homogeneous_parts(ctx: SweepContext, histories: dict) -> set[str]:
    """The parts whose results at any speed follow from those at the first speed: no
    constant load part (every load source's ``C_g`` None: no gravity, no table-top
    weight) and no dynamic response. Their loads are ``s C_i``, the pin pressures' harmonics
    too (``|F| a_k e^{ik theta}``: positively homogeneous of degree 1), so every stress and
    deflection is ``s`` times its value at ``s = 1`` and every fatigue factor ``1 / s`` of
    it (:func:`scaled_part`), as :func:`railcheck.sweep.verdicts.scaled_results` takes
    for a whole sweep without gravity."""
    return {
        name
        for name, m in ctx.models.items()
        if m.constant is None and m.dynamic is None and all(C_gravity is None for C_gravity, _ in histories[name])
    }


def scaled_part(results: tuple, s, idx: np.ndarray | None = None) -> tuple:
    """(von Mises Pa, fatigue factor, tip m, amplification) of a :func:`homogeneous_parts`
    part at speed ratio squared ``s`` (scalar, or one per setting) from ``results``, its
    (S,) arrays at ``s = 1``, of the settings ``idx`` (None: all)."""
    vm, fat, tip, amp = (r if idx is None else r[idx] for r in results)
    s = np.asarray(s, float)
    with np.errstate(divide="ignore"):  # at rest (s = 0) the fatigue factor is infinite
        return s * vm, fat / s, s * tip, amp


def _margin_safe(ctx: SweepContext, spectra: Spectra, at, results, base: dict, upper) -> tuple:
    """(safe s (S,), (part, criterion) that sets it) with the certificate's estimate as a
    margin (:func:`railcheck.sweep.validity.with_margin`): ``at(s, decide, idx)`` the
    parts' exact results, ``results(s)`` every setting's at ``s``, ``base`` those at s = 1.
    ``upper`` None: loads ``C_g + s C_i``, convex in s, bounded by the estimate's crossing
    (:func:`railcheck.sweep.validity.certified_safe_ratio_sq`); else the quasi-static safe s, the
    crossing searched below it (:func:`railcheck.sweep.validity.safe_ratio_sq_with_margin`)."""
    n_sel = next(iter(base.values()))[0].size

    def margin(s) -> dict:
        return with_margin(ctx, results(s), spectra.at(s))

    def margin_of(s, idx) -> dict:  # the settings idx at their s
        return with_margin(ctx, at(s, False, idx), spectra.at(s, idx))

    if upper is None:
        share = lambda s, idx: np.max([quasi_static_share(a) for a in spectra.at(s, idx).values()], axis=0)  # noqa: E731
        u1 = worst_utilisation(with_margin(ctx, base, spectra.at(1.0)))
        safe, at_safe = certified_safe_ratio_sq(ctx, margin_of, share, n_sel, u1)
    else:
        safe = safe_ratio_sq_with_margin(margin, upper, n_sel)
        at_safe = margin(np.where(np.isfinite(safe), safe, 1.0))
    return safe, margin_governs(ctx, at_safe)


def evaluate_chunk(ctx: SweepContext, lengths: dict, ids: np.ndarray) -> dict:
    """The table rows of the settings ``lengths`` (bar -> (S,) m), one per setting and
    speed (setting-major): column name -> array."""
    n = ids.size
    flags = configuration_flags(ctx, lengths)
    checks = checks_of(flags)
    passed = passes_checks(flags)
    idx = np.flatnonzero(revolvable(ctx, lengths, flags))
    rev = revolving_results(ctx, lengths, idx, passed)
    fe = (rev["fe_at"], rev["fe"]) if "fe" in rev else None
    rows = []
    motor = motor_columns(ctx, n, idx, rev, passed)
    for j, w in enumerate(ctx.speeds):
        col = {"setting": ids, "kind": np.full(n, ctx.kind, dtype=object)}
        col |= {f"{b}_mm": v * 1e3 for b, v in lengths.items()}
        col["speed_Hz"] = np.full(n, w / (2 * math.pi))
        col |= {f"check_{k}": v.astype(bool) for k, v in checks.items()}
        col["checks_passed"] = passed
        col["mu_min_deg"], col["mu_max_deg"] = np.degrees(flags["mu_min"]), np.degrees(flags["mu_max"])
        for key in kinematic_columns(ctx):
            col[key] = _scatter(n, idx, rev["kin"][j][key]) if idx.size else np.full(n, np.nan)
        col |= fe_columns(ctx, n, fe, j, passed, checks)
        col |= motor["columns"]
        rows.append(col)
    out = {k: np.stack([r[k] for r in rows], axis=1).reshape(-1) for k in rows[0]}
    out[MOTOR_CURVE_KEY] = motor["curve"]
    return out


def group_size(steps: int) -> int:
    """Revolving settings evaluated together: one block of the batch kinematics
    (:data:`railcheck.kinematics.batch.BLOCK_ELEMENTS` settings x steps), so that no
    settings x steps array is ever joined from blocks."""
    return max(1, batch.BLOCK_ELEMENTS // max(steps, 1))


def revolving_results(ctx: SweepContext, lengths: dict, idx: np.ndarray, passed: np.ndarray) -> dict:
    """What the revolving settings ``idx`` give, the kinematics evaluated in groups of
    :func:`group_size` settings (a group's loads are dropped once reduced; of its settings
    with FE only their coefficient histories and motor torque are held, until every
    group is done): ``kin``, per speed the kinematic columns (:func:`motor_and_bearings`);
    ``curve``, the motor demand at :func:`motor_curve_speeds`; for the settings that also
    pass the checks (with parts to check) ``fe_at`` (their rows in the chunk), ``fe``
    (:func:`fe_results`) and ``at_safe`` (the motor demand at their safe speed). Every
    array's first axis runs over the revolving settings, or over ``fe_at``."""
    size = group_size(ctx.steps)
    groups = [_revolving_group(ctx, lengths, idx[a : a + size], passed) for a in range(0, idx.size, size)]
    if not groups:
        return {}
    out = {key: concat_trees([g[key] for g in groups]) for key in ("kin", "curve")}
    with_fe = [g for g in groups if "fe_sel" in g]
    if with_fe:
        # every group's FE settings at once: the settings that share a part's hole pair are
        # screened together (:func:`railcheck.fea.screening.groups.peak_and_fatigue`); a chunk holds at
        # most :func:`railcheck.sweep.run.checked_chunk_size` of them
        n_fe = sum(g["fe_sel"].size for g in with_fe)
        res = (
            fe_results(
                ctx,
                joined_histories([g["fe_histories"] for g in with_fe]),
                {b: np.concatenate([g["fe_lengths"][b] for g in with_fe]) for b in lengths},
                [(w / ctx.speeds[0]) ** 2 for w in ctx.speeds],
            )
            if ctx.models
            else no_part_results(n_fe, len(ctx.speeds))
        )
        if "components" in with_fe[0]:  # the joints' components bound the safe speed too
            res = with_components(res, concat_trees([g["components"] for g in with_fe]))
        ends = np.cumsum([g["fe_sel"].size for g in with_fe])
        safe = np.split(res["safe_s"], ends[:-1])
        out |= {
            "fe_at": np.concatenate([g["fe_at"] for g in with_fe]),
            "fe": res,
            "at_safe": concat_trees([demand_at_safe(ctx, g["fe_torque"], s) for g, s in zip(with_fe, safe)]),
        }
    return out


def _revolving_group(ctx: SweepContext, lengths: dict, rows: np.ndarray, passed: np.ndarray) -> dict:
    """:func:`revolving_results` of one group of revolving settings ``rows``: its
    kinematic columns and motor curve, and for its settings that pass the checks (with
    parts to check) their rows in the chunk ``fe_at``, positions in the group
    ``fe_sel``, bar lengths, FE histories (:func:`fe_histories`) and motor torque
    (:func:`torque_parts`)."""
    sub = {b: v[rows] for b, v in lengths.items()}
    loads = loads_of(ctx, sub)
    out = {
        "kin": [motor_and_bearings(ctx, loads, w) for w in ctx.speeds],
        "curve": motor_demand(loads, ctx.speeds[0], motor_curve_speeds(ctx.speeds)),
    }
    fe_sel = np.flatnonzero(passed[rows])
    components = swept_components(ctx)
    if (ctx.models or components) and fe_sel.size:
        out |= {
            "fe_at": rows[fe_sel],
            "fe_sel": fe_sel,
            "fe_lengths": {b: v[fe_sel] for b, v in sub.items()},
            "fe_torque": torque_parts(loads, fe_sel),
        }
        if ctx.models:
            out["fe_histories"] = fe_histories(ctx, loads, fe_sel)
        if components:
            out["components"] = components_of_settings(ctx, loads, fe_sel)
    return out


def concat_trees(trees: list):
    """Join trees of the same shape (dicts, lists, tuples of arrays) leaf by leaf along
    the arrays' first axis."""
    first = trees[0]
    if isinstance(first, dict):
        return {k: concat_trees([t[k] for t in trees]) for k in first}
    if isinstance(first, (list, tuple)):
        return type(first)(concat_trees(list(parts)) for parts in zip(*trees))
    return first if len(trees) == 1 else np.concatenate(trees, axis=0)


def _scatter(n: int, idx: np.ndarray, values: np.ndarray, fill=np.nan) -> np.ndarray:
    out = np.full(n, fill, dtype=float)
    out[idx] = values
    return out
