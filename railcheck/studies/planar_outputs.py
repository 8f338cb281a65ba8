"""What a planar mechanism study shows: ``summary.json``'s dict, the console lines, the
tracers' and reactions' CSV tables (a header row with units) and the interactive page.

Units at this edge: mm, mm/s, mm/s^2, N, N m, and the driver in deg (an angle) or mm (a
slide); every table and the page state theirs.
"""

from __future__ import annotations

import math
from pathlib import Path

import numpy as np

from railcheck.files import atomic_write_text, to_json
from railcheck.studies.planar_page import write_planar_page
from railcheck.studies.planar_study import PlanarStudy, driver_shown

IDEALISATIONS = (
    "rigid bodies",
    "ideal joints (no friction, no clearance)",
    "the driver parameter moves at a constant speed",
    "gravity along -y of the ground frame",
    "each body's mass at its stated centre of mass",
)


def _peak(values: np.ndarray, driver: np.ndarray) -> dict:
    """The largest magnitude of (steps,) or (steps, 2) values and the driver value there."""
    size = np.hypot(values[:, 0], values[:, 1]) if values.ndim == 2 else np.abs(values)
    k = int(np.argmax(size))
    return {"value": float(size[k]), "at": float(driver[k])}


def _mobility(study: PlanarStudy) -> dict:
    m = study.mobility
    return {
        "moving_bodies": m.bodies,
        "gruebler": m.gruebler,
        "dof": m.dof,
        "redundant": m.redundant,
        "redundant_equations": [{"joint": r.joint, "equation": r.equation, "relax": r.relax} for r in study.redundant],
        "dof_along_motion": list(study.dof_along),
    }


def _motion(study: PlanarStudy, driver: np.ndarray) -> dict:
    cond = study.motion.conditioning
    least = None
    if cond is not None:  # the continuation's watch (a motion built from a closed form has none)
        k = int(np.argmin(cond))
        least = {"value": float(cond[k]), "at": float(driver[k])}
    return {
        "steps_solved": int(study.motion.s.size),
        "steps_asked": study.scene.steps,
        "ended": study.motion.ended,
        "least_conditioning": least,
    }


def planar_summary(study: PlanarStudy) -> dict:
    """summary.json of a planar study (mm, N, N m; the driver in deg or mm)."""
    driver, unit = driver_shown(study)
    r = study.reactions
    effort_unit = {name: ("N m" if type(d).__name__ == "RotationDriver" else "N") for name, d in _drivers(study)}
    to = float(np.degrees(study.scene.stop) if unit == "deg" else study.scene.stop * 1e3)
    frm = float(np.degrees(study.scene.start) if unit == "deg" else study.scene.start * 1e3)
    speed = abs(study.scene.rate) * (180 / math.pi if unit == "deg" else 1e3)
    return {
        "mechanism": study.mechanism.name,
        "source": study.scene.source,
        "idealisations": list(IDEALISATIONS),
        "mobility": _mobility(study),
        "driver": {"unit": unit, "from": frm, "to": to, "steps": study.scene.steps, f"speed_{unit}_per_s": speed},
        "motion": _motion(study, driver),
        "tracers": {name: _tracer_summary(t) for name, t in study.tracers.items()},
        "reactions_N": {name: _peak(f, driver) for name, f in r.forces.items()},
        "drives": {name: dict(_peak(e, driver), unit=effort_unit[name]) for name, e in r.efforts.items()},
        "closed_form": _closed(study),
        "gravity_m_s2": study.scene.gravity,
        "loaded": any(b.mass for b in study.mechanism.bodies),
        "slides_mm": _slides(study),
        "equilibrium": {"largest_residual": float(r.residual.max()), "relative": float(r.residual.max() / r.scale)},
    }


def _closed(study: PlanarStudy) -> dict:
    """The closed-form check: the dyads solved in order and the largest point distance (mm)."""
    c = study.closed_form
    if c is None:
        return {"dyads": None, "why": "not a driven crank plus RRR, RRP and RPR dyads: Newton's solution only"}
    return {"dyads": list(c.order), "largest_difference_mm": c.largest_difference * 1e3}


def _slides(study: PlanarStudy) -> dict:
    """Each prismatic joint's travel: where body i's point sits along body j's line, from
    body j's point (mm, least and most): on a rail, the stretch its carriage bears on."""
    out = {}
    for j in study.mechanism.joints:
        if type(j).__name__ != "Prismatic":
            continue
        on, _, _ = study.motion.point(j.j, j.pj)
        ahead, _, _ = study.motion.point(j.j, j.qj)
        at, _, _ = study.motion.point(j.i, j.pi)
        e = (ahead - on) / np.linalg.norm(ahead - on, axis=1)[:, None]
        travel = np.einsum("ij,ij->i", at - on, e) * 1e3
        out[j.name] = {"body": study.mechanism.body(j.j).name, "from": float(travel.min()), "to": float(travel.max())}
    return out


def _drivers(study: PlanarStudy):
    return [(d.name, d) for d in study.mechanism.drivers]


def _tracer_summary(t: np.ndarray) -> dict:
    return {
        "x_mm": [float(t[:, 0].min() * 1e3), float(t[:, 0].max() * 1e3)],
        "y_mm": [float(t[:, 1].min() * 1e3), float(t[:, 1].max() * 1e3)],
        "speed_peak_mm_s": float(np.hypot(t[:, 2], t[:, 3]).max() * 1e3),
    }


