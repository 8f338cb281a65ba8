"""`railcheck kinematics`: JSON contract, plots, and bad input -> exit 2 naming the field."""

import json
import subprocess
import sys

import pytest

from helpers import FINAL_DESIGN, assert_picture
from railcheck.cli import main

GOOD = (
    FINAL_DESIGN
    + """speed = "1 Hz"
steps = 5000
assembly = "open"
[dynamics]
formulation = "seed-2013"
"""
)


def run(argv, capsys):
    code = main(argv)
    out, err = capsys.readouterr()
    return code, out, err


def test_json_contract(tmp_path, capsys, sig):
    scene = tmp_path / "s.toml"
    scene.write_text(GOOD)
    code, out, err = run(["kinematics", str(scene), "--json"], capsys)
    assert code == 0
    data = json.loads(out)
    assert data["formulation"] == "seed-2013"
    assert set(data["peak_reactions_N"]) == {"O2", "A", "B", "O4"}
    assert set(data["peak_crank_angle_deg"]) == {"O2", "A", "B", "O4", "torque"}
    assert sig(data["peak_reactions_N"]["O2"], 450.1626)
    assert sig(data["peak_torque_Nm"], 113.7598)
    assert sig(data["transmission_angle_deg"]["min"], 38.7192)
    assert all(set(c) == {"ok", "message"} for c in data["checks"].values())
    assert {"assembly", "grashof", "transmission_angle", "crank_rail_collision", "hole_grid"} <= set(data["checks"])


def test_default_scene_is_the_seed_final_design(capsys):
    code, out, _ = run(["kinematics", "--json"], capsys)
    data = json.loads(out)
    assert code == 0
    assert data["mechanism"]["crank_mm"] == 480 and data["mechanism"]["ground_mm"] == 1020
    assert data["formulation"] == "newton-euler"


def test_plots_written(tmp_path, capsys):
    code, out, _ = run(["kinematics", "--plots", str(tmp_path / "p")], capsys)
    assert code == 0
    names = sorted(p.name for p in (tmp_path / "p").iterdir())
    assert names == ["angles.png", "angular_accelerations.png", "angular_velocities.png", "reactions.png", "torque.png"]
    for n in names:
        assert_picture(tmp_path / "p" / n)


BAD = [
    ('crank = "480 mm"', "crank = 480", "mechanism.crank"),  # bare number
    ('crank = "480 mm"', 'crank = "480 kg"', "mechanism.crank"),  # wrong unit
    ('crank = "480 mm"', 'crank = "-480 mm"', "mechanism.crank"),  # negative
    ('crank = "480 mm"', 'crank = "0 mm"', "mechanism.crank"),  # zero
    ('crank = "480 mm"', 'crank = "nan mm"', "mechanism.crank"),  # NaN
    ('crank = "480 mm"', "", "mechanism.crank"),  # missing
    ('speed = "1 Hz"', 'speed = "1 Hz"\ncolour = "red"', "mechanism.colour"),  # unknown key
    ('speed = "1 Hz"', 'speed = "1 mm"', "mechanism.speed"),
    ("steps = 5000", "steps = 2.5", "mechanism.steps"),
    ('assembly = "open"', 'assembly = "sideways"', "mechanism.assembly"),
    ('formulation = "seed-2013"', 'formulation = "lagrange"', "dynamics.formulation"),
    ('kind = "four-bar"', 'kind = "five-bar"', "mechanism.kind"),
    ('ground = "1020 mm"', 'ground = "3000 mm"', "mechanism.ground"),  # cannot be assembled
]


@pytest.mark.parametrize("old,new,field", BAD)
def test_bad_input_exits_2_naming_the_field(tmp_path, capsys, old, new, field):
    scene = tmp_path / "bad.toml"
    scene.write_text(GOOD.replace(old, new))
    code, out, err = run(["kinematics", str(scene)], capsys)
    assert code == 2
    assert out == ""
    lines = err.strip().splitlines()
    assert len(lines) == 1 and field in lines[0], err


def test_crank_that_cannot_revolve_is_refused(tmp_path, capsys):
    scene = tmp_path / "bad.toml"
    scene.write_text(GOOD.replace('rocker = "780 mm"', 'rocker = "300 mm"'))
    code, _, err = run(["kinematics", str(scene)], capsys)
    assert code == 2 and "cannot make a full revolution" in err


def test_malformed_toml_and_missing_file(tmp_path, capsys):
    scene = tmp_path / "bad.toml"
    scene.write_text("[mechanism\nkind=")
    code, _, err = run(["kinematics", str(scene)], capsys)
    assert code == 2 and "malformed TOML" in err and len(err.strip().splitlines()) == 1
    code, _, err = run(["kinematics", str(tmp_path / "nope.toml")], capsys)
    assert code == 2 and "file not found" in err


