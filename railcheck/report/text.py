"""Console tables and JSON for the results. Units appear here: mm, MPa, N, N m, deg."""

from __future__ import annotations

import json
import math
import textwrap
from pathlib import Path

import numpy as np

from railcheck.model.assumptions import assumptions
from railcheck.model.inputs import parts_input
from railcheck.model.records import safe_speed_words
from railcheck.parts import kind_of
from railcheck.units import floored, for_people


def _fmt(x: float, digits: int = 6) -> str:
    return f"{x:.{digits}g}"


def kinematics_table(summary: dict) -> str:
    """A readable console report of a kinematics summary."""
    m = summary["mechanism"]
    lines = []
    lengths = ", ".join(f"{k[:-3]} {_fmt(v)} mm" for k, v in m.items() if k.endswith("_mm"))
    lines.append(f"{m['kind']} ({m['assembly']}): {lengths}; {_fmt(m['speed_Hz'])} Hz, {m['steps']} steps")
    lines.append(f"inverse dynamics: {summary['formulation']}; effects: {', '.join(summary['effects']) or 'none (statics)'}")
    ta = summary["transmission_angle_deg"]
    lines.append(f"transmission angle: min {ta['min']:.2f} deg, max {ta['max']:.2f} deg")
    lines.append("")
    lines.append("checks")
    for name, c in summary["checks"].items():
        lines.append(f"  {'ok  ' if c['ok'] else 'FAIL'}  {name:<28} {c['message']}")
    lines.append("")
    lines.append(f"  {'joint':<8}{'peak reaction (N)':>20}{'at crank angle (deg)':>24}")
    for joint, value in summary["peak_reactions_N"].items():
        lines.append(f"  {joint:<8}{value:>20.1f}{summary['peak_crank_angle_deg'][joint]:>24.2f}")
    lines.append(f"  {'torque':<8}{summary['peak_torque_Nm']:>16.2f} N·m{summary['peak_crank_angle_deg']['torque']:>24.2f}")
    for w in summary.get("warnings", []):
        lines.append(f"warning: {w}")
    return "\n".join(lines)


def aligned(header: list[str], rows: list[list[str]], left: frozenset = frozenset({0}), indent: str = "  ") -> list[str]:
    """Rows of text under ``header``, each column as wide as its widest cell (the columns
    numbered in ``left`` left-aligned, words; the rest right-aligned, numbers), two spaces
    apart: a FAIL or a long number widens its column instead of running into the next."""
    widths = [max(len(r[c]) for r in [header, *rows]) for c in range(len(header))]

    def line(cells):
        return (
            indent
            + "  ".join(
                cell.ljust(w) if c in left else cell.rjust(w) for c, (cell, w) in enumerate(zip(cells, widths))
            ).rstrip()
        )

    return [line(header), *(line(r) for r in rows)]


#: the console's width: every line of a check's report fits it (longer notes wrap)
CONSOLE_WIDTH = 100


def fit_width(text: str, width: int = CONSOLE_WIDTH) -> str:
    """``text`` with every line longer than ``width`` wrapped at words, its continuation
    indented four spaces past the line's own indent (tables' rows are built to fit)."""
    out = []
    for line in text.splitlines():
        if len(line) <= width:
            out.append(line)
            continue
        indent = " " * (len(line) - len(line.lstrip()))
        out += textwrap.wrap(
            line.strip(),
            width,
            initial_indent=indent,
            subsequent_indent=indent + "    ",
            break_on_hyphens=False,
            break_long_words=False,  # a path stays whole: it may run past the width
        )
    return "\n".join(out)


