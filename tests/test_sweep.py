"""`railcheck sweep`: the grid, the seed's cases, the kinematics and checks of every
setting against independent calculations, Dask against serial, streaming, bearings."""

import math
import tracemalloc

import numpy as np
import pytest

from helpers import (
    FE_SWEEP,
    FINAL_DESIGN_SWEEP,
    check_scene_of_row,
    run_sweep_text,
    table_rows,
    utilisation_at_safe_speed,
)
from railcheck.check.pipeline import run_pipeline
from railcheck.kinematics import batch
from railcheck.kinematics.massmodel import MassModel, fourbar_bodies
from railcheck.loads.bearings import BEARING_6205, bearing_life
from railcheck.scene import parse_scene
from railcheck.sweep.table import read_table

# seed 000, 3.3.6: (b2, b3, b4, d) mm -> mu_max, mu_min (deg) and the seed's label
SEED_336 = [
    ((540, 900, 780, 1058), 143.9544, 35.0009, "cannot be mounted"),
    ((540, 840, 780, 1020), 148.6930, 34.2160, "fails the transmission angle"),
    ((480, 840, 780, 1020), 135.5846, 38.7192, "passes"),
]


def _assert_same_tables(one_run, other_run):
    """Every kind's table of ``other_run`` equals ``one_run``'s bit for bit (NaN where NaN)."""
    for kind in one_run.tables:
        _assert_same_rows(table_rows(one_run, kind), table_rows(other_run, kind), kind)


def _assert_same_rows(one: dict, other: dict, kind: str = "four-bar") -> None:
    """The columns ``other`` (:func:`table_rows`) equal ``one`` bit for bit (NaN where NaN)."""
    assert one.keys() == other.keys()
    for k in one:
        assert np.array_equal(one[k], other[k], equal_nan=one[k].dtype.kind == "f"), (kind, k)


def _independent_lengths(rail_mm: float) -> list[float]:
    """Written apart from railcheck.sweep.grid: holes at 20 mm, then every 60 mm, the last at
    least 20 mm from the end; a bar runs from the middle of the first two holes (its upper
    plate's two screws) to the middle of two other neighbouring holes (its far plate's)."""
    holes, x = [], 20.0
    while x <= rail_mm - 20.0 + 1e-9:
        holes.append(x)
        x += 60.0
    joints = [0.5 * (a + b) for a, b in zip(holes, holes[1:])]
    return [j - joints[0] for j in joints[1:]]


def _independent_checks(b2, b3, b4, d) -> bool:
    """Seed 000's final limits by hand: Grashof crank-rocker, 35 < mu < 145 deg, d > 660
    mm, every joint on its rail's holes."""
    s, *_, l = sorted((b2, b3, b4, d))
    p, q = sorted((b2, b3, b4, d))[1:3]
    if not (l < b2 + b3 + b4 + d - l and s + l < p + q and b2 == s):
        return False
    cos_min = (b3**2 + b4**2 - (d - b2) ** 2) / (2 * b3 * b4)
    cos_max = (b3**2 + b4**2 - (d + b2) ** 2) / (2 * b3 * b4)
    if not (-1 <= cos_min <= 1 and -1 <= cos_max <= 1):
        return False
    mu_min, mu_max = math.degrees(math.acos(cos_min)), math.degrees(math.acos(cos_max))
    return 35 < mu_min and mu_max < 145 and d > 660 and b2 <= 600 and b3 <= 900 and b4 <= 900


KINEMATICS_ONLY = """
[sweep]
speeds = ["1 Hz"]
steps = 90
"""


@pytest.fixture(scope="module")
def kinematic_sweep(tmp_path_factory):
    return run_sweep_text(tmp_path_factory.mktemp("sweep"), KINEMATICS_ONLY, serial=True)


def test_grid_counts_equal_an_independent_enumeration(kinematic_sweep):
    crank, coupler, rocker, ground = (_independent_lengths(L) for L in (700, 1000, 1000, 2500))
    s = kinematic_sweep.summary
    assert s["grid"]["four-bar"]["crank_m"] == pytest.approx([x / 1e3 for x in crank], abs=1e-12)
    assert s["grid"]["four-bar"]["ground_m"] == pytest.approx([x / 1e3 for x in ground], abs=1e-12)
    total = len(crank) * len(coupler) * len(rocker) * len(ground)
    assert s["by_kind"]["four-bar"]["settings_total"] == total == 90000
    assert s["by_kind"]["slider-crank"]["settings_total"] == len(crank) * len(coupler)
    passing = sum(_independent_checks(a, b, c, d) for a in crank for b in coupler for c in rocker for d in ground)
    assert s["by_kind"]["four-bar"]["settings_passing_checks"] == passing
    rows = table_rows(kinematic_sweep)
    assert rows["setting"].size == total and np.array_equal(np.sort(rows["setting"]), np.arange(total))


def test_seed_336_cases_are_found_with_the_seeds_check_results(tmp_path):
    """540/900/780/1058 (off the hole grid: given as an extra setting) cannot be mounted;
    540/840/780/1020 fails the transmission angle; 480/840/780/1020 passes; the
    transmission angles are the seed's to its 4 decimals."""
    run = run_sweep_text(
        tmp_path,
        KINEMATICS_ONLY
        + """
kind = "four-bar"
crank = ["480 mm", "540 mm"]
coupler = ["840 mm", "900 mm"]
rocker = ["780 mm", "780 mm"]
ground = ["1020 mm", "1020 mm"]
[[sweep.settings]]
crank = "540 mm"
coupler = "900 mm"
rocker = "780 mm"
ground = "1058 mm"
""",
        serial=True,
    )
    rows = table_rows(run)
    for (b2, b3, b4, d), mu_max, mu_min, label in SEED_336:
        i = np.flatnonzero(
            (rows["crank_mm"] == b2)
            & (rows["coupler_mm"] == b3)
            & (rows["rocker_mm"] == b4)
            & np.isclose(rows["ground_mm"], d)
        )
        assert i.size == 1, (b2, b3, b4, d)
        i = i[0]
        assert rows["mu_max_deg"][i] == pytest.approx(mu_max, abs=1e-4)
        assert rows["mu_min_deg"][i] == pytest.approx(mu_min, abs=1e-4)
        if label == "cannot be mounted":
            assert not rows["check_hole_grid"][i] and rows["check_transmission_angle"][i]
            assert rows["verdict"][i] == "refused" and rows["reason"][i] == "hole_grid"
        elif label == "fails the transmission angle":
            assert rows["check_hole_grid"][i] and not rows["check_transmission_angle"][i]
            assert rows["reason"][i] == "transmission_angle"
        else:
            assert rows["checks_passed"][i] and rows["verdict"][i] == "pass"


