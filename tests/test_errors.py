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