def parts_table(result) -> str:
    """The console table: the cycle envelope's peak and where in the cycle, the fatigue
    factor, the largest deflection, the utilisation with the criterion that governs it,
    and each verdict naming every failed criterion; then the legend and the notes. The
    2013 study's single instant, the factor of safety, the peak's place and the support's
    peak are in report.html and summary.json."""
    header = ["part", "max vM (MPa)", "fatigue n", "deflection (mm)", "utilisation", "governs", "verdict"]
    rows = [_part_row(name, p) for name, p in result.parts.items()]
    lines = aligned(header, rows, left=frozenset({0, 5, 6}))
    limits = sorted({p.limit for p in result.parts.values()})
    lines.append(
        "  max vM: the largest von Mises over the crank cycle (limit "
        + ", ".join(f"{x / 1e6:.0f}" for x in limits)
        + " MPa); fatigue n: the least fatigue safety factor (Shigley 6-14, the [fatigue] criterion); deflection: "
        "the largest, relative to the part's joints or support; utilisation: the largest of stress / limit, "
        "required / fatigue n, deflection / its limit, peak / yield and (amplification - 1) / (its limit - 1); "
        "a FAIL's criteria and figures: the fails: lines; each peak's crank angle, the 2013 study's instant and "
        "factors of safety: report.html; where each peak lies: summary.json"
    )
    lines += certificate_lines(result)
    lines += dynamic_lines(result)
    lines += _model_notes(result)
    lines += ["  assumptions:"] + [f"    - {a}" for a in assumptions(*_assumed(result.scene), result.parts)]
    return fit_width("\n".join(lines))


def _part_row(name: str, p) -> list[str]:
    """One part's row of the console table (MPa, mm); what fails is on the report's
    "fails:" lines, with its figures."""
    c = p.cycle
    verdict = ("PASS" if p.passed else "FAIL") if np.any(c.C) else "NO LOAD"
    return [
        name,
        f"{p.verdict_stress / 1e6:.1f}",
        _factor(c.fatigue.min_safety_factor),
        f"{c.envelope.max_tip * 1e3:.2f}",
        f"{p.utilisation:.0%}",
        p.governing_criterion,
        verdict,
    ]


def _model_notes(result) -> list[str]:
    """The parts table's notes on the models: the clamped parts' singular support, what
    a free body's verdict and deflection mean, and the 2013 clamped model's figures."""
    lines: list[str] = []
    free = [n for n, p in result.parts.items() if p.job.free_body is not None]
    clamped = [n for n in result.parts if n not in free]
    if clamped:
        lines.append(
            f"  {', '.join(clamped)}: clamped at the support; its peak there grows with mesh refinement (a "
            "singularity); the verdict uses the peak farther than one hole diameter from it"
        )
    if free:
        lines.append(
            f"  {', '.join(free)}: free bodies (joint forces bearing on their holes or bearing seat as a cosine "
            "over the loaded half, their own and the point masses' inertia, one load factor; a bolted-down part's "
            "loads balanced by a rigid foundation's linear reaction on its base; inertia relief, no support): the "
            "verdict reads every node; the deflection is the crank's at A relative to its two screws at O2, a "
            "link's mid-span sag relative to its joints, a plate's seat relative to its bolts, a bracket's top "
            "relative to its base"
        )
    compared = {n: p.clamped for n, p in result.parts.items() if p.clamped is not None}
    if compared:
        lines.append(
            "  the 2013 model (each rail clamped at its first hole, each plate at its seat or base, the joint forces "
            "as uniform tractions; for comparison, not the "
            "verdict): "
            + "; ".join(
                f"{n} {k.max_von_mises / 1e6:.1f} MPa ({k.support_peak / 1e6:.1f} at the clamp), "
                f"fatigue n {_factor(k.fatigue_factor)}, tip {k.max_tip * 1e3:.2f} mm"
                for n, k in compared.items()
            )
        )
    return lines


def certificate_lines(result) -> list[str]:
    """Per part whose loads vary with a turning crank: whether quasi-static holds (the
    one-mode estimate against its tolerance) and what was done about it."""
    certs = {n: p.job.certificate for n, p in result.parts.items() if p.job.certificate is not None}
    if not certs:
        return []
    c0 = next(iter(certs.values()))
    lines = [
        f"  where quasi-static holds (one-mode estimate of the dynamic amplification from each part's lowest "
        f"mode and the load cycle's harmonics, tolerance {c0.tolerance:.2f}; above it the dynamic response is computed):"
    ]
    lines += [f"    {name:<14} {c.sentence()}" for name, c in certs.items()]
    return lines


