"""`railcheck check`: load cases, staged pipeline, outputs, verdicts."""

import ast
import json
import math
import pickle
import re
import subprocess
import sys
import tomllib
from dataclasses import replace

import numpy as np
import pytest
from hypothesis import given, settings
from hypothesis import strategies as st

from helpers import FINAL_DESIGN, PLATE_LOADS, assert_picture, browse, check_exit_status
from railcheck.check.pipeline import run_pipeline
from railcheck.check.summary import rail_masses
from railcheck.fea.errors import ModelError
from railcheck.loads.rotation import to_rail_axes
from railcheck.model.inputs import parts_input
from railcheck.model.jobs import build_load_cases, part_geometries
from railcheck.model.kinematics_stage import kinematics_input, run_kinematics
from railcheck.parts import geometry_of
from railcheck.scene import load_scene, parse_scene

KINEMATICS_ONLY = FINAL_DESIGN + 'speed = "1 Hz"\n'

PLATE_ONLY = (
    PLATE_LOADS
    + """[mesh]
order = 2
size = "8 mm"
hole_size = "4 mm"
"""
)

COARSE_CRANK = (
    KINEMATICS_ONLY
    + """
[check]
parts = ["crank-rail"]
factor = FACTOR
[mesh]
order = 2
size = "20 mm"
hole_size = "6 mm"
"""
)


def test_rotation_unit_cases():
    f = np.array([3.0, 4.0])
    np.testing.assert_allclose(to_rail_axes(f, 0.0), [3.0, 4.0], atol=1e-15)
    np.testing.assert_allclose(to_rail_axes(f, math.pi / 2), [4.0, -3.0], atol=1e-15)
    np.testing.assert_allclose(to_rail_axes(f, math.pi), [-3.0, -4.0], atol=1e-15)


@given(st.floats(-1e4, 1e4), st.floats(-1e4, 1e4), st.floats(-20.0, 20.0))
@settings(max_examples=200, deadline=None)
def test_rotation_preserves_magnitude(fx, fy, theta):
    out = to_rail_axes(np.array([fx, fy]), theta)
    assert math.hypot(*out) == pytest.approx(math.hypot(fx, fy), rel=1e-12, abs=1e-9)


def test_load_cases_sum_to_factor_times_peak_reaction():
    """The clamped (2013) model's load case: the factored peak reaction at the worst bolts."""
    scene = load_scene(None)
    scene = replace(scene, check=replace(scene.check, support="clamped"))
    kin = run_kinematics(kinematics_input(scene))
    cases = build_load_cases(parts_input(scene), kin, part_geometries(parts_input(scene)))
    dyn, th = kin.dynamics, kin.motion.theta
    expected = {
        "crank-rail": (-dyn.reactions["A"], th[:, 0]),
        "coupler-rail": (-dyn.reactions["B"], th[:, 1]),
        "rocker-rail": (dyn.reactions["B"], th[:, 2]),
    }
    for part, (force, angle) in expected.items():
        k = int(np.argmax(np.hypot(force[:, 0], force[:, 1])))
        want = 1.4 * to_rail_axes(force[k], angle[k])
        got = cases[part].total_force[:2]
        assert np.linalg.norm(got - want) <= 1e-10 * np.linalg.norm(want)
        assert len(cases[part].bolts) == 2
        # worst position: the last two holes of the rail
        n = len(part_geometries(parts_input(scene))[part].get("hole_x"))
        assert [b.group for b in cases[part].bolts] == [f"hole_{n - 2}", f"hole_{n - 1}"]
    plate = cases["PF_4b_003_v2"]
    assert [b.force for b in plate.bolts] == [(250.0, 250.0, 0.0)] * 4


def test_actual_bolt_position_is_at_the_bar_length():
    scene = load_scene(None)
    scene = replace(scene, check=replace(scene.check, bolt_position="actual"))
    cases = build_load_cases(
        parts_input(scene), run_kinematics(kinematics_input(scene)), part_geometries(parts_input(scene))
    )
    # crank 480 mm from the shaft hole (x = 20 mm): the hole at x = 500 mm is hole 8
    assert [b.group for b in cases["crank-rail"].bolts] == ["hole_8", "hole_9"]
    assert [b.group for b in cases["coupler-rail"].bolts] == ["hole_14", "hole_15"]


