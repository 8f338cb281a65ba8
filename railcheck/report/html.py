"""``report.html``: one self-contained file (pictures inline, no script, no network) an
engineer can hand on: the verdict and its reasons, the scene, the configuration checks,
the kinematics, the table per part (cycle peak, seed method, factor of safety,
utilisation, deflection against its limit, fatigue), the pictures, mesh statistics, the
equilibrium check (applied loads against the support's reaction), timings and software
versions. Units at this edge: mm, MPa, N, deg.
"""

from __future__ import annotations

import base64
import html
import json
import platform
from pathlib import Path

import numpy as np

from railcheck.model.records import safe_speed_words
from railcheck.report.forces import applied_factor, governing_forces, support_words
from railcheck.report.text import component_figures, component_needs, given_components

CSS = """
body{font-family:system-ui,sans-serif;margin:2em;color:#222;max-width:1400px}
h1{font-size:1.6em} h2{border-bottom:1px solid #ccc;padding-bottom:.2em;margin-top:1.6em}
table{border-collapse:collapse;margin:.5em 0} td,th{border:1px solid #ccc;padding:.25em .6em;text-align:right}
th{background:#f3f3f3} td.l,th.l{text-align:left} .pass{color:#17772b;font-weight:bold}
.fail{color:#b00020;font-weight:bold} img{max-width:100%;border:1px solid #ddd;margin:.3em 0}
pre{background:#f7f7f7;padding:.6em;overflow:auto;font-size:12px} .note{color:#555;font-size:.9em}
"""


def html_escape(x) -> str:
    return html.escape(str(x))


def html_image(path: Path, alt: str) -> str:
    if not path.exists():
        return ""
    data = base64.b64encode(path.read_bytes()).decode()
    return f'<img alt="{html_escape(alt)}" src="data:image/png;base64,{data}">'


def _verdict(ok: bool) -> str:
    return '<span class="pass">PASS</span>' if ok else '<span class="fail">FAIL</span>'


def html_table(head: list[str], rows: list[list], left: int = 1) -> str:
    th = "".join(f'<th class="{"l" if i < left else ""}">{html_escape(h)}</th>' for i, h in enumerate(head))
    body = "".join(
        "<tr>" + "".join(f'<td class="{"l" if i < left else ""}">{c}</td>' for i, c in enumerate(r)) + "</tr>" for r in rows
    )
    return f"<table><tr>{th}</tr>{body}</table>"


def write_report(path: Path, scene, result, summary: dict, directory: Path) -> None:
    """Write report.html into ``path`` (pictures read from ``directory``)."""
    sections = [
        _header(result, summary),
        _parts(result),
        _linkage(directory),
        _components(result, directory),
        _loads(result),
        _assumptions(summary),
        _dynamic(result, directory),
        _checks(result),
        _pictures(result, directory),
        _kinematics(result, directory),
        _mesh_and_equilibrium(result),
        _scene(scene),
        _timings(result),
        _versions(),
    ]
    page = (
        f'<!DOCTYPE html><html lang="en"><head><meta charset="utf-8"><title>railcheck report</title>'
        f"<style>{CSS}</style></head><body>{''.join(sections)}</body></html>\n"
    )
    path.write_text(page, encoding="utf-8")


def _linkage(directory: Path) -> str:
    """The linkage whose joints the tables name (linkage.png), when it was drawn."""
    if not (directory / "linkage.png").exists():
        return ""
    return "<h2>The linkage</h2>" + html_image(directory / "linkage.png", "the linkage with its joints O2, A, B, O4")


def _header(result, summary) -> str:
    reasons = "; ".join(result.failures_with_figures)
    verdict = summary["verdict"]
    title = (
        _verdict(not result.failures) if verdict in ("PASS", "FAIL") else f'<span class="note">{html_escape(verdict)}</span>'
    )
    unloaded = (
        f"<p>NO LOAD: {html_escape(', '.join(result.unloaded))}: no load at any step (no speed, no gravity, no explicit "
        "load); nothing to check, so not meshed or solved</p>"
        if result.unloaded
        else ""
    )
    passes = "<p>every check and part passes</p>" if result.parts else ""
    return (
        f"<h1>railcheck report: {title}</h1>"
        + (f'<p class="fail">fails: {html_escape(reasons)}</p>' if reasons else passes)
        + "".join(f"<p>to pass: {html_escape(t)}</p>" for t in result.to_pass)
        + (f"<p>safe speed: {html_escape(safe_speed_words(result.safe_speed))}</p>" if result.safe_speed else "")
        + unloaded
        + f'<p class="note">scene: {html_escape(result.scene.source)}; '
        + f"stages run: {html_escape(', '.join(result.stages_run))}</p>"
        + "".join(f'<p class="note">warning: {html_escape(w)}</p>' for w in summary.get("warnings", []))
    )


