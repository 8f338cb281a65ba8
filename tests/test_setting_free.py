"""Issue 59: a free rail is solved once for every setting (railcheck.fea.holebasis,
railcheck.model.setting_free). Its setting's load vectors are exact combinations of the
hole basis's; fields projected from the basis equal a direct solve of the setting's own
cases (superposition against a direct solve); and a check of another setting after one
check solves nothing (a spy on the solver) and writes what a cold check of that setting
writes."""

import json
import tomllib

import numpy as np
import pytest

from helpers import COARSE_RAILS, FINAL_DESIGN
from railcheck.fea.elasticity import assemble
from railcheck.fea.holebasis import hole_basis, project, surface_nodes
from railcheck.fea.materials import MATERIALS
from railcheck.fea.mesh import group_nodes, node_cells
from railcheck.fea.unitcases import case_matrix, solve_unit_cases
from railcheck.model.inputs import parts_input


def _scene(crank="480 mm", coupler="840 mm", rocker="780 mm", effects='["inertia", "gravity", "rail-inertia"]', parts=None):
    mechanism = FINAL_DESIGN.replace("480 mm", crank).replace("840 mm", coupler).replace("780 mm", rocker)
    parts = parts or '["crank-rail", "coupler-rail"]'
    return (
        mechanism
        + f'speed = "1 Hz"\nsteps = 180\nplane = "vertical"\n[check]\nparts = {parts}\n'
        + f"effects = {effects}\n"
        + COARSE_RAILS
    )


def _rail_job(name="crank-rail", text=None):
    """The check's job for one free rail of the coarse scene, and its mesh."""
    from railcheck.api import scene_of
    from railcheck.model.cycle import job_mesh
    from railcheck.model.jobs import build_load_cases, part_geometries, part_jobs
    from railcheck.model.kinematics_stage import kinematics_input, run_kinematics

    scene = scene_of(text or _scene())
    kin = run_kinematics(kinematics_input(scene))
    geometries = part_geometries(parts_input(scene))
    cases = build_load_cases(parts_input(scene), kin, geometries)
    job = part_jobs(parts_input(scene), kin, geometries, cases, MATERIALS["steel"], 375e6)[name]
    return job, job_mesh(job)


@pytest.fixture(scope="module")
def crank():
    from railcheck.model.loading import unit_cases

    job, mesh = _rail_job()
    return job, mesh, unit_cases(job.loads, job.geometry, list(job.holes))


def _holes(job):
    return [f"hole_{k}" for k in range(len(job.geometry.get("hole_x")))]


def test_a_settings_load_vectors_are_combinations_of_the_hole_basis(crank):
    """Every case of the crank (pins, the motor's couple, the far bolts shared by the lever
    rule, pin pressures, body and weight cases) is its transform's combination of the
    basis's load vectors, assembled independently."""
    job, mesh, cases = crank
    basis = hole_basis(cases, _holes(job))
    _, fe = assemble(mesh.points, mesh.tets, job.material, 1, None)
    direct = case_matrix(fe, mesh.groups, cases, job.free_body)
    combined = case_matrix(fe, mesh.groups, basis.cases, job.free_body) @ basis.transform
    scale = np.abs(direct).max(axis=0)
    assert np.all(np.abs(combined - direct).max(axis=0) <= 1e-12 * scale)
    assert len(basis.cases) > len(cases)  # every hole, not only the setting's
    with pytest.raises(ValueError, match="lacks"):
        hole_basis(cases, _holes(job)[:-3])  # a basis without the setting's far holes


