"""The joints' components over a sweep's settings (:mod:`railcheck.components`): each
component's utilisation at every speed of the table, and the speed at which the largest
reaches 1, which bounds the setting's safe speed with the FE parts'. Analytic and
vectorised over the settings and steps: a fraction of the parts' cost. SI.

Every component's utilisation grows with the speed (its loads are the constant part plus
the speed ratio squared times the inertial part, and a bearing's life shortens as it turns
faster), so the crossing is single.
"""

from __future__ import annotations

import numpy as np

from railcheck.components import kinds
from railcheck.components.checks import JointHistories
from railcheck.components.kinds import check_components
from railcheck.components.ratings import NOT_ON_SLIDER_CRANK
from railcheck.components.scene_checks import FIRST_JOINTS, ComponentsInput
from railcheck.loads.bearings import relative_speeds
from railcheck.loads.weight import joint_vertical_loads, screw_pulls, shaft_moment
from railcheck.model.crossing import increasing_crossing
from railcheck.model.loading import rail_weight
from railcheck.sweep.context import Loads, SweepContext, reactions_at, setting_lengths


def swept_components(ctx: SweepContext) -> tuple[str, ...]:
    """The components the sweep's scene lists that this kind of linkage has (none listed:
    none run; a slider-crank has no rocker, so no O4 shaft or bearings)."""
    listed = ctx.inputs.components.listed if ctx.inputs.components is not None else ()
    return tuple(c for c in listed if ctx.kind == "four-bar" or c not in NOT_ON_SLIDER_CRANK)


def sweep_histories(ctx: SweepContext, loads: Loads, sel: np.ndarray, s) -> JointHistories:
    """The components' loads of the settings ``sel`` at speed ratio squared ``s`` (scalar
    or one per setting of ``sel``): their joint forces and torque, the bars' angles, the
    bearings' relative speeds, and a table-top rig's weight through the joints."""
    s = np.broadcast_to(np.asarray(s, float), sel.shape)
    n = loads.motion.theta.shape[1]
    full = np.ones(n)
    full[sel] = s
    R, torque = reactions_at(loads, full)
    m = loads.motion
    omega = m.omega[:, sel] * np.sqrt(s)[None, :, None]
    return JointHistories(
        reactions={j: r[sel] for j, r in R.items()},
        torque=torque[sel],
        angles={"crank": m.theta[0][sel], "coupler": m.theta[1][sel], "rocker": m.theta[2][sel]},
        relative_speed=relative_speeds(omega[0], omega[1], omega[2], ctx.kind),
        **weight_of_settings(ctx, m, sel),
    )


def weight_of_settings(ctx: SweepContext, motion, sel: np.ndarray) -> dict:
    """``vertical``, ``moments`` and ``screw_tension`` of :class:`JointHistories` for the
    settings ``sel`` (empty for a vertical rig: its weight is in the joint forces)."""
    if ctx.inputs.plane != "horizontal":
        return {"vertical": {}, "moments": {}, "screw_tension": {}}
    lengths = {bar: v[:, 0] for bar, v in setting_lengths(motion, sel).items()}
    moments, pulls = {}, {}
    for joint, bar in FIRST_JOINTS.items():
        if ctx.kind == "four-bar" or bar != "rocker":
            w = rail_weight(ctx.inputs.masses, ctx.inputs.geometry, bar, ctx.kind)
            pulls[joint] = screw_pulls(w, lengths)
            if bar != "coupler":
                moments[joint] = shaft_moment(w, lengths)
    crank = rail_weight(ctx.inputs.masses, ctx.inputs.geometry, "crank", ctx.kind)
    return {"vertical": joint_vertical_loads(crank, lengths), "moments": moments, "screw_tension": pulls}


def component_results(ctx: SweepContext, loads: Loads, sel: np.ndarray, s, h: JointHistories | None = None) -> dict:
    """name -> :class:`railcheck.components.checks.ComponentResult` (arrays (len(sel),))
    of every listed component for the settings ``sel`` at speed ratio squared ``s`` (their
    loads ``h`` when the caller has them, :func:`sweep_histories`)."""
    h = sweep_histories(ctx, loads, sel, s) if h is None else h
    c = _listing(ctx)
    return check_components(swept_components(ctx), c.spec, h, c.factor, c.strengths)


def worst_component(results: dict) -> tuple[np.ndarray, np.ndarray, np.ndarray]:
    """(largest utilisation, its component, its criterion), each (S,), over ``results``."""
    names = list(results)
    u = np.array([np.asarray(r.utilisation, float) for r in results.values()])
    k = np.argmax(np.where(np.isnan(u), np.inf, u), axis=0)
    cols = np.arange(u.shape[1])
    criteria = np.array([np.asarray(r.governing_criterion, dtype=object) for r in results.values()], dtype=object)
    return u[k, cols], np.asarray(names, dtype=object)[k], criteria[k, cols]