def planar_lines(summary: dict) -> list[str]:
    """The console's report of a planar study."""
    m, d, mo = summary["mobility"], summary["driver"], summary["motion"]
    u = d["unit"]
    lines = [
        f"{summary['mechanism']} ({summary['source']})",
        f"mobility: {m['moving_bodies']} moving bodies, Gruebler count {m['gruebler']}, actual DOF {m['dof']} "
        f"(rank of the joints' Jacobian), {m['redundant']} redundant equation(s); DOF along the motion "
        f"{m['dof_along_motion'][0]} to {m['dof_along_motion'][1]}",
    ]
    lines += [f"  redundant: joint {r['joint']!r}: {r['relax']}" for r in m["redundant_equations"]]
    lines.append(f"driver: {d['from']:g} to {d['to']:g} {u} in {d['steps']} steps at {d[f'speed_{u}_per_s']:.4g} {u}/s")
    c = summary["closed_form"]
    if c["dyads"]:
        lines.append(
            f"closed form ({', '.join(c['dyads'])}): every body point within {c['largest_difference_mm']:.1e} mm of Newton's"
        )
    else:
        lines.append(f"closed form: none ({c['why']})")
    if mo["ended"]:
        lines.append(f"motion stops after {mo['steps_solved']} of {mo['steps_asked']} steps: {mo['ended']}")
    for name, t in summary["tracers"].items():
        lines.append(
            f"tracer {name}: x {t['x_mm'][0]:.3f} to {t['x_mm'][1]:.3f} mm, y {t['y_mm'][0]:.3f} to {t['y_mm'][1]:.3f} mm, "
            f"peak speed {t['speed_peak_mm_s']:.4g} mm/s"
        )
    for name, t in summary["slides_mm"].items():
        lines.append(f"slide {name}: along {t['body']} from {t['from']:.1f} to {t['to']:.1f} mm")
    if not summary["loaded"]:
        lines.append("reactions: none to show (no body has a mass: give bodies a mass for the inverse dynamics)")
        lines.append("model: " + "; ".join(summary["idealisations"][:2]))
        return lines
    for name, r in summary["reactions_N"].items():
        lines.append(f"joint {name}: peak reaction {r['value']:.4g} N at {r['at']:.4g} {u}")
    for name, e in summary["drives"].items():
        lines.append(f"{name}: peak effort {e['value']:.4g} {e['unit']} at {e['at']:.4g} {u}")
    eq = summary["equilibrium"]
    lines.append(f"equilibrium: largest residual {eq['relative']:.1e} of the largest force (every body, every step)")
    lines.append("model: " + "; ".join(summary["idealisations"]))
    return lines


def tracers_csv(study: PlanarStudy) -> str:
    """Every tracer's path, velocity and acceleration by driver step, units in the header."""
    driver, unit = driver_shown(study)
    head = [f"driver_{unit}"]
    cols = [driver]
    for name, t in study.tracers.items():
        head += [f"{name}_{q}" for q in ("x_mm", "y_mm", "vx_mm_s", "vy_mm_s", "ax_mm_s2", "ay_mm_s2")]
        cols += list((t * 1e3).T)
    rows = np.column_stack(cols)
    return ",".join(head) + "\n" + "\n".join(",".join(f"{v:.12g}" for v in row) for row in rows) + "\n"


def reactions_csv(study: PlanarStudy) -> str:
    """By driver step: each joint's force that its first body exerts on its second (ground
    frame, N), its load on each of its moving bodies in that body's own axes (along the
    body's local x and y, N, and the moment about its centre of mass, N m), and each
    drive's effort (N m or N)."""
    driver, unit = driver_shown(study)
    head, cols = [f"driver_{unit}"], [driver]
    mech, q, r = study.mechanism, study.motion.q, study.reactions
    for j in mech.joints:
        head += [f"{j.name}_Fx_N", f"{j.name}_Fy_N"]
        cols += list(r.forces[j.name].T)
        for body, load in r.loads[j.name].items():
            th = q[:, 3 * body - 1]
            c, s = np.cos(th), np.sin(th)
            who = f"{j.name}_on_{mech.body(body).name}"
            head += [f"{who}_local_x_N", f"{who}_local_y_N", f"{who}_moment_Nm"]
            cols += [c * load[:, 0] + s * load[:, 1], -s * load[:, 0] + c * load[:, 1], load[:, 2]]
    for name, e in r.efforts.items():
        head.append(f"{name}_effort_{'Nm' if type(mech_driver(mech, name)).__name__ == 'RotationDriver' else 'N'}")
        cols.append(e)
    rows = np.column_stack(cols)
    return ",".join(head) + "\n" + "\n".join(",".join(f"{v:.12g}" for v in row) for row in rows) + "\n"


def mech_driver(mech, name: str):
    """The driver of that name."""
    return next(d for d in mech.drivers if d.name == name)


def write_planar_outputs(study: PlanarStudy, summary: dict, out: Path) -> list[Path]:
    """summary.json, tracers.csv, reactions.csv and mechanism.html into ``out``."""
    files = {
        "summary.json": to_json(summary) + "\n",
        "tracers.csv": tracers_csv(study),
        "reactions.csv": reactions_csv(study),
    }
    written = []
    for name, text in files.items():
        atomic_write_text(out / name, text)
        written.append(out / name)
    write_planar_page(out / "mechanism.html", study)
    return written + [out / "mechanism.html"]
