"""Inertia relief: a free body in dynamic equilibrium, with no support.

A bar of the linkage carries its joint forces and its own d'Alembert and gravity body
forces; together they balance (Newton-Euler), so no support is needed. Numerically the
stiffness matrix of an unsupported part is singular (six rigid-body modes), so, as the
inertia relief of Nastran (SOL 101, PARAM,INREL) and Abaqus (``*INERTIA RELIEF``) do:

1. the residual imbalance of the load ``f`` (what the joint forces and body forces leave
   unbalanced: rounding, or a mass model that differs from the dynamics') is removed as a
   rigid-body acceleration, ``f_r = f - M Phi (Phi^T M Phi)^-1 Phi^T f``, with ``Phi`` the
   six rigid-body modes and ``M`` the consistent mass matrix (``M Phi`` is the load vector
   of the rigid acceleration fields times the density, :func:`rigid_mass_loads`);
2. ``K u = f_r`` is solved holding a statically determinate 3-2-1 set of DOFs
   (:func:`three_two_one`), whose reactions are then zero to solver precision because
   ``f_r`` is balanced;
3. the rigid-body part of ``u`` is removed (:func:`without_rigid_motion`), so the
   displacement is the elastic deformation alone.

Every step is linear, so a combination of relieved unit cases is the relieved
combination: superposition, the envelope and fatigue are unchanged. Units SI.
"""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np

from .loading import body_force_vector, surface_dofs, traction_vector
from .mesh import cached_on, dof_components
from .system import solve

__all__ = [
    "FreeBodySolve",
    "foundation_reaction",
    "RigidModes",
    "imbalance",
    "relieve",
    "rigid_modes",
    "solve_free_body",
    "three_two_one",
    "without_rigid_motion",
]


@dataclass(frozen=True)
class RigidModes:
    """The six rigid-body modes of a part's vector basis: ``Phi`` (N, 6) (translations x,
    y, z in m per m, rotations about x, y, z through ``centre`` in m per rad), ``MPhi``
    (N, 6) the mass matrix times them (the load vectors, N, of the unit rigid accelerations
    of a body of ``density`` kg/m^3), ``centre`` (3,) m."""

    Phi: np.ndarray
    MPhi: np.ndarray
    centre: np.ndarray

    @property
    def mass_matrix(self) -> np.ndarray:
        """(6, 6) Phi^T M Phi: the part's mass (kg), first moments and inertia (kg m^2)."""
        return self.Phi.T @ self.MPhi


def _mode_fields(centre: np.ndarray):
    """The six rigid displacement fields x -> (3, ...) about ``centre``."""
    c = centre

    def translation(k):
        return lambda x: np.stack([np.full(np.shape(x[0]), float(k == i)) for i in range(3)])

    def rotation(axis):
        def field(x):
            r = [x[i] - c[i] for i in range(3)]
            zero = 0.0 * r[0]
            # omega e_axis x r
            return {
                0: np.stack([zero, -r[2], r[1]]),
                1: np.stack([r[2], zero, -r[0]]),
                2: np.stack([-r[1], r[0], zero]),
            }[axis]

        return field

    return [translation(0), translation(1), translation(2), rotation(0), rotation(1), rotation(2)]


def rigid_modes(basis, density: float) -> RigidModes:
    """The :class:`RigidModes` of ``basis`` for a body of ``density`` (kg/m^3), rotations
    about the centroid of the DOF locations. The modes and their unit-density mass
    products are integrated once per basis (read-only, shared by every call)."""
    unit = cached_on(basis, "rigid_modes", lambda: _unit_density_modes(basis))
    return RigidModes(Phi=unit.Phi, MPhi=density * unit.MPhi, centre=unit.centre)


def _unit_density_modes(basis) -> RigidModes:
    """:func:`rigid_modes` at a density of 1 kg/m^3, its arrays read-only."""
    locs = basis.doflocs
    centre = locs.mean(axis=1)
    fields = _mode_fields(centre)
    comp = dof_components(basis)
    Phi = np.stack([f(locs)[comp, np.arange(basis.N)] for f in fields], axis=1)
    MPhi = body_force_vector(basis, fields)
    for a in (Phi, MPhi, centre):
        a.flags.writeable = False
    return RigidModes(Phi=Phi, MPhi=MPhi, centre=centre)


def imbalance(modes: RigidModes, F: np.ndarray) -> np.ndarray:
    """(6[, k]): the resultant force (N) and moment about the modes' centre (N m) of the
    load vectors ``F`` (N[, k]); zero for a body in equilibrium."""
    return modes.Phi.T @ F