def dynamic_lines(result) -> list[str]:
    """Per part with a dynamic response: its lowest frequencies, the crank harmonics
    nearest them, and the amplification against its limit."""
    parts = {n: p.cycle.dynamic for n, p in result.parts.items() if p.cycle.dynamic is not None}
    if not parts:
        return []
    d0 = next(iter(parts.values()))
    lines = [
        f"  dynamic response (modes, modal damping {d0.damping:g}, crank {d0.crank_hz:.3g} Hz; amplification = cycle "
        f"peak with the modes' response over the quasi-static peak, limit {d0.max_amplification:.3g}):"
    ]
    for name, d in parts.items():
        freqs = ", ".join(f"{f:.3g}" for f in d.hz[:3])
        harmonics = ", ".join(str(n) for n in d.harmonics[:3])
        lines.append(
            f"    {name:<14} {freqs} Hz (nearest crank harmonics {harmonics}); amplification "
            f"{d.amplification:.4f} {'PASS' if d.passed else 'FAIL'}"
        )
    return lines


def _factor(x: float) -> str:
    return for_people(x, ".2f")


def check_report(run) -> str:
    """The console report of a finished check: kinematics, the FE table, warnings, the
    stages run and one verdict line naming every reason for a FAIL."""
    result, summary, scene = run.result, run.summary, run.result.scene
    lines = [f"scene: {scene.source}"]
    if result.kinematics_summary is not None:
        lines += [kinematics_table(result.kinematics_summary), ""]
    if result.parts:
        c = scene.check
        pairs = sorted({(p.job.mesh.size, p.job.mesh.hole_size) for p in result.parts.values()}, reverse=True)
        sizes = ", ".join(f"{a * 1e3:g} mm (holes {b * 1e3:.3g} mm)" for a, b in pairs)
        lines.append(
            f"FE check: material {c.material}, factor {c.factor:g}, {support_words(result)}, "
            f"P{scene.mesh.order} tetrahedra, size {sizes}"
        )
        lines.append(parts_table(result))
    if result.components:
        lines += components_table(result)
    if result.unloaded:
        lines.append(
            f"  NO LOAD: {', '.join(result.unloaded)}: no load at any step (no speed, no gravity, no explicit load)"
        )
        lines.append("  nothing to check, so not meshed or solved")
    if result.parts:
        if "rail_mass_per_m_kg" in summary:
            m = summary["rail_mass_per_m_kg"]
            lines.append(
                f"  rail mass: the grooved size-25 section {m['model_section']:.2f} kg/m "
                f"({m['model_with_holes']:.2f} with its holes), HIWIN HGR25 {m['HIWIN HGR25 catalogue']:.2f} kg/m, "
                f"the 2013 study {m['seed 000 (Anexo I)']:.2f} kg/m; the dynamics and the FE carry "
                f"{m['dynamics']:.2f} kg/m"
            )
        known = (result.kinematics_summary or {}).get("warnings", [])
        lines += [f"warning: {w}" for w in result.warnings if w not in known]
    lines.append(f"stages run: {', '.join(result.stages_run)}")
    lines += [f"fails: {f}" for f in result.failures_with_figures]
    lines += [f"to pass: {f}" for f in result.to_pass]
    lines += [f"safe speed: {safe_speed_words(result.safe_speed)}"] if result.safe_speed is not None else []
    return fit_width("\n".join(lines)) + "\n" + verdict_line(result, summary["verdict"], run.target)


def verdict_line(result, verdict: str, target) -> str:
    """The report's last lines: where the results are, then one line to grep, the verdict
    and what fails (their figures are on the "fails:" lines above), or their count where
    the names would not fit the console."""
    reasons = f" ({'; '.join(result.failures)})" if result.failures else ""
    line = f"verdict: {verdict}{reasons}"
    if len(line) > CONSOLE_WIDTH:
        line = f"verdict: {verdict} ({len(result.failures)} failures, above)"
    return fit_width(f"results in {target}/") + "\n" + line