@pytest.mark.slow  # pin pressures doubled its cost (cold: the bracket's 5 s): out of the fast tier
def test_stages_run_kinematics_only_and_plate_only():
    r = run_pipeline(parse_scene(tomllib.loads(KINEMATICS_ONLY)))
    assert list(r.stages_run) == ["scene", "kinematics", "report"]
    r = run_pipeline(parse_scene(tomllib.loads(PLATE_ONLY)))
    assert list(r.stages_run) == ["scene", "loads", "geometry", "mesh", "solve", "stress", "report"]
    assert r.kinematics is None
    part = r.parts["PF_4b_003_v2"]
    assert [b.force for b in part.job.load_case.bolts] == [(250.0, 250.0, 0.0)] * 4  # 1000 N along x and y
    # a free body on its foundation (the default support): the hole loads and the base's reaction balance
    assert part.job.loads.is_on_foundation
    np.testing.assert_allclose(sum(part.solution.applied_forces.values()), 0.0, atol=1e-8)


def test_kinematics_only_run_imports_no_heavy_module(tmp_path):
    scene = tmp_path / "k.toml"
    scene.write_text(KINEMATICS_ONLY)
    code = (
        f"import sys; from railcheck.cli import main; rc = main(['check', {str(scene)!r}, '--out', "
        f"{str(tmp_path / 'out')!r}, '--json']); heavy = sorted(m for m in sys.modules if m.split('.')[0] "
        "in ('gmsh', 'skfem', 'pyvista', 'vtk', 'meshio', 'pyamg')); print('HEAVY', heavy, rc, file=sys.stderr)"
    )
    proc = subprocess.run([sys.executable, "-P", "-c", code], capture_output=True, text=True)
    assert "HEAVY [] 0" in proc.stderr, proc.stderr
    summary = json.loads(proc.stdout)
    assert summary["stages_run"] == ["scene", "kinematics", "report"]
    assert summary["verdict"] == "NO CHECK"


def test_reading_a_scene_loads_no_fe_solver():
    """A scene is validated before anything is solved: reading one imports none of scipy
    and none of our FE stack beyond the fatigue criteria, the materials and von Mises
    (numpy-only modules), so a bad scene is refused at once."""
    code = (
        "import sys; from railcheck.scene import load_scene; load_scene(None); "
        "print(sorted(m for m in sys.modules if m.startswith(('scipy', 'railcheck.fea'))))"
    )
    proc = subprocess.run([sys.executable, "-P", "-c", code], capture_output=True, text=True, check=True)
    loaded = ast.literal_eval(proc.stdout)
    assert loaded == ["railcheck.fea", "railcheck.fea.fatigue", "railcheck.fea.invariants", "railcheck.fea.materials"]


@pytest.mark.slow
def test_factor_doubles_the_stress():
    out = {}
    for factor in (1.4, 2.8):
        r = run_pipeline(parse_scene(tomllib.loads(COARSE_CRANK.replace("FACTOR", str(factor)))))
        out[factor] = r.parts["crank-rail"].solution
    assert out[2.8].max_von_mises == pytest.approx(2 * out[1.4].max_von_mises, rel=1e-9)
    assert out[2.8].max_von_mises_away == pytest.approx(2 * out[1.4].max_von_mises_away, rel=1e-9)
    assert out[2.8].tip_deflection == pytest.approx(2 * out[1.4].tip_deflection, rel=1e-9)


def test_gravity_only_when_listed():
    base = parse_scene(tomllib.loads(COARSE_CRANK.replace("FACTOR", "1.4")))
    assert run_kinematics(kinematics_input(base)).effects == ("inertia",)
    grav = replace(base, check=replace(base.check, effects=("inertia", "gravity")))
    assert run_kinematics(kinematics_input(grav)).effects == ("inertia", "gravity")
    still = replace(base, mechanism=replace(base.mechanism, speed=0.0))
    r = run_kinematics(kinematics_input(still))
    assert r.effects == () and all(np.all(x == 0) for x in r.dynamics.reactions.values())


