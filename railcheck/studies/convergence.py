"""`railcheck convergence`: what accuracy costs in time.

For each element order and mesh size: DOFs, elements, seconds per stage (mesh, assembly,
solve, stress), peak memory, tip deflection, peak von Mises (away from the support) and
their errors: against Timoshenko beam theory for the cantilever, against a Richardson
extrapolation from the three finest meshes for a part. The peak at the clamped support is
reported too, so its growth under refinement (a singularity) is shown, not hidden.

Each row runs in its own process, so ``peak_memory_bytes`` is that solve's peak resident
memory (the interpreter and libraries included, about 0.2 GB). ``kinematics`` as TARGET
studies the number of crank steps instead.
"""

from __future__ import annotations

import math
import time

import numpy as np

from railcheck.base.errors import InputError
from railcheck.base.machine import refuse_kinematics_beyond_memory
from railcheck.fea.cantilever import HEIGHT, LENGTH, LOAD, WIDTH, timoshenko_tip
from railcheck.fea.elasticity import HoleLoad, Support, solve_elasticity
from railcheck.fea.materials import MATERIALS
from railcheck.files import atomic_path
from railcheck.geometry.mesher import mesh_part
from railcheck.geometry.models import bar
from railcheck.kinematics.dynamics import inverse_dynamics
from railcheck.kinematics.motion import solve_motion
from railcheck.model.inputs import parts_input
from railcheck.model.jobs import build_load_cases, part_geometries, refuse_beyond_memory
from railcheck.model.kinematics_stage import kinematics_input, run_kinematics
from railcheck.parts import PARTS, geometry_of, kind_of
from railcheck.scene import load_scene

DEFAULT_SIZES_MM = {
    "cantilever": [20.0, 14.0, 10.0, 7.0, 5.0],
    "rail": [20.0, 14.0, 10.0, 7.0],
    "plate": [12.0, 8.5, 6.0, 4.2],
}
HOLE_RATIO = 0.3  # hole_size / size, as in the default scene (3 mm / 10 mm)
ELEMENTS = {"1": "P1", "2": "P2", "2s": "P2s"}  # --orders token -> element: P2 curved, P2s straight-sided


def element_order(element: str) -> tuple[int, bool]:
    """(order, curved) of an element label: P1, P2 (isoparametric, curved) or P2s (straight)."""
    return (1, False) if element == "P1" else (2, element == "P2")


# -- Richardson extrapolation ---------------------------------------------------------


def richardson(h: list[float], f: list[float], max_iter: int = 100) -> tuple[float, float]:
    """Extrapolate three solutions ``f`` at mesh sizes ``h`` (coarse to fine) to h -> 0.

    Assumes f(h) = f0 + C h^p; solves for the observed order p by fixed-point iteration
    (Celik et al. 2008, valid for a non-constant refinement ratio) and returns (f0, p).
    Raises ValueError when the three values do not converge monotonically.
    """
    # Celik et al. number the grids from the finest: 1 fine, 2 medium, 3 coarse
    (h3, h2, h1), (f3, f2, f1) = h[-3:], f[-3:]
    r21, r32 = h2 / h1, h3 / h2
    e21, e32 = f2 - f1, f3 - f2
    if e21 == 0:
        return f1, math.inf
    ratio = e32 / e21
    if ratio <= 0:
        raise ValueError("oscillating convergence: no Richardson extrapolation")
    s = 1.0
    p = abs(math.log(ratio)) / math.log(r21)
    for _ in range(max_iter):
        q = math.log((r21**p - s) / (r32**p - s))
        p_new = abs(math.log(ratio) + q) / math.log(r21)
        if abs(p_new - p) < 1e-14 * max(1.0, p):
            p = p_new
            break
        p = p_new
    f0 = (r21**p * f1 - f2) / (r21**p - 1.0)
    return f0, p


# -- one row (run in a subprocess) ------------------------------------------------------


