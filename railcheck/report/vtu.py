"""A checked part's VTU file (ParaView): the governing instant's displacement, stress and
von Mises, the cycle's envelope, the fatigue factor, the support, loaded-hole and verdict
masks, and the lowest mode shapes. SI (m, Pa) as the VTU's arrays.
"""

from __future__ import annotations

from pathlib import Path

import numpy as np

from railcheck.fea.stress import von_mises
from railcheck.fea.superpose import node_envelope_of
from railcheck.fea.vtk import write_vtu
from railcheck.files import atomic_path
from railcheck.model.records import PartResult


def mode_shapes(p: PartResult) -> dict[str, np.ndarray]:
    """The lowest mode shapes (nodes, 3), mass-normalised, as VTU point data named with
    their frequency, when the part has a dynamic response."""
    d = p.cycle.dynamic
    if d is None:
        return {}
    k = p.cycle.load_C.shape[1]
    return {f"mode_{i + 1}_{hz:.1f}Hz": p.cycle.fields.displacement[:, :, k + i] for i, hz in enumerate(d.hz)}


def node_envelope(p: PartResult) -> np.ndarray:
    """(nodes,) Pa: each node's largest von Mises over the governing history (computed
    here: the check itself needs only the peaks)."""
    env = p.cycle.envelope
    return env.node_envelope if env.node_envelope is not None else node_envelope_of(p.cycle.fields, p.cycle.C)


def write_part_vtu(path: Path, p: PartResult) -> None:
    """The part's VTU on every node of its order: the governing instant's displacement,
    stress and von Mises, the cycle envelope, the fatigue factor, and 0/1 masks of the
    support, the loaded holes and the verdict zone (away from the support)."""
    f, s = p.cycle.fields, p.solution
    assert f.cells is not None and s.stress is not None and s.node_displacement is not None  # a checked part's
    assert p.cycle.fatigue.node_factor is not None  # node fields are kept when a VTU is written
    n = f.nodes.shape[0]
    none = np.zeros(0, dtype=np.int64)
    masks = {
        name: np.isin(np.arange(n), none if idx is None else idx).astype(float)
        for name, idx in (("support_surface", f.support), ("loaded_holes", f.loaded))
    }
    with atomic_path(path) as tmp:
        write_vtu(
            tmp,
            f.nodes,
            f.cells,
            s.node_displacement,
            von_mises(s.stress),
            {
                "stress": s.stress.T,
                "von_mises_envelope": node_envelope(p),
                "fatigue_safety_factor": p.cycle.fatigue.node_factor,
                "verdict_zone": f.verdict_mask.astype(float),
                **masks,
                **mode_shapes(p),
            },
        )