@pytest.mark.slow
def test_default_check_end_to_end(tmp_path):
    import meshio

    out = tmp_path / "results"
    proc = subprocess.run(
        [sys.executable, "-P", "-m", "railcheck.cli", "check", "--out", str(out)],
        capture_output=True,
        text=True,
        cwd=tmp_path,
    )
    assert proc.returncode == check_exit_status(out) == 1, proc.stderr  # the built-in scene fails (O2 slip)
    counts = [int(k) for k in re.findall(r"\((\d)/5\) ", proc.stderr)]
    assert sorted(set(counts)) == [1, 2, 3, 4, 5]
    assert [k for i, k in enumerate(counts) if k not in counts[:i]] == [1, 2, 3, 4, 5]  # the parts count up
    summary = json.loads((out / "summary.json").read_text())
    stages = ["scene", "kinematics", "components", "loads", "geometry", "mesh", "solve", "stress", "report"]
    assert summary["stages_run"] == stages
    parts = ["crank-rail", "coupler-rail", "rocker-rail", "PF_4b_006", "PF_4b_003_v2"]
    assert list(summary["parts"]) == parts
    assert len(summary["components"]) == 16  # the default lists every joint component
    assert (out / "joints.png").exists() and all((out / f"{n}-utilisation.png").exists() for n in parts)
    for name in parts:
        m = meshio.read(out / f"{name}.vtu")
        assert m.point_data["displacement"].shape[1] == 3 and "von_mises" in m.point_data
        assert_picture(out / f"{name}.png", min_size=(1000, 500))
        if name != "PF_4b_003_v2":  # constant explicit loads: no cycle to plot
            assert_picture(out / f"{name}-cycle.png")
        assert m.cells[0].type == "tetra10"  # every P2 node
        env, zone = m.point_data["von_mises_envelope"], m.point_data["verdict_zone"] > 0
        # what ParaView shows = the report: the check finds the peaks on the nodes that can hold them,
        # the VTU evaluates every node; the same products, rounded by BLAS on differently shaped blocks
        assert env.max() == pytest.approx(summary["parts"][name]["support_peak_von_mises_Pa"], rel=1e-13)
        assert env[zone].max() == pytest.approx(summary["parts"][name]["max_von_mises_Pa"], rel=1e-13)
        vm = m.point_data["von_mises"]
        assert np.isfinite(vm).all() and vm.max() > 0
        assert m.point_data["von_mises_envelope"].max() >= vm.max() * (1 - 1e-12)
        p = summary["parts"][name]
        assert set(p) >= {"max_von_mises_Pa", "tip_deflection_m", "limit_Pa", "pass", "factor_of_safety"}
        seed = p["load_case"] if "load_case" in p else p["seed_load_case"]  # a free body's is the 2013 case
        assert ("seed_load_case" in p) == (p.get("support", {}).get("model") == "free-body")
        bolts = seed["bolts"]  # every bolt's force, not a count
        assert isinstance(bolts, dict) and all(len(f) == 3 for f in bolts.values())
        for load in p["loads_at_governing_instant"]:  # as applied, and without the factor
            assert np.allclose(np.array(load["applied_N"]), load["factor"] * np.array(load["unfactored_N"]))
        assert p["factor_of_safety"] == pytest.approx(p["limit_Pa"] / p["max_von_mises_Pa"], rel=1e-12)
        # the console shows the same figures
        line = next(l for l in proc.stdout.splitlines() if l.strip().startswith(name + " "))
        cells = line.split()
        assert f"{p['max_von_mises_Pa'] / 1e6:.1f}" == cells[1]  # the header gives the unit (MPa)
        assert f"{p['tip_deflection_m'] * 1e3:.2f}" in cells
        assert ("PASS" if p["pass"] else "FAIL") in line
    assert proc.returncode == (0 if summary["verdict"] == "PASS" else 1)
    assert_readme_example_is(proc.stdout)
    assert all(len(line) <= 100 for line in proc.stdout.splitlines() if not line.startswith("results in"))
    # one self-contained report: tables and every picture inline, as a browser shows it
    page = (out / "report.html").read_text()
    assert "http://" not in page and "https://" not in page and "<script" not in page
    dom = browse(out / "report.html", tmp_path, "--dump-dom").stdout
    # a von Mises and a utilisation picture per part, a cycle plot per part but the constant-load
    # PF_4b_003_v2, two kinematics plots, the joints' load paths
    assert (
        dom.count("<table") >= 5 and dom.count("data:image/png;base64,") == 2 * len(parts) + (len(parts) - 1) + 2 + 1 + 1
    )  # + linkage.png
    assert all(name in dom for name in parts) and ("PASS" in dom or "FAIL" in dom)
    shot = tmp_path / "report.png"
    browse(out / "report.html", tmp_path, "--window-size=1400,1600", f"--screenshot={shot}")
    assert_picture(shot, min_size=(1400, 1600), min_colours=200)
    assert (out / "parts.pvd").read_text().count("<DataSet") == len(parts)
    # a second run never overwrites the first
    again = subprocess.run(
        [sys.executable, "-P", "-m", "railcheck.cli", "check", "--out", str(out), "--json"],
        capture_output=True,
        text=True,
        cwd=tmp_path,
    )
    assert (tmp_path / "results-2" / "summary.json").exists()
    # determinism: the same scene gives a byte-identical summary
    assert (tmp_path / "results-2" / "summary.json").read_bytes() == (out / "summary.json").read_bytes()
    assert json.loads(again.stdout)["parts"] == summary["parts"]