def _assumptions(summary: dict) -> str:
    """Every default and assumption behind the verdict, and where quasi-static holds."""
    items = "".join(f"<li>{html_escape(a)}</li>" for a in summary.get("assumptions", []))
    certs = [
        f"<li>{html_escape(name)}: {html_escape(_certificate_words(p['quasi_static']))}</li>"
        for name, p in summary.get("parts", {}).items()
        if "quasi_static" in p
    ]
    out = f"<h2>Assumptions</h2><ul>{items}</ul>" if items else ""
    return out + (f"<h3>Where quasi-static holds</h3><ul>{''.join(certs)}</ul>" if certs else "")


def _certificate_words(c: dict) -> str:
    """A part's certificate (summary.json's ``quasi_static``) in one sentence."""
    relation = "<=" if c["holds"] else ">"
    return (
        f"one-mode amplification estimate {c['amplification_estimate']:.3f} {relation} {c['tolerance']:.2f} "
        f"(lowest mode {c['lowest_frequency_Hz']:.3g} Hz by {c['lowest_frequency_from']}, crank {c['crank_Hz']:.3g} Hz): "
        f"{c['then']}"
    )


def _scene(scene) -> str:
    return f"<h2>Scene</h2><pre>{html_escape(json.dumps(scene.raw, indent=2, ensure_ascii=False))}</pre>"


def _checks(result) -> str:
    if not result.checks:
        return ""
    rows = [
        [html_escape(n), _verdict(c.ok), f'<span class="l">{html_escape(c.message)}</span>']
        for n, c in result.checks.items()
    ]
    return "<h2>Configuration checks</h2>" + html_table(["check", "result", "detail"], rows, left=3)


def _kinematics(result, directory: Path) -> str:
    k = result.kinematics_summary
    if k is None:
        return ""
    rows = [[html_escape(j), f"{v:.1f}", f"{k['peak_crank_angle_deg'][j]:.1f}"] for j, v in k["peak_reactions_N"].items()]
    rows.append(["motor torque (N·m)", f"{k['peak_torque_Nm']:.1f}", f"{k['peak_crank_angle_deg']['torque']:.1f}"])
    return (
        "<h2>Kinematics and joint reactions</h2>"
        f"<p>{html_escape(k['formulation'])}, effects: {html_escape(', '.join(k['effects']) or 'none')}; transmission angle "
        f"{k['transmission_angle_deg']['min']:.2f} to {k['transmission_angle_deg']['max']:.2f} deg</p>"
        + html_table(["joint", "peak (N)", "at crank angle (deg)"], rows)
        + html_image(directory / "reactions.png", "joint reactions")
        + html_image(directory / "torque.png", "motor torque")
    )


def _clamped_cell(k) -> str:
    """A free rail's 2013 clamped model: its cycle peak and the peak at the clamp (MPa)."""
    return "—" if k is None else f"{k.max_von_mises / 1e6:.1f} ({k.support_peak / 1e6:.1f})"


def _parts(result) -> str:
    """The parts table: each part's cycle peak, seed method, limit, utilisation,
    deflection, fatigue and verdict, and a note on the support models."""
    if not result.parts:
        return ""
    dynamic = any(p.cycle.dynamic is not None for p in result.parts.values())
    compared = any(p.clamped is not None for p in result.parts.values())
    rows = [_part_row(name, p, dynamic, compared) for name, p in result.parts.items()]
    head = [
        "part",
        "cycle max von Mises (MPa)",
        "at crank (deg)",
        "2013 inst. (MPa)",
        *(["2013 clamp: peak (at the clamp) MPa, not the verdict"] if compared else []),
        "limit (MPa)",
        "factor of safety",
        "utilisation (governs)",
        "deflection* (mm)",
        "deflection limit (mm)",
        "fatigue factor",
        "σa / σm (MPa)",
        *(["dynamic amplification"] if dynamic else []),
        "verdict",
    ]
    crit = next(iter(result.parts.values())).cycle.fatigue
    return (
        "<h2>Parts</h2>"
        + html_table(head, rows)
        + f'<p class="note">cycle max: the largest von Mises over the whole crank cycle; * {_support_models(result)}'
        f"2013 inst.: at the instant of the peak reaction magnitude (the 2013 study's method); "
        f"factor of safety = limit / cycle max; fatigue: {html_escape(crit.criterion)}, endurance limit "
        f"{crit.marin.endurance_limit / 1e6:.0f} MPa (Shigley ch. 6, Marin factors in summary.json).</p>"
    )


