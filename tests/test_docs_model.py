"""docs/model.md's figures of the current code, computed here and found in the page (issue 78,
item 6: docs that cannot disagree). Each test renders the phrase the page quotes from the
code's own functions, so a change to the code that moves a figure fails here until the page
says the new figure. The figures of earlier code are in docs/changelog.md with their commits."""

from __future__ import annotations

import json
import math
from dataclasses import replace
from pathlib import Path

import pytest

from railcheck.cli import main
from railcheck.kinematics.checks import transmission_extremes
from railcheck.kinematics.dynamics import inverse_dynamics
from railcheck.kinematics.linkage import FourBar
from railcheck.kinematics.motion import solve_motion
from railcheck.model.inputs import parts_input

PAGE = Path(__file__).resolve().parents[1] / "docs" / "model.md"
SEED_CASES = ((540, 900, 780, 1058), (540, 840, 780, 1020), (480, 840, 780, 1020))  # seed 000, table 3.3.6
JOINTS = ("O2", "A", "B", "O4")


def _text() -> str:
    """The page with its line breaks folded into spaces (a phrase may wrap)."""
    return " ".join(PAGE.read_text().split())


def _peaks(lengths_mm: tuple[int, ...], formulation: str) -> list[float]:
    """Peak reactions at O2, A, B, O4 (N) and the peak motor torque (N m) over one crank
    revolution at 1 Hz in 5000 steps (Anexo I's), seed 000's masses."""
    motion = solve_motion(FourBar(*(x / 1000 for x in lengths_mm)), 2 * math.pi, 5000)
    dyn = inverse_dynamics(motion, formulation)
    return [float(dyn.peak(j)[0]) for j in JOINTS] + [float(dyn.peak_torque()[0])]


@pytest.mark.parametrize("lengths", SEED_CASES)
def test_the_seed_table_rows_are_the_codes(lengths):
    """The railcheck rows beside seed 000's table 3.3.6 (`seed-2013`, 4 decimals)."""
    lo, hi = (math.degrees(v) for v in transmission_extremes(FourBar(*(x / 1000 for x in lengths))))
    cells = [f"{v:.4f}" for v in _peaks(lengths, "seed-2013")] + [f"{hi:.4f} / {lo:.4f}"]
    assert "| railcheck | " + " | ".join(cells) + " |" in PAGE.read_text()


def test_the_newton_euler_peaks_of_the_final_design_are_the_codes():
    ne, seed = _peaks((480, 840, 780, 1020), "newton-euler"), _peaks((480, 840, 780, 1020), "seed-2013")
    names = [f"R_{j}" for j in JOINTS] + ["M2"]
    units = ["N"] * 4 + ["N·m"]
    phrase = ", ".join(f"{n} {v:.1f} {u}" for n, v, u in zip(names, ne, units))
    assert f"{phrase} (against {', '.join(f'{v:.1f}' for v in seed)})" in _text()


def test_the_default_scenes_peak_reactions_and_torque_are_the_codes(capsys):
    """The rail's profile section quotes the built-in scene's peaks (`railcheck kinematics`)."""
    assert main(["kinematics", "--json"]) == 0
    data = json.loads(capsys.readouterr().out)
    reactions = " / ".join(f"{data['peak_reactions_N'][j]:.1f}" for j in JOINTS)
    assert f"reactions O2 / A / B / O4 are {reactions} N, its peak motor torque {data['peak_torque_Nm']:.1f} N·m" in _text()


