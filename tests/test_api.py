"""The Python API (railcheck.api): a scene from a path, TOML text, a dict, a Scene or None;
the check's summary equals the command line's summary.json; the sweep's tables are pyarrow
tables equal to the files the command line writes; the docs' example runs as printed."""

import json
import subprocess
import sys
import tomllib
from pathlib import Path

import pytest

import railcheck
from helpers import FINAL_DESIGN, FINAL_DESIGN_SWEEP
from railcheck.api import Sweep, scene_of
from railcheck.base.errors import InputError
from railcheck.frames import column_name, parts_frame
from railcheck.scene import Scene, load_scene

ROOT = Path(__file__).parents[1]
ONE_PART = FINAL_DESIGN + 'steps = 360\n[check]\nparts = ["coupler-rail"]\n'


def test_a_path_with_an_equals_sign_in_its_name_is_a_path(tmp_path):
    """An existing file is read as a file even when its name holds "=" (it was parsed as
    TOML text: issue 79)."""
    path = tmp_path / "speed=1Hz.toml"
    path.write_text(ONE_PART)
    read = scene_of(str(path))
    assert read.raw == tomllib.loads(ONE_PART) and read.source == scene_of(path).source != "<text>"
    with pytest.raises(InputError):
        scene_of("check = 1")  # no such file: TOML text, refused by the scene reader


def test_a_scene_is_a_path_toml_text_a_dict_a_scene_or_none(tmp_path):
    path = tmp_path / "s.toml"
    path.write_text(ONE_PART)
    scenes = [scene_of(path), scene_of(str(path)), scene_of(ONE_PART), scene_of(tomllib.loads(ONE_PART))]
    assert {s.checked.parts for s in scenes} == {("coupler-rail",)}
    assert {s.linkage_spec.steps for s in scenes} == {360}
    default = scene_of(None)
    assert isinstance(default, Scene) and default.checked.parts == load_scene(None).checked.parts
    assert scene_of(default) is default


def test_bad_scenes_are_refused_naming_the_field():
    with pytest.raises(InputError) as err:
        scene_of(42)
    assert err.value.field == "scene"
    with pytest.raises(InputError) as err:
        scene_of("[mechanism\nkind = 1")
    assert err.value.field == "scene" and "malformed" in str(err.value)
    with pytest.raises(InputError) as err:
        scene_of({"mechanism": {"kind": "four-bar"}})
    assert err.value.field == "mechanism.crank"


def test_railcheck_check_and_sweep_are_callable_and_the_packages_importable():
    import railcheck.check.run  # noqa: F401  the package's modules still import
    import railcheck.sweep.table  # noqa: F401

    assert callable(railcheck.check) and callable(railcheck.sweep)
    assert railcheck.check.run_pipeline is not None


@pytest.mark.slow  # a coupler-rail check twice (the API and the command line)
def test_the_api_check_equals_the_command_lines_summary(tmp_path):
    path = tmp_path / "s.toml"
    path.write_text(ONE_PART)
    run = railcheck.check(str(path))
    assert run.target is None and run.passed and run.exit_status == 0
    proc = subprocess.run(
        [sys.executable, "-P", "-m", "railcheck.cli", "check", str(path), "--out", str(tmp_path / "cli")],
        capture_output=True,
        text=True,
    )
    assert proc.returncode == 0, proc.stderr
    assert run.summary == json.loads((tmp_path / "cli" / "summary.json").read_text())
    written = railcheck.check(str(path), out=tmp_path / "api")
    assert written.target == tmp_path / "api" and (tmp_path / "api" / "summary.json").is_file()


