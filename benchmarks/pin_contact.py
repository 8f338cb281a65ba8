"""How a pin's force is spread over its hole: railcheck's models against frictionless contact.

A pin only pushes: frictionless contact over the part of the bore it bears on, pressure
radial. This compares, on a 200 mm size-25 rail clamped at its far end with a rigid pin
of the hole's diameter (zero clearance) in its first hole, 1000 N:

* ``uniform``: a uniform traction over the whole bore (the 2013 model, ``support =
  "clamped"``: it pushes on the loaded half and pulls on the other);
* ``pin pressure``: railcheck's free-body model, the cosine over the loaded half as the
  k = 1 radial pressure plus the harmonics :data:`railcheck.loads.pin_pressure.HARMONICS`
  (the unit fields and coefficients the check uses);
* ``cosine``: the exact radial pressure p0 max(0, cos(phi - theta)), p0 set so the
  resultant is the force;
* ``contact``: frictionless contact by penalty with an active set, the pin a rigid body
  loaded by the force alone: free to translate and to tilt (the joint's force, no couple).
  ``contact, no tilt``: the same pin held upright; it then also applies a couple about
  the rail's section axes (its pressure piles up toward one end of the bore), which the
  linkage's joint force does not contain: reported, not the reference.

Reported: the peak von Mises within three radii of the hole (in brackets: over the bore's
middle, 2 mm from its ends), per model and direction (the axial push toward the rail's
end, the axial push toward the clamp, the transverse push), and the ratios to contact.
Run by hand:

    python benchmarks/pin_contact.py [--size-hole MM] [--penalty FACTOR] [--harmonics 0,2]
"""

from __future__ import annotations

import argparse

import numpy as np
import scipy.sparse as sp

from railcheck.fea.assembly import assemble
from railcheck.fea.loading import surface_node_weights, traction_vector, unit_traction_vectors
from railcheck.fea.materials import MATERIALS
from railcheck.fea.mesh import scalar_basis, stress_nodes, vector_dof_map
from railcheck.fea.pin_pressure import bearing_vectors
from railcheck.fea.solvers import factorise
from railcheck.fea.stress import peak, recover_stress, von_mises
from railcheck.fea.system import free_submatrix, supports
from railcheck.geometry import mesh_part, rail
from railcheck.loads.pin_pressure import HARMONICS, harmonic_coefficients

STEEL = MATERIALS["steel"]
FORCE = 1000.0  # N


def bore(basis, mesh, centre):
    """The bore's scalar nodes: their x, y DOFs (n, 2), weights m^2, unit radial normals (n, 2)."""
    nodes, weights = surface_node_weights(basis, mesh.groups, "hole_0")
    sb = scalar_basis(basis)
    xy = sb.doflocs[:2, nodes].T - centre
    normals = xy / np.linalg.norm(xy, axis=1, keepdims=True)
    return vector_dof_map(basis, sb)[nodes][:, :2], weights, normals


def solve_contact(K, basis, mesh, fixed, direction, penalty, centre, mid_height, tilt=True, iterations=40):
    """U (N,) with a rigid pin pushed by FORCE along ``direction`` (unit, in-plane), by a
    penalty (N/m^3) on the bore's nodes that penetrate the pin; active set iterated. The
    pin's unknowns: its translation (x, y) and, with ``tilt``, its rotations about x and y
    through ``mid_height`` m (loaded by no moment)."""
    dofs, weights, normals = bore(basis, mesh, centre)
    nodes, _ = surface_node_weights(basis, mesh.groups, "hole_0")
    z = scalar_basis(basis).doflocs[2, nodes] - mid_height
    n_pin = 4 if tilt else 2
    N = K.shape[0]
    free = np.setdiff1d(np.arange(N), fixed)
    keep = np.concatenate([free, N + np.arange(n_pin)])
    # the pin's displacement along n_i at node i: [n_x, n_y, -n_y z, n_x z] . (dx, dy, rot_x, rot_y)
    G = np.stack([normals[:, 0], normals[:, 1], -normals[:, 1] * z, normals[:, 0] * z], axis=1)[:, :n_pin]
    active = normals @ direction > 0  # where the pin pushes: the bore's side it moves toward
    for _ in range(iterations):
        idx = np.flatnonzero(active)
        m = idx.size
        plate = sp.csr_matrix(
            (normals[idx].T.ravel(), (np.tile(np.arange(m), 2), dofs[idx].T.ravel())), shape=(m, N)
        )  # gap = u . n - G p
        B = sp.hstack([plate, sp.csr_matrix(-G[idx])]).tocsr()
        A = sp.bmat([[K, None], [None, sp.csr_matrix((n_pin, n_pin))]]).tocsr() + B.T @ sp.diags(penalty * weights[idx]) @ B
        b = np.zeros(keep.size)
        b[free.size : free.size + 2] = FORCE * direction  # the force on the pin
        x = factorise(free_submatrix(A, keep), "direct").solve(b)
        U = np.zeros(N)
        U[free] = x[: free.size]
        gap = np.einsum("nc,nc->n", U[dofs], normals) - G @ x[free.size :]
        now = gap < 0
        if np.array_equal(now, active):
            return U, int(active.sum()), len(active)
        active = now
    raise RuntimeError("the contact's active set did not settle")