def test_the_profile_table_is_the_closed_form_sections():
    from railcheck.geometry.catalogue import RAIL, rail_mass_per_metre_with_holes, rail_section

    solid_spec = replace(RAIL, groove_radius=0.0)
    grooved, solid = rail_section(RAIL), rail_section(solid_spec)
    mm2, mm4 = 1e6, 1e12
    drop = lambda a, b: f" ({(b / a - 1) * 100:.0f}%)"  # noqa: E731
    rows = [
        f"| area | {solid.area * mm2:,.0f} mm² | {grooved.area * mm2:,.1f} mm² |",
        f"| mass, with the holes | {rail_mass_per_metre_with_holes(solid_spec):.2f} kg/m | "
        f"{rail_mass_per_metre_with_holes(RAIL):.2f} kg/m |",
        f"| in-plane second moment I_z (bending by the joint forces) | {solid.inertia_in_plane * mm4:,.0f} mm⁴ | "
        f"{grooved.inertia_in_plane * mm4:,.0f} mm⁴{drop(solid.inertia_in_plane, grooved.inertia_in_plane)} |",
        f"| out-of-plane I_y | {solid.inertia_out_of_plane * mm4:,.0f} mm⁴ | "
        f"{grooved.inertia_out_of_plane * mm4:,.0f} mm⁴{drop(solid.inertia_out_of_plane, grooved.inertia_out_of_plane)} |",
    ]
    page = PAGE.read_text()
    for row in rows:
        assert row in page, row


def test_the_default_scenes_weight_figures_are_the_codes():
    """The table-top weight's unfactored moments and forces on the built-in scene."""
    from railcheck.fea.materials import MATERIALS
    from railcheck.loads.weight import joint_forces, shaft_moment
    from railcheck.model.loading import linkage_lengths, load_model
    from railcheck.scene import load_scene

    scene = load_scene(None)
    lengths = linkage_lengths(scene.linkage_spec.linkage)
    models = {
        bar: load_model(parts_input(scene), f"{bar}-rail", MATERIALS["steel"].density)
        for bar in ("crank", "coupler", "rocker")
    }
    crank, rocker = (float(shaft_moment(models[b].weight, lengths)) for b in ("crank", "rocker"))
    first, second, _ = (float(v) for v in joint_forces(models["crank"].weight, lengths))
    on_a, _, on_b = (float(v) for v in joint_forces(models["coupler"].weight, lengths))
    text = _text()
    assert f"the crank's shaft carries {crank:.1f} N·m" in text
    assert f"the rocker's shaft {rocker:.1f} N·m" in text
    assert f"the coupler rests {on_a:.1f} N on A and {on_b:.1f} N on B" in text
    assert f"on the crank {second:.0f} N down on the second screw and {-first:.0f} N up on the first" in text


def _quoted_runs(block: str) -> list[list[str]]:
    """A console block's runs of lines between its ``[...]`` marks (lines left out)."""
    return [[line for line in run.splitlines() if line] for run in block.split("[...]\n")]


def assert_console_quotes(stdout: str, block: str, where: str) -> None:
    """Each run of ``block``'s lines appears, in order and unbroken, in ``stdout``."""
    lines, at = stdout.splitlines(), 0
    for want in _quoted_runs(block):
        found = [k for k in range(at, len(lines) - len(want) + 1) if lines[k : k + len(want)] == want]
        assert found, f"{where} is not the console's: {want}"
        at = found[0] + len(want)


@pytest.fixture(scope="module")
def default_check(tmp_path_factory):
    """One ``railcheck check`` of the built-in scene: (its console, its summary.json)."""
    import subprocess
    import sys

    out = tmp_path_factory.mktemp("docs") / "results"
    proc = subprocess.run(
        [sys.executable, "-P", "-m", "railcheck.cli", "check", "--out", str(out)], capture_output=True, text=True
    )
    assert proc.returncode == 1, proc.stderr  # the default rig fails on its O2 screws' slip
    return proc.stdout, json.loads((out / "summary.json").read_text())


@pytest.mark.slow
def test_the_default_free_body_figures_are_a_fresh_checks(default_check):
    _, summary = default_check
    mpa = {name: p["max_von_mises_Pa"] / 1e6 for name, p in summary["parts"].items()}
    phrase = (
        f"crank rail {mpa['crank-rail']:.1f} MPa, coupler {mpa['coupler-rail']:.1f}, rocker {mpa['rocker-rail']:.1f}, "
        f"PF_4b_006 (the v2 upper plate) {mpa['PF_4b_006']:.1f}, PF_4b_003_v2 {mpa['PF_4b_003_v2']:.1f} MPa"
    )
    text = _text()
    assert phrase in text
    bracket = summary["parts"]["PF_4b_003_v2"]
    where = ", ".join(f"{x * 1000:.1f}" for x in bracket["max_von_mises_location_m"])
    assert f"the peak, {mpa['PF_4b_003_v2']:.1f} MPa at the web's root fillet ({where} mm)" in text
    assert f"(translation and rotation): {bracket['tip_deflection_m'] * 1000:.3f} mm." in text


