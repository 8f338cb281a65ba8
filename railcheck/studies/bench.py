"""`railcheck bench cantilever`: the FE core against Timoshenko beam theory (the CLI prints it)."""

from __future__ import annotations

from railcheck.base.errors import InputError
from railcheck.fea.cantilever import HEIGHT, LENGTH, LOAD, WIDTH, run_cantilever
from railcheck.geometry.models import bar
from railcheck.model.jobs import refuse_beyond_memory


def run_bench(order: int = 2, size_mm: float = 4.0, solver: str = "auto") -> dict:
    """The cantilever against Timoshenko beam theory: a JSON-ready dict (SI)."""

    if not (0.5 <= size_mm <= 50):
        raise InputError("--size", f"must be between 0.5 and 50 mm, got {size_mm:g}")
    refuse_beyond_memory(bar(LENGTH, WIDTH, HEIGHT), size_mm * 1e-3, size_mm * 1e-3, order, "--size")
    r = run_cantilever(order=order, size=size_mm * 1e-3, solver=solver)
    return {
        "length_m": LENGTH,
        "width_m": WIDTH,
        "height_m": HEIGHT,
        "tip_load_N": LOAD,
        "tip_deflection_m": r.computed,
        "analytic_m": r.analytic,
        "relative_error": r.relative_error,
        "dofs": r.solution.dofs,
        "elements": r.solution.elements,
        "seconds": {k: r.seconds[k] for k in ("mesh", "assembly", "solve", "stress")},
        "order": order,
        "size_mm": size_mm,
        "solver": r.solution.solver.get("solver"),
        "max_von_mises_Pa": r.solution.max_von_mises,
    }