def peak_near_hole(basis, U, centre, r, bore_top):
    """(peak von Mises within 3 r of the hole's axis, the same over the bore's middle
    (2 mm from its bottom and its top: away from where a rigid pin's contact ends), Pa)."""
    S = recover_stress(basis, U, STEEL)
    nodes = stress_nodes(basis)
    near = np.hypot(nodes[:, 0] - centre[0], nodes[:, 1] - centre[1]) < 3 * r
    middle = near & (nodes[:, 2] > 2e-3) & (nodes[:, 2] < bore_top - 2e-3)
    vm = von_mises(S)
    return peak(vm, nodes, near)[0], peak(vm, nodes, middle)[0]


def main() -> None:
    parser = argparse.ArgumentParser()
    parser.add_argument("--size-hole", type=float, default=0.6, help="mesh size at the holes, mm")
    parser.add_argument("--penalty", type=float, default=1e3, help="penalty as a multiple of E / hole radius")
    parser.add_argument(
        "--harmonics", default=",".join(map(str, HARMONICS)), help="the pin pressure's harmonics beyond k = 1 (0 and even k)"
    )
    args = parser.parse_args()
    harmonics = tuple(int(k) for k in args.harmonics.split(","))
    geo = rail(0.2)
    mesh = mesh_part(geo, 4e-3, args.size_hole * 1e-3)
    K, basis = assemble(mesh.points, mesh.tets, STEEL, 2, mesh.curved)
    fixed = supports(basis, mesh.groups, ["end_free"])
    Kr_free = np.setdiff1d(np.arange(K.shape[0]), fixed)
    factor = factorise(free_submatrix(K, Kr_free), "direct")
    centre = np.array([geo.get("hole_x")[0], 0.0])
    r = geo.get("hole_diameter") / 2
    penalty = args.penalty * STEEL.youngs_modulus / r
    bore_top = geo.get("height") - geo.get("counterbore_depth")
    print(f"rail 200 mm, P2, size 4 mm, {args.size_hole} mm at the holes: {basis.N} DOFs; penalty {args.penalty:g} E/r")
    print(f"pin pressure: k = 1 and the harmonics {harmonics} of the loaded-half cosine")
    print("peak von Mises within 3 r of the hole, MPa (in brackets: over the bore's middle, 2 mm from its ends)")
    models = ("uniform", "pin pressure", "cosine", "contact", "contact, no tilt")
    print(
        f"{'pin force':<22}" + "".join(f"{m:>18}" for m in models) + "   ratios to contact (uniform, pin pressure, cosine)"
    )
    pressure = bearing_vectors(basis, mesh.groups, "hole_0", harmonics)
    directions = (
        ("axial, toward the end", np.array([-1.0, 0.0])),
        ("axial, toward clamp", np.array([1.0, 0.0])),
        ("transverse", np.array([0.0, 1.0])),
    )
    for label, direction in directions:

        def solved(F):
            U = np.zeros(K.shape[0])
            U[Kr_free] = factor.solve(F[Kr_free])
            return U

        force = FORCE * direction
        uniform = solved(unit_traction_vectors(basis, mesh.groups, "hole_0")[:, :2] @ force)
        pin = solved(pressure @ np.concatenate([force, harmonic_coefficients(force, harmonics)]))
        d3 = np.array([*direction, 0.0])

        def cosine(x, d=d3):
            radial = np.stack([x[0] - centre[0], x[1] - centre[1], 0 * x[2]])
            radial = radial / np.linalg.norm(radial[:2], axis=0)
            c = radial[0] * d[0] + radial[1] * d[1]  # cos of the angle from the force
            return np.maximum(c, 0.0) * radial  # the pin pushes the bore's material outward

        F_cos = traction_vector(basis, mesh.groups, "hole_0", cosine)
        total = np.array([F_cos[vector_dof_map(basis, scalar_basis(basis))[:, c]].sum() for c in range(2)])
        F_cos *= FORCE / np.linalg.norm(total)
        cos_u = solved(F_cos)
        tilting, n_active, n = solve_contact(K, basis, mesh, fixed, direction, penalty, centre, bore_top / 2, tilt=True)
        upright, *_ = solve_contact(K, basis, mesh, fixed, direction, penalty, centre, bore_top / 2, tilt=False)
        values = [peak_near_hole(basis, U, centre, r, bore_top) for U in (uniform, pin, cos_u, tilting, upright)]
        cells = "".join(f"{a / 1e6:>10.2f} ({b / 1e6:5.2f})" for a, b in values)
        ratios = "  ".join(f"{values[k][0] / values[3][0]:.3f} ({values[k][1] / values[3][1]:.3f})" for k in (0, 1, 2))
        print(f"{label:<22}{cells}   {ratios}   {n_active}/{n} bore nodes in contact")


if __name__ == "__main__":
    main()