def relieve(modes: RigidModes, F: np.ndarray) -> np.ndarray:
    """``F - M Phi (Phi^T M Phi)^-1 Phi^T F``: the loads with their imbalance removed as a
    rigid-body acceleration (the d'Alembert force of the acceleration that the imbalance
    would give the free body); balanced to rounding."""
    acceleration = np.linalg.solve(modes.mass_matrix, imbalance(modes, F))
    return F - modes.MPhi @ acceleration


def foundation_reaction(basis, groups: dict, group: str, F: np.ndarray) -> np.ndarray:
    """(N[, k]): the reaction of a rigid foundation the part is bolted down to by the face
    ``group``, balancing the loads ``F`` (N[, k]): a traction linear in position,
    t(x) = a + w x (x - c) (c the face's area centroid: the bolted-flange idealisation of
    a rigid base, pressure and shear varying linearly over the face), its six
    coefficients set so that force and moment vanish, integrated exactly on the face."""
    T = cached_on(basis, f"foundation_tractions:{group}", lambda: _face_tractions(basis, groups, group))
    modes = rigid_modes(basis, 1.0)
    coefficients = np.linalg.solve(imbalance(modes, T), -imbalance(modes, F))
    return T @ coefficients


def _face_tractions(basis, groups: dict, group: str) -> np.ndarray:
    """(N, 6) the load vectors of the face ``group``'s six linear tractions (uniform x, y,
    z; turning about x, y, z through the face's area centroid), read-only: a part's unit
    cases share them (:func:`foundation_reaction`)."""
    face = surface_dofs(basis, groups, group)
    c = face.weights @ face.points / face.weights.sum()
    units = np.eye(3)

    def uniform(k):
        return lambda x: np.broadcast_to(units[k].reshape((3,) + (1,) * (x.ndim - 1)), x.shape) + 0.0 * x

    def turning(k):
        return lambda x: np.cross(units[k], x - c.reshape((3,) + (1,) * (x.ndim - 1)), axis=0)

    T = traction_vector(basis, groups, group, [uniform(k) for k in range(3)] + [turning(k) for k in range(3)])
    T.flags.writeable = False
    return T


def three_two_one(basis) -> np.ndarray:
    """Six DOFs that hold a free body statically determinately (3-2-1): every component at
    the node nearest one end of the part's longest extent, the two components across that
    extent at the node farthest from it, and the third component at the node farthest
    from the line between them."""
    locs = basis.doflocs.T
    comp = dof_components(basis)
    extent = np.ptp(locs, axis=0)
    a = int(np.argmax(extent))
    first = np.argmin(locs[:, a])
    p1 = locs[first]
    far = np.argmax(np.linalg.norm(locs - p1, axis=1))
    p2 = locs[far]
    line = (p2 - p1) / np.linalg.norm(p2 - p1)
    offset = (locs - p1) - np.outer((locs - p1) @ line, line)
    third = np.argmax(np.linalg.norm(offset, axis=1))
    b = int(np.argmax(np.abs(offset[third])))
    c = 3 - a - b if a != b else (a + 1) % 3

    def dof_at(point, component):
        same = np.flatnonzero(np.all(np.isclose(locs, point, rtol=0, atol=1e-12), axis=1) & (comp == component))
        return int(same[0])

    held = [dof_at(p1, i) for i in range(3)] + [dof_at(p2, i) for i in range(3) if i != a] + [dof_at(locs[third], c)]
    return np.array(sorted(held))


def without_rigid_motion(modes: RigidModes, U: np.ndarray) -> np.ndarray:
    """``U`` (N[, k]) less its rigid-body part (the mass-weighted projection on the modes):
    the elastic deformation, mass-orthogonal to every rigid motion."""
    return U - modes.Phi @ np.linalg.solve(modes.mass_matrix, modes.MPhi.T @ U)


@dataclass(frozen=True)
class FreeBodySolve:
    """A free body's solve: ``U`` (N[, k]) m the elastic displacement (rigid part
    removed), ``imbalance`` (6[, k]) the loads' resultant force (N) and moment (N m) before
    relief, ``reactions`` (6[, k]) N what the 3-2-1 DOFs carry after relief (zero to
    solver precision), ``modes`` and the solver's ``info``."""

    U: np.ndarray
    imbalance: np.ndarray
    reactions: np.ndarray
    modes: RigidModes
    info: dict


def solve_free_body(K, F: np.ndarray, basis, density: float, method="auto", report=None) -> FreeBodySolve:
    """Solve an unsupported part under loads ``F`` (N[, k]) by inertia relief (module doc);
    ``density`` kg/m^3 the mass the imbalance accelerates."""
    modes = rigid_modes(basis, density)
    relieved = relieve(modes, F)
    held = three_two_one(basis)
    U, info = solve(K, relieved, held, method, basis, report=report)
    reactions = (K @ U - relieved)[held]
    return FreeBodySolve(
        U=without_rigid_motion(modes, U), imbalance=imbalance(modes, F), reactions=reactions, modes=modes, info=info
    )
