"""The verdict's fail side: a part fails on stress, on fatigue and on deflection, each
alone, with exit 1 and its own entry in ``failures``; the default limit is sigma_u / 2;
the sweep refuses a setting for each criterion and names it. A planted bug in any of the
verdict's comparisons (a limit scaled, a check forced to pass) fails one of these tests."""

import contextlib
import io
import json
import math
import tomllib

import numpy as np
import pytest

from helpers import COARSE_RAILS, FINAL_DESIGN, FINAL_DESIGN_SWEEP
from railcheck.cli import main
from railcheck.scene import parse_scene
from railcheck.sweep.run import run_sweep
from railcheck.sweep.table import read_table
from railcheck.units import floored

#: PF_4b_003_v2 under the seed's constant explicit loads (4.2.1) on the default mesh, as
#: in the default scene (whose check, CI's main job, leaves its mesh and unit fields
#: cached: about 1 s here, against 8 s for a coarse mesh of its own, twice under two test
#: workers): about 93 MPa, fatigue factor about 8 (constant loads: n = Sut / sigma_m),
#: 0.11 mm
PLATE = """
[check]
parts = ["PF_4b_003_v2"]
EXTRA
[loads.PF_4b_003_v2]
longitudinal = "250 N"
transverse = "250 N"
[output]
vtk = false
png = false
plots = false
"""


def _check(tmp_path, extra: str, fatigue: str = ""):
    """``railcheck check`` through its command line (in this process): (exit status,
    stdout, summary)."""
    scene = tmp_path / "scene.toml"
    scene.write_text(PLATE.replace("EXTRA", extra) + fatigue)
    out = tmp_path / "out"
    stdout, stderr = io.StringIO(), io.StringIO()
    with contextlib.redirect_stdout(stdout), contextlib.redirect_stderr(stderr):
        status = main(["check", str(scene), "--out", str(out)])
    assert "Traceback" not in stderr.getvalue(), stderr.getvalue()
    return status, stdout.getvalue(), json.loads((out / "summary.json").read_text())


@pytest.fixture(scope="module")
def passing(tmp_path_factory):
    """The same plate with no limit given: the default limit, every check passing."""
    return _check(tmp_path_factory.mktemp("pass"), "")


def test_default_limit_is_half_the_ultimate_strength_and_the_plate_passes(passing):
    status, stdout, summary = passing
    part = summary["parts"]["PF_4b_003_v2"]
    assert part["limit_Pa"] == 375e6  # seed 000, 3.3.1: sigma_u / 2 of the 750 MPa steel
    assert summary["verdict"] == "PASS" and summary["failures"] == [] and status == 0
    assert stdout.strip().splitlines()[-1].startswith("verdict: PASS")
    assert 60e6 < part["max_von_mises_Pa"] < 120e6 and part["pass"] is True


@pytest.mark.parametrize(
    ("extra", "fatigue", "criterion"),
    [
        ('limit = "40 MPa"', "", "stress"),
        ("", "[fatigue]\nmin_safety = 20\n", "fatigue"),
        ('max_deflection = "0.05 mm"', "", "deflection"),
    ],
)
def test_a_part_fails_on_each_criterion_alone(tmp_path, passing, extra, fatigue, criterion):
    """Each scene breaks one criterion, which the passing run meets with margin: exit 1,
    exactly that failure, and the console's verdict line names it."""
    *_, ok = passing
    base = ok["parts"]["PF_4b_003_v2"]
    assert base["max_von_mises_Pa"] > 40e6 and base["tip_deflection_m"] > 0.05e-3
    status, stdout, summary = _check(tmp_path, extra, fatigue)
    assert status == 1
    assert summary["verdict"] == "FAIL" and summary["failures"] == [f"PF_4b_003_v2 {criterion}"]
    part = summary["parts"]["PF_4b_003_v2"]
    assert part["pass"] is False
    # the same figures as the passing run: only the verdict moved
    assert part["max_von_mises_Pa"] == pytest.approx(base["max_von_mises_Pa"], rel=1e-12)
    assert f"PF_4b_003_v2 {criterion}" in stdout.strip().splitlines()[-1]
    # the figure against its limit, the words to act on: the console, summary.json
    figures = {
        "stress": f"stress {part['max_von_mises_Pa'] / 1e6:.1f} MPa > 40 MPa",
        "fatigue": f"fatigue n {part['fatigue']['min_safety_factor']:.2f} < 20.00",
        "deflection": f"deflection {part['tip_deflection_m'] * 1e3:.2f} mm > 0.05 mm",
    }
    assert summary["failures_with_figures"] == [f"PF_4b_003_v2 {figures[criterion]}"]
    assert f"fails: PF_4b_003_v2 {figures[criterion]}" in stdout.splitlines()  # its own line, above the verdict
    assert all(len(line) <= 100 for line in stdout.splitlines() if not line.startswith("results in"))  # a path runs on