def test_fields_projected_from_the_basis_equal_a_direct_solve(crank):
    """Superposition against a direct solve: the setting's cases solved as they are, and
    projected from the basis solved with every far pair's deflection, give the same
    stresses, displacements, deflection, resultants and loaded nodes."""
    from dataclasses import replace

    from railcheck.model.setting_free import pair_deflections

    job, mesh, cases = crank
    basis = hole_basis(cases, _holes(job))
    kw = {"order": 1, "tip_group": job.tip}
    direct, d_solve = solve_unit_cases(mesh, job.material, [], cases, free_body=job.free_body, **kw)
    solved, b_solve = solve_unit_cases(
        mesh,
        job.material,
        [],
        basis.cases,
        free_body=replace(job.free_body, deflection=pair_deflections(job.loads, job.geometry)),
        **kw,
    )
    loaded = surface_nodes(solved.cells, [mesh.groups[g] for g in sorted({"hole_0", "hole_1", *job.holes})])
    fields, solve = project(solved, b_solve, basis, tuple(cases), tuple(job.holes), loaded)
    for name in ("stress", "displacement", "tip"):
        want, got = getattr(direct, name), getattr(fields, name)
        assert np.abs(got - want).max() <= 1e-9 * np.abs(want).max(), name
    np.testing.assert_allclose(solve.resultants, d_solve.resultants, atol=1e-9)
    np.testing.assert_array_equal(fields.loaded, direct.loaded)
    assert fields.names == direct.names


def test_surface_nodes_are_the_group_nodes_without_a_basis(crank):
    job, mesh, _ = crank
    _, fe = assemble(mesh.points, mesh.tets, job.material, 2, None)
    for g in ("hole_0", job.holes[-1]):
        np.testing.assert_array_equal(surface_nodes(node_cells(fe), [mesh.groups[g]]), group_nodes(fe, mesh.groups, [g]))


def _check(tmp_path, label, text, monkeypatch, cache):
    """summary.json of a check of ``text`` (its scene file named by the text: the same
    scene, the same file) with its cache in ``cache``, out in ``label``."""
    from railcheck.api import check

    monkeypatch.setenv("RAILCHECK_CACHE", str(cache))
    scene = tmp_path / f"{abs(hash(text))}.toml"
    scene.write_text(text)
    check(str(scene), out=tmp_path / label, jobs=1)
    return json.loads((tmp_path / label / "summary.json").read_text())


def test_another_setting_after_a_check_solves_nothing_and_equals_its_cold_check(tmp_path, monkeypatch, cache_with_meshes):
    """A check of the default setting fills the store; a check of 420/900/720 mm then
    assembles and solves nothing (every solve counted) and writes the summary a check of
    that setting from an empty store writes."""
    import railcheck.fea.store as store

    solves = []
    real = store.solve_unit_cases

    def counted(*args, **kw):
        solves.append(args[3].keys())
        return real(*args, **kw)

    monkeypatch.setattr(store, "solve_unit_cases", counted)
    crank = '["crank-rail"]'  # the coupler's sharing is the sweep test's (slow tier)
    other = _scene("420 mm", "900 mm", "720 mm", parts=crank)
    cache, empty = (cache_with_meshes(tmp_path / name) for name in ("cache", "empty"))  # no unit fields
    _check(tmp_path, "first", _scene(parts=crank), monkeypatch, cache)
    assert len(solves) == 1
    solves.clear()
    warm = _check(tmp_path, "warm", other, monkeypatch, cache)
    assert solves == []
    cold = _check(tmp_path, "cold", other, monkeypatch, empty)
    assert len(solves) == 1
    assert warm == cold
    first = json.loads((tmp_path / "first" / "summary.json").read_text())
    assert first["parts"]["crank-rail"]["max_von_mises_Pa"] != warm["parts"]["crank-rail"]["max_von_mises_Pa"]