@pytest.mark.slow  # a one-setting sweep twice
def test_the_api_sweep_gives_the_tables_the_command_line_writes(tmp_path):
    text = FINAL_DESIGN_SWEEP + '[check]\nparts = ["coupler-rail"]\n'
    result = railcheck.sweep(text, serial=True)
    assert result.target is None and set(result.tables) == {"four-bar"}
    table = result.tables["four-bar"]
    assert table.num_rows == 1 and "coupler-rail_utilisation" in table.column_names
    passing = result.summary["by_kind"]["four-bar"]["settings_passing"]
    assert repr(result) == f"Sweep(kinds={{'four-bar': '{passing}/1 settings pass'}}, rows={{'four-bar': 1}}, target=None)"
    path = tmp_path / "s.toml"
    path.write_text(text)
    proc = subprocess.run(
        [sys.executable, "-P", "-m", "railcheck.cli", "sweep", str(path), "--serial", "--out", str(tmp_path / "cli")],
        capture_output=True,
        text=True,
    )
    assert proc.returncode == (0 if passing == 1 else 1), proc.stderr  # the verdict: every setting passes
    cli = railcheck.sweep.read_table(next((tmp_path / "cli").glob("*four-bar*.parquet")))
    assert cli.equals(table)


@pytest.mark.slow  # the docs' example: a coupler-rail check
def test_the_docs_example_runs_as_printed(capsys):
    text = (ROOT / "docs" / "api.md").read_text()
    code = text.split("```python\n", 1)[1].split("```", 1)[0]
    exec(compile(code, "docs/api.md", "exec"), {})
    lines = capsys.readouterr().out.splitlines()
    first = lines[0].split()
    assert first[0] in ("True", "False") and float(first[2]) > 0
    assert lines[2].startswith("Check(verdict=") and lines[3].split() == [
        "part",
        "stress_MPa",
        "fatigue_factor",
        "utilisation",
    ]
    assert lines[4].split()[0] == "coupler-rail" and float(lines[4].split()[1]) == pytest.approx(float(lines[1].split()[0]))


@pytest.mark.slow  # three checks of the coupler rail with their pictures
def test_two_checks_on_two_threads_give_one_checks_summary_and_pictures(tmp_path):
    """Issue 79: two ``railcheck.check`` calls on two threads gave the coupler rail other
    last digits than one call alone, and with PNG output one thread raised from pyvista's
    half-imported module. Calls now run one after another: each thread's summary is the
    lone call's, byte for byte, and both write their pictures."""
    import threading

    results: dict = {}

    def run(i: int) -> None:
        try:
            results[i] = railcheck.check(ONE_PART, out=tmp_path / f"t{i}").summary
        except Exception as exc:  # noqa: BLE001 - the test reports it
            results[i] = exc

    threads = [threading.Thread(target=run, args=(i,)) for i in range(2)]
    for t in threads:
        t.start()
    for t in threads:
        t.join(timeout=600)
    alone = railcheck.check(ONE_PART, out=tmp_path / "alone").summary  # after: pyvista first imported on the threads
    for i in range(2):
        assert not isinstance(results[i], Exception), results[i]
        assert json.dumps(results[i], sort_keys=True) == json.dumps(alone, sort_keys=True)
        assert list((tmp_path / f"t{i}").glob("*.png"))


def test_an_api_sweep_killed_before_leaves_nothing_after_the_next(tmp_path, monkeypatch):
    """Issue 79: ``kill -9`` of ``railcheck.sweep(scene)`` left its scratch folder in
    $TMPDIR for good. The folder carries its process id; the next in-memory sweep removes
    those of processes no longer running, and leaves a running one's and foreign folders."""
    import os
    import tempfile

    monkeypatch.setattr(tempfile, "tempdir", str(tmp_path))
    dead = subprocess.Popen([sys.executable, "-c", "pass"])
    dead.wait()
    (tmp_path / f"railcheck-sweep-{dead.pid}-abc" / "sweep").mkdir(parents=True)
    (tmp_path / f"railcheck-sweep-{os.getppid()}-live").mkdir()  # pytest's parent: running
    (tmp_path / "railcheck-sweep-notes").mkdir()
    scene = '[sweep]\nkind = "four-bar"\nsteps = 16\ncrank = ["480 mm", "480 mm"]\n[output]\nplots = false\n'
    run = railcheck.sweep(scene, serial=True)
    assert run.summary["by_kind"]["four-bar"]["settings_total"] > 0
    assert sorted(p.name for p in tmp_path.iterdir()) == [f"railcheck-sweep-{os.getppid()}-live", "railcheck-sweep-notes"]


