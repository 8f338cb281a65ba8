"""Bad input end to end: exit 2, one clear line, nothing half-written, earlier results kept."""

import json
import subprocess
import sys

import pytest
from scene_texts import FINAL_DESIGN, PLATE_LOADS

PLATE = PLATE_LOADS + """[mesh]
size = "12 mm"
hole_size = "4 mm"
"""

FOURBAR = FINAL_DESIGN


def check(tmp_path, scene_text, *extra, out="results"):
    scene = tmp_path / "scene.toml"
    scene.write_text(scene_text)
    return subprocess.run([sys.executable, "-m", "railcheck.cli", "check", str(scene), "--out",
                           str(tmp_path / out), *extra], capture_output=True, text=True, cwd=tmp_path)


def one_line_exit_2(proc, *needles):
    assert proc.returncode == 2, (proc.returncode, proc.stderr)
    errors = [l for l in proc.stderr.splitlines() if l.startswith("railcheck:")]
    assert len(errors) == 1 and "Traceback" not in proc.stderr, proc.stderr
    for n in needles:
        assert n in errors[0], errors[0]


CASES = [
    ("malformed TOML", "[check\nparts = [", ("scene", "malformed TOML")),
    ("length in kg", FOURBAR.replace('"480 mm"', '"480 kg"'), ("mechanism.crank", "kg")),
    ("unknown part", PLATE.replace('["PF_4b_003_v2"]', '["PF_4b_003_v2", "flux-capacitor"]'),
     ("check.parts", "flux-capacitor")),
    ("gravity with seed-2013", FOURBAR + '[dynamics]\nformulation = "seed-2013"\n[check]\nparts = ["crank-rail"]\n'
     'effects = ["inertia", "gravity"]\n', ("check.effects", "seed-2013")),
    ("loads for an unchecked part", PLATE.replace('parts = ["PF_4b_003_v2"]', 'parts = ["PF_4b_006"]'),
     ("loads.PF_4b_003_v2",)),
    ("unknown effect", PLATE.replace('[loads.', 'effects = ["wind"]\n[loads.'), ("check.effects", "wind")),
    ("hole size above size", PLATE.replace('hole_size = "4 mm"', 'hole_size = "40 mm"'), ("mesh.hole_size",)),
    ("mesh beyond memory", PLATE.replace('size = "12 mm"', 'size = "0.3 mm"').replace('hole_size = "4 mm"', ''),
     ("mesh.size", "GiB")),
    ("rocker rail of a slider-crank", '[mechanism]\nkind = "slider-crank"\ncrank = "300 mm"\ncoupler = "800 mm"\n'
     '[check]\nparts = ["rocker-rail"]\n', ("check.parts", "rocker")),
]


@pytest.mark.parametrize("name,text,needles", CASES, ids=[c[0] for c in CASES])
def test_bad_scene_exits_2_and_writes_nothing(tmp_path, name, text, needles):
    proc = check(tmp_path, text)
    one_line_exit_2(proc, *needles)
    assert sorted(p.name for p in tmp_path.iterdir()) == ["scene.toml"]   # nothing half-written


def test_output_dir_that_is_a_file(tmp_path):
    (tmp_path / "results").write_text("precious")
    proc = check(tmp_path, PLATE)
    one_line_exit_2(proc, "output.dir", "not a directory")
    assert (tmp_path / "results").read_text() == "precious"


def test_output_dir_not_writable(tmp_path):
    proc = check(tmp_path, PLATE, out="/proc/railcheck-results")
    one_line_exit_2(proc, "output.dir")


@pytest.mark.slow
def test_failed_run_leaves_earlier_results_untouched(tmp_path):
    good = check(tmp_path, PLATE)
    assert good.returncode == 0, good.stderr
    before = {p.name: p.read_bytes() for p in (tmp_path / "results").iterdir()}
    bad = check(tmp_path, PLATE.replace('size = "12 mm"', 'size = "0.3 mm"'), "--force")
    one_line_exit_2(bad, "mesh.size")
    after = {p.name: p.read_bytes() for p in (tmp_path / "results").iterdir()}
    assert before == after
    assert sorted(p.name for p in tmp_path.iterdir()) == ["results", "scene.toml"]


@pytest.mark.slow
def test_same_scene_twice_gives_byte_identical_summary(tmp_path):
    a = check(tmp_path, PLATE, out="a")
    b = check(tmp_path, PLATE, out="b")
    assert a.returncode == b.returncode == 0
    assert (tmp_path / "a" / "summary.json").read_bytes() == (tmp_path / "b" / "summary.json").read_bytes()
    assert json.loads((tmp_path / "a" / "summary.json").read_text())["verdict"] == "PASS"


def test_toggle_scene_exits_2_naming_the_crank_angle(tmp_path):
    aligned = FOURBAR.replace('"1020 mm"', '"420 mm"').replace('"840 mm"', '"840 mm"').replace('"780 mm"', '"780 mm"')
    # d = 420: d + b2 = 900 < 1620, |d - b2| = 60 = |840 - 780|: aligned at crank angle 0 (change point)
    scene = tmp_path / "t.toml"
    scene.write_text(aligned)
    proc = subprocess.run([sys.executable, "-m", "railcheck.cli", "kinematics", str(scene)], capture_output=True,
                          text=True)
    one_line_exit_2(proc, "crank angle 0 deg")