def assert_readme_example_is(stdout: str) -> None:
    """The README's worked example is this console as printed: each run of its lines
    between the ``[...]`` marks (lines left out) appears, in order and unbroken, in
    ``stdout``."""
    from pathlib import Path

    readme = (Path(__file__).parents[1] / "README.md").read_text()
    block = readme.split("## Worked example", 1)[1].split("```\n", 2)[1]
    lines, at = stdout.splitlines(), 0
    for run in block.split("  [...]\n"):
        want = [line for line in run.splitlines() if line]
        found = [k for k in range(at, len(lines) - len(want) + 1) if lines[k : k + len(want)] == want]
        assert found, f"the README's worked example is not the console's: {want}"
        at = found[0] + len(want)


def test_rail_mass_is_reported_beside_the_seeds():

    m = rail_masses(load_scene(None).geometry)
    assert m["model_with_holes"] < m["model_section"] < 0.023 * 0.022 * 7850
    # the grooved profile with its holes within 3% of the catalogues' 3.1-3.2 kg/m (issue 21)
    assert 0.97 * 3.2 <= m["model_with_holes"] <= 1.03 * 3.1
    assert m["seed 000 (Anexo I)"] == 2.7 and m["HIWIN HGR25 catalogue"] == 3.21
    assert m["dynamics"] == m["model_with_holes"]  # one mass model
    assert rail_masses({}, "seed-2013")["dynamics"] == 2.7  # the 2013 tables keep theirs


def test_the_grooved_section_in_closed_form_equals_a_fine_grid():
    """Area, centroid and both second moments of the grooved profile against a 2000 x 2000
    midpoint grid over the 23 x 22 mm rectangle with the four discs removed (1e-4)."""
    from railcheck.geometry.catalogue import RAIL, rail_section

    n = 2000
    y = (np.arange(n) + 0.5) / n * RAIL.width - RAIL.width / 2
    z = (np.arange(n) + 0.5) / n * RAIL.height
    Y, Z = np.meshgrid(y, z)
    inside = np.ones_like(Y, dtype=bool)
    for zg in (RAIL.lower_groove_z, RAIL.upper_groove_z):
        for yc in (-RAIL.width / 2, RAIL.width / 2):
            inside &= (Y - yc) ** 2 + (Z - zg) ** 2 > RAIL.groove_radius**2
    dA = RAIL.width * RAIL.height / n**2
    area = inside.sum() * dA
    zc = (Z * inside).sum() * dA / area
    s = rail_section(RAIL)
    assert s.area == pytest.approx(area, rel=1e-4)
    assert s.centroid_z == pytest.approx(zc, rel=1e-4)
    assert s.inertia_in_plane == pytest.approx((Y**2 * inside).sum() * dA, rel=1e-4)
    assert s.inertia_out_of_plane == pytest.approx(((Z - zc) ** 2 * inside).sum() * dA, rel=1e-4)
    # no grooves: the rectangle
    solid = rail_section(replace(RAIL, groove_radius=0.0))
    assert solid.inertia_in_plane == pytest.approx(RAIL.height * RAIL.width**3 / 12, rel=1e-12)