def test_a_second_rail_of_one_size_is_checked_last(monkeypatch):
    """The coupler and rocker rails (both 1000 mm) share one hole basis: the second is
    taken last, so it reads the first's fields instead of solving them beside it."""
    from railcheck.api import scene_of
    from railcheck.check.workers import shared_fields, work_order
    from railcheck.model.jobs import build_load_cases, part_geometries, part_jobs
    from railcheck.model.kinematics_stage import kinematics_input, run_kinematics

    scene = scene_of(None)
    kin = run_kinematics(kinematics_input(scene))
    geometries = part_geometries(parts_input(scene))
    jobs = part_jobs(
        parts_input(scene), kin, geometries, build_load_cases(parts_input(scene), kin, geometries), MATERIALS["steel"], 375e6
    )
    order = work_order(jobs)
    # costliest first, the coupler's by its group (+ the rocker, which waits for it); since the
    # element estimate counts the rails' grooves (issue 79) a rail's cost is its mesh's
    # (21.7k elements on the crank, 12.2k on PF_4b_006), so the crank precedes the plate
    assert order == ["coupler-rail", "PF_4b_003_v2", "crank-rail", "PF_4b_006", "rocker-rail"]
    assert shared_fields(jobs) == {"rocker-rail": "coupler-rail"}  # the crank rail: another size, another basis
    monkeypatch.setenv("RAILCHECK_STORE", "0")
    assert shared_fields(jobs) == {}  # nothing stored: waiting for the coupler would gain nothing


@pytest.mark.slow
def test_a_second_rail_of_one_size_waits_for_the_first_and_reads_its_fields(tmp_path, monkeypatch):
    """Checked in two processes from an empty cache, the coupler and rocker rails of one
    size (one hole basis): the rocker's taker waits for the coupler and then reads its unit
    fields from the store, one basis solved instead of two side by side (10 s of the cold
    default check, issue 59), and the summary is the one of a check one part after another."""
    from railcheck.api import scene_of
    from railcheck.check.run import run_check
    from railcheck.progress import Progress

    lines: list[str] = []

    class Heard(Progress):
        def say(self, stage, message):
            lines.append(message)

    text = _scene(parts='["coupler-rail", "rocker-rail"]')
    monkeypatch.setenv("RAILCHECK_CACHE", str(tmp_path / "cache"))
    two = run_check(scene_of(text), str(tmp_path / "two"), progress=Heard(), jobs=2)
    solved = [m for m in lines if "unit cases solved for every hole of the rail" in m]
    stored = [m for m in lines if "unit fields from the store" in m]
    assert len(solved) == 1 and solved[0].startswith("(1/2) coupler-rail"), lines
    assert len(stored) == 1 and stored[0].startswith("(2/2) rocker-rail"), lines
    monkeypatch.setenv("RAILCHECK_CACHE", str(tmp_path / "cache-one"))
    one = run_check(scene_of(text), str(tmp_path / "one"), jobs=1)
    assert json.dumps(two.summary["parts"], sort_keys=True) == json.dumps(one.summary["parts"], sort_keys=True)


@pytest.mark.slow
def test_a_sweep_after_a_check_reads_the_checks_rails(tmp_path, monkeypatch):
    """The sweep's free rails are projected from the same hole basis: after one check, a
    sweep of settings round it (other bar lengths, so other hole pairs) solves no rail,
    and its row of the checked setting equals the check."""
    import railcheck.fea.store as store
    from helpers import sweep_table
    from railcheck.api import sweep

    real = store.solve_unit_cases

    def counted(*args, **kw):
        with open(tmp_path / "solves", "a") as f:  # a forked worker counts here too
            f.write(f"{len(args[3])}\n")
        return real(*args, **kw)

    monkeypatch.setattr(store, "solve_unit_cases", counted)
    text = _scene(effects='["inertia"]')
    first = _check(tmp_path, "first", text, monkeypatch, tmp_path / "cache")
    (tmp_path / "solves").unlink()
    ranges = {"crank": (420, 480), "coupler": (840, 900), "rocker": (720, 780), "ground": (1020, 1020)}
    found = sweep(text + sweep_table(steps=180, **ranges), serial=True)
    assert not (tmp_path / "solves").exists()
    table = found.tables["four-bar"]
    rows = {name: table[name].to_pylist() for name in table.column_names}
    lengths = list(zip(rows["crank_mm"], rows["coupler_mm"], rows["rocker_mm"]))
    at = [i for i, setting in enumerate(lengths) if setting == (480, 840, 780)]
    assert len(at) == 1 and len(lengths) > 4, lengths
    for part in ("crank-rail", "coupler-rail"):
        want = first["parts"][part]["max_von_mises_Pa"] / 1e6
        assert abs(rows[f"{part}_stress_MPa"][at[0]] - want) <= 1e-9 * want, part


