"""How each part is loaded over the cycle: its :class:`LoadModel` (resolved once from the
scene), its unit load cases, and the coefficient history of every load source.

Unit cases per part (part frame, :mod:`railcheck.fea.unitcases`): ``bolt_x`` and
``bolt_y``, a total force of 1 N along the part's longitudinal / transverse axis shared by
the joint's bolt holes; with ``gravity`` or ``rail-inertia``, ``body_x`` and ``body_y``
(1 N/m^3); with ``rail-inertia`` on a rail, ``body_rot`` and ``body_rad`` (the rigid
rotation's tangential and centripetal fields about the rail's pivot). Each load source of
the part (a joint it can sit at) gives a coefficient history (steps, cases). The check and
the sweep share these functions, so a sweep's setting equals a check of it.
"""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np

from railcheck.check.kinematics_stage import KinematicsResult
from railcheck.fea.unitcases import BodyCase, TractionCase
from railcheck.loads.histories import bolt_history, gravity_history, rail_inertia_history
from railcheck.parts import BAR_INDEX, PARTS, LoadSource
from railcheck.scene import ExplicitLoad, Scene

GRAVITY = 9.80665  # m/s^2
PIVOT_JOINT = {"crank": "O2", "coupler": "A", "rocker": "O4"}


@dataclass(frozen=True)
class LoadModel:
    """How one part is loaded: its ``sources`` (the joints it can sit at), the load
    ``factor`` on reactions, whether ``gravity`` and the rail's own d'Alembert inertia
    (``rail_inertia``) are applied, the ``explicit`` per-hole load that replaces the
    linkage (or None), the ``bar`` whose axes and motion a rail follows, and the
    material ``density`` (kg/m^3) of the body forces."""

    part: str
    bar: str | None
    sources: tuple[LoadSource, ...]
    factor: float
    gravity: bool
    rail_inertia: bool
    explicit: ExplicitLoad | None
    density: float


@dataclass(frozen=True)
class SourceHistory:
    """A load source's coefficient history ``C`` (steps, cases) over ``crank_angle``
    (steps,) rad; ``seed_step`` the instant of its reaction's peak magnitude."""

    joint: str
    C: np.ndarray
    crank_angle: np.ndarray
    seed_step: int


def load_model(scene: Scene, name: str, density: float) -> LoadModel:
    """The part's :class:`LoadModel` from the scene's [check] (density kg/m^3)."""
    effects, explicit = scene.check.effects, scene.check.loads.get(name)
    bar = PARTS[name].bar
    return LoadModel(
        part=name,
        bar=bar,
        sources=PARTS[name].sources,
        factor=scene.check.factor,
        gravity="gravity" in effects,
        rail_inertia="rail-inertia" in effects and bar is not None and explicit is None,
        explicit=explicit,
        density=density,
    )


def unit_cases(model: LoadModel, geo, holes: list[str]) -> dict:
    """The part's unit load cases, named (see the module doc)."""
    cases = {"bolt_x": TractionCase(tuple(holes), 0), "bolt_y": TractionCase(tuple(holes), 1)}
    if model.gravity or model.rail_inertia:
        cases.update(body_x=BodyCase("uniform", 0), body_y=BodyCase("uniform", 1))
    if model.rail_inertia:
        pivot = (float(geo.get("hole_x")[0]), 0.0)
        cases.update(body_rot=BodyCase("rotational", pivot=pivot), body_rad=BodyCase("radial", pivot=pivot))
    return cases


def source_coefficients(
    model: LoadModel, src: LoadSource, reactions: dict, angles: dict, accelerations: dict, omega: dict, alpha: dict
) -> np.ndarray:
    """(..., k): one load source's coefficients in the order of :func:`unit_cases`, for
    arrays with any leading dimensions (one setting's steps, or settings x steps):
    ``reactions`` and ``accelerations`` joint -> (..., 2) ground frame (N, m/s^2);
    ``angles``, ``omega``, ``alpha`` bar -> (...) (rad, rad/s, rad/s^2)."""
    force = src.sign * reactions[src.joint]
    angle = angles[src.axes_bar] if src.axes_bar else np.zeros(force.shape[:-1])
    cols = [bolt_history(force, angle, model.factor)]
    if model.gravity or model.rail_inertia:
        cols.append(gravity_history(angle, model.density, GRAVITY) if model.gravity else np.zeros(force.shape))
    if model.rail_inertia:
        bar = model.bar
        rigid = rail_inertia_history(accelerations[PIVOT_JOINT[bar]], angle, omega[bar], alpha[bar], model.density)
        cols[-1] = cols[-1] + rigid[..., :2]
        cols.append(rigid[..., 2:])
    return np.concatenate(cols, axis=-1)


def source_histories(model: LoadModel, kin: KinematicsResult | None, holes: list[str]) -> tuple[SourceHistory, ...]:
    """The coefficient history of every load source of the part, columns in the order
    of :func:`unit_cases` (``kin`` may be None for explicit loads)."""
    if model.explicit is not None:
        load = model.explicit
        c = [len(holes) * load.longitudinal, len(holes) * load.transverse]
        if model.gravity:
            c += list(gravity_history(np.zeros(1), model.density, GRAVITY)[0])
        return (SourceHistory("explicit", np.array([c]), np.zeros(1), 0),)
    dyn, motion = kin.dynamics, kin.motion
    by_bar = lambda a: {bar: a[:, i] for bar, i in BAR_INDEX.items()}  # noqa: E731
    out = []
    for src in model.sources:
        if src.joint not in dyn.reactions:
            continue
        C = source_coefficients(
            model, src, dyn.reactions, by_bar(motion.theta), motion.accelerations, by_bar(motion.omega), by_bar(motion.alpha)
        )
        force = dyn.reactions[src.joint]
        out.append(SourceHistory(src.joint, C, motion.theta2, int(np.argmax(np.hypot(force[:, 0], force[:, 1])))))
    return tuple(out)