def test_the_api_has_the_functions_signatures_and_docs_a_short_repr_and_a_progress_callback(capsys):
    """``inspect.signature`` and ``help`` read the functions (not ``(*args, **kwargs)`` and
    the package's text); a check's repr is one short line with its verdict, utilisations
    and safe speed; ``progress=`` a callable receives the command line's progress lines."""
    import inspect

    import railcheck

    assert list(inspect.signature(railcheck.check).parameters)[:2] == ["scene", "out"]
    assert "progress" in inspect.signature(railcheck.sweep).parameters
    assert railcheck.check.__doc__.startswith("railcheck.check(scene") and "railcheck.sweep(scene" in railcheck.sweep.__doc__
    for function in (railcheck.check, railcheck.sweep):  # numpydoc: every parameter documented
        documented = function.__doc__.split("Parameters\n", 1)[1].split("Returns\n", 1)[0]
        for name in inspect.signature(function).parameters:
            assert f"\n    {name} : " in documented, name
    lines: list[str] = []
    data = {
        "mechanism": {"kind": "four-bar", "crank": "480 mm", "coupler": "840 mm", "rocker": "780 mm"}
        | {"ground": "1020 mm", "speed": "1 Hz", "steps": 360},
        "check": {"parts": ["crank-screws-O2"], "effects": ["inertia"]},
    }
    run = railcheck.check(data, progress=lines.append)
    text = repr(run)
    assert text.startswith("Check(verdict='FAIL', failures=['crank-screws-O2 slip']") and len(text) < 400
    assert "'crank-screws-O2': 6.2" in text and "safe_speed='0.399" in text
    assert any("kinematics" in line for line in lines) and all(line.startswith("[") for line in lines)
    capsys.readouterr()
    railcheck.check(data)  # silent by default (the command line's lines are opt-in)
    assert capsys.readouterr().err == ""
    railcheck.check(data, progress=True)
    assert "kinematics" in capsys.readouterr().err


def test_frames_of_parts_components_and_settings_have_attribute_columns_with_units():
    """A check's parts and components as pandas frames with the summary's figures (in MPa
    and mm at this edge), columns reachable as attributes; a sweep table's columns renamed
    the same way; a kind the sweep lacks refused naming it."""
    assert column_name("crank-rail_stress_MPa") == "crank_rail_stress_MPa"
    assert column_name("small-displacement utilisation") == "small_displacement_utilisation"
    data = {
        "mechanism": {"kind": "four-bar", "crank": "480 mm", "coupler": "840 mm", "rocker": "780 mm"}
        | {"ground": "1020 mm", "speed": "1 Hz", "steps": 360},
        "check": {"parts": ["crank-screws-O2", "shaft-O2"], "effects": ["inertia"]},
    }
    run = railcheck.check(data)
    comps = run.components_frame()
    assert list(comps.component) == ["crank-screws-O2", "shaft-O2"]
    assert comps.utilisation[0] == run.summary["components"]["crank-screws-O2"]["utilisation"]
    assert comps.slip_utilisation[0] > 1 and not comps.passed[0] and comps.governs[0] == "slip"
    assert run.parts_frame().empty
    part = {"max_von_mises_Pa": 18e6, "limit_Pa": 375e6, "fatigue": {"min_safety_factor": 19.2}, "pass": True}
    part |= {"tip_deflection_m": None, "max_deflection_m": 2.4e-4, "utilisation": 0.05, "governing_criterion": "fatigue"}
    part |= {"utilisation_by_criterion": {"stress": 0.048, "small-displacement": 0.01}}
    parts = parts_frame({"parts": {"coupler-rail": part}})  # a free body's tip is null in summary.json: NaN
    assert parts.stress_MPa[0] == pytest.approx(18.0) and parts.max_deflection_mm[0] == pytest.approx(0.24)
    assert parts.tip_deflection_mm.isna()[0] and parts.small_displacement_utilisation[0] == 0.01
    import pyarrow as pa

    table = pa.table({"crank-rail_stress_MPa": [1.0, 2.0], "setting": [0, 1]})
    frame = Sweep({"by_kind": {}}, {"four-bar": table}).frame()
    assert list(frame.columns) == ["crank_rail_stress_MPa", "setting"] and frame.crank_rail_stress_MPa[1] == 2.0
    with pytest.raises(InputError) as refused:
        Sweep({}, {"four-bar": table}).frame("slider-crank")
    assert refused.value.field == "kind"