def test_a_fail_says_how_far_the_loads_must_fall_and_they_pass_there(tmp_path):
    """A part's "to pass" share of its loads (1 / utilisation: the linear model scales with
    them) is where it really passes: 0.1% below passes, 0.1% above fails."""
    (tmp_path / "fails").mkdir()
    status, stdout, summary = _check(tmp_path / "fails", 'limit = "40 MPa"')
    u = summary["parts"]["PF_4b_003_v2"]["utilisation"]
    assert status == 1 and u > 1
    assert summary["to_pass"][0].startswith(f"PF_4b_003_v2: its loads down to {1 / u:.0%} of these (stress")
    assert f"to pass: {summary['to_pass'][0]}" in fit_width_lines(stdout)
    for share, verdict in ((0.999, "PASS"), (1.001, "FAIL")):
        load = f'"{250.0 * share / u!r} N"'
        case = tmp_path / f"at-{share}"
        case.mkdir()
        (case / "scene.toml").write_text(PLATE.replace("EXTRA", 'limit = "40 MPa"').replace('"250 N"', load))
        out = case / "out"
        with contextlib.redirect_stdout(io.StringIO()), contextlib.redirect_stderr(io.StringIO()):
            main(["check", str(case / "scene.toml"), "--out", str(out)])
        assert json.loads((out / "summary.json").read_text())["verdict"] == verdict


#: the crank rail without grooves on a coarse linear mesh (a second to mesh), its weight in
#: plane with the inertia, failing a lowered stress limit at 1 Hz
CRANK_AT = (
    FINAL_DESIGN
    + """speed = "SPEED"
steps = 180
plane = "vertical"
[check]
parts = ["crank-rail"]
limit = "60 MPa"
effects = ["inertia", "gravity", "rail-inertia"]
"""
    + COARSE_RAILS
)


def _check_text(case, text: str) -> tuple[int, str, dict]:
    """``railcheck check`` of the scene ``text`` in the folder ``case``: (status, stdout, summary)."""
    case.mkdir()
    (case / "scene.toml").write_text(text)
    stdout, stderr = io.StringIO(), io.StringIO()
    with contextlib.redirect_stdout(stdout), contextlib.redirect_stderr(stderr):
        status = main(["check", str(case / "scene.toml"), "--out", str(case / "out")])
    assert "Traceback" not in stderr.getvalue(), stderr.getvalue()
    return status, stdout.getvalue(), json.loads((case / "out" / "summary.json").read_text())


def test_a_failing_parts_safe_speed_is_where_the_check_itself_flips(tmp_path):
    """A part that fails at its speed gets the crank speed up to which it passes at this
    setting (its cycle re-evaluated at trial speeds on its solved fields): a check 0.2%
    below that speed passes, 0.2% above fails; with weight the speed is no square-root
    scaling of the utilisation (planted: the weight left out of the trials fails this)."""
    status, stdout, summary = _check_text(tmp_path / "fails", CRANK_AT.replace("SPEED", "1 Hz"))
    u = summary["parts"]["crank-rail"]["utilisation"]
    safe = summary["parts_safe_speed"]["crank-rail"]
    assert status == 1 and u > 1.05 and safe["criterion"] == "stress"
    assert abs(safe["Hz"] - 1 / np.sqrt(u)) > 1e-3  # the weight does not scale with the speed
    assert f"to pass: crank-rail: passes up to {floored(safe['Hz'])} Hz at this setting" in fit_width_lines(stdout)
    assert summary["safe_speed"] == {"Hz": safe["Hz"], "set_by": "crank-rail", "criterion": "stress"}
    for share, verdict in ((0.998, "PASS"), (1.002, "FAIL")):
        _, _, at = _check_text(tmp_path / f"at-{share}", CRANK_AT.replace("SPEED", f"{safe['Hz'] * share!r} Hz"))
        assert at["verdict"] == verdict, (share, at["parts"]["crank-rail"]["utilisation"])


