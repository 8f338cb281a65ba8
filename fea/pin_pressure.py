"""Bearing on a hole: how a pin or bolt pushes on its bore, as radial pressures.

A pin only pushes, and frictionless contact carries no shear: the pressure is radial and
lies on the half of the bore the force points to. The model (a cosine over the loaded
half, the classic pin-loaded-lug idealisation; docs/model.md "Free bodies", Shenoy & Fatemi's connecting
rods) is

    p(phi) = p0 max(0, cos(phi - theta)),      p0 = 2 F / R,   R = integral of cos^2 phi dA

for a force F at angle theta in the part's x-y plane (phi the angle of a point of the bore
about the hole's axis; R = pi r t on a bore of radius r and length t). Its Fourier series

    max(0, cos psi) = a_0 + a_1 cos psi + sum over even k of a_k cos k psi

(:func:`half_cosine_coefficient`) splits it into fields that do not depend on the force:
radial pressures ``cos k phi`` and ``sin k phi`` over the whole bore, with coefficients
``F a_k cos k theta`` and ``F a_k sin k theta`` (:mod:`railcheck.loads.pin_pressure`). The
k = 1 pair carries the whole force (it replaces the uniform traction); k = 0 and the even
harmonics are self-equilibrated (their resultant is projected out exactly). So the load
stays a fixed combination of unit fields, with coefficients that are nonlinear in the
joint force but known at every step: superposition, the envelope and fatigue are unchanged.

Every nodal force is radial through the hole's axis (the consistent integral of the
pressure times the shape function, along the node's radial direction), so the pressures
have no moment about the axis. Units SI; the axis and the angle are in the part frame.
"""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np

from .errors import ModelError
from .loading import surface_node_integrals
from .mesh import scalar_basis, vector_dof_map

__all__ = ["Bore", "bore_of", "bearing_vectors", "harmonic_names"]


@dataclass(frozen=True)
class Bore:
    """A hole's bore on the mesh: its scalar ``nodes``, their ``weights`` m^2 (integral of
    each shape function over the bore), ``points`` (n, 3) m, the axis ``centre`` (2,) m
    (through the circle of its vertices) and each node's ``angle`` (n,) rad about it."""

    nodes: np.ndarray
    weights: np.ndarray
    points: np.ndarray
    centre: np.ndarray
    angle: np.ndarray


def bore_of(basis, groups: dict, group: str) -> Bore:
    """The :class:`Bore` of a hole group (a cylindrical surface about an axis along z)."""
    nodes, w = surface_node_integrals(basis, groups, group)
    points = scalar_basis(basis).doflocs.T[nodes]
    weights = w[:, 0]
    centre = circle_centre(points[nodes < basis.mesh.nvertices, :2])
    d = points[:, :2] - centre
    radius = np.hypot(d[:, 0], d[:, 1])
    if radius.min() < 0.2 * radius.max():  # a coarse mesh makes a polygon of the bore; a face is no bore
        raise ModelError(  # the scene's field that makes the bore: the mesh at the holes
            "mesh.hole_size",
            f"the mesh makes a polygon of {group}'s bore (a node {radius.min() * 1e3:.2f} mm from its axis, "
            f"radius {radius.max() * 1e3:.2f} mm): the pins cannot bear on it; use a smaller hole_size",
        )
    return Bore(nodes, weights, points, centre, np.arctan2(d[:, 1], d[:, 0]))


def circle_centre(xy: np.ndarray) -> np.ndarray:
    """(2,) the centre of the circle through points ``xy`` (n, 2) (algebraic least squares,
    exact when they lie on one): a bore's vertices lie on its circle however coarse the
    mesh, its area centroid does not."""
    A = np.column_stack([2 * xy, np.ones(len(xy))])
    solution, *_ = np.linalg.lstsq(A, (xy**2).sum(axis=1), rcond=None)
    return solution[:2]


def harmonic_names(harmonics: tuple[int, ...]) -> tuple[str, ...]:
    """The names of the self-equilibrated fields of ``harmonics`` (k = 0 has one, ``"0"``;
    k >= 2 two, ``"2c"``, ``"2s"``), in the order :func:`bearing_vectors` gives them."""
    return tuple(n for k in harmonics for n in ((f"{k}",) if k == 0 else (f"{k}c", f"{k}s")))


def bearing_vectors(basis, groups: dict, group: str, harmonics: tuple[int, ...]) -> np.ndarray:
    """(N, 2 + m) load vectors on ``group``'s bore: a unit force (1 N) along x and along y
    as the k = 1 radial pressure (``cos phi``, ``sin phi`` combined so that each resultant
    is exactly 1 N along its axis), then the self-equilibrated radial pressures ``(2 / R)
    cos k phi`` and ``(2 / R) sin k phi`` of ``harmonics`` (k = 0 or even k >= 2; names in
    :func:`harmonic_names`), each with its resultant removed exactly (module doc)."""
    if any(k == 1 or k < 0 for k in harmonics):
        raise ValueError("harmonics are k = 0 or k >= 2 (k = 1 carries the force)")
    shapes = [(1, np.cos), (1, np.sin)] + [(k, f) for k in harmonics for f in ((np.cos,) if k == 0 else (np.cos, np.sin))]
    b = bore_of(basis, groups, group)
    c = b.centre

    def at(k, f):
        return lambda x: f(k * np.arctan2(x[..., 1] - c[1], x[..., 0] - c[0]))

    _, integrals = surface_node_integrals(basis, groups, group, [at(k, f) for k, f in shapes])
    radial = np.stack([np.cos(b.angle), np.sin(b.angle)], axis=1)  # (n, 2)
    forces = integrals[:, 1:, None] * radial[:, None, :]  # (n, fields, 2): nodal forces per unit pressure
    resultants = forces.sum(axis=0)  # (fields, 2)
    unit = np.linalg.solve(resultants[:2].T, np.eye(2))  # the cos, sin mix giving 1 N along x, along y
    R = resultants[0, 0]  # the integral of cos^2 phi over the bore, m^2
    force_fields = np.einsum("nfc,fg->ngc", forces[:, :2], unit)  # (n, 2, 2)
    harmonic = forces[:, 2:] * (2.0 / R)
    harmonic = harmonic - np.einsum("nfc,hf->nhc", force_fields, resultants[2:] * (2.0 / R))
    nodal = np.concatenate([force_fields, harmonic], axis=1)  # (n, 2 + m, 2)
    dofs = vector_dof_map(basis, scalar_basis(basis))[b.nodes]
    out = np.zeros((basis.N, nodal.shape[1]))
    out[dofs[:, 0]] = nodal[..., 0]
    out[dofs[:, 1]] = nodal[..., 1]
    return out