def components_table(result) -> list[str]:
    """The joints' components' lines: each component's figures, its utilisation with the
    criterion that governs and its verdict; then the standards and what was assumed."""
    factor = result.scene.checked.factor
    header = ["component", "figures", "utilisation", "governs", "verdict", "needs"]
    rows = [
        [
            name,
            component_figures(c),
            f"{c.utilisation:.0%}",
            str(c.governing_criterion),
            "PASS" if c.passed else "FAIL",
            component_needs(c),
        ]
        for name, c in result.components.items()
    ]
    lines = [
        f"components: the joints' parts by their standards (strength on loads x{factor:g}; slip, bearings and",
        "    carriages on the loads as they are; V, N per screw; M alternating+mean; needs: what passes)",
    ]
    lines += aligned(header, rows, left=frozenset({0, 1, 3, 4, 5}))
    standards = sorted({f"{c.kind} {c.standard}" for c in result.components.values()})
    lines += textwrap.wrap("standards: " + "; ".join(standards), 98, initial_indent="  ", subsequent_indent="    ")
    assumed = sorted({a for c in result.components.values() for a in c.assumed})
    if assumed:
        text = f"assumed (not in seed 000 or a cited catalogue; [components] overrides): {', '.join(assumed)}"
        lines += textwrap.wrap(text, 98, initial_indent="  ", subsequent_indent="    ")
    given = given_components(result.scene)
    if given:
        text = f"given (the scene's [components], not assumed): {', '.join(given)}"
        lines += textwrap.wrap(text, 98, initial_indent="  ", subsequent_indent="    ")
    return lines


def given_components(scene) -> list[str]:
    """The ``[components]`` values the scene sets, as it wrote them ("key = value", TOML
    spelling, sorted): what the components' outputs call given rather than assumed."""
    table = scene.raw.get("components", {})
    return [f"{k} = {json.dumps(v) if isinstance(v, str) else v}" for k, v in sorted(table.items())]


def component_figures(c) -> str:
    """A component's figures in engineer's units (kN, N m, h)."""
    f = c.figures
    words = {
        "force_N": lambda v: f"F {v / 1e3:.2f} kN",
        "moment_Nm": lambda v: f"M {v:.3g}{'' if f.get('mean_moment_Nm', 0.0) > 0 else ' N m'}",
        "mean_moment_Nm": lambda v: f"+{v:.3g} N m" if v > 0 else "",
        "torque_Nm": lambda v: f"T {v:.3g} N m" if v > 0 else "",
        "shear_N": lambda v: f"V {v / 1e3:.2f} kN",
        "tension_N": lambda v: f"N {v / 1e3:.2f} kN",
        "static_safety": lambda v: f"s0 {_factor(v)}",
        "life_h": lambda v: f"L10 {v:.2g} h" if math.isfinite(v) else "L10 unlimited (at rest)",
        "equivalent_load_N": lambda v: f"P0 {v / 1e3:.2f} kN",
    }
    return ", ".join(w for k, v in f.items() if k in words and (w := words[k](v))).replace(", +", "+")


def component_needs(c) -> str:
    """What a component needs to pass, short: a screw and its tightening torque, a shaft's
    diameter, a bearing spacing (``c.needs``; "-" where it has none)."""
    n = c.needs
    if c.kind == "screws":
        if n.get("screw"):
            return f"{n['screw']}, {n['tightening_torque_Nm']:.1f} N m"
        friction = n.get("friction_needed", math.inf)
        shown = math.ceil(friction * 100) / 100
        return f"none (mu_T {shown:.2f})" if math.isfinite(friction) else "no screw fits"
    if "diameter_needed_m" in n:
        return f"d {n['diameter_needed_m'] * 1e3:.1f} mm"
    spacing = n.get("spacing_needed_m")
    if spacing is not None and spacing > 0:
        return f"spacing {spacing * 1e3:.1f} mm" if math.isfinite(spacing) else "a larger bearing"
    return "-"


