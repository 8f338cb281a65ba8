"""One error hierarchy: every error names its field, carries its exit status, survives
pickling (worker processes, Dask) with every attribute, and the CLI turns each into one
line and that status."""

import pickle

import pytest

from railcheck.base.errors import EXIT_INPUT, EXIT_NUMERICAL, InputError, NumericalError, RailcheckError
from railcheck.cli import report_error
from railcheck.fea.errors import ModelError
from railcheck.kinematics.errors import MechanismError, SingularConfigurationError

CASES = [
    (InputError("mechanism.crank", "must be positive"), EXIT_INPUT, "error"),
    (MechanismError("mechanism.ground", "the linkage cannot be assembled"), EXIT_INPUT, "error"),
    (SingularConfigurationError("mechanism", "a toggle at 12 deg", 0.21), EXIT_INPUT, "error"),
    (ModelError("hole_9", "no such group in the mesh"), EXIT_INPUT, "error"),
    (NumericalError("PARDISO failed in phase 22"), EXIT_NUMERICAL, "numerical failure"),
]


@pytest.mark.parametrize("error, status, label", CASES)
def test_every_error_pickles_whole_and_maps_to_its_status(error, status, label, capsys):
    back = pickle.loads(pickle.dumps(error))
    assert type(back) is type(error) and isinstance(back, RailcheckError)
    assert (back.field, back.message, str(back), back.args) == (error.field, error.message, str(error), error.args)
    assert vars(back) == vars(error)
    assert back.exit_status == status
    assert report_error(back) == status
    err = capsys.readouterr().err
    assert err == f"railcheck: {label}: {error}\n"


def test_a_singular_configuration_keeps_its_crank_angle_through_pickling():
    back = pickle.loads(pickle.dumps(SingularConfigurationError("mechanism", "toggle", 1.25)))
    assert back.crank_angle_rad == 1.25


def test_domain_errors_are_input_errors_with_a_field():
    assert issubclass(MechanismError, InputError) and issubclass(ModelError, InputError)
    assert str(InputError("", "bare message")) == "bare message"
    assert NumericalError("did not converge", field="solve").field == "solve"


def test_interrupts_and_disk_errors_map_to_their_statuses(capsys):
    assert report_error(KeyboardInterrupt()) == 130
    assert report_error(OSError(28, "No space left on device", "results/summary.json")) == EXIT_INPUT
    assert "cannot write results/summary.json: No space left on device" in capsys.readouterr().err


BAD_EVERYWHERE = {
    "mechanism": {"kind": "four-bar", "crank": "480 mm", "coupler": "840 mm", "rocker": "780 mm"}
    | {"ground": "1020 mm", "sped": "1 Hz", "steps": "many"},
    "check": {"parts": ["crank-rail"], "factor": "x"},
    "mesh": {"size": "10 kg"},
}


def test_every_bad_value_of_a_scene_is_reported_at_once_each_on_its_line(tmp_path, capsys):
    """A misspelled key no longer hides a bad unit: each table's unknown keys and bad
    values come together, in the file's order, one line each on the command line, exit 2;
    a single error is refused as before, and the shipped scenes survey clean."""
    import tomllib
    from importlib import resources

    from railcheck.base.errors import InputErrors
    from railcheck.cli import main
    from railcheck.scene import parse_scene, scene_errors

    with pytest.raises(InputErrors) as caught:
        parse_scene(BAD_EVERYWHERE)
    fields = [e.field for e in caught.value.errors]
    assert fields == ["mechanism.sped", "mechanism.steps", "check.factor", "mesh.size"]
    assert caught.value.field == "mechanism.sped" and str(caught.value).count("\n") == 3
    assert pickle.loads(pickle.dumps(caught.value)).errors[3].field == "mesh.size"
    one = {"mechanism": {**BAD_EVERYWHERE["mechanism"], "steps": 720}, "mesh": BAD_EVERYWHERE["mesh"]}
    one["mechanism"].pop("sped")
    with pytest.raises(InputError) as single:
        parse_scene(one)
    assert not isinstance(single.value, InputErrors) and single.value.field == "mesh.size"
    scene = tmp_path / "bad.toml"
    scene.write_text(
        '[mechanism]\nkind = "four-bar"\ncrank = "480 mm"\ncoupler = "840 mm"\nrocker = "780 mm"\n'
        'ground = "1020 mm"\nsped = "1 Hz"\n[mesh]\nsize = "10 kg"\n'
    )
    capsys.readouterr()
    assert main(["check", str(scene), "--out", str(tmp_path / "out")]) == EXIT_INPUT
    err = capsys.readouterr().err.splitlines()
    assert len(err) == 2 and err[0].startswith("railcheck: error: mechanism.sped: unknown key")
    assert err[1].startswith("railcheck: error: mesh.size: unit 'kg'") and not (tmp_path / "out").exists()
    for name in ("default.toml", "starter.toml"):
        text = resources.files("railcheck").joinpath("scenes", name).read_text()
        assert scene_errors(tomllib.loads(text)) == []