def components_safe_ratio_sq(ctx: SweepContext, loads: Loads, sel: np.ndarray) -> tuple[np.ndarray, tuple]:
    """(speed ratio squared (len(sel),) at which the settings' largest component
    utilisation reaches 1 (:func:`railcheck.model.crossing.increasing_crossing`: 0 where a
    component fails at rest, inf where none reaches 1); (component, criterion) that sets
    it)."""

    def worst(s, idx):
        return worst_component(component_results(ctx, loads, sel[idx], s))[0]

    safe = increasing_crossing(worst, sel.size)
    _, name, criterion = worst_component(component_results(ctx, loads, sel, np.where(np.isfinite(safe), safe, 1.0)))
    return safe, (name, criterion)


def failed_words(result) -> np.ndarray:
    """(S,) object: each setting's failed criteria of one component, "+"-joined ("" where
    it passes; NaN fails)."""
    names = list(result.utilisations)
    fails = np.array([~(np.asarray(u, float) <= 1.0) for u in result.utilisations.values()])
    words = [["+".join(n for n, f in zip(names, col) if f)] for col in fails.T]
    return np.array([w[0] for w in words], dtype=object) if words else np.zeros(0, dtype=object)


def components_of_settings(ctx: SweepContext, loads: Loads, sel: np.ndarray) -> dict:
    """The listed components of the settings ``sel``: ``per_speed``, at each of the
    table's speeds, name -> (utilisation, governing criterion, failed criteria, what it
    needs (:func:`needs_of_settings`; "" where nothing is sized)), each (len(sel),);
    ``safe_s`` and ``governs`` (:func:`components_safe_ratio_sq`)."""
    per_speed = []
    for w in ctx.speeds:
        s = (w / ctx.speeds[0]) ** 2
        h = sweep_histories(ctx, loads, sel, s)
        results, needs = component_results(ctx, loads, sel, s, h), needs_of_settings(ctx, h)
        per_speed.append(
            {
                n: (
                    np.asarray(r.utilisation, float),
                    np.asarray(r.governing_criterion, dtype=object),
                    failed_words(r),
                    needs.get(n, np.full(sel.size, "", dtype=object)),
                )
                for n, r in results.items()
            }
        )
    safe, governs = components_safe_ratio_sq(ctx, loads, sel)
    return {"per_speed": per_speed, "safe_s": safe, "governs": governs}


def needs_of_settings(ctx: SweepContext, h: JointHistories) -> dict:
    """Component -> (S,) what each setting needs to pass at the loads ``h``: a screw
    group's smallest screw that passes slip and EN 1993-1-8 T3.4 (object: ``"M5 8.8"``;
    ``"none"`` where no screw the rail's hole admits does), a shaft's least diameter in m,
    a pair of bearings' least spacing in m (:func:`railcheck.components.kinds.needs_of_settings`)."""
    c = _listing(ctx)
    return kinds.needs_of_settings(swept_components(ctx), c.spec, h, c.factor, c.strengths)


def no_part_results(n: int, speeds: int) -> dict:
    """What :func:`railcheck.sweep.chunk.fe_results` gives when the sweep checks no FE
    part (components only): nothing per speed, no limit on the speed."""
    return {"per_speed": [{} for _ in range(speeds)], "safe_s": np.full(n, np.inf), "safe_governs": _no_governs(n)}


def _no_governs(n: int) -> tuple:
    return np.full(n, "", dtype=object), np.full(n, "", dtype=object)


def with_components(res: dict, comp: dict) -> dict:
    """The parts' results ``res`` with the components': each setting's safe speed the
    lower of the two, set by whichever reaches its limit first; the components' columns
    under ``components``."""
    lower = comp["safe_s"] < res["safe_s"]
    part, criterion = res["safe_governs"]
    governs = (np.where(lower, comp["governs"][0], part), np.where(lower, comp["governs"][1], criterion))
    safe = np.minimum(res["safe_s"], comp["safe_s"])
    return res | {"safe_s": safe, "safe_governs": governs, "components": comp["per_speed"]}


def _listing(ctx: SweepContext) -> ComponentsInput:
    """The components' record of a sweep that lists some (a [check] table)."""
    if ctx.inputs.components is None:
        raise ValueError("a sweep without [check] lists no components")
    return ctx.inputs.components
