"""`railcheck bench cantilever`: the FE core against Timoshenko beam theory."""

from __future__ import annotations

from .errors import EXIT_PASS, InputError
from .report import to_json


def run_bench_command(args) -> int:
    from railcheck.fea.cantilever import HEIGHT, LENGTH, LOAD, WIDTH, run_cantilever

    if not (0.5 <= args.size <= 50):
        raise InputError("--size", f"must be between 0.5 and 50 mm, got {args.size:g}")
    from railcheck.geometry.models import bar

    from .pipeline import refuse_beyond_memory
    refuse_beyond_memory(bar(LENGTH, WIDTH, HEIGHT), args.size * 1e-3, args.size * 1e-3, args.order, "--size")
    r = run_cantilever(order=args.order, size=args.size * 1e-3, solver=args.solver)
    out = {"tip_deflection_m": r.computed, "analytic_m": r.analytic, "relative_error": r.relative_error,
           "dofs": r.solution.dofs, "elements": r.solution.elements,
           "seconds": {k: r.seconds[k] for k in ("mesh", "assembly", "solve", "stress")},
           "order": args.order, "size_mm": args.size, "solver": r.solution.solver.get("solver"),
           "max_von_mises_Pa": r.solution.max_von_mises}
    if args.json:
        print(to_json(out))
        return EXIT_PASS
    print(f"cantilever {LENGTH*1e3:g} x {WIDTH*1e3:g} x {HEIGHT*1e3:g} mm steel, clamped at x = 0, "
          f"{LOAD:g} N transverse tip load; P{args.order} tetrahedra, size {args.size:g} mm")
    print(f"  tip deflection (FE)         {r.computed*1e3:12.6f} mm")
    print(f"  Timoshenko PL^3/3EI+PL/kGA  {r.analytic*1e3:12.6f} mm")
    print(f"  relative error              {r.relative_error*100:+12.4f} %")
    print(f"  DOFs {r.solution.dofs}, elements {r.solution.elements}, solver {out['solver']}")
    print("  seconds: " + ", ".join(f"{k} {v:.2f}" for k, v in out["seconds"].items()))
    return EXIT_PASS