def test_a_passing_check_gives_the_speed_up_to_which_it_passes_floored(tmp_path):
    """A check that passes still ends with its safe speed: found from below (the passing
    part's own crossing, no component to cap it), it is where the check itself flips (0.1%
    above fails, 0.1% below passes), the console's figure floored (at most the crossing)
    and the scene key to set; planted: the search ignoring passing parts gives no line."""
    status, stdout, summary = _check_text(tmp_path / "passes", CRANK_AT.replace("SPEED", "0.5 Hz"))
    safe = summary["safe_speed"]
    assert status == 0 and summary["verdict"] == "PASS" and safe["set_by"] == "crank-rail"
    assert 0.5 < safe["Hz"] < 1.0 and safe["criterion"] == "stress"
    line = next(line for line in stdout.splitlines() if line.startswith("safe speed:"))
    printed = float(line.split("passes up to ")[1].split(" Hz")[0])
    assert printed <= safe["Hz"] < printed * 1.01 and f'[mechanism] speed = "{floored(safe["Hz"])} Hz"' in stdout
    for share, verdict in ((0.999, "PASS"), (1.0, "PASS"), (1.001, "FAIL")):  # at the figure itself: a pass
        _, _, at = _check_text(tmp_path / f"at-{share}", CRANK_AT.replace("SPEED", f"{safe['Hz'] * share!r} Hz"))
        assert at["verdict"] == verdict, (share, at["parts"]["crank-rail"]["utilisation"])
    # the same crossing found under the components' cap (evaluated at the cap, then refined)
    held = '[components]\nscrew_class = "12.9"\njoint_friction = 0.5\n'
    capped = CRANK_AT.replace("SPEED", "0.5 Hz").replace('"crank-rail"]', '"crank-rail", "crank-screws-O2"]') + held
    _, _, both = _check_text(tmp_path / "capped", capped)
    assert both["components_safe_speed"]["Hz"] > safe["Hz"] and both["safe_speed"]["set_by"] == "crank-rail"
    assert both["safe_speed"]["Hz"] == pytest.approx(safe["Hz"], rel=1e-6)


def test_a_safe_speed_is_floored_never_rounded_up():
    assert floored(1.195) == "1.19" and floored(0.29) == "0.29" and floored(2.999999) == "2.99"
    assert floored(12.345) == "12.3" and floored(1.0) == "1" and floored(0.0012399) == "0.00123"


def test_a_failures_figures_never_read_equal():
    """A criterion that fails by less than its printed decimals gets more of them."""
    from railcheck.model.records import apart

    assert apart(0.49, 1.0, 2) == 2 and apart(0.998, 1.0, 2) == 3 and apart(0.9999999, 1.0, 2) == 6
    assert apart(375.04, 375.0, 1) == 2 and apart(638.8, 375.0, 1) == 1


def fit_width_lines(stdout: str) -> str:
    """The console's text with its wrapped lines joined (a long line continues indented)."""
    return " ".join(line.strip() for line in stdout.splitlines())


SWEEP = (
    FINAL_DESIGN_SWEEP
    + """[check]
parts = ["crank-rail"]
EXTRA
[mesh]
size = "20 mm"
hole_size = "6 mm"
[geometry]
rail_groove_radius = "0 mm"
"""
)
# a rail without its grooves (a solid 23 x 22 mm section): the verdict's logic does not
# depend on the section, and the grooves' fine mesh costs 9 s cold against 1.4 s (and
# half the unknowns to solve)


def _sweep_row(tmp_path, extra: str, fatigue: str = "") -> dict:
    scene = parse_scene(tomllib.loads(SWEEP.replace("EXTRA", extra) + fatigue), "test")
    run = run_sweep(scene, str(tmp_path / "sweep"), serial=True)
    table = read_table(run.tables["four-bar"])
    rows = {k: np.asarray(v.to_numpy(zero_copy_only=False)) for k, v in zip(table.column_names, table.columns)}
    assert rows["setting"].size == 1
    return {k: v[0] for k, v in rows.items()}


