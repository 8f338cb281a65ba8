"""Work refused before it starts: a part whose stress recovery certainly cannot fit in this
run's memory is refused before any part is meshed, from its geometry, its mesh sizes and
the unit cases its solve will carry (the exact count after meshing remains the last word:
:func:`railcheck.fea.unitcases.refuse_fields_beyond_memory`). SI; bytes."""

from __future__ import annotations

from railcheck.base import machine
from railcheck.base.errors import InputError
from railcheck.fea.holebasis import hole_basis
from railcheck.fea.unitcases import stress_recovery_bytes
from railcheck.geometry.mesher import estimate_elements
from railcheck.model.jobs import PartJob
from railcheck.model.loading import unit_cases
from railcheck.model.setting_free import uses_hole_basis


def solved_columns(job: PartJob) -> int:
    """The unit cases the part's solve carries: a free rail's hole basis (a case per hole
    of the rail, any setting's projected from them), else its own cases."""
    cases = unit_cases(job.loads, job.geometry, list(job.holes))
    if uses_hole_basis(job):
        holes = [f"hole_{k}" for k in range(len(job.geometry.get("hole_x")))]
        try:
            return len(hole_basis(cases, holes).cases)
        except ValueError:  # a case the basis does not hold: solved as it is
            pass
    return len(cases)


#: how far below the estimate the stress recovery may really need (the element estimate
#: is within about 30%): refused before meshing only when even this share is too much;
#: nearer the line, the exact count after meshing decides
#: (:func:`fea.unitcases.refuse_fields_beyond_memory`)
RECOVERY_ESTIMATE_LOW = 0.6

#: P2 (P1) nodes per tetrahedron of the shipped meshes (the crank rail: 41,114 / 21,698)
NODES_PER_ELEMENT = {1: 0.25, 2: 1.9}


def refuse_recovery_before_meshing(jobs: dict) -> None:
    """Refuse, before any part is meshed, a part whose stress recovery certainly cannot
    fit in this run's memory (``mesh.size``, one line): its elements estimated from its
    geometry and sizes (:func:`geometry.mesher.estimate_elements`), its unit cases counted
    from its loads; the 0.5 mm grooves under a 6 GB limit were refused after 70 s of
    meshing, now at once."""
    avail = machine.available_memory()
    for name, job in jobs.items():
        elements = estimate_elements(job.geometry, job.mesh.size, job.mesh.hole_size)
        columns = solved_columns(job)
        per_element = 10 if job.mesh.order == 2 else 4
        need = stress_recovery_bytes(elements, per_element, int(NODES_PER_ELEMENT[job.mesh.order] * elements), columns)
        if RECOVERY_ESTIMATE_LOW * need > machine.MEMORY_FRACTION * avail:
            raise InputError(
                "mesh.size",
                f"{name}: recovering the stresses of about {elements:,} elements (estimated before meshing) for "
                f"{columns} unit cases needs at least {machine.short(RECOVERY_ESTIMATE_LOW * need / 2**30)} GiB, more "
                f"than this run may use ({machine.usable_words(avail)}): use a larger mesh size or hole_size",
            )