def bench_report(out: dict) -> str:
    """`railcheck bench cantilever` on the console."""

    return "\n".join(
        [
            f"cantilever {out['length_m'] * 1e3:g} x {out['width_m'] * 1e3:g} x {out['height_m'] * 1e3:g} mm steel, "
            f"clamped at x = 0, {out['tip_load_N']:g} N transverse tip load; "
            f"P{out['order']} tetrahedra, size {out['size_mm']:g} mm",
            f"  tip deflection (FE)         {out['tip_deflection_m'] * 1e3:12.6f} mm",
            f"  Timoshenko PL^3/3EI+PL/kGA  {out['analytic_m'] * 1e3:12.6f} mm",
            f"  relative error              {out['relative_error'] * 100:+12.4f} %",
            f"  DOFs {out['dofs']}, elements {out['elements']}, solver {out['solver']}",
            "  seconds: " + ", ".join(f"{k} {v:.2f}" for k, v in out["seconds"].items()),
        ]
    )


def convergence_report(result: dict) -> str:
    """`railcheck convergence` on the console."""
    rows, target = result["rows"], result["target"]
    if target == "kinematics":
        lines = [
            f"default scene, newton-euler; reference: {result['reference_steps']} steps",
            f"  {'steps':>7}{'seconds':>10}{'max |error|':>13}  4 sig. figures",
        ]
        lines += [
            f"  {r['steps']:>7}{r['seconds']:>10.4f}{r['max_abs_error']:>13.2e}  "
            f"{'yes' if r['four_significant_figures'] else 'no'}"
            for r in rows
        ]
        return "\n".join(lines)
    lines = [
        f"{target}: errors against "
        + ("Timoshenko beam theory" if target == "cantilever" else "Richardson extrapolation of the three finest meshes"),
        f"  {'elem':>4}{'size mm':>8}{'DOFs':>9}{'elements':>9}{'mesh':>7}{'asm':>7}{'solve':>7}{'stress':>7}"
        f"{'mem GB':>7}{'tip mm':>11}{'err':>10}{'vM MPa':>9}{'err':>10}{'support':>9}",
    ]
    for r in rows:
        s = r["seconds"]
        lines.append(
            f"  {r['element']:>4}{r['size_m'] * 1e3:>8.3g}{r['dofs']:>9}{r['elements']:>9}{s['mesh']:>7.2f}"
            f"{s['assembly']:>7.2f}{s['solve']:>7.2f}{s['stress']:>7.2f}{r['peak_memory_bytes'] / 1e9:>7.2f}"
            f"{r['tip_deflection_m'] * 1e3:>11.5f}{r['error_deflection'] * 100:>9.3f}%"
            f"{r['max_von_mises_Pa'] / 1e6:>9.2f}{r['error_von_mises'] * 100:>9.3f}%"
            f"{r['support_peak_von_mises_Pa'] / 1e6:>9.1f}"
        )
    if target != "cantilever":
        for name, ref in result["references"].items():
            d, v = ref["tip_deflection_m"], ref["max_von_mises_Pa"]
            lines.append(
                f"  {name} extrapolated: tip {d['extrapolated'] * 1e3:.5f} mm (observed order "
                f"{d['observed_order']:.2f}), von Mises {v['extrapolated'] / 1e6:.2f} MPa "
                f"(order {v['observed_order']:.2f})"
            )
    return "\n".join(lines)


def mechanism_report(run) -> str:
    """`railcheck mechanism` on the console."""
    mech, table = run.mech, run.table
    x, y = table[:, 1] * 1e3, table[:, 2] * 1e3
    return "\n".join(
        [
            f"{mech.name}: {mech.description}",
            f"mobility: {run.mobility.report()}",
            f"driver: {math.degrees(table[0, 0]):.2f} to {math.degrees(table[-1, 0]):.2f} deg in {run.steps} steps "
            f"({math.degrees(run.rate):.0f} deg/s)",
            f"tracer ({mech.bodies[mech.tracer[0] - 1].name}.{mech.tracer[1]}): x {x.min():.4f} to {x.max():.4f} mm, "
            f"y {y.min():.4f} to {y.max():.4f} mm",
        ]
    )


