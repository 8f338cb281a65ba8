"""Scene texts shared by the tests (TOML)."""

#: seed 000's final design ("CUMPLE Y MONTABLE", 3.3.6), mechanism only
FINAL_DESIGN = """
[mechanism]
kind = "four-bar"
crank = "480 mm"
coupler = "840 mm"
rocker = "780 mm"
ground = "1020 mm"
"""

#: a sweep of seed 000's final design alone (one setting), at 1 Hz and 90 steps
FINAL_DESIGN_SWEEP = """
[sweep]
kind = "four-bar"
speeds = ["1 Hz"]
steps = 90
crank = ["480 mm", "480 mm"]
coupler = ["840 mm", "840 mm"]
rocker = ["780 mm", "780 mm"]
ground = ["1020 mm", "1020 mm"]
"""

#: PF_4b_003_v2 alone with the seed's explicit loads (4.2.1): no linkage runs
PLATE_LOADS = """
[check]
parts = ["PF_4b_003_v2"]
[loads.PF_4b_003_v2]
longitudinal = "250 N"
transverse = "250 N"
"""


def assert_picture(path, min_size=(400, 300), min_colours=20):
    """The image at ``path`` decodes, is at least ``min_size`` (width, height) pixels and
    is not blank: many distinct colours and a spread of intensities."""
    import numpy as np
    from PIL import Image

    with Image.open(path) as im:
        im.load()
        width, height = im.size
        frame = np.asarray(im.convert("RGB"), dtype=float)
    assert width >= min_size[0] and height >= min_size[1], (path, im.size)
    colours = np.unique(frame.reshape(-1, 3)[::7], axis=0).shape[0]
    assert colours >= min_colours, (path, colours)
    assert frame.std() > 5.0, path


def chromium():
    """Path of a headless Chromium, or None (CI must have one: .ci/run installs it)."""
    import os
    import shutil

    import pytest

    for name in ("chromium", "chromium-browser", "google-chrome"):
        path = shutil.which(name)
        if path:
            return path
    if os.environ.get("CI"):
        pytest.fail("headless Chromium is needed in CI (.ci/run installs it)")
    pytest.skip("no Chromium on this machine")


def browse(page, tmp_path, *args):
    """Run headless Chromium on a local page with the given output flags; returns the process."""
    import subprocess

    return subprocess.run(
        [
            chromium(),
            "--headless",
            "--no-sandbox",
            "--disable-gpu",
            "--disable-background-networking",
            "--disable-component-update",
            "--disable-sync",
            "--no-first-run",
            f"--user-data-dir={tmp_path / 'profile'}",
            *args,
            f"file://{page}",
        ],
        capture_output=True,
        text=True,
        timeout=120,
    )


def one_line_exit_2(proc, *needles):
    """A CLI run refused its input: exit 2, one ``railcheck:`` line holding every needle,
    no traceback."""
    assert proc.returncode == 2, (proc.returncode, proc.stderr)
    errors = [l for l in proc.stderr.splitlines() if l.startswith("railcheck:")]
    assert len(errors) == 1 and "Traceback" not in proc.stderr, proc.stderr
    for n in needles:
        assert n in errors[0], errors[0]