def _newton_euler_9x9(b2, b3, b4, d, theta2, speed):
    """Reference: the three bars' Newton-Euler equations (forces, and moments about each
    centre of mass) assembled as one 9 x 9 linear system per step and solved by numpy.
    Unknowns: O2 on the crank (0, 1); A on the coupler, minus on the crank (2, 3); B on
    the rocker, minus on the coupler (4, 5); O4 on the rocker (6, 7); the torque (8)."""
    from types import SimpleNamespace

    m = batch.fourbar_motion(b2, b3, b4, d, 1.0, speed, theta2)
    bodies = fourbar_bodies(SimpleNamespace(crank=b2, coupler=b3, rocker=b4), MassModel())
    origins = ("O2", "A", "O4")
    acting = {0: [(0, "O2", 1.0), (2, "A", -1.0)], 1: [(2, "A", 1.0), (4, "B", -1.0)], 2: [(4, "B", 1.0), (6, "O4", 1.0)]}
    out = []
    for t in range(theta2.size):
        M, rhs = np.zeros((9, 9)), np.zeros(9)
        for b, bar in enumerate(bodies):
            th, w, al = m.theta[b, 0, t], m.omega[b, 0, t], m.alpha[b, 0, t]
            e = np.array([math.cos(th), math.sin(th)])
            n = np.array([-e[1], e[0]])
            G = m.points[origins[b]][0, t] + bar.com * e
            aG = m.accelerations[origins[b]][0, t] + al * bar.com * n - w**2 * bar.com * e
            rhs[3 * b : 3 * b + 3] = [bar.mass * aG[0], bar.mass * aG[1], bar.inertia_com * al]
            for col, joint, sgn in acting[b]:
                r = m.points[joint][0, t] - G
                M[3 * b, col] += sgn
                M[3 * b + 1, col + 1] += sgn
                M[3 * b + 2, col] -= sgn * r[1]
                M[3 * b + 2, col + 1] += sgn * r[0]
        M[2, 8] = 1.0
        out.append(np.linalg.solve(M, rhs))
    return np.array(out)


@pytest.mark.parametrize("lengths", [(0.48, 0.84, 0.78, 1.02), (0.06, 0.3, 0.42, 0.36), (0.6, 0.96, 0.96, 1.2)])
def test_closed_form_inverse_dynamics_equals_the_9x9_system(lengths):
    theta2 = np.linspace(0, 2 * np.pi, 37)
    ref = _newton_euler_9x9(*lengths, theta2, 2 * np.pi)
    dyn = batch.newton_euler(batch.fourbar_motion(*lengths, 1.0, 2 * np.pi, theta2))
    got = np.column_stack(
        [dyn.reactions["O2"][0], dyn.reactions["A"][0], dyn.reactions["B"][0], dyn.reactions["O4"][0], dyn.torque[0]]
    )
    np.testing.assert_allclose(got, ref, rtol=1e-10, atol=1e-9 * np.abs(ref).max())


def test_batch_of_settings_equals_each_setting_alone():
    rng = np.random.default_rng(3)
    b2 = rng.uniform(0.05, 0.2, 20)
    b3, b4, d = b2 + rng.uniform(0.4, 0.6, 20), b2 + rng.uniform(0.4, 0.6, 20), b2 + rng.uniform(0.4, 0.6, 20)
    speed = rng.uniform(1, 20, 20)
    th = np.linspace(0, 2 * np.pi, 50)
    together = batch.newton_euler(batch.fourbar_motion(b2, b3, b4, d, 1.0, speed, th), gravity=9.81)
    for i in (0, 7, 19):
        alone = batch.newton_euler(batch.fourbar_motion(b2[i], b3[i], b4[i], d[i], 1.0, speed[i], th), gravity=9.81)
        for j in together.reactions:
            np.testing.assert_allclose(together.reactions[j][i], alone.reactions[j][0], rtol=1e-13, atol=1e-9)