def solve_row(target: str, element: str, size: float) -> dict:
    """Mesh and solve one configuration; returns the row (SI)."""
    import resource

    steel = MATERIALS["steel"]
    if target == "cantilever":
        geo = bar(LENGTH, WIDTH, HEIGHT)
        hole = size
        supports, loads, tip, exclude = [Support("clamp")], [HoleLoad("tip", (0.0, 0.0, LOAD))], "tip", HEIGHT
    else:
        scene = load_scene(None)  # the 2013 load case: clamped, the peak reaction at the worst bolts
        inputs = parts_input(scene).clamped(target)
        geos = part_geometries(inputs)
        kin = run_kinematics(kinematics_input(scene)) if target not in inputs.check.loads else None
        case = build_load_cases(inputs, kin, geos)[target]
        geo = geos[target]
        hole = size * HOLE_RATIO
        supports, tip = [Support(case.support)], case.tip_group
        loads = [HoleLoad(b.group, b.force) for b in case.bolts]
        exclude = kind_of(target).exclusion(geo)
    t = time.perf_counter()
    mesh = mesh_part(geo, size, hole, cache=False)
    t_mesh = time.perf_counter() - t
    order, curved = element_order(element)
    sol = solve_elasticity(
        mesh,
        steel,
        supports,
        loads,
        order=order,
        tip_group=tip,
        exclude_distance=exclude,
        curved=mesh.curved if curved else None,
    )
    row = {
        "target": target,
        "element": element,
        "order": order,
        "size_m": size,
        "hole_size_m": hole,
        "dofs": sol.dofs,
        "elements": sol.elements,
        "seconds": {"mesh": t_mesh, **{k: sol.seconds[k] for k in ("assembly", "solve", "stress")}},
        "peak_memory_bytes": resource.getrusage(resource.RUSAGE_SELF).ru_maxrss * 1024,
        "tip_deflection_m": sol.tip_deflection,
        "max_von_mises_Pa": sol.max_von_mises_away,
        "max_von_mises_location_m": [float(x) for x in sol.max_von_mises_away_location],  # type: ignore[union-attr]  # set by every solve
        "support_peak_von_mises_Pa": sol.max_von_mises,
        "solver": sol.solver.get("solver"),
    }
    return row


def beam_stress(x: float) -> float:
    """Bending stress (Pa) of the benchmark cantilever at distance x (m) from the clamp."""
    inertia = WIDTH * HEIGHT**3 / 12
    return LOAD * (LENGTH - x) * (HEIGHT / 2) / inertia


def add_errors(rows: list[dict], target: str) -> dict:
    """Fill ``error_deflection`` and ``error_von_mises`` (relative, signed) in place;
    return the reference values used, per order."""
    refs = {}
    if target == "cantilever":
        analytic = timoshenko_tip(LOAD, LENGTH, WIDTH, HEIGHT, MATERIALS["steel"], "z")
        for r in rows:
            r["error_deflection"] = (r["tip_deflection_m"] - analytic) / analytic
            sb = beam_stress(r["max_von_mises_location_m"][0])
            r["error_von_mises"] = (r["max_von_mises_Pa"] - sb) / sb
        refs = {"tip_deflection_m": analytic, "von_mises": "beam theory at the peak's x"}
        return refs
    for element in sorted({r["element"] for r in rows}):
        sub = sorted((r for r in rows if r["element"] == element), key=lambda r: -r["size_m"])
        h = [r["size_m"] for r in sub]
        ref = {}
        for key, name in (("tip_deflection_m", "error_deflection"), ("max_von_mises_Pa", "error_von_mises")):
            try:
                f0, p = richardson(h, [r[key] for r in sub]) if len(sub) >= 3 else (sub[-1][key], float("nan"))
            except ValueError:
                f0, p = sub[-1][key], float("nan")
            ref[key] = {"extrapolated": f0, "observed_order": p}
            for r in sub:
                r[name] = (r[key] - f0) / f0 if f0 else float("nan")
        refs[element] = ref
    return refs


def _refuse_beyond_memory(target: str, elements: list[str], sizes_mm: list[float]) -> None:
    """Every row's mesh is estimated before any is built (as `railcheck check` does)."""

    geo = bar(LENGTH, WIDTH, HEIGHT) if target == "cantilever" else geometry_of(target, {})
    hole = 1.0 if target == "cantilever" else HOLE_RATIO
    for size in sizes_mm:
        for element in elements:
            refuse_beyond_memory(geo, size * 1e-3, size * 1e-3 * hole, element_order(element)[0], "--sizes")


def run_study(target: str, elements: list[str], sizes: list[float], progress=print) -> tuple[list[dict], dict]:
    """One row per (element, size), each solved in a fresh worker process so that its peak
    memory is its own (``max_tasks_per_child=1``)."""
    from concurrent.futures import ProcessPoolExecutor

    rows = []
    total = len(elements) * len(sizes)
    with ProcessPoolExecutor(max_workers=1, max_tasks_per_child=1) as pool:
        for i, element in enumerate(elements):
            for j, size in enumerate(sorted(sizes, reverse=True)):
                t = time.perf_counter()
                row = pool.submit(solve_row, target, element, size).result()
                rows.append(row)
                progress(
                    f"[{i * len(sizes) + j + 1}/{total}] {target} {element} {size * 1e3:g} mm: {row['dofs']} DOFs, "
                    f"{time.perf_counter() - t:.1f} s"
                )
    refs = add_errors(rows, target)
    return rows, refs


# -- kinematics: crank steps ------------------------------------------------------------