@pytest.mark.slow
def test_the_components_pages_default_rig_is_a_fresh_checks_console(default_check):
    """docs/components.md's console block under "The default rig" is the check's console."""
    page = (PAGE.parent / "components.md").read_text()
    block = page.split("## The default rig", 1)[1].split("```\n", 2)[1]
    assert_console_quotes(default_check[0], block, "docs/components.md's default rig")


def test_the_components_pages_clamps_are_the_codes():
    """docs/components.md's VDI 2230 clamps: an M6 8.8 and the strongest M6 (12.9) tightened
    with a torque wrench, the default assumptions."""
    from railcheck.components import screws
    from railcheck.components.ratings import COMPONENT_SPEC

    m6 = screws.THREADS["M6"]
    kn = {c: screws.least_clamp(m6, screws.CLASSES[c], COMPONENT_SPEC) / 1000 for c in ("8.8", "12.9")}
    text = " ".join((PAGE.parent / "components.md").read_text().split())
    assert f"An M6 8.8 at μ_G 0.12 clamps {kn['8.8']:.1f} kN this way" in text
    assert f"an M6 8.8 tightened with a torque wrench clamps {kn['8.8']:.1f} kN" in text
    assert f"the strongest screw the rail's hole admits (M6 12.9) {kn['12.9']:.1f} kN" in text


def test_the_components_pages_motor_couple_is_the_codes(capsys):
    """The peak motor torque (N m) of the built-in scene over the O2 screws' 60 mm pitch."""
    assert main(["kinematics", "--json"]) == 0
    torque = json.loads(capsys.readouterr().out)["peak_torque_Nm"]
    text = " ".join((PAGE.parent / "components.md").read_text().split())
    per_screw = torque / 0.060 / 1000  # kN: the couple over the 60 mm pitch
    assert f"The peak motor torque, {torque:.0f} N m, over the two O2 screws 60 mm apart is {per_screw:.1f} kN" in text


@pytest.mark.slow
def test_the_fe_accuracy_table_is_the_cantilever_benchmarks(capsys):
    """Each row of "FE accuracy": `railcheck bench cantilever --order P --size S --json`."""
    page = PAGE.read_text()
    rows = [line for line in page.split("## FE accuracy", 1)[1].splitlines() if line.startswith("| P")]
    assert len(rows) == 5
    for row in rows:
        order, size = row.split("|")[1].strip()[1:], row.split("|")[2].strip().removesuffix(" mm")
        assert main(["bench", "cantilever", "--order", order, "--size", size, "--json"]) == 0
        got = json.loads(capsys.readouterr().out)
        cells = [c.strip() for c in row.strip("|").split("|")]
        assert cells[2] == f"{got['dofs']:,}", row
        printed = cells[3].removesuffix("%")
        digits = len(printed.split(".")[1])
        assert printed == f"{got['relative_error'] * 100:.{digits}f}", row
    assert f"Timoshenko {got['analytic_m'] * 1000:.6f} mm" in page


@pytest.mark.slow
def test_the_readmes_hand_check_quotes_a_fresh_check(default_check):
    """The README's hand check of the crank rail and its rocker sentence: the peak instant,
    the FE's peak and where it is (mm), the rocker's peak (MPa), from the check's summary."""
    _, summary = default_check
    crank, rocker = summary["parts"]["crank-rail"], summary["parts"]["rocker-rail"]
    x, y, z = (v * 1000 for v in crank["max_von_mises_location_m"])
    text = " ".join((PAGE.parents[1] / "README.md").read_text().split())
    assert f"At the peak instant ({crank['crank_angle_deg']:.1f} deg)" in text
    assert f"The FE's peak, {crank['max_von_mises_Pa'] / 1e6:.1f} MPa, is" in text
    assert f"(x = {x:.0f}, y = {y:.1f}, z = {z:.1f} mm)" in text
    assert f"loads it most: {rocker['max_von_mises_Pa'] / 1e6:.0f} MPa at its second hole" in text