def _motor_lines(sizing: dict | None, mm, drawn: bool = True) -> list[str]:
    """The motor a rig needs: peak and RMS torque and peak power to run every passing
    setting at each listed speed, and the largest at a setting's own safe speed."""
    if not sizing:
        return []
    out = []
    for speed, entry in sizing["at_listed_speeds"].items():
        if "torque_peak_Nm" not in entry:
            out.append(f"  motor at {float(speed):g} Hz: no setting passes")
            continue
        t, r, p = (entry[q] for q in ("torque_peak_Nm", "torque_rms_Nm", "power_peak_W"))
        out.append(
            f"  motor at {float(speed):g} Hz (every passing setting): peak torque {t['value']:.3g} N·m "
            f"({mm(t['lengths_m'])}), RMS {r['value']:.3g} N·m, peak power {p['value']:,.0f} W"
        )
    safe = sizing["at_safe_speed"]
    if "torque_peak_Nm" in safe:
        t, p = safe["torque_peak_Nm"], safe["power_peak_W"]
        out.append(
            f"  motor at each setting's safe speed: peak torque {t['value']:.3g} N·m ({mm(t['lengths_m'])} at "
            f"{t['safe_speed_Hz']:.3g} Hz), peak power {p['value']:,.0f} W; the 2013 estimate: "
            f"{sizing['estimate_2013_Nm']:.0f} N·m" + " (motor.png)" * drawn
        )
    return out + _demand_lines(sizing)


def _demand_lines(sizing: dict) -> list[str]:
    """The motor's demand at each listed speed: the peak torque that drives every setting
    passing the configuration checks, whatever its verdict (the motor curve's ``demand``)."""
    curve = sizing.get("curve") or {}
    hz, demand = curve.get("speed_Hz", []), curve.get("demand_torque_peak_Nm", [])
    out = []
    for speed in sizing["at_listed_speeds"]:
        near = [t for h, t in zip(hz, demand) if math.isclose(h, float(speed), rel_tol=1e-9) and t is not None]
        if near:
            out.append(
                f"  motor to drive every setting that passes the configuration checks at {float(speed):g} Hz, whatever "
                f"its verdict: peak torque {near[0]:.3g} N·m"
            )
    return out


def _bar_order(k: dict) -> list[str]:
    """The bars a kind's settings are written by ("480/840/780/1020 mm"), in order: the
    keys of the first setting its summary names (none: no line)."""
    found = [e.get("lengths_m") for e in (k.get("worst"), k.get("shortest_bearing_life")) if e]
    sizing = k.get("motor_sizing") or {}
    found += [e["torque_peak_Nm"]["lengths_m"] for e in sizing.get("at_listed_speeds", {}).values() if "torque_peak_Nm" in e]
    return list(found[0]) if found else []


