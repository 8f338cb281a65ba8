"""Two cold runs of one scene give the same summary.json bytes (issue 61). gmsh's high-order
untangling left a grooved rail's nodes apart from run to run (its optimiser orders patches
and their elements by memory address, std::set<MElement*>); railcheck untangles the folded
elements itself, in a fixed order (railcheck.geometry.untangling), so a mesh built afresh is
the same bytes every run, whatever the process, its threads or its heap. The rig's parts at
their default sizes are also shipped meshed (geometry/meshes/): the three rails here."""

import os
import subprocess
import sys

import pytest

from helpers import FINAL_DESIGN


@pytest.mark.slow  # two cold checks of the three rails in their own processes, about 40 s
def test_two_cold_checks_write_the_same_summary_bytes(tmp_path):
    scene = tmp_path / "s.toml"
    rails = '["crank-rail", "coupler-rail", "rocker-rail"]'
    scene.write_text(
        FINAL_DESIGN + f"steps = 360\n[check]\nparts = {rails}\n[output]\nvtk = false\npng = false\nplots = false\n"
    )
    out = []
    for run in ("a", "b"):
        env = {**os.environ, "RAILCHECK_CACHE": str(tmp_path / f"cache-{run}")}
        proc = subprocess.run(
            [sys.executable, "-P", "-m", "railcheck.cli", "check", str(scene), "--out", str(tmp_path / run)],
            capture_output=True,
            text=True,
            env=env,
        )
        assert proc.returncode == 0, proc.stderr
        assert "(cached)" not in proc.stderr  # each from an empty cache, on the shipped meshes
        assert proc.stderr.count("(shipped with railcheck)") == 3
        out.append((tmp_path / run / "summary.json").read_bytes())
    assert out[0] == out[1]


_MESH_A_GROOVED_RAIL = """
import hashlib, sys
import numpy as np
from railcheck.geometry.mesher import build_mesh
from railcheck.geometry.models import rail
mesh = build_mesh(rail(float(sys.argv[1])), 0.02, 0.006)
assert mesh.curved_edges.shape[0] > 1000
digest = hashlib.sha256()
for a in (mesh.points, mesh.tets, mesh.curved_edges, mesh.curved_points):
    digest.update(np.ascontiguousarray(a).tobytes())
print(digest.hexdigest(), mesh.warning)
"""


@pytest.mark.slow  # a 240 mm grooved rail meshed in three processes, about 8 s
def test_a_grooved_rail_built_afresh_is_the_same_bytes_in_every_process():
    """A grooved rail no shipped mesh covers (240 mm), untangled, meshed in three fresh
    processes (another heap each, BLAS threads 1 or 2 in the last): the same bytes. Planted:
    gmsh's untangling back in (``Mesh.HighOrderOptimize``) fails this on longer rails."""

    def run(env_threads: str) -> str:
        env = {**os.environ, "OPENBLAS_NUM_THREADS": env_threads, "OMP_NUM_THREADS": env_threads}
        proc = subprocess.run(
            [sys.executable, "-P", "-c", _MESH_A_GROOVED_RAIL, "0.24"], capture_output=True, text=True, env=env
        )
        assert proc.returncode == 0, proc.stderr
        return proc.stdout

    first = run("1")
    assert first == run("1") == run("2")