def _loads(result) -> str:
    """Each part's joint forces at its governing instant, in its own axes, factored as the
    FE applied them and unfactored (the crank's motor couple too)."""
    rows = []
    for name, p in result.parts.items():
        factor = applied_factor(p)
        for f in governing_forces(p):
            rows.append(
                [
                    html_escape(name),
                    html_escape(f.name),
                    f"{factor:g}" if p.job.loads.explicit is None else "1 (as given)",
                    f"{f.force[0]:.1f}",
                    f"{f.force[1]:.1f}",
                    f"{np.linalg.norm(f.force):.1f}",
                    f"{np.linalg.norm(f.force) / factor:.1f}",
                    "" if f.couple is None else f"{f.couple:.2f} ({f.couple / factor:.2f})",
                ]
            )
    if not rows:
        return ""
    head = [
        "part",
        "load",
        "load factor",
        "x, along (N, applied)",
        "y, across (N, applied)",
        "applied (N)",
        "unfactored (N)",
        "motor couple, N·m applied (unfactored)",
    ]
    return (
        "<h2>Loads at each part's governing instant</h2>"
        + html_table(head, rows, left=2)
        + "<p class='note'>In each part's axes (x along it, y across it in the mechanism's plane), at the "
        "instant of its cycle peak; applied: as the FE applied them (times the scene's load factor; explicit "
        "[loads] as given), unfactored: over the factor. The parts' own and carried masses' inertia and, on a "
        "table-top rig, the weight out of plane act as body and hole loads besides these (summary.json's unit "
        "cases).</p>"
    )


def _components(result, directory: Path) -> str:
    """The joints' components: each one's standard, whether its loads carry the load
    factor, its figures, utilisation and verdict, and what was assumed."""
    if not result.components:
        return ""
    factor = result.scene.checked.factor
    rows = [
        [
            html_escape(name),
            html_escape(c.standard),
            f"x{factor:g} (factored)" if c.factored else "unfactored",
            html_escape(component_figures(c)),
            f"{c.utilisation:.0%} ({html_escape(c.governing_criterion)})",
            _verdict(bool(c.passed)),
            html_escape(component_needs(c)),
        ]
        for name, c in result.components.items()
    ]
    head = ["component", "standard", "loads", "figures", "utilisation (governs)", "verdict", "needs (what passes)"]
    assumed = sorted({a for c in result.components.values() for a in c.assumed})
    return (
        "<h2>Components</h2>"
        + html_table(head, rows)
        + '<p class="note">Screws and shafts on factored loads with the standard\'s resistance factors '
        "(EN 1993-1-8: γM0 = 1.0, γM2 = 1.25; Shigley: n ≥ 1); the screws' slip (VDI 2230, a failure: a joint "
        "that slips under a reversing load loosens), bearings and carriages on the loads as they are, "
        "against their standards' required static safety and life. Assumed (not in seed 000 or a cited catalogue; "
        f"the scene's [components] table overrides them): {html_escape(', '.join(assumed)) or 'nothing'}. "
        f"Given by the scene: {html_escape(', '.join(given_components(result.scene))) or 'nothing'}.</p>"
        + html_image(directory / "joints.png", "the joints' load paths")
    )


def _part_row(name: str, p, dynamic: bool, compared: bool) -> list:
    """One part's row of the parts table (MPa, mm, deg)."""
    c = p.cycle
    angle = f"{c.history.crank_angle_deg:.1f}" if c.C.shape[0] > 1 else "constant"
    fos = p.limit / p.verdict_stress if p.verdict_stress > 0 else np.inf
    dlim = f"{p.deflection_limit * 1e3:.3g}" if p.deflection_limit else "none"
    return [
        html_escape(name),
        f"{p.verdict_stress / 1e6:.1f}",
        angle,
        f"{c.seed_method.max_von_mises / 1e6:.1f}",
        *([_clamped_cell(p.clamped)] if compared else []),
        f"{p.limit / 1e6:.0f}",
        f"{fos:.2f}",
        f"{p.utilisation:.0%} ({html_escape(p.governing_criterion)})",
        f"{c.envelope.max_tip * 1e3:.3g}",
        dlim,
        f"{c.fatigue.min_safety_factor:.2f}",
        f"{c.fatigue.sigma_a / 1e6:.1f} / {c.fatigue.sigma_m / 1e6:.1f}",
        *([f"{c.dynamic.amplification:.4f}" if c.dynamic else "—"] if dynamic else []),
        _verdict(p.passed),
    ]


def _support_models(result) -> str:
    """The parts table's footnote: what the peak and the deflection mean for the clamped
    parts and for the free bodies."""
    free = [n for n, p in result.parts.items() if p.job.free_body is not None]
    clamped = [n for n in result.parts if n not in free]
    return (
        f"clamped ({html_escape(', '.join(clamped))}): the peak away from the idealised support's singular edge, the "
        "deflection at the free end; "
        if clamped
        else ""
    ) + (
        f"free bodies ({html_escape(', '.join(free))}): no support, every node in the verdict, the crank's deflection "
        "at A relative to its two screws at O2, a link's mid-span sag relative to its joints, a plate's seat "
        "relative to its bolts; "
        if free
        else ""
    )