def kinematics_study(steps_list: list[int], reference_steps: int = 200_000) -> tuple[list[dict], dict]:
    """Error of each peak reaction and of the peak torque against ``reference_steps``,
    and the median time of a full cycle, for the default scene."""

    scene = load_scene(None)
    assert scene.mechanism is not None  # the built-in scene has its linkage
    lk, speed = scene.mechanism.linkage, scene.mechanism.speed

    def peaks(n):
        dyn = inverse_dynamics(solve_motion(lk, speed, n), scene.formulation)
        return {**{j: dyn.peak(j)[0] for j in dyn.reactions}, "torque": dyn.peak_torque()[0]}

    ref = peaks(reference_steps)
    rows = []
    for n in steps_list:
        times = []
        for _ in range(5):
            t = time.perf_counter()
            p = peaks(n)
            times.append(time.perf_counter() - t)
        err = {k: (p[k] - ref[k]) / ref[k] for k in ref}
        four = all(abs(p[k] - ref[k]) <= 0.5 * 10 ** (math.floor(math.log10(ref[k])) - 3) for k in ref)
        rows.append(
            {
                "steps": n,
                "seconds": float(np.median(times)),
                "errors": err,
                "max_abs_error": max(abs(e) for e in err.values()),
                "four_significant_figures": four,
            }
        )
    return rows, ref


# -- command ----------------------------------------------------------------------------


def _parse_list(text: str, kind, name: str) -> list:
    try:
        values = [kind(x.strip()) for x in text.split(",") if x.strip()]
    except ValueError:
        raise InputError(name, f"must be a comma-separated list, got {text!r}") from None
    if not values:
        raise InputError(name, "is empty")
    return values


def plot_study(rows: list[dict], target: str, path: str) -> None:
    import matplotlib

    matplotlib.use("Agg")
    import matplotlib.pyplot as plt
    import matplotlib.ticker

    fig, axes = plt.subplots(1, 2, figsize=(11, 4.5))
    for ax, key, title in (
        (axes[0], "error_deflection", "tip deflection"),
        (axes[1], "error_von_mises", "peak von Mises (away from support)"),
    ):
        for element in sorted({r["element"] for r in rows}):
            # a row that is its own reference (error exactly 0) has no place on a log axis
            sub = [
                r for r in rows if r["element"] == element and r.get(key) is not None and r[key] == r[key] and r[key] != 0.0
            ]
            t = [sum(r["seconds"].values()) for r in sub]
            e = [abs(r[key]) for r in sub]
            ax.loglog(t, e, "o-", label=element)
            for r, ti, ei in zip(sub, t, e):
                ax.annotate(f"{r['size_m'] * 1e3:g} mm", (ti, ei), fontsize=7, textcoords="offset points", xytext=(3, 3))
        ax.set(xlabel="wall time per solve (s)", ylabel="relative error", title=f"{target}: {title}")
        ax.xaxis.set_minor_formatter(matplotlib.ticker.NullFormatter())
        ax.grid(alpha=0.3, which="both")
        ax.legend()
    fig.tight_layout()
    with atomic_path(path) as tmp:
        fig.savefig(tmp, dpi=110, format="png")
    plt.close(fig)


def run_convergence(target: str, orders: str = "1,2", sizes: str | None = None, progress=None) -> dict:
    """The study of ``target`` (cantilever, kinematics or a part): validates the lists
    (mm for meshes, step counts for kinematics) and returns {"target", "rows", ...}."""
    if target == "kinematics":
        steps = _parse_list(sizes, int, "--sizes") if sizes else [50, 100, 200, 500, 1000, 2000, 5000, 10000]
        if any(n < 3 or n > 10_000_000 for n in steps):
            raise InputError("--sizes", "crank step counts must be whole numbers from 3 to 10 000 000")
        refuse_kinematics_beyond_memory(max(max(steps), 200_000), "--sizes")
        rows, ref = kinematics_study(steps)
        return {"target": target, "rows": rows, "reference": ref, "reference_steps": 200_000}
    if target != "cantilever" and target not in PARTS:
        raise InputError("TARGET", f"unknown target {target!r} (cantilever, kinematics, {', '.join(PARTS)})")
    tokens = _parse_list(orders, str, "--orders")
    if any(o not in ELEMENTS for o in tokens):
        raise InputError("--orders", f"orders are 1, 2 (curved P2) or 2s (straight-sided P2), got {orders!r}")
    order_list = [ELEMENTS[o] for o in dict.fromkeys(tokens)]
    kind = "cantilever" if target == "cantilever" else ("rail" if kind_of(target).bolts_on_rail else "plate")
    sizes_mm = _parse_list(sizes, float, "--sizes") if sizes else DEFAULT_SIZES_MM[kind]
    if any(not (1.0 <= s <= 50.0) for s in sizes_mm):
        raise InputError("--sizes", "mesh sizes must lie between 1 and 50 mm")
    _refuse_beyond_memory(target, order_list, sizes_mm)
    rows, refs = run_study(target, order_list, [s * 1e-3 for s in sizes_mm], progress=progress or (lambda m: None))
    return {"target": target, "rows": rows, "references": refs}