@pytest.mark.parametrize(
    ("extra", "fatigue", "criterion"),
    [
        ('limit = "30 MPa"', "", "stress"),
        ("", "[fatigue]\nmin_safety = 30\n", "fatigue"),
        ('max_deflection = "0.01 mm"', "", "deflection"),
        pytest.param("", "", None, marks=pytest.mark.slow),
    ],
)
def test_sweep_fails_a_setting_on_each_criterion_and_names_it(tmp_path, extra, fatigue, criterion):
    row = _sweep_row(tmp_path, extra, fatigue)
    assert row["checks_passed"]
    if criterion is None:
        assert row["verdict"] == "pass" and row["reason"] is None and row["utilisation"] < 1.0
        assert row["crank-rail_stress_MPa"] > 30 and row["crank-rail_fatigue"] < 30 and row["crank-rail_tip_mm"] > 0.01
    else:
        assert row["verdict"] == "fail" and row["reason"] == f"crank-rail {criterion}"
        assert row["utilisation"] > 1.0


@pytest.fixture(scope="module")
def plate_result():
    """The plate's check in this process (the records themselves, not their JSON)."""
    from railcheck.check.pipeline import run_pipeline

    return run_pipeline(parse_scene(tomllib.loads(PLATE.replace("EXTRA", "")), "test"))


def test_each_limit_is_inclusive_and_the_next_float_below_fails(plate_result):
    """At exactly its limit a part passes (stress <= limit, deflection <= limit, fatigue
    factor >= required); one float beyond, it fails that criterion alone."""
    from dataclasses import replace

    part = plate_result.parts["PF_4b_003_v2"]
    stress, tip = part.verdict_stress, part.cycle.envelope.max_tip
    at = replace(part, job=replace(part.job, limit=stress, max_deflection=tip))
    assert at.stress_passed and at.deflection_passed and at.passed
    below = replace(part, job=replace(part.job, limit=np.nextafter(stress, 0)))
    assert not below.stress_passed and below.deflection_passed and not below.passed
    stiff = replace(part, job=replace(part.job, max_deflection=np.nextafter(tip, 0)))
    assert stiff.stress_passed and not stiff.deflection_passed and not stiff.passed
    unlimited = replace(part, job=replace(part.job, max_deflection=None))
    assert unlimited.deflection_passed and unlimited.deflection_limit is None
    assert part.limit == part.job.limit and part.name == "PF_4b_003_v2"


def test_a_failed_configuration_check_is_a_failure_of_the_run(plate_result):
    from dataclasses import replace

    from railcheck.kinematics.checks import CheckResult

    assert plate_result.passed and plate_result.failures == []
    bad = replace(plate_result, checks={"grashof": CheckResult(False, "no"), "assembly": CheckResult(True, "ok")})
    assert bad.failures == ["check grashof"] and not bad.passed
    failing_part = replace(
        plate_result.parts["PF_4b_003_v2"], job=replace(plate_result.parts["PF_4b_003_v2"].job, limit=1e6)
    )
    both = replace(bad, parts={"PF_4b_003_v2": failing_part})
    assert both.failures == ["check grashof", "PF_4b_003_v2 stress"]


def test_the_records_are_frozen(plate_result):
    """Every record of a check is immutable once built (workers and the report share them)."""
    import dataclasses

    part = plate_result.parts["PF_4b_003_v2"]
    cycle = part.cycle
    for record in (plate_result, part, cycle, cycle.fatigue, cycle.seed_method, cycle.history):
        field = dataclasses.fields(record)[0].name
        with pytest.raises(dataclasses.FrozenInstanceError):
            setattr(record, field, None)


