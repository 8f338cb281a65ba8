"""The forces a checked part carries at its governing instant, in its own axes (x along it,
y across it in the mechanism's plane): one place for the picture's arrows and the report's
load table. Every force as the FE applied it: factored by the scene's load factor, or as
given for explicit ``[loads]`` (:func:`applied_factor`). SI (N, N m)."""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np


@dataclass(frozen=True)
class PartForce:
    """One load on a part: its ``name``, the mesh ``holes`` it acts on, the ``force`` (3,)
    N (factored, the part's frame) or, for the motor couple, ``couple`` N m."""

    name: str
    holes: tuple[str, ...]
    force: np.ndarray
    couple: float | None = None


def governing_forces(part) -> list[PartForce]:
    """The loads on ``part`` at its governing instant: the far joint's bolts, a plate's
    seat, a free rail's first joint on its upper plate's two screws (its first two holes)
    and, on the crank, the motor couple over the same two screws (the second screw's share
    ``+T / pitch`` across the rail, and the couple itself)."""
    cycle = part.cycle
    c, names = cycle.C[cycle.envelope.step], list(cycle.fields.names)
    bolts = tuple(b.group for b in part.load_case.bolts)
    plural = f" ({len(bolts)} screws)" if len(bolts) > 1 else ""
    out = [PartForce(f"joint force at the screws{plural}", bolts, _xy(c, names, "bolt"))]
    if "seat_x" in names:
        out.append(PartForce("joint force on the shaft's bore", ("bearing_seat",), _xy(c, names, "seat")))
    if "pin_x" in names:
        near = ("hole_0", "hole_1")
        out.append(PartForce("first joint's force on its plate's two screws", near, _xy(c, names, "pin")))
    if "torque" in names:  # the motor couple: +T / pitch on the second screw, -T / pitch on the first
        xs = part.geometry.get("hole_x")
        torque = float(c[names.index("torque")])
        second = np.array([0.0, torque / float(xs[1] - xs[0]), 0.0])
        out.append(PartForce("motor couple on the two screws (the second's share)", ("hole_1",), second, torque))
    return out


def applied_factor(part) -> float:
    """The factor the FE applied to the part's joint loads: the scene's load factor, or 1
    for explicit ``[loads]`` (applied as given)."""
    return 1.0 if part.job.loads.explicit is not None else float(part.job.loads.factor)


def newtons(force: np.ndarray) -> str:
    """A force's magnitude for people: whole newtons from 100 N, three figures below."""
    size = float(np.linalg.norm(force))
    return f"{size:.0f} N" if size >= 100 else f"{size:.3g} N"


def _xy(c: np.ndarray, names: list, case: str) -> np.ndarray:
    return np.array([c[names.index(f"{case}_x")], c[names.index(f"{case}_y")], 0.0])


def support_words(part) -> str:
    """How the part is held in its FE model, in the words its picture and the report's
    equilibrium table share: on its rigid foundation, a free body, or the 2013 clamp."""
    if part.job.loads.is_on_foundation:
        return "rigid foundation"
    if part.job.free_body is not None:
        return "free body (inertia relief)"
    return "2013 clamp (black; magenta: singular)"