def test_no_traceback_in_a_real_process(tmp_path):
    scene = tmp_path / "bad.toml"
    scene.write_text(GOOD.replace('crank = "480 mm"', "crank = 480"))
    proc = subprocess.run(
        [sys.executable, "-P", "-m", "railcheck.cli", "kinematics", str(scene)], capture_output=True, text=True
    )
    assert proc.returncode == 2
    assert "Traceback" not in proc.stderr
    assert proc.stderr.strip() == (
        'railcheck: error: mechanism.crank: needs a unit, e.g. "480 mm" (got the bare number 480)'
    )


REJECTED = GOOD.replace('crank = "480 mm"', 'crank = "540 mm"')  # seed 3.3.6 "NO CUMPLE": mu min 34.2 deg


def test_seeds_rejected_design_fails_naming_the_transmission_angle(tmp_path, capsys):
    scene = tmp_path / "rejected.toml"
    scene.write_text(REJECTED)
    code, out, err = run(["kinematics", str(scene)], capsys)
    assert code == 1
    assert "verdict: FAIL (check transmission_angle)" in out.splitlines()[-1]


def test_failed_configuration_check_fails_the_check_run(tmp_path, capsys):
    scene = tmp_path / "rejected.toml"
    scene.write_text(
        REJECTED + '[check]\nparts = ["PF_4b_003_v2"]\n[loads.PF_4b_003_v2]\nlongitudinal = "10 N"\n'
        "[output]\nvtk = false\npng = false\nplots = false\n"  # the default mesh: cached by CI's main job
    )
    code, out, err = run(["check", str(scene), "--out", str(tmp_path / "r"), "--json"], capsys)
    summary = json.loads(out)
    assert code == 1
    assert summary["verdict"] == "FAIL" and summary["failures"] == ["check transmission_angle"]
    assert summary["parts"]["PF_4b_003_v2"]["pass"] is True  # the part itself passes


def test_a_joint_beyond_its_rail_fails(tmp_path, capsys):
    scene = tmp_path / "long.toml"
    scene.write_text(GOOD.replace('coupler = "840 mm"', 'coupler = "1200 mm"').replace('"1020 mm"', '"1320 mm"'))
    code, out, err = run(["kinematics", str(scene), "--json"], capsys)
    check = json.loads(out)["checks"]["joints_on_rails"]
    assert code == 1 and not check["ok"] and "beyond the rail's last two holes" in check["message"]


def test_init_writes_a_commented_scene_that_runs(tmp_path, capsys):
    path = tmp_path / "mine.toml"
    assert run(["init", str(path)], capsys)[0] == 0
    text = path.read_text()
    assert text.count("#") > 20 and "[fatigue]" in text
    code, out, err = run(["kinematics", str(path), "--json"], capsys)
    assert code == 0 and json.loads(out)["mechanism"]["crank_mm"] == 480
    code, out, err = run(["init", str(path)], capsys)
    assert code == 2 and "exists" in err


def test_init_writes_a_scene_that_checks_exactly_what_the_default_checks(tmp_path, capsys):
    """#24: the starter scene is the built-in default (explicit plate loads included):
    every parsed setting equal, so `railcheck check` of it gives the default's results (only
    the scene's text and name in summary.json differ)."""
    import dataclasses

    from railcheck.scene import load_scene

    path = tmp_path / "mine.toml"
    assert run(["init", str(path)], capsys)[0] == 0
    mine, default = load_scene(path), load_scene(None)
    for f in dataclasses.fields(default):
        if f.name not in ("raw", "source"):
            assert getattr(mine, f.name) == getattr(default, f.name), f.name


def test_bare_command_prints_usage_and_version(capsys):
    assert main([]) == 2
    assert "usage: railcheck" in capsys.readouterr().out
    with pytest.raises(SystemExit) as exc:
        main(["--version"])
    assert exc.value.code == 0 and capsys.readouterr().out.startswith("railcheck ")


def test_output_paths_are_checked_before_any_work(tmp_path, capsys):
    blocker = tmp_path / "file"
    blocker.write_text("x")
    code, out, err = run(["kinematics", "--plots", str(blocker)], capsys)
    assert code == 2 and "--plots" in err and out == ""  # nothing computed, nothing printed
    code, out, err = run(["mechanism", "a-z-1139", "--gif", str(blocker / "x.gif")], capsys)
    assert code == 2 and "--gif" in err and out == ""


def test_every_command_help_has_a_description_and_the_main_ones_their_exit_statuses():
    """Each command's --help says what it does; check and kinematics say their exit statuses
    (and check where its results go)."""
    from railcheck.cli import build_parser

    parser = build_parser()
    commands = next(a for a in parser._actions if a.dest == "command").choices
    for name, sub in commands.items():
        assert sub.description, name
    for name in ("check", "kinematics", "sweep"):
        assert "exit status: 0" in commands[name].format_help(), name
    assert "results/" in commands["check"].format_help()
    assert "local cluster for large" not in commands["sweep"].format_help()  # it forks by default
    parsers = [(name, sub) for name, sub in commands.items()]
    while parsers:  # every option of every command and subcommand says what it does
        name, sub = parsers.pop()
        for action in sub._actions:
            assert action.help, (name, action.option_strings or action.dest)
            if isinstance(action.choices, dict):
                parsers += [(f"{name} {n}", s) for n, s in action.choices.items()]