def _dynamic(result, directory: Path) -> str:
    """The dynamic response (effect ``dynamic``): per part its lowest frequencies, the
    crank harmonics nearest them and the amplification, then the Campbell diagram."""
    parts = {n: p.cycle.dynamic for n, p in result.parts.items() if p.cycle.dynamic is not None}
    if not parts:
        return ""
    rows = [
        [
            html_escape(name),
            ", ".join(f"{f:.3g}" for f in d.hz[:3]),
            ", ".join(str(n) for n in d.harmonics[:3]),
            f"{d.quasi_static_peak / 1e6:.1f}",
            f"{d.dynamic_peak / 1e6:.1f}",
            f"{d.amplification:.4f}",
            _verdict(d.passed),
        ]
        for name, d in parts.items()
    ]
    d0 = next(iter(parts.values()))
    head = [
        "part",
        "lowest natural frequencies (Hz)",
        "nearest crank harmonics",
        "quasi-static peak (MPa)",
        "dynamic peak (MPa)",
        "amplification",
        "verdict",
    ]
    return (
        "<h2>Dynamic response</h2>"
        + html_table(head, rows)
        + f'<p class="note">steady state over one revolution at {d0.crank_hz:.3g} Hz by modal superposition with the '
        f"mode-acceleration correction; modal damping {d0.damping:g} (assumed); a part fails above an amplification "
        f"of {d0.max_amplification:.3g}; free bodies pinned at their joints, clamped parts at their clamp.</p>"
        + html_image(directory / "campbell.png", "Campbell diagram")
    )


def _pictures(result, directory: Path) -> str:
    out = []
    for name in result.parts:
        out.append(
            f"<h3>{html_escape(name)}</h3>"
            + html_image(directory / f"{name}.png", f"{name} von Mises")
            + html_image(directory / f"{name}-utilisation.png", f"{name} utilisation over the cycle")
            + html_image(directory / f"{name}-cycle.png", f"{name} over the cycle")
        )
    return "<h2>Pictures</h2>" + "".join(out) if out else ""


def _mesh_and_equilibrium(result) -> str:
    if not result.parts:
        return ""
    rows = []
    for name, p in result.parts.items():
        solve, c = p.cycle.solve, p.cycle.load_C[p.cycle.envelope.step]
        applied, reaction = solve.resultants @ c, solve.support_reactions @ c
        if p.job.free_body is not None:  # no support: the loads balance themselves, the rest is relieved
            names = list(p.cycle.fields.names)
            joints = [i for i, n in enumerate(names) if n.startswith(("pin_", "bolt_"))]
            scale = max(float(np.abs(c[joints]).max()), 1e-300)
            held, balance = support_words(p), f"{np.linalg.norm(applied) / scale:.1e} of the largest joint force"
        else:
            scale = max(float(np.linalg.norm(applied)), 1e-300)
            held = ", ".join(f"{v:.2f}" for v in reaction)
            balance = f"{np.linalg.norm(applied + reaction) / scale:.1e}"
        rows.append(
            [
                html_escape(name),
                f"{solve.dofs}",
                f"{solve.elements}",
                f"{p.mesh.min_quality:.2f}",
                f"{p.mesh.slivers}",
                html_escape(solve.solver.get("solver")),
                ", ".join(f"{v:.2f}" for v in applied),
                held,
                balance,
            ]
        )
    head = [
        "part",
        "DOFs",
        "elements",
        "min quality",
        "slivers",
        "solver",
        "applied load (N, x y z)",
        "support reaction (N)",
        "imbalance",
    ]
    return (
        "<h2>Mesh and equilibrium</h2>"
        + html_table(head, rows)
        + '<p class="note">at each part\'s governing instant. A supported part: the support reaction is the '
        "resultant of K u - f over the fixed nodes, and balances the applied bolt and body forces. A free body: "
        "the applied load is the resultant of its joint forces and its own inertia, which balance each other; "
        "what remains is removed as a rigid-body acceleration (inertia relief).</p>"
    )


def _timings(result) -> str:
    rows = [[html_escape(k), f"{v:.2f}"] for k, v in result.timings.items()]
    return "<h2>Timings</h2>" + html_table(["stage", "seconds"], rows) if rows else ""


def _versions() -> str:
    from importlib.metadata import PackageNotFoundError, version

    rows = [["python", html_escape(platform.python_version())]]
    for pkg in ("railcheck", "numpy", "scipy", "scikit-fem", "gmsh", "meshio", "pyvista", "pyamg", "pypardiso", "mkl"):
        try:
            rows.append([pkg, html_escape(version(pkg))])
        except PackageNotFoundError:
            rows.append([pkg, "not installed"])
    return "<h2>Software</h2>" + html_table(["package", "version"], rows, left=2)