def test_the_meshed_rail_weighs_what_the_closed_form_section_says():
    """A rail on the default check's curved P2 mesh (10 mm, 4 mm at the holes, the grooves
    as the check meshes them): its volume (the FE's own mass matrix) per metre against the
    closed-form grooved section less its holes, to 1%; and the dynamics carry that mass (one
    mass model), the 2013 formulation the seed's 2.7 kg/m. 300 mm of rail, not the crank
    rail's 700: the same section and holes, meshed in 3 s instead of 9 with every cache cold."""
    from railcheck.fea.elasticity import assemble, mass_matrix
    from railcheck.fea.materials import MATERIALS
    from railcheck.geometry import mesh_part, rail, rail_mass_per_metre_with_holes
    from railcheck.parts import mass_model

    geo = rail(0.3)
    mesh = mesh_part(geo, 10e-3, 4e-3)
    _, basis = assemble(mesh.points, mesh.tets, MATERIALS["steel"], 2, mesh.curved)
    volume = mass_matrix(basis).sum()
    holes = len(geo.get("hole_x")) * math.pi / 4 * (7e-3**2 * 13e-3 + 11e-3**2 * 9e-3)
    # 0.5% over: the few curved edges straightened to keep elements from folding (chords
    # across the grooves); without untangling it is 5% (benchmarks/groove_mesh.py)
    assert volume == pytest.approx(geo.section.area * 0.3 - holes, rel=1e-2)
    assert mass_model("newton-euler", {}).rail_mass_per_m == rail_mass_per_metre_with_holes()
    assert mass_model("seed-2013", {}).rail_mass_per_m == 2.7


def test_a_rail_without_grooves_is_a_solid_rectangle_of_its_width_and_height():
    """``[geometry] rail_groove_radius = "0 mm"`` (the catalogue's "no grooves"): the scene
    takes it, the section is the 23 x 22 mm rectangle, and the meshed rail's volume is that
    rectangle's less the holes, to 1% (at 6 mm the holes' curved edges fold and are
    straightened: faceted holes, 8% of their volume, said in the mesh's warning); zero is
    still refused for any other dimension, and a negative radius too."""
    from railcheck.base.errors import InputError
    from railcheck.fea.elasticity import assemble, mass_matrix
    from railcheck.fea.materials import MATERIALS
    from railcheck.geometry import mesh_part

    scene = parse_scene(tomllib.loads(FINAL_DESIGN + '[geometry]\nrail_groove_radius = "0 mm"\n'), "test")
    geo = geometry_of("crank-rail", scene.geometry)
    assert geo.section.area == pytest.approx(23e-3 * 22e-3, rel=1e-12)
    mesh = mesh_part(geo, 20e-3, 6e-3)
    _, basis = assemble(mesh.points, mesh.tets, MATERIALS["steel"], 2, mesh.curved)
    holes = len(geo.get("hole_x")) * math.pi / 4 * (7e-3**2 * 13e-3 + 11e-3**2 * 9e-3)
    assert mass_matrix(basis).sum() == pytest.approx(23e-3 * 22e-3 * 0.7 - holes, rel=1e-2)
    assert "straightened" in mesh.warning
    for text in ('rail_width = "0 mm"', 'rail_groove_radius = "-1 mm"'):
        with pytest.raises(InputError, match="geometry.rail_"):
            parse_scene(tomllib.loads(FINAL_DESIGN + f"[geometry]\n{text}\n"), "test")


@pytest.mark.slow
def test_parts_in_worker_processes_equal_parts_in_this_process():
    """Two parts on two worker processes (spawned) give exactly the serial results, and a
    worker's error reaches the caller as the same exception with its field."""

    scene = parse_scene(
        tomllib.loads(
            COARSE_CRANK.replace("FACTOR", "1.4").replace('parts = ["crank-rail"]', 'parts = ["crank-rail", "coupler-rail"]')
        )
    )
    serial = run_pipeline(scene, jobs=1)
    parallel = run_pipeline(scene, jobs=2)
    assert list(parallel.parts) == list(serial.parts) == ["crank-rail", "coupler-rail"]
    for name in serial.parts:
        a, b = serial.parts[name].cycle, parallel.parts[name].cycle
        assert a.envelope.max_von_mises == b.envelope.max_von_mises
        assert a.envelope.max_tip == b.envelope.max_tip
        assert a.fatigue.min_safety_factor == b.fatigue.min_safety_factor
    error = ModelError("hole_9", "no such group")
    again = pickle.loads(pickle.dumps(error))
    assert type(again) is ModelError and (again.field, str(again)) == ("hole_9", str(error))