def test_the_console_table_keeps_its_columns_when_a_part_fails(plate_result):
    """A failing part's verdict ("FAIL stress+fatigue+deflection") and long numbers widen
    their columns: every cell starts where its header starts, and the utilisation names the
    criterion that governs it (fatigue counts: #24)."""
    from dataclasses import replace

    from railcheck.report.text import parts_table

    part = plate_result.parts["PF_4b_003_v2"]
    spec = replace(part.job.fatigue, min_safety=100.0)
    failing = replace(part, job=replace(part.job, limit=1e6, max_deflection=1e-6, fatigue=spec))
    failing = replace(failing, cycle=replace(failing.cycle, fatigue=replace(failing.cycle.fatigue, required=100.0)))
    result = replace(plate_result, parts={"PF_4b_003_v2": failing, "copy-of-the-plate": part})
    lines = parts_table(result).splitlines()
    header, rows = lines[0], lines[1:3]
    assert rows[0].split()[-1] == "FAIL" and rows[1].split()[-1] == "PASS"
    assert all(len(line) <= 100 for line in lines)  # the console's width: notes wrap, rows fit
    starts = [header.index(h) for h in ("utilisation", "governs", "verdict")]
    for row in rows:
        for s in starts[1:]:
            assert row[s - 2 : s] == "  " and row[s] != " "  # two spaces, then the cell
    assert failing.governing_criterion == "deflection" and failing.utilisation > 10
    assert part.governing_criterion == "stress" and part.utilisation == pytest.approx(part.verdict_stress / 375e6)
    fatigue_governs = replace(part, job=replace(part.job, fatigue=replace(spec, min_safety=9.0)))
    fatigue_governs = replace(fatigue_governs, cycle=replace(part.cycle, fatigue=replace(part.cycle.fatigue, required=9.0)))
    assert fatigue_governs.governing_criterion == "fatigue"
    assert fatigue_governs.utilisation == pytest.approx(9.0 / part.cycle.fatigue.min_safety_factor)


def test_the_dynamic_verdict_is_inclusive_and_its_record_frozen():
    """Amplification at exactly its limit passes, one float above fails (records alone,
    no FE: test_dynamic.py runs the response itself)."""
    import dataclasses

    from railcheck.model.records import DynamicResult

    d = DynamicResult(
        hz=np.array([30.0]),
        harmonics=np.array([30]),
        crank_hz=1.0,
        amplification=1.05,
        quasi_static_peak=100e6,
        dynamic_peak=105e6,
        damping=0.02,
        max_amplification=1.05,
    )
    assert d.passed
    assert not dataclasses.replace(d, amplification=np.nextafter(1.05, 2.0)).passed
    with pytest.raises(dataclasses.FrozenInstanceError):
        d.amplification = 1.0


def test_each_criterions_utilisation_by_hand(plate_result):
    """stress / limit; required / fatigue factor (a factor below 1 too, and 0: unlimited);
    deflection / its limit; dynamic: (A - 1) / (A_max - 1), 0 for A = 1 and, with no
    allowed excess, unlimited above 1; yield: peak / sigma_y, failing above 1."""
    from dataclasses import replace

    from railcheck.model.records import DynamicResult

    part = plate_result.parts["PF_4b_003_v2"]
    c = part.cycle
    weak = replace(part, cycle=replace(c, fatigue=replace(c.fatigue, min_safety_factor=0.5, required=1.0)))
    assert weak.utilisations["fatigue"] == pytest.approx(2.0) and weak.governing_criterion == "fatigue"
    broken = replace(part, cycle=replace(c, fatigue=replace(c.fatigue, min_safety_factor=0.0)))
    assert broken.utilisations["fatigue"] == float("inf")
    limited = replace(part, job=replace(part.job, max_deflection=4 * c.envelope.max_tip))
    assert limited.utilisations["deflection"] == pytest.approx(0.25)
    d = DynamicResult(np.array([30.0]), np.array([30]), 1.0, 1.05, 1e8, 1.05e8, 0.02, 1.10)
    dyn = replace(part, cycle=replace(c, dynamic=d))
    assert dyn.utilisations["dynamic"] == pytest.approx(0.5, rel=1e-12)
    assert replace(part, cycle=replace(c, dynamic=replace(d, amplification=1.0))).utilisations["dynamic"] == 0.0
    none_allowed = replace(d, max_amplification=1.0)
    assert replace(part, cycle=replace(c, dynamic=none_allowed)).utilisations["dynamic"] == float("inf")
    exact = replace(none_allowed, amplification=1.0)
    assert replace(part, cycle=replace(c, dynamic=exact)).utilisations["dynamic"] == 0.0
    assert set(part.utilisations) == {"stress", "fatigue", "yield", "small-displacement"}  # no limit, no response
    assert part.utilisations["yield"] == pytest.approx(part.verdict_stress / 490e6, rel=1e-12)
    # a linear peak above yield fails the part even under a limit set above yield
    beyond = replace(
        part, job=replace(part.job, limit=1e9), cycle=replace(c, envelope=replace(c.envelope, max_von_mises=5e8))
    )
    assert beyond.stress_passed and not beyond.within_yield and not beyond.passed
    assert beyond.governing_criterion == "yield" and beyond.utilisations["yield"] == pytest.approx(5e8 / 490e6)
    # small displacements: the largest deflection over 2 % of the part's length
    length = part.geometry.get("length")
    assert part.utilisations["small-displacement"] == pytest.approx(c.envelope.max_tip / (0.02 * length), rel=1e-12)
    for share, holds in ((0.0199, True), (0.0201, False)):
        sagging = replace(part, cycle=replace(c, envelope=replace(c.envelope, max_tip=share * length)))
        assert sagging.small_displacements is holds and sagging.passed is holds
        failures = replace(plate_result, parts={"PF_4b_003_v2": sagging}).failures
        assert ("PF_4b_003_v2 beyond small displacements" in failures) is (not holds)