def sweep_report(run) -> str:
    """The console report of a finished sweep: per kind the counts, the worst setting,
    the motor and bearing envelope, then seed 000's hypotheses and where the results are."""
    s = run.summary
    lines = [
        f"sweep: {', '.join(f'{v:g}' for v in s['speeds_Hz'])} Hz, {s['steps']} steps per revolution, "
        f"{s['assembly']} assembly, effects: {', '.join(s['effects'])}"
    ]
    mm = lambda d: "/".join(f"{v * 1e3:.0f}" for v in d.values()) + " mm"  # noqa: E731
    drawn = (Path(run.target) / "motor.png").exists()  # [output] plots = false draws none
    for kind, k in s["by_kind"].items():
        lines.append(
            f"{kind}: {k['settings_total']} settings, {k['settings_assemblable']} assemble, "
            f"{k['settings_revolving']} revolve, {k['settings_passing_checks']} pass the configuration "
            f"checks, {k['settings_passing']} pass every check at {s['speeds_Hz'][0]:g} Hz"
        )
        order = _bar_order(k)
        if order:
            lines.append(f"  settings written {'/'.join(order)} (mm)")
        if k["worst"]:
            w = k["worst"]
            lines.append(
                f"  worst passing-checks setting {mm(w['lengths_m'])}: {w['part']} utilisation {w['utilisation']:.3f} "
                f"({w['criterion']})"
            )
        if k["lowest_safe_speed"]:
            m = k["lowest_safe_speed"]
            lines.append(
                f"  lowest safe speed {floored(m['safe_speed_Hz'])} Hz at {mm(m['lengths_m'])}: there {m['part']} "
                f"reaches its {m['criterion']} limit"
                if m["safe_speed_Hz"] > 0
                else f"  lowest safe speed: none at {mm(m['lengths_m'])}, which fails at rest ({m['part']} "
                f"{m['criterion']} beyond its limit with the crank still)"
            )
        lines += _motor_lines(k.get("motor_sizing"), mm, drawn)
        if k["shortest_bearing_life"]:
            b = k["shortest_bearing_life"]
            lines.append(
                f"  6205 bearings: shortest L10 {b['hours']:.3g} h at {mm(b['lengths_m'])}, static "
                f"safety {b['static_safety']:.3g}"
            )
        lines += _screw_need_lines(k.get("screw_needs") or {}, s["speeds_Hz"][0])
        sizes = k.get("sizes_needed_m") or {}
        if sizes:
            said = ", ".join(f"{n.replace('_', ' ')} {d * 1e3:.1f} mm" for n, d in sizes.items())
            lines.append(f"  what passes at every setting checked: {said}")
    if s.get("seed_hypotheses"):
        held = sum(h["holds"] is True for h in s["seed_hypotheses"])
        tested = sum(h["holds"] is not None for h in s["seed_hypotheses"])
        lines.append(
            f"the 2013 design study's hypotheses (chapter 3.3): {held} of {tested} tested hold on this sweep "
            "(summary.json seed_hypotheses)"
        )
    lines.append(
        f"results in {run.target}/ (report.html first; {', '.join(s['tables'].values())}, "
        + ("maps, motor.png, " if drawn else "no maps or motor.png: [output] plots = false; ")
        + f"summary.json), {run.seconds:.1f} s"
    )
    return fit_width("\n".join(lines))


def _screw_need_lines(needs: dict, hz: float) -> list[str]:
    """Per screw group, the settings checked at ``hz`` by the smallest screw that passes
    slip and T3.4 there, and the one that passes at all of them."""
    if not needs:
        return []
    lines = [f"  screws needed at {hz:g} Hz (the smallest that passes; settings that pass the configuration checks):"]
    for name, n in needs.items():
        counts = ", ".join(f"{screw} {k:,}" for screw, k in n["settings"].items())
        every = n["every_setting"]
        said = f"every setting passes with {every}" if every != "none" else "no admitted screw passes at some setting"
        lines.append(f"    {name}: {said} ({counts})")
    return lines


def support_words(result) -> str:
    """How the checked rails are held and where their far joint's bolts are, in words."""
    on_rail = {n: kind_of(n).bolts_on_rail for n, p in result.parts.items()}
    rails = [p for n, p in result.parts.items() if on_rail[n] and p.job.loads.explicit is None]
    plates = [p for n, p in result.parts.items() if not on_rail[n]]
    words = []
    if any(p.job.free_body is not None for p in rails):
        words.append("rails as free bodies (far screws at the bar length)")
    if any(p.job.free_body is None for p in rails):
        words.append(f"rails clamped (bolts {result.scene.check.bolt_position})")
    if any(p.job.free_body is not None for p in plates):
        words.append("joint plates as free bodies")
    if any(p.job.free_body is None for p in plates):
        words.append("plates clamped at their support")
    return ", ".join(words)


def _assumed(scene) -> tuple:
    """The parts' record (None without a [check]) and the components' spec whose
    assumptions a check states."""
    return (None if scene.check is None else parts_input(scene)), scene.components