def test_bearing_life_matches_the_rating_formula():
    """Constant load and speed: L10 = (C/P)^3 10^6 / (3600 n); a load on half the turn
    gives the cubic mean; the two bearings of a joint share it."""
    T = 1000
    speed = 2 * np.pi * np.ones((1, T))  # 1 rev/s
    load = np.zeros((1, T, 2))
    load[..., 0] = 2000.0  # N on the joint, 1000 N per bearing
    life = bearing_life(load, speed)
    expected = (BEARING_6205.dynamic_capacity / 1000.0) ** 3 * 1e6 / 3600.0
    assert life.l10_hours[0] == pytest.approx(expected, rel=1e-12)
    assert life.static_safety[0] == pytest.approx(7800.0 / 1000.0)
    load[0, T // 2 :, 0] = 0.0
    half = bearing_life(load, speed)
    assert half.equivalent_load[0] == pytest.approx(1000.0 * 0.5 ** (1 / 3), rel=1e-12)


def test_bearing_life_weights_each_load_by_the_turns_it_is_carried():
    """A speed that varies over the turn: 1000 N per bearing for the first half of the
    steps at 1 rev/s, 2000 N for the second half at 3 rev/s (uniform steps in time). By
    hand: P_m^3 = (1000^3 * 1 + 2000^3 * 3) / 4, n_mean = 2 rev/s, L10 = (C / P_m)^3 10^6
    revolutions in hours at n_mean. A plain time mean of P^3 would give (1 + 8) / 2."""
    T = 1000
    speed = np.where(np.arange(T) < T // 2, 2 * np.pi, 6 * np.pi)[None, :]
    load = np.zeros((1, T, 2))
    load[0, :, 1] = np.where(np.arange(T) < T // 2, 2000.0, 4000.0)  # on the joint: two bearings share it
    life = bearing_life(load, -speed)  # either sense of rotation turns the rings the same
    pm = ((1000.0**3 * 1 + 2000.0**3 * 3) / 4) ** (1 / 3)
    assert life.equivalent_load[0] == pytest.approx(pm, rel=1e-12)
    hours = (BEARING_6205.dynamic_capacity / pm) ** 3 * 1e6 / (3600.0 * 2.0)
    assert life.l10_hours[0] == pytest.approx(hours, rel=1e-12)
    assert life.peak_load[0] == 2000.0 and life.static_safety[0] == pytest.approx(7800.0 / 2000.0)
    still = bearing_life(load, np.zeros((1, T)))  # rings that never turn: no rating life
    assert still.l10_hours[0] == np.inf


def test_bearing_life_over_settings_and_joints_slow_rings_and_light_loads():
    """Leading dimensions (settings, joints) are kept apart; a ring turning at 0.2 rev/s
    under 0.4 N still has a finite (huge) life; rings that never turn carry an equivalent
    load of 0 and no rating life; the 6205's ratings are the 2013 study's (3.3.6)."""
    import dataclasses

    assert (BEARING_6205.dynamic_capacity, BEARING_6205.static_capacity) == (14_900.0, 7_800.0)
    with pytest.raises(dataclasses.FrozenInstanceError):
        BEARING_6205.dynamic_capacity = 1.0
    T = 400
    load = np.zeros((2, 3, T, 2))
    load[..., 0] = np.arange(1, 7).reshape(2, 3, 1) * 100.0  # 100 .. 600 N on the joint
    speed = np.full((2, 3, T), 2 * np.pi)
    life = bearing_life(load, speed)
    assert life.l10_hours.shape == life.peak_load.shape == life.static_safety.shape == (2, 3)
    np.testing.assert_allclose(life.peak_load, np.arange(1, 7).reshape(2, 3) * 50.0, rtol=1e-12)
    with pytest.raises(dataclasses.FrozenInstanceError):
        life.l10_hours = None
    crawl = bearing_life(load[:1, :1], np.full((1, 1, T), 1e-5))  # 0.004 rad in all: still a life
    assert np.isfinite(crawl.l10_hours[0, 0]) and crawl.equivalent_load[0, 0] == pytest.approx(50.0, rel=1e-12)
    per_bearing = np.arange(1, 7).reshape(2, 3) * 50.0
    np.testing.assert_allclose(life.equivalent_load, per_bearing, rtol=1e-12)
    np.testing.assert_allclose(life.l10_hours, (14_900.0 / per_bearing) ** 3 * 1e6 / 3600.0, rtol=1e-12)
    light = np.zeros((1, T, 2))
    light[..., 1] = 0.8  # 0.4 N per bearing
    slow = bearing_life(light, np.full((1, T), 0.4 * np.pi))  # 0.2 rev/s
    assert slow.equivalent_load[0] == pytest.approx(0.4, rel=1e-12)
    assert slow.l10_hours[0] == pytest.approx((14_900.0 / 0.4) ** 3 * 1e6 / (3600.0 * 0.2), rel=1e-12)
    assert slow.static_safety[0] == pytest.approx(7_800.0 / 0.4, rel=1e-12)
    still = bearing_life(light, np.zeros((1, T)))
    assert still.equivalent_load[0] == 0.0 and still.l10_hours[0] == np.inf
    nothing = bearing_life(np.zeros((1, T, 2)), np.full((1, T), 2 * np.pi))
    assert nothing.l10_hours[0] == np.inf and nothing.static_safety[0] == np.inf


@pytest.mark.slow
def test_dask_and_serial_give_identical_tables(tmp_path, monkeypatch):
    """Both linkage kinds, their chunks in one Dask queue, the contexts mapped from shared
    files; and again with the shared files refused by the disk (the contexts scattered
    instead, said so): every table equals the serial run's, and no shared file is left
    in the results."""
    import railcheck.parallel.executor as executor_module

    text = KINEMATICS_ONLY + 'crank = ["420 mm", "540 mm"]\ncoupler = ["780 mm", "900 mm"]\nspeeds = ["1 Hz", "1.5 Hz"]\n'
    text = text.replace('speeds = ["1 Hz"]\n', "")
    serial = run_sweep_text(tmp_path, text, "serial", serial=True)
    small = text.replace("[sweep]", '[sweep]\nmemory = "2 MB"')
    parallel = run_sweep_text(tmp_path, small, "dask", workers=2, serial=False, dask=True)

    def full_disk(obj, path):
        raise OSError(28, "No space left on device")

    monkeypatch.setattr(executor_module, "write_shared", full_disk)
    lines = []
    progress = type("P", (), {"say": lambda self, stage, msg: lines.append(msg)})()
    scattered = run_sweep_text(tmp_path, small, "scattered", workers=2, serial=False, dask=True, progress=progress)
    assert any("scattering it" in line for line in lines)
    assert set(serial.tables) == {"four-bar", "slider-crank"}
    for run in (parallel, scattered):
        assert not list(run.target.glob(".context*"))
        _assert_same_tables(serial, run)


@pytest.mark.slow  # forks, like tests/test_sweep_forked.py
def test_chunks_on_forked_processes_give_the_serial_tables(tmp_path, monkeypatch):
    """Both linkage kinds on one process per core forked from this one (a sweep without
    FE, too small for Dask: each kind in two chunks per process; threads where the
    platform does not fork), said so: every table equals the serial run's. Asked for a
    million workers it uses one per core, and says so."""
    import os

    from railcheck.parallel import forked

    # the forked executor itself: earlier tests of this pytest process may leave threads
    # (whether a process with threads forks: tests/test_sweep_forked.py)
    monkeypatch.setattr(forked, "alone", lambda: True)

    cores = os.cpu_count() or 1
    text = KINEMATICS_ONLY + 'crank = ["420 mm", "540 mm"]\ncoupler = ["780 mm", "900 mm"]\n'
    serial = run_sweep_text(tmp_path, text, "serial", serial=True)
    lines = []
    progress = type("P", (), {"say": lambda self, stage, msg: lines.append(msg)})()
    local = run_sweep_text(tmp_path, text, "local", workers=10**6, progress=progress)
    assert f"--workers 1000000: this machine has {cores} cores; using {cores}" in lines
    how = "processes forked from this one" if forked.available() else "threads in this process"
    assert f"{cores} {how}" in lines or cores == 1
    assert not any("Dask" in line for line in lines)
    assert set(serial.tables) == {"four-bar", "slider-crank"}
    _assert_same_tables(serial, local)


@pytest.mark.slow
def test_an_external_scheduler_gets_the_context_scattered_and_the_serial_tables(tmp_path, monkeypatch):
    """``--scheduler`` an existing cluster (its workers may not see this disk): the
    contexts are scattered to its workers, no shared file is written, and both kinds'
    tables equal the serial run's."""
    from dask.distributed import LocalCluster

    import railcheck.parallel.executor as executor_module

    written = []
    monkeypatch.setattr(executor_module, "write_shared", lambda obj, path: written.append(path) or path)
    text = KINEMATICS_ONLY + 'crank = ["420 mm", "540 mm"]\ncoupler = ["780 mm", "900 mm"]\n'
    small = text.replace("[sweep]", '[sweep]\nmemory = "2 MB"')
    serial = run_sweep_text(tmp_path, text, "serial", serial=True)
    with LocalCluster(n_workers=2, threads_per_worker=1, processes=False, protocol="tcp", dashboard_address=None) as cluster:
        external = run_sweep_text(tmp_path, small, "external", scheduler=cluster.scheduler_address)
    assert not written and not list(external.target.glob(".context*"))
    _assert_same_tables(serial, external)


@pytest.mark.slow
def test_sweep_larger_than_its_memory_budget_streams_to_disk(tmp_path):
    """A 2 MB working-memory budget and a table more than ten times larger: the rows are
    written chunk by chunk and the traced peak (numpy and Python allocations, imports
    done beforehand; the maps' matplotlib figure is about 13 MB of it) stays far below
    the table's size."""
    text = """
[sweep]
kind = "four-bar"
steps = 16
memory = "2 MB"
crank = ["60 mm", "660 mm"]
coupler = ["600 mm", "960 mm"]
rocker = ["600 mm", "960 mm"]
ground = ["660 mm", "2460 mm"]
speeds = ["0.25 Hz", "0.5 Hz", "0.75 Hz", "1 Hz", "1.25 Hz", "1.5 Hz", "1.75 Hz", "2 Hz", "2.25 Hz", "2.5 Hz",
          "2.75 Hz", "3 Hz", "3.25 Hz", "3.5 Hz", "3.75 Hz", "4 Hz"]
"""
    run_sweep_text(tmp_path, text.replace('"2460 mm"', '"720 mm"'), "warm", serial=True)  # imports, not measured
    tracemalloc.start()
    try:
        run = run_sweep_text(tmp_path, text, serial=True)
        _, peak = tracemalloc.get_traced_memory()
    finally:
        tracemalloc.stop()
    table = read_table(run.tables["four-bar"])
    settings = run.summary["by_kind"]["four-bar"]["settings_total"]
    assert table.num_rows == settings * 16
    assert table.nbytes > 10 * 2e6
    assert peak < table.nbytes / 3, (peak, table.nbytes)


def test_csv_table_equals_parquet(tmp_path):
    text = KINEMATICS_ONLY + 'kind = "slider-crank"\n[output]\nplots = false\n'
    plain = run_sweep_text(tmp_path, text, "pq", serial=True)
    a = table_rows(plain, "slider-crank")
    _draws_no_plots(plain)
    b = table_rows(
        run_sweep_text(tmp_path, text.replace("[sweep]", '[sweep]\nformat = "csv"'), "csv", serial=True), "slider-crank"
    )
    for k in a:
        if a[k].dtype.kind == "f":
            np.testing.assert_allclose(b[k].astype(float), a[k], rtol=1e-15, equal_nan=True)
        else:
            assert [str(x) for x in a[k]] == [str(x) for x in b[k]], k


def _draws_no_plots(run) -> None:
    """[output] plots = false: no map, no motor.png, and the report and the console say so
    instead of naming pictures that are not there; the tables and pages are written."""
    from railcheck.report.text import sweep_report

    assert not list(run.target.glob("map-*.png")) and not (run.target / "motor.png").exists()
    assert (run.target / "summary.json").exists() and (run.target / "report.html").exists()
    assert "[output] plots = false" in (run.target / "report.html").read_text()
    text = sweep_report(run)
    assert "motor.png" not in text.replace("no maps or motor.png: [output] plots = false", "")


def test_a_sweep_draws_its_maps_and_motor_curve_unless_the_scene_says_plots_false(kinematic_sweep):
    """The default draws them (the FAIL side of :func:`_draws_no_plots`)."""
    assert (kinematic_sweep.target / "map-four-bar.png").exists() and (kinematic_sweep.target / "motor.png").exists()
    with pytest.raises(AssertionError):
        _draws_no_plots(kinematic_sweep)


@pytest.fixture(scope="module")
def fe_sweep(tmp_path_factory):
    return table_rows(run_sweep_text(tmp_path_factory.mktemp("fe"), FE_SWEEP, serial=True))


@pytest.mark.slow
def test_a_sweep_row_equals_railcheck_check_of_that_setting(fe_sweep):
    """Stress, fatigue factor and tip deflection of every part: the sweep's superposition
    over all hole pairs equals `railcheck check` of the same setting (bolts at the
    setting's holes, same mesh) to 1e-9."""

    rows = fe_sweep
    passing = np.flatnonzero(rows["checks_passed"])
    assert passing.size >= 2
    for i in passing[[0, -1]]:
        row = {k: v[i] for k, v in rows.items()}
        result = run_pipeline(check_scene_of_row(row, 1.0))
        for name, part in result.parts.items():
            env, fat = part.cycle.envelope, part.cycle.fatigue
            assert row[f"{name}_stress_MPa"] * 1e6 == pytest.approx(env.max_von_mises, rel=1e-9), name
            assert row[f"{name}_fatigue"] == pytest.approx(fat.min_safety_factor, rel=1e-9), name
            if part.geometry.kind == "rail":
                assert row[f"{name}_tip_mm"] / 1e3 == pytest.approx(env.max_tip, rel=1e-9), name


@pytest.mark.slow
def test_an_fe_sweep_on_dask_gives_the_serial_table(fe_sweep, tmp_path):
    """With Dask (the parts' models built in this process, then the chunks on two Dask
    workers, the models reaching them through the shared context file): the table equals
    the serial run's bit for bit."""
    parallel = table_rows(run_sweep_text(tmp_path, FE_SWEEP, "dask", workers=2, serial=False, dask=True))
    _assert_same_rows(fe_sweep, parallel)


@pytest.mark.slow
@pytest.mark.parametrize("forks", [True, False], ids=["forked", "threads"])
def test_an_fe_sweep_on_local_workers_gives_the_serial_table(fe_sweep, tmp_path, monkeypatch, forks):
    """The FE sweep's chunks, a few settings with FE each, on two processes forked from
    this one, or on two threads of this process where it cannot fork (BLAS on one thread
    meanwhile), said so: the table equals the serial run's bit for bit."""
    from railcheck.parallel import forked

    if forks and not forked.available():
        pytest.skip("this platform does not fork")
    monkeypatch.setattr(forked, "available", lambda: forks)
    monkeypatch.setattr(forked, "alone", lambda: True)  # earlier tests may leave threads in this process
    lines = []
    progress = type("P", (), {"say": lambda self, stage, msg: lines.append(msg)})()
    run = run_sweep_text(tmp_path, FE_SWEEP, "local", workers=2, dask=False, progress=progress)
    assert ("2 processes forked from this one" if forks else "2 threads in this process") in lines
    _assert_same_rows(fe_sweep, table_rows(run))


def test_a_part_is_built_after_the_one_whose_unit_fields_it_reuses():
    """The default scene's parts over both linkage kinds: each free rail once per kind (the
    second kind reads the first's stored fields), the rocker after the coupler (the same
    rail with the same settable lengths, as on the whole rig's grid: one store entry), the
    plates once for both kinds. Built one at a time, the plates (whose models are small)
    come first, largest first, so the bracket's solve, the largest, runs beside no model,
    and each task that reads another's fields right after that one."""
    from railcheck.scene import load_scene
    from railcheck.sweep.inputs import sweep_input
    from railcheck.sweep.run import build_order, part_tasks

    inputs = sweep_input(load_scene(None))
    same = np.array([0.36, 0.78, 0.84])  # m: the coupler's and the rocker's settable lengths
    by_kind = {
        "four-bar": {"crank": np.array([0.48]), "coupler": same, "rocker": same, "ground": np.array([1.02])},
        "slider-crank": {"crank": np.array([0.48]), "coupler": np.array([0.84]), "offset": np.array([0.0])},
    }
    tasks = part_tasks(inputs, by_kind)
    index = {(t.name, t.kinds): i for i, t in enumerate(tasks)}
    four, both = ("four-bar",), ("four-bar", "slider-crank")
    after = {
        key: None if tasks[i].after is None else (tasks[tasks[i].after].name, tasks[tasks[i].after].kinds)
        for key, i in index.items()
    }
    assert after == {
        ("crank-rail", four): None,
        ("crank-rail", ("slider-crank",)): ("crank-rail", four),
        ("coupler-rail", four): None,
        ("coupler-rail", ("slider-crank",)): ("coupler-rail", four),
        ("rocker-rail", four): ("coupler-rail", four),
        ("PF_4b_006", both): None,
        ("PF_4b_003_v2", both): None,
    }
    order = [(tasks[i].name, tasks[i].kinds) for i in build_order(tasks, inputs.parts)]
    # the plates first, the largest first; then the rails, each reuse right after its source
    assert order == [
        ("PF_4b_003_v2", both),
        ("PF_4b_006", both),
        ("coupler-rail", four),
        ("coupler-rail", ("slider-crank",)),
        ("rocker-rail", four),
        ("crank-rail", four),
        ("crank-rail", ("slider-crank",)),
    ]


def test_motor_sizing_at_every_speed_and_its_curve_from_the_table(kinematic_sweep):
    """The motor a rig needs: at the listed speed, the largest peak torque, RMS torque and
    peak power over the settings that pass (from the table's rows, aggregated here
    independently); along the curve, the largest peak torque of the passing settings grows
    with the square of the speed (inertia alone: every acceleration scales with omega^2),
    checked at every curve point against the table's 1 Hz torque x (f / 1 Hz)^2; the console
    names the figures and motor.png is drawn."""
    from helpers import assert_picture
    from railcheck.report.text import sweep_report

    rows = table_rows(kinematic_sweep)
    sizing = kinematic_sweep.summary["by_kind"]["four-bar"]["motor_sizing"]
    passing = rows["verdict"] == "pass"
    at_1hz = sizing["at_listed_speeds"]["1"]
    for q in ("torque_peak_Nm", "torque_rms_Nm", "power_peak_W"):
        assert at_1hz[q]["value"] == pytest.approx(np.max(rows[q][passing]), rel=1e-12), q
    i = int(np.argmax(np.where(passing, rows["torque_peak_Nm"], -np.inf)))
    assert at_1hz["torque_peak_Nm"]["lengths_m"]["crank"] == pytest.approx(rows["crank_mm"][i] / 1e3)
    curve = sizing["curve"]
    f = np.array(curve["speed_Hz"])
    assert f[0] == 0 and f[-1] == pytest.approx(3.0) and len(f) > 20
    expected = np.max(rows["torque_peak_Nm"][rows["checks_passed"]]) * f**2
    assert np.array(curve["torque_peak_Nm"], float) == pytest.approx(expected, rel=1e-9, abs=1e-9)
    assert np.array(curve["power_peak_W"], float) == pytest.approx(expected * 2 * np.pi * f, rel=1e-9, abs=1e-9)
    assert set(curve["settings"]) == {int(np.sum(rows["checks_passed"]))}  # no FE: no speed limit known
    text = sweep_report(kinematic_sweep)
    assert f"motor at 1 Hz (every passing setting): peak torque {at_1hz['torque_peak_Nm']['value']:.3g} N·m" in text
    assert "seed 3.3" not in text and "hypotheses (chapter 3.3)" in text  # the 2013 hypotheses: summary.json only
    assert "settings written crank/coupler/rocker/ground (mm)" in text  # the order of "480/840/780/1020 mm"
    assert all(len(line) <= 100 for line in text.splitlines() if not line.startswith("results in"))
    assert_picture(kinematic_sweep.target / "motor.png")
    page = (kinematic_sweep.target / "report.html").read_text()
    assert "<script" not in page and "http" not in page  # self-contained, offline
    assert page.count("data:image/png;base64,") == 3  # the two kinds' maps and the motor plot
    assert "The motor a rig needs" in page and "The best passing setting per criterion" in page
    assert f"{at_1hz['torque_peak_Nm']['value']:.3g}" in page


def test_map_legend_lists_only_the_refusal_reasons_that_occur(tmp_path):
    """The legend's reasons are the first failing checks of the refused settings, read
    from the table independently; a narrowed sweep where only some checks fail lists
    only those."""
    from railcheck.report.maps import occurring_reasons
    from railcheck.sweep.aggregate import REASON_ORDER, Aggregate
    from railcheck.sweep.inputs import sweep_input
    from railcheck.sweep.run import sweep_settings

    text = KINEMATICS_ONLY + 'kind = "four-bar"\ncrank = ["360 mm", "540 mm"]\ncoupler = ["780 mm", "900 mm"]\n'
    text += 'rocker = ["660 mm", "900 mm"]\nground = ["960 mm", "1080 mm"]\n'
    run = run_sweep_text(tmp_path, text, serial=True)
    rows = table_rows(run)
    expected = set()
    for i in np.flatnonzero(~rows["checks_passed"]):
        expected.add(next(r for r in REASON_ORDER if f"check_{r}" in rows and not rows[f"check_{r}"][i]))
    inputs = sweep_input(parse_scene(__import__("tomllib").loads(text), "test"))
    agg = Aggregate(inputs, "four-bar", sweep_settings(inputs)["four-bar"])
    agg.add({k: v for k, v in rows.items()})
    assert set(occurring_reasons(agg)) == expected and 0 < len(expected) < len(REASON_ORDER)


@pytest.mark.slow
def test_checking_at_the_safe_speed_gives_utilisation_one(fe_sweep):
    """A check at the safe speed puts the governing part exactly at its limit as the sweep
    reads it (its quasi-static utilisation times its certificate's estimate, or the
    estimate at its tolerance), and its verdict passes."""

    rows = fe_sweep
    i = np.flatnonzero(rows["checks_passed"])[0]
    row = {k: v[i] for k, v in rows.items()}
    result = run_pipeline(check_scene_of_row(row, row["safe_speed_Hz"]))
    u = max(utilisation_at_safe_speed(p) for p in result.parts.values())
    assert u == pytest.approx(1.0, abs=1e-6) and result.passed
    # the motor at that safe speed: the check's own inverse dynamics at that speed
    assert row["torque_peak_at_safe_Nm"] == pytest.approx(result.kinematics.dynamics.peak_torque()[0], rel=1e-9)
    assert row["power_peak_at_safe_W"] == pytest.approx(
        row["torque_peak_at_safe_Nm"] * 2 * np.pi * row["safe_speed_Hz"], rel=1e-12
    )


@pytest.mark.slow
def test_safe_speed_with_gravity_by_bisection(tmp_path):
    """With gravity the loads are C_g + s C_i and the safe speed comes from bisection:
    sweeping the same setting at that speed reaches the criterion that set it (utilisation 1,
    or the certificate's estimate at its tolerance: on the v2 joints' rig the crank rail's
    estimate sets it, 1.057 Hz), to the bisection's tolerance, and the rows at other speeds
    stay consistent (above: over 1, below: under)."""
    text = (
        FE_SWEEP.replace('crank = ["480 mm", "540 mm"]', 'crank = ["480 mm", "480 mm"]')
        .replace('rocker = ["780 mm", "840 mm"]', 'rocker = ["780 mm", "780 mm"]')
        .replace('ground = ["1020 mm", "1080 mm"]', 'ground = ["1020 mm", "1020 mm"]')
        .replace("parts = [", 'effects = ["inertia", "gravity"]\nparts = [')
    )
    first = table_rows(run_sweep_text(tmp_path, text, "g1", serial=True))
    safe = float(first["safe_speed_Hz"][0])
    assert 0.5 < safe < 10
    again = table_rows(
        run_sweep_text(
            tmp_path,
            text.replace(
                'speeds = ["1 Hz"]', f'speeds = ["{safe:.17g} Hz", "{0.9 * safe:.17g} Hz", "{1.1 * safe:.17g} Hz"]'
            ),
            "g2",
            serial=True,
        )
    )
    from railcheck.model.certificate import QUASI_STATIC_TOLERANCE

    part, criterion = first["safe_speed_part"][0], first["safe_speed_criterion"][0]
    if criterion == "quasi-static":  # the certificate's estimate reaches its tolerance there
        assert again[f"{part}_amplification_estimate"][0] == pytest.approx(QUASI_STATIC_TOLERANCE, abs=1e-9)
        assert again["utilisation"][0] <= 1.0
    else:
        assert again["utilisation"][0] == pytest.approx(1.0, abs=1e-9)
    assert again["utilisation"][1] < 1.0
    if criterion == "quasi-static":  # above it the row is the exact response (issue 78), its verdict on real criteria
        assert again["exact_dynamic"][2] and not again["exact_dynamic"][1]
        assert "quasi-static" not in (again["reason"][2] or "")
    else:
        assert again["utilisation"][2] > 1.0 and list(again["verdict"][1:]) == ["pass", "fail"]


def test_a_chunk_in_groups_of_one_setting_equals_one_group(monkeypatch):
    """The revolving settings are evaluated in groups (one block of the batch kinematics
    each) and their results joined: groups of one, two and every setting give the same
    columns and motor curve bit for bit, over settings that fail checks, do not revolve or
    pass, at two speeds."""
    from railcheck.sweep import chunk
    from railcheck.sweep.inputs import sweep_input
    from railcheck.sweep.run import sweep_context, sweep_settings

    text = KINEMATICS_ONLY.replace('speeds = ["1 Hz"]', 'speeds = ["1 Hz", "2 Hz"]')
    text += 'crank = ["360 mm", "480 mm"]\ncoupler = ["780 mm", "900 mm"]\nrocker = ["720 mm", "840 mm"]\n'
    inputs = sweep_input(parse_scene(__import__("tomllib").loads(text), "test"))
    lengths = sweep_settings(inputs)["four-bar"]
    ctx = sweep_context(inputs, "four-bar", {})
    ids = np.arange(lengths["crank"].size)
    results = []
    for size in (1, 2, 10**6):
        monkeypatch.setattr(chunk, "group_size", lambda steps, size=size: size)
        results.append(chunk.evaluate_chunk(ctx, lengths, ids))
    flags = chunk.configuration_flags(ctx, lengths)
    turns = chunk.revolvable(ctx, lengths, flags)
    passed = np.logical_and.reduce([v for k, v in flags.items() if k not in ("mu_min", "mu_max")])
    assert 2 < turns.sum() < turns.size and 0 < passed.sum() < turns.sum()  # every kind of setting
    whole = results[-1]
    assert whole[chunk.MOTOR_CURVE_KEY]["rows"].tolist() == np.flatnonzero(passed).tolist()
    for other in results[:-1]:
        assert other.keys() == whole.keys()
        for key, value in whole.items():
            if key == chunk.MOTOR_CURVE_KEY:
                for q in value:
                    np.testing.assert_array_equal(other[key][q], value[q])
            elif value.dtype == object:
                assert other[key].tolist() == value.tolist(), key
            else:
                np.testing.assert_array_equal(other[key], value, err_msg=key)
    curve = whole[chunk.MOTOR_CURVE_KEY]["torque_peak_Nm"]  # the passing settings' curve, row by row
    first = whole["speed_Hz"] == 1.0
    at_1hz = np.flatnonzero(np.isclose(chunk.motor_curve_speeds(ctx.speeds) / (2 * math.pi), 1.0))
    assert at_1hz.size == 1
    np.testing.assert_allclose(curve[:, at_1hz[0]], whole["torque_peak_Nm"][first][passed], rtol=1e-12)


def test_refusal_reasons_list_each_settings_failed_checks_in_order():
    """Each setting's reason is its failed configuration checks joined in the checks'
    order ("" when none fails), as one join per setting gives it; the combinations are
    joined once each."""
    from railcheck.sweep.columns import refusal_reasons

    rng = np.random.default_rng(3)
    names = ["assembly", "grashof", "transmission_angle", "crank_rail_collision", "hole_grid", "joints_on_rails"]
    checks = {name: rng.random(5000) > 0.3 for name in names}
    expected = [", ".join(n for n in names if not checks[n][i]) for i in range(5000)]
    reasons = refusal_reasons(checks, 5000)
    assert reasons.dtype == object and list(reasons) == expected
    assert "" in expected and max(map(len, expected)) > 60  # no failure, and every one


def test_joined_histories_keep_each_part_s_sources_in_order():
    """The FE histories of several groups of settings joined as one: each part's load
    sources' arrays follow one another along the settings, and a source without a
    constant part (None) stays None."""
    from railcheck.sweep.chunk import joined_histories

    rng = np.random.default_rng(3)
    first = {"a": [(None, rng.normal(size=(2, 5, 3)))], "b": [(rng.normal(size=(2, 5, 4)), rng.normal(size=(2, 5, 4)))]}
    second = {"a": [(None, rng.normal(size=(1, 5, 3)))], "b": [(rng.normal(size=(1, 5, 4)), rng.normal(size=(1, 5, 4)))]}
    joined = joined_histories([first, second])
    assert joined["a"][0][0] is None
    np.testing.assert_array_equal(joined["a"][0][1], np.concatenate([first["a"][0][1], second["a"][0][1]]))
    for j in (0, 1):
        np.testing.assert_array_equal(joined["b"][0][j], np.concatenate([first["b"][0][j], second["b"][0][j]]))


@pytest.mark.slow
def test_a_chunk_s_fe_settings_screened_together_equal_each_group_s_alone(monkeypatch):
    """The FE settings of every group of revolving settings in a chunk are screened
    together (the settings that share a part's hole pair in one box): free-body parts over
    sixteen settings, in groups of one, five and every setting, give the same FE columns
    to rounding (each a maximum or minimum of the same exact values) and the same
    verdicts and motor demand at the safe speed."""
    from railcheck.fea.screening import tuning
    from railcheck.progress import Progress
    from railcheck.sweep import chunk
    from railcheck.sweep.inputs import sweep_input
    from railcheck.sweep.run import prepare_models, sweep_context, sweep_settings

    text = FE_SWEEP.replace("parts = [", 'support = "free-body"\nparts = [')
    text = text.replace('crank = ["480 mm", "540 mm"]', 'crank = ["300 mm", "480 mm"]')  # 4 x 1 x 2 x 2 settings
    inputs = sweep_input(parse_scene(__import__("tomllib").loads(text), "test"))
    settings = sweep_settings(inputs)
    lengths = settings["four-bar"]
    models = prepare_models(inputs, settings, Progress(quiet=True))["four-bar"]
    ctx = sweep_context(inputs, "four-bar", models)
    ids = np.arange(lengths["crank"].size)
    results = []
    for size in (1, 5, 10**6):
        monkeypatch.setattr(chunk, "group_size", lambda steps, size=size: size)
        results.append(chunk.evaluate_chunk(ctx, lengths, ids))
    with monkeypatch.context() as m:  # every hole pair's histories cut into groups of two
        m.setattr(tuning, "GROUP_MOST", 2)
        results.insert(0, chunk.evaluate_chunk(ctx, lengths, ids))
    whole = results[-1]
    assert np.isfinite(whole["crank-rail_stress_MPa"]).sum() >= 4  # settings with FE in several groups
    # the settings with FE are those the run's chunks count as checked (one row per speed)
    checked = np.repeat(chunk.checked_settings(ctx, lengths), len(inputs.sweep.speeds))
    assert np.isfinite(whole["crank-rail_stress_MPa"]).tolist() == checked.tolist()
    # the motor demand is each setting's own at its own safe speed: peak power = peak torque x omega
    safe = np.isfinite(whole["safe_speed_Hz"])
    assert safe.sum() >= 4
    np.testing.assert_allclose(
        whole["power_peak_at_safe_W"][safe],
        whole["torque_peak_at_safe_Nm"][safe] * 2 * math.pi * whole["safe_speed_Hz"][safe],
        rtol=1e-12,
    )
    for other in results[:-1]:
        assert other.keys() == whole.keys()
        for key, value in whole.items():
            if key == chunk.MOTOR_CURVE_KEY:
                continue
            if value.dtype == object:
                assert other[key].tolist() == value.tolist(), key
            else:
                np.testing.assert_allclose(other[key], value, rtol=1e-12, err_msg=key)


@pytest.mark.parametrize("seed", range(4))
def test_chunks_hold_consecutive_settings_within_both_limits(seed):
    """A run's chunks cover every setting once, in order; each holds at most ``size``
    settings and at most ``checked_size`` settings checked by FE, and ends only where
    the next setting would break a limit (or the settings end)."""
    from railcheck.parallel.executor import chunk_ranges

    rng = np.random.default_rng(seed)
    checked = rng.random(int(rng.integers(1, 3000))) < rng.choice([0.0, 0.04, 0.5, 1.0])
    size, checked_size = int(rng.integers(1, 400)), int(rng.integers(1, 40))
    chunks = list(chunk_ranges(checked, size, checked_size))
    assert np.concatenate(chunks).tolist() == list(range(checked.size))
    for ids in chunks:
        assert ids.size <= size and checked[ids].sum() <= checked_size
        end = ids[-1] + 1
        if end < checked.size:  # the next setting would break a limit
            assert ids.size == size or checked[ids].sum() + checked[end] > checked_size


@pytest.mark.slow
def test_the_local_cluster_s_workers_run_without_the_dask_profiler_and_with_their_heap_settings():
    """The local cluster's workers get :data:`railcheck.parallel.dask.WORKER_CONFIG` (no
    statistical profiler sampling the computing thread) and the glibc heap settings of
    :data:`railcheck.parallel.dask.WORKER_MALLOC` in their environment."""
    import os

    import dask

    from railcheck.parallel.dask import WORKER_MALLOC
    from railcheck.parallel.executor import ChunkExecutor
    from railcheck.progress import Progress

    def settings():
        return dask.config.get("distributed.worker.profile.enabled"), {k: os.environ.get(k) for k in WORKER_MALLOC}

    with ChunkExecutor(None, 1, True, Progress(quiet=True)) as executor:
        seen = list(executor.client.run(settings).values())
    assert seen == [(False, {k: str(v) for k, v in WORKER_MALLOC.items()})]
    assert dask.config.get("distributed.worker.profile.enabled")  # this process keeps its own


def test_a_cluster_left_half_started_by_an_interrupt_closes_quietly_at_exit(monkeypatch):
    """Ctrl-C while the local cluster starts left it to distributed's exit hook, whose
    assertion on a worker still starting printed a traceback after "railcheck:
    interrupted". The hook is replaced (once) by one that closes the clusters quietly."""
    from distributed.deploy import spec

    from railcheck.parallel.dask import quiet_cluster_exit

    quiet_cluster_exit()
    quiet = spec.close_clusters._railcheck_quiet
    quiet_cluster_exit()  # once only
    assert spec.close_clusters._railcheck_quiet is quiet

    def half_started():
        raise AssertionError("Status.init")

    monkeypatch.setattr(spec, "close_clusters", half_started)
    quiet()  # the hook's error does not reach the exit


TWO_PLATES = (
    FINAL_DESIGN_SWEEP
    + """[check]
parts = ["PF_4b_006", "PF_4b_003_v2"]
[loads.PF_4b_003_v2]
longitudinal = "250 N"
transverse = "250 N"
[mesh]
size = "8 mm"
hole_size = "4 mm"
"""
)


@pytest.mark.slow
def test_parts_are_built_one_at_a_time_only_when_one_must_be_meshed_or_solved(tmp_path, monkeypatch):
    """With an empty cache the parts are built in this process one at a time; once their
    meshes are cached and their unit fields stored they are read on this process's
    threads, into the same models (each thread's screens bit for bit the builds'); with
    the store off (RAILCHECK_STORE=0) they are built one at a time again."""
    import railcheck.sweep.run as run_module
    from railcheck.fea.materials import MATERIALS
    from railcheck.progress import Progress
    from railcheck.sweep.inputs import sweep_input
    from railcheck.sweep.parts import part_is_stored

    monkeypatch.setenv("RAILCHECK_CACHE", str(tmp_path / "cache"))
    one_at_a_time = []
    serial = run_module.build_one_at_a_time

    def serial_recorded(tasks, args, say):  # records the call, builds one at a time
        one_at_a_time.append([t.name for t in tasks])
        return serial(tasks, args, say)

    monkeypatch.setattr(run_module, "build_one_at_a_time", serial_recorded)
    on_threads = []
    threaded = run_module.build_on_threads

    def threads_recorded(tasks, args, say, jobs):  # records the call, builds on the threads
        on_threads.append([t.name for t in tasks])
        return threaded(tasks, args, say, jobs)

    monkeypatch.setattr(run_module, "build_on_threads", threads_recorded)
    inputs = sweep_input(parse_scene(__import__("tomllib").loads(TWO_PLATES), "test"))
    settings = run_module.sweep_settings(inputs)
    tasks = run_module.part_tasks(inputs, settings)
    stored = lambda: [part_is_stored(inputs, t.name, t.lengths, MATERIALS["steel"]) for t in tasks]  # noqa: E731
    assert stored() == [False, False]
    cold = run_module.prepare_models(inputs, settings, Progress(quiet=True), jobs=2)["four-bar"]
    assert one_at_a_time == [["PF_4b_006", "PF_4b_003_v2"]] and stored() == [True, True]
    warm = run_module.prepare_models(inputs, settings, Progress(quiet=True), jobs=2)["four-bar"]
    assert len(one_at_a_time) == 1 and on_threads == [["PF_4b_006", "PF_4b_003_v2"]]  # nothing to mesh or solve
    for name in cold:
        for key, screen in cold[name].screens.items():
            np.testing.assert_array_equal(screen.stress, warm[name].screens[key].stress)
    monkeypatch.setenv("RAILCHECK_STORE", "0")
    assert stored() == [False, False]
    run_module.prepare_models(inputs, settings, Progress(quiet=True), jobs=2)
    assert len(one_at_a_time) == 2 and len(on_threads) == 1
