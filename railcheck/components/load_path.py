"""Each joint's load path at one instant: the components in the order the joint force
passes them (docs/components.md), each checked on that instant alone by the same
functions as the verdict (:func:`railcheck.components.kinds.check_component` with
each step a one-step cycle), so a diagram's figures cannot drift from the table's.
SI.
"""

from __future__ import annotations

import dataclasses
from dataclasses import dataclass

import numpy as np

from railcheck.components.checks import ComponentResult, JointHistories, Strengths
from railcheck.components.kinds import check_component
from railcheck.components.ratings import COMPONENTS, ComponentSpec

#: each joint's path as the v2 joints build it: the rail the force comes from, the
#: components in order, and where it ends (a rail, or the ground frame). The next rail is
#: screwed to the upper plate, which turns on the shaft between two bearings in the lower
#: plate; at O2 the motor drives the shaft, its torque reaching the crank rail through the
#: upper plate's two screws; at A and B the lower plate sits on the previous rail's carriage
#: and is screwed to that rail
PATHS = {
    "O2": ("crank rail", ("crank-screws-O2", "shaft-O2", "bearings-O2"), "ground frame (the motor)"),
    "A": ("coupler rail", ("coupler-screws-A", "shaft-A", "bearings-A", "carriage-A", "crank-screws-A"), "crank rail"),
    "B": ("rocker rail", ("rocker-screws-B", "shaft-B", "bearings-B", "carriage-B", "coupler-screws-B"), "coupler rail"),
    "O4": ("rocker rail", ("rocker-screws-O4", "shaft-O4", "bearings-O4"), "ground frame"),
}


@dataclass(frozen=True)
class JointPath:
    """One joint's path at ``step`` (index into the cycle, crank angle ``crank_deg``):
    the joint force there (N, unfactored, ground frame: ``force_N`` its magnitude), the
    bar it comes from, where it ends, and each checked component's result on that
    instant alone (figures and utilisations at that step; a bearing's life as if that
    load were steady)."""

    joint: str
    step: int
    crank_deg: float
    force_N: float
    source: str
    sink: str
    components: dict


def each_step_alone(h: JointHistories) -> JointHistories:
    """The histories (T, ...) as T one-step cycles: the steps become a leading axis, so a
    check returns each step's utilisation on that instant alone (vectorised)."""
    return dataclasses.replace(
        h,
        reactions={j: np.asarray(r)[:, None, :] for j, r in h.reactions.items()},
        torque=np.asarray(h.torque)[:, None],
        angles={b: np.asarray(a)[:, None] for b, a in h.angles.items()},
        relative_speed={j: np.asarray(w)[:, None] for j, w in h.relative_speed.items()},
        projected={},
    )


def governing_step(names, spec: ComponentSpec, alone: JointHistories, factor: float, material: Strengths) -> int:
    """The step at which the most utilised of the components ``names`` (at one joint)
    peaks, from ``alone`` (:func:`each_step_alone`)."""
    u = np.max([check_component(COMPONENTS[n], spec, alone, factor, material).utilisation for n in names], axis=0)
    return int(np.argmax(u))


def joint_paths(checked, spec: ComponentSpec, h: JointHistories, factor: float, material: Strengths, crank) -> dict:
    """joint -> :class:`JointPath` of every joint with a checked component, each at the
    instant its most utilised component peaks; ``crank`` (T,) rad the crank's angle."""
    out, alone = {}, each_step_alone(h)
    for joint, (source, order, sink) in PATHS.items():
        names = [n for n in order if n in checked]
        if not names:
            continue
        k = governing_step(names, spec, alone, factor, material)
        results = {n: _at(check_component(COMPONENTS[n], spec, alone, factor, material), k) for n in names}
        force = float(np.hypot(*np.asarray(h.reactions[joint])[k]))
        out[joint] = JointPath(joint, k, float(np.degrees(crank[k])) % 360.0, force, source, sink, results)
    return out


def _at(r: ComponentResult, k: int) -> ComponentResult:
    """``r`` (arrays over the steps) at step ``k``, as floats."""

    def pick(v):
        a = np.asarray(v, float)
        return float(a if a.ndim == 0 else a[k])

    return dataclasses.replace(
        r, utilisations={n: pick(v) for n, v in r.utilisations.items()}, figures={n: pick(v) for n, v in r.figures.items()}
    )