def test_each_part_is_resolved_once_into_a_picklable_job_without_the_scene():
    """Downstream stages take the job: it pickles whole (worker processes), carries no
    Scene, and holds what the scene asked for (mesh sizes, holes, histories, limits)."""
    import dataclasses
    import pickle

    from railcheck.fea.materials import MATERIALS
    from railcheck.model.jobs import build_load_cases, part_jobs
    from railcheck.scene import Scene

    scene = load_scene(None)
    kin = run_kinematics(kinematics_input(scene))
    geos = part_geometries(parts_input(scene))
    steel = MATERIALS["steel"]
    jobs = part_jobs(parts_input(scene), kin, geos, build_load_cases(parts_input(scene), kin, geos), steel, 375e6)
    assert list(jobs) == list(scene.check.parts)

    def values(x):
        if dataclasses.is_dataclass(x):
            for f in dataclasses.fields(x):
                yield from values(getattr(x, f.name))
        elif isinstance(x, (tuple, list)):
            for v in x:
                yield from values(v)
        yield x

    for name, job in jobs.items():
        assert not any(isinstance(v, Scene) for v in values(job))
        back = pickle.loads(pickle.dumps(job))
        assert back.name == name and back.holes == job.holes and back.mesh == job.mesh
        for h, g in zip(back.histories, job.histories):
            np.testing.assert_array_equal(h.C, g.C)
    crank = jobs["crank-rail"]
    assert (crank.mesh.size, crank.mesh.hole_size, crank.mesh.order) == (10e-3, 4e-3, 2)
    # the default free body: pin x/y, motor torque, bolts x/y, body x/y, rotational, radial, the table-top
    # rig's weight out of plane (body z, pin z, driving pin z, bolts z), then the pin pressures' harmonics
    # on its four loaded holes (the shaft's and the driving pin's, the far joint's two bolts)
    from railcheck.fea.pin_pressure import harmonic_names
    from railcheck.loads.pin_pressure import HARMONICS

    per_hole = len(harmonic_names(HARMONICS))
    assert crank.limit == 375e6 and crank.loads.factor == 1.4 and crank.histories[0].C.shape == (5000, 9 + 4 + 4 * per_hole)
    assert crank.free_body is not None and crank.loads.is_free_body
    assert jobs["PF_4b_006"].mesh.size == 6e-3 and len(jobs["PF_4b_006"].histories) == 2


def _crank_check_without_inertia(tmp_path, effects: str, speed: str = "1 Hz"):
    """(exit status, summary.json) of `railcheck check` of the free crank rail of the final
    design on its table top, [check] ``effects`` at crank ``speed``."""
    from helpers import FINAL_DESIGN
    from railcheck.cli import main

    scene = tmp_path / "s.toml"
    scene.write_text(
        FINAL_DESIGN + f'speed = "{speed}"\nsteps = 360\n[check]\nparts = ["crank-rail"]\neffects = {effects}\n'
        "[output]\nvtk = false\npng = false\nplots = false\n"
    )
    status = main(["check", str(scene), "--out", str(tmp_path / "out")])
    return status, json.loads((tmp_path / "out" / "summary.json").read_text())


@pytest.fixture(scope="module")
def weight_alone(tmp_path_factory):
    """The crank rail under its weight alone, at 3 Hz: what no listed inertia leaves."""
    return _crank_check_without_inertia(tmp_path_factory.mktemp("weight"), "[]", "3 Hz")[1]["parts"]["crank-rail"]


@pytest.mark.slow  # two crank-rail checks, 10-20 s
@pytest.mark.parametrize("effects", ["[]", '["rail-inertia"]', '["rail-inertia", "rail-inertia"]'])
def test_a_check_without_inertia_runs_and_gives_a_verdict(tmp_path, effects, weight_alone):
    """A scene whose effects include no inertia loads each part by one source (issue 61:
    an IndexError before, exit 1 read as a FAIL): the check runs, its exit status its
    verdict. On the table top the weight alone acts, whatever the crank speed: a free
    rail's "rail-inertia" is the free body's own inertia, which comes with "inertia", and
    the point masses its joints carry get no d'Alembert force without it (their -m a
    reached the crank's far screws at any speed before: 35 N at 1 Hz, 139 N at 2 Hz)."""
    status, summary = _crank_check_without_inertia(tmp_path, effects)
    assert status == check_exit_status(tmp_path / "out") == 0 and summary["verdict"] == "PASS"
    assert summary["safe_speed"] == {"Hz": None, "set_by": None, "criterion": None}  # no speed limits it
    part = summary["parts"]["crank-rail"]
    assert part["max_von_mises_Pa"] > 30e6  # the weight's: the crank cantilevered from its shaft
    for key in ("max_von_mises_Pa", "tip_deflection_m", "utilisation"):
        assert part[key] == pytest.approx(weight_alone[key], rel=1e-12), key
    for load in part["loads_at_governing_instant"]:  # nothing in the plane but the weight's share
        assert load["unfactored_N"][:2] == pytest.approx([0.0, 0.0], abs=1e-9), load["name"]
