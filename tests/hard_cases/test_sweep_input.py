"""`railcheck sweep` with bad input: exit 2 and one line naming the field, nothing written."""

import subprocess
import sys

import pytest

from helpers import one_line_exit_2
from railcheck.base.errors import InputError
from railcheck.scene import parse_scene
from railcheck.sweep.inputs import sweep_input
from railcheck.sweep.run import validate

BASE = '[sweep]\nsteps = 16\nkind = "slider-crank"\n'


def sweep(tmp_path, text, *extra):
    scene = tmp_path / "scene.toml"
    scene.write_text(text)
    return subprocess.run(
        [sys.executable, "-P", "-m", "railcheck.cli", "sweep", str(scene), "--out", str(tmp_path / "out"), *extra],
        capture_output=True,
        text=True,
        cwd=tmp_path,
        timeout=120,
    )


@pytest.mark.parametrize(
    "text, needles",
    [
        (BASE + 'crank = "60 mm"\n', ("sweep.crank", "[min, max]")),
        (BASE + 'crank = ["660 mm", "60 mm"]\n', ("sweep.crank", "above max")),
        (BASE + 'crank = ["60 kg", "660 mm"]\n', ("sweep.crank", "kg")),
        (BASE + "speeds = []\n", ("sweep.speeds",)),
        (BASE + 'speeds = ["1e9 Hz"]\n', ("sweep.speeds", "physical range")),
        (BASE + 'speeds = ["1 Hz", "2 Hz", "1 Hz"]\n', ("sweep.speeds", "'1 Hz' is 1 Hz, already listed")),
        (BASE + 'speeds = ["1 Hz", "60 rpm"]\n', ("sweep.speeds", "'60 rpm' is 1 Hz, already listed")),
        (BASE.replace("steps = 16", "steps = 3"), ("sweep.steps",)),
        (BASE + 'memory = "1 kB"\n', ("sweep.memory",)),
        (BASE + 'format = "xlsx"\n', ("sweep.format",)),
        (BASE.replace('"slider-crank"', '"crane"'), ("sweep.kind",)),
        (BASE + '[[sweep.settings]]\ncrank = "60 mm"\n', ("sweep.settings[0]", "bars")),
        (BASE + 'colour = "red"\n', ("sweep.colour", "unknown key")),
        (BASE + 'crank = ["-60 mm", "660 mm"]\n', ("sweep.crank", "positive")),
        (BASE + 'crank = ["0 mm", "660 mm"]\n', ("sweep.crank", "greater than zero")),
        (BASE + 'coupler = ["60 mm", "1e308 mm"]\n', ("sweep.coupler", "physical range")),
        (BASE + 'offset = ["-1e308 mm", "0 mm"]\n', ("sweep.offset", "physical range")),
        (
            BASE + '[[sweep.settings]]\ncrank = "120 mm"\ncoupler = "480 mm"\noffset = "1e308 mm"\n',
            ("sweep.settings[0].offset",),
        ),
        (BASE + 'offset = ["10 mm", "20 mm"]\n', ("sweep.offset", "0 mm only", "[[sweep.settings]]")),
        (BASE.replace('"slider-crank"', '"four-bar"') + 'ground = ["2500 mm", "3000 mm"]\n', ("sweep.ground", "2400 mm")),
        ('[dynamics]\nformulation = "seed-2013"\n' + BASE, ("sweep.kind", "seed-2013")),
        (
            '[dynamics]\nformulation = "seed-2013"\n[sweep]\nsteps = 16\nkind = "four-bar"\n'
            '[check]\nparts = ["crank-rail"]\n'
            'effects = ["inertia", "gravity"]\n',
            ("check.effects", "seed-2013"),
        ),
    ],
)
def test_bad_sweep_input_names_the_field(text, needles):
    """Refused when the scene is read, before any work (validate: what the sweep itself checks)."""
    import tomllib

    with pytest.raises(InputError) as err:
        validate(sweep_input(parse_scene(tomllib.loads(text), "test")))
    for n in needles:
        assert n in str(err.value), str(err.value)


def test_bad_sweep_input_on_the_command_line_is_one_line_and_writes_nothing(tmp_path):
    one_line_exit_2(sweep(tmp_path, BASE + 'crank = ["660 mm", "60 mm"]\n'), "sweep.crank", "above max")
    one_line_exit_2(sweep(tmp_path, BASE, "--workers", "0"), "--workers")
    assert not (tmp_path / "out").exists()


@pytest.mark.slow
def test_unreachable_scheduler(tmp_path):
    proc = sweep(tmp_path, BASE, "--scheduler", "tcp://127.0.0.1:9")
    one_line_exit_2(proc, "--scheduler", "cannot reach")
    assert not (tmp_path / "out").exists()


@pytest.mark.parametrize("extra", ["", "--serial"])
def test_a_range_without_a_settable_length_is_refused_naming_the_nearest(tmp_path, extra):
    """A range that holds no hole of the rig (#26: it used to end in "cannot write the
    results"): exit 2, the field, the nearest settable lengths, nothing written."""
    proc = sweep(tmp_path, BASE + 'crank = ["61 mm", "62 mm"]\n', *([extra] if extra else []))
    one_line_exit_2(proc, "sweep.crank", "no settable length", "60 mm and 120 mm")
    assert not (tmp_path / "out").exists()