def test_the_load_rule_is_built_once_and_dropped_before_the_factorisation(crank, monkeypatch):
    """Issue 59's memory: a free rail's unit solve integrates its loads and its rigid
    modes with the load rule's basis, built once, and drops it before factorising (a
    third of what the bracket's process held then); the fields equal those of a solve
    that keeps it."""
    import skfem

    import railcheck.fea.unitcases as unitcases

    job, mesh, cases = crank
    real_basis, real_solve, rules, held = skfem.Basis, unitcases.solve_free_body, [], []

    def counting(*args, **kw):
        rules.append(kw.get("intorder"))
        return real_basis(*args, **kw)

    def spying(K, F, basis, *args, **kw):
        held.append("integration_basis" in basis.__dict__.get("_railcheck_cache", {}))
        return real_solve(K, F, basis, *args, **kw)

    kw = {"order": 1, "tip_group": job.tip, "free_body": job.free_body}
    with monkeypatch.context() as m:
        m.setattr(unitcases, "loads_integrated", lambda basis, free: None)
        kept, _ = solve_unit_cases(mesh, job.material, [], cases, **kw)
    monkeypatch.setattr(skfem, "Basis", counting)
    monkeypatch.setattr(unitcases, "solve_free_body", spying)
    dropped, _ = solve_unit_cases(mesh, job.material, [], cases, **kw)
    assert rules.count(1) == 3 and held == [False]  # the vector, scalar and load rules' bases, once each
    for name in ("stress", "displacement", "tip"):
        np.testing.assert_array_equal(getattr(dropped, name), getattr(kept, name))


def test_stored_parts_checked_on_threads_equal_one_after_another(tmp_path, monkeypatch, cache_with_meshes):
    """Issue 59's every-file check: with every part's unit fields stored, the parts'
    cycles run on two threads of the process (BLAS on one thread each) and their files
    are written on the calling thread; the summary and the VTU's node fields (the
    envelope now computed with the cycle) are the one-after-another check's, byte for
    byte (OpenBLAS on one thread in every stage they show, wherever it runs)."""
    import threading

    import meshio

    import railcheck.check.workers as workers
    from railcheck.check.run import run_check
    from railcheck.scene import parse_scene

    monkeypatch.setenv("RAILCHECK_CACHE", str(cache_with_meshes(tmp_path / "cache")))
    text = _scene(parts='["crank-rail", "coupler-rail"]').replace("vtk = false", "vtk = true")
    scene = parse_scene(tomllib.loads(text), "test")
    run_check(scene, str(tmp_path / "fill"), False, jobs=1)  # fills the store
    ran_on, real = [], workers.check_part

    def spied(*args, **kw):
        ran_on.append(threading.current_thread().name)
        return real(*args, **kw)

    monkeypatch.setattr(workers, "check_part", spied)
    run_check(scene, str(tmp_path / "threads"), False, jobs=None)
    assert len(ran_on) == 2 and all(name.startswith("railcheck-parts") for name in ran_on)
    run_check(scene, str(tmp_path / "serial"), False, jobs=1)
    assert ran_on[2:] == ["MainThread", "MainThread"]
    summaries = [(tmp_path / d / "summary.json").read_text() for d in ("threads", "serial")]
    assert summaries[0] == summaries[1]
    for name in ("crank-rail", "coupler-rail"):
        a, b = (meshio.read(tmp_path / d / f"{name}.vtu").point_data for d in ("threads", "serial"))
        assert a.keys() == b.keys() and "von_mises_envelope" in a
        for key in a:
            np.testing.assert_array_equal(a[key], b[key], err_msg=key)
