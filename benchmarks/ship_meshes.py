"""Build the meshes railcheck ships (``geometry/meshes/``): every registry part at its
default mesh sizes, meshed afresh and stored compressed with a content hash, keyed like the
mesh cache but without the installed gmsh's version. A maintainer's step, rerun whenever
the mesher, a part's geometry or a default size changes (then bump ``SHIPPED_SET``); the tests
check that each default part has its shipped mesh and that it is the mesh gmsh builds.

    python benchmarks/ship_meshes.py
"""

from __future__ import annotations

import time

from railcheck.geometry.mesher import SHIPPED_DIR, shipped_entry, write_shipped_mesh
from railcheck.model.jobs import mesh_sizes
from railcheck.parts import PARTS, geometry_of
from railcheck.scene import load_scene


def main() -> None:
    mesh = load_scene(None).mesh
    for old in SHIPPED_DIR.glob("*.npz"):
        old.unlink()
    written = set()
    for name in PARTS:
        part = geometry_of(name, {})
        size, hole = mesh_sizes(mesh, part.kind)
        if shipped_entry(part, size, hole, mesh.optimize)[0] in written:  # the coupler's and rocker's rail: one mesh
            continue
        t = time.perf_counter()
        path = write_shipped_mesh(part, size, hole, mesh.optimize)
        written.add(path)
        print(f"{name}: {path.name} ({path.stat().st_size / 1e6:.2f} MB, {time.perf_counter() - t:.1f} s)")


if __name__ == "__main__":
    main()
