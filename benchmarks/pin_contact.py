"""How a pin's force is spread over its hole: the linear model against frictionless contact.

railcheck applies a joint's force on a hole as a uniform traction over the hole's bore (the
force / the bore's area, in the force's direction, on the whole cylinder: it pushes on the
loaded half and pulls on the other). A real pin only pushes: frictionless contact over
the part of the bore it bears on, pressure about a cosine of the angle from the force.
This compares, on a 200 mm size-25 rail clamped at its far end and a rigid pin of the
hole's diameter (zero clearance) in its first hole:

* ``uniform``: railcheck's model;
* ``cosine``: a radial pressure p0 cos(phi) over the loaded half (phi from the force's
  direction), p0 set so the resultant is the force;
* ``contact``: frictionless contact by penalty with an active set, the pin a rigid body
  whose in-plane translation is an unknown loaded by the force.

Reported: the peak von Mises near the hole (x < 100 mm, away from the clamp), per model
and direction (the axial pull toward the rail's end and the transverse push), and the
ratios to contact. Run by hand:

    python benchmarks/pin_contact.py [--size-hole MM] [--penalty FACTOR]
"""

from __future__ import annotations

import argparse

import numpy as np
import scipy.sparse as sp

from railcheck.fea import (
    MATERIALS,
    assemble,
    factorise,
    free_submatrix,
    peak,
    recover_stress,
    stress_nodes,
    supports,
    unit_traction_vectors,
    von_mises,
)
from railcheck.fea.loading import surface_node_weights, traction_vector
from railcheck.fea.mesh import scalar_basis, vector_dof_map
from railcheck.geometry import mesh_part, rail

STEEL = MATERIALS["steel"]
FORCE = 1000.0  # N


def bore(basis, mesh, centre):
    """The bore's scalar nodes: their x, y DOFs (n, 2), weights m^2, unit radial normals (n, 2)."""
    nodes, weights = surface_node_weights(basis, mesh.groups, "hole_0")
    sb = scalar_basis(basis)
    xy = sb.doflocs[:2, nodes].T - centre
    normals = xy / np.linalg.norm(xy, axis=1, keepdims=True)
    return vector_dof_map(basis, sb)[nodes][:, :2], weights, normals


def solve_contact(K, basis, mesh, fixed, direction, penalty, centre, iterations=30):
    """U (N,) with a rigid pin pushed by FORCE along ``direction`` (unit, in-plane), by a
    penalty (N/m^3) on the bore's nodes that penetrate the pin; active set iterated."""
    dofs, weights, normals = bore(basis, mesh, centre)
    N = K.shape[0]
    free = np.setdiff1d(np.arange(N), fixed)
    index = -np.ones(N + 2, dtype=np.int64)
    index[free] = np.arange(free.size)
    index[N:] = free.size + np.arange(2)
    active = normals @ direction < 0  # where the pin pushes: the bore's side opposite to its motion
    for _ in range(iterations):
        rows, cols, vals = [], [], []
        for i in np.flatnonzero(active):
            g = np.concatenate([normals[i], -normals[i]])  # gap = (u_i - delta) . n_i
            ids = np.concatenate([dofs[i], [N, N + 1]])
            k = penalty * weights[i]
            rows.append(np.repeat(ids, 4))
            cols.append(np.tile(ids, 4))
            vals.append(k * np.outer(g, g).ravel())
        Kc = sp.coo_matrix((np.concatenate(vals), (np.concatenate(rows), np.concatenate(cols))), shape=(N + 2, N + 2))
        A = sp.bmat([[K, None], [None, sp.csr_matrix((2, 2))]]).tocsr() + Kc.tocsr()
        keep = np.concatenate([free, [N, N + 1]])
        Ar = free_submatrix(A, keep)
        b = np.zeros(keep.size)
        b[-2:] = FORCE * direction  # the force on the pin
        x = factorise(Ar, "direct").solve(b)
        U = np.zeros(N)
        U[free] = x[:-2]
        delta = x[-2:]
        gap = np.einsum("nc,nc->n", U[dofs] - delta, normals)
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
    args = parser.parse_args()
    geo = rail(0.2)
    mesh = mesh_part(geo, 4e-3, args.size_hole * 1e-3)
    K, basis = assemble(mesh.points, mesh.tets, STEEL, 2, mesh.curved)
    fixed = supports(basis, mesh.groups, ["end_free"])
    Kr_free = np.setdiff1d(np.arange(K.shape[0]), fixed)
    factor = factorise(free_submatrix(K, Kr_free), "direct")
    centre = np.array([geo.get("hole_x")[0], 0.0])
    r = geo.get("hole_diameter") / 2
    penalty = args.penalty * STEEL.youngs_modulus / r
    print(f"rail 200 mm, P2, size 4 mm, {args.size_hole} mm at the holes: {basis.N} DOFs; penalty {args.penalty:g} E/r")
    bore_top = geo.get("height") - geo.get("counterbore_depth")
    print("peak von Mises within 3 r of the hole (in brackets: over the bore's middle, 2 mm from its ends)")
    print(f"{'pin force':<24}{'uniform':>22}{'cosine':>22}{'contact':>22}{'uniform/contact':>20}{'cosine/contact':>20}")
    for label, direction in (("axial, toward the end", np.array([-1.0, 0.0])), ("transverse", np.array([0.0, 1.0]))):

        def solved(F):
            U = np.zeros(K.shape[0])
            U[Kr_free] = factor.solve(F[Kr_free])
            return U

        uniform = solved(unit_traction_vectors(basis, mesh.groups, "hole_0")[:, :2] @ (FORCE * direction))
        d3 = np.array([*direction, 0.0])

        def cosine(x, d=d3):
            radial = np.stack([x[0] - centre[0], x[1] - centre[1], 0 * x[2]])
            radial = radial / np.linalg.norm(radial[:2], axis=0)
            c = -(radial[0] * d[0] + radial[1] * d[1])  # cos of the angle from the loaded side
            return np.maximum(c, 0.0) * radial  # pressure pushes the material outward

        F_cos = traction_vector(basis, mesh.groups, "hole_0", cosine)
        total = np.array([F_cos[vector_dof_map(basis, scalar_basis(basis))[:, c]].sum() for c in range(2)])
        F_cos *= FORCE / np.linalg.norm(total)
        cos_u = solved(F_cos)
        contact, n_active, n = solve_contact(K, basis, mesh, fixed, direction, penalty, centre)
        values = [peak_near_hole(basis, U, centre, r, bore_top) for U in (uniform, cos_u, contact)]
        cells = "".join(f"{a / 1e6:>9.2f} ({b / 1e6:5.2f}) MPa" for a, b in values)
        ratios = "".join(f"{values[k][0] / values[2][0]:>11.3f} ({values[k][1] / values[2][1]:.3f})" for k in (0, 1))
        print(f"{label:<24}{cells}{ratios}   {n_active}/{n} bore nodes in contact")


if __name__ == "__main__":
    main()