def test_the_load_table_gives_explicit_loads_as_given_and_says_so(plate_result):
    """The report's load table and the picture's labels read one list of forces: the
    bracket's explicit loads (250 + 250 N on each of four holes) are applied as given, so
    applied = unfactored and no label claims a load factor."""
    from railcheck.report.forces import applied_factor, governing_forces
    from railcheck.report.render import picture_caption

    part = plate_result.parts["PF_4b_003_v2"]
    (bolts,) = governing_forces(part)
    assert bolts.force[:2] == pytest.approx([1000.0, 1000.0]) and applied_factor(part) == 1.0
    assert "as given" in picture_caption("PF_4b_003_v2", part, 1.0) and "x1.4" not in picture_caption("x", part, 1.0)


def test_the_report_tabulates_each_parts_loads_applied_and_unfactored(plate_result, tmp_path):
    from railcheck.check.summary import summary_of
    from railcheck.report.html import write_report

    page = tmp_path / "report.html"
    write_report(page, plate_result.scene, plate_result, summary_of(plate_result), tmp_path)
    text = page.read_text()
    table = text[text.index("<h2>Loads at each part's governing instant</h2>") :].split("</table>", 1)[0]
    assert "1 (as given)" in table and table.count("1414.2") == 2  # applied and unfactored alike


def test_the_assumptions_name_each_mesh_and_where_it_came_from():
    """The meshes' line: elements, sizes, shipped or built on this machine, and the curved
    edges straightened where the mesh says so (planted: the count dropped, or the shipped
    flag ignored, fails this)."""
    from types import SimpleNamespace

    from railcheck.model.assumptions import mesh_assumption

    def part(shipped, warning=None, order=2):
        job = SimpleNamespace(mesh=SimpleNamespace(order=order, curved=True, size=0.02, hole_size=0.006))
        return SimpleNamespace(job=job, mesh=SimpleNamespace(shipped=shipped, tets=np.zeros((123, 4)), warning=warning))

    folded = "38 curved edges straightened to keep elements from folding (0.4% of the curved edges; ...)"
    words = mesh_assumption({"crank-rail": part(True, folded), "PF_4b_006": part(False), "bar": part(False, order=1)})
    assert words == (
        "meshes: crank-rail 123 quadratic tetrahedra, curved edges, 20 mm (6 mm at the holes), shipped with railcheck, "
        "38 curved edges straightened; PF_4b_006 123 quadratic tetrahedra, curved edges, 20 mm (6 mm at the holes), "
        "built by gmsh on this machine; bar 123 linear tetrahedra, 20 mm (6 mm at the holes), built by gmsh on this machine"
    )


@pytest.mark.parametrize("hz", [math.inf, 0.0, 1.2345])
def test_a_safe_speed_reads_in_words_at_rest_at_a_speed_and_at_any_speed(hz):
    """A part or a check whose loads do not grow with the speed passes at any speed: said
    in words, never "inf Hz" (it raised OverflowError before); 0 fails at rest; a finite
    speed is floored to three figures."""
    from railcheck.check.margins import SafeSpeed
    from railcheck.model.records import passes_up_to, safe_speed_words

    safe = SafeSpeed(hz, "crank-rail", "stress")
    part, check = passes_up_to("crank-rail", safe), safe_speed_words(safe)
    assert "inf" not in part + check and "nan" not in part + check
    if hz == math.inf:
        assert "any speed" in part and "any speed" in check
    elif hz == 0:
        assert "fails at rest" in part and "fails at rest" in check
    else:
        assert '"1.23 Hz"' in part and '"1.23 Hz"' in check
