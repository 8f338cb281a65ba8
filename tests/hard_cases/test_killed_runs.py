"""A run killed outright (SIGKILL) at any moment leaves nothing the next run trips on: the
next run into the same --out reclaims the killed run's reservation (it writes ``r``, not
``r-2``) and removes its staging; afterwards only the results are left. A process id the
system has given to another process since does not keep a dead run's reservation."""

import os
import signal
import subprocess
import sys
import time

import pytest

from helpers import FINAL_DESIGN, check_exit_status
from railcheck.files import Staging, process_tag, remove_dead_staging, reserve_results_dir


def test_a_reservation_whose_process_id_was_reused_is_reclaimed(tmp_path):
    """The killed run's id now names another process (a small container reuses ids
    quickly): told apart by its start time, the reservation and the staging are the dead
    run's, reclaimed; the same marks naming the live process itself are kept."""
    other = subprocess.Popen([sys.executable, "-c", "import time; time.sleep(60)"])
    try:
        reused = f"{other.pid}-1"  # the live process's id with another start time: the dead run's
        for tag, kept in ((reused, False), (process_tag(other.pid), True)):
            target = tmp_path / f"r-{kept}"
            target.mkdir()
            (target / f".railcheck-reserved-by.{tag}").touch()
            staging = tmp_path / f".{target.name}.staging.{tag}.abc"
            staging.mkdir()
            got, replaces = reserve_results_dir(target)
            assert (got == target) is not kept and not replaces
            assert (staging in remove_dead_staging(tmp_path)) is not kept and staging.exists() is kept
    finally:
        other.kill()
        other.wait()


def test_a_staging_directory_names_its_process_with_its_start_time(tmp_path):
    """The staging directory's name carries this process's tag, so a later run can tell
    whether it is still running."""
    target, _ = reserve_results_dir(tmp_path / "r")
    staging = Staging(target)
    try:
        assert f".staging.{process_tag()}." in staging.path.name and "-" in process_tag()
        assert remove_dead_staging(tmp_path) == [] and staging.path.exists()
    finally:
        staging.abandon()
    assert sorted(p.name for p in tmp_path.iterdir()) == []


CHECK = FINAL_DESIGN + 'steps = 400\n[check]\nparts = ["PF_4b_006"]\n[output]\nvtk = true\npng = false\nplots = false\n'


def _run(tmp_path, scene):
    return subprocess.Popen(
        [sys.executable, "-P", "-m", "railcheck.cli", "check", str(scene), "--out", str(tmp_path / "r")],
        stdout=subprocess.DEVNULL,
        stderr=subprocess.DEVNULL,
        cwd=tmp_path,
    )


@pytest.mark.slow  # a timed run, then three killed and three complete runs of a one-plate check, about 20 s
def test_a_check_killed_at_any_moment_leaves_nothing_the_next_run_trips_on(tmp_path):
    """A complete run is timed first; then SIGKILL at 20, 50 and 80% of that time (imports,
    kinematics and the store, the solve and the files), each followed by a
    complete run into the same --out: the results land in ``r`` and nothing else is left."""
    scene = tmp_path / "scene.toml"
    scene.write_text(CHECK)
    start = time.perf_counter()
    assert _run(tmp_path, scene).wait(timeout=300) == check_exit_status(tmp_path / "r")
    whole = time.perf_counter() - start
    subprocess.run(["rm", "-rf", str(tmp_path / "r")], check=True)
    for share in (0.2, 0.5, 0.8):
        proc = _run(tmp_path, scene)
        time.sleep(share * whole)
        os.kill(proc.pid, signal.SIGKILL)
        proc.wait(timeout=60)
        left = {p.name for p in (tmp_path / "r").iterdir()} if (tmp_path / "r").exists() else set()
        if "summary.json" in left:  # it finished before the signal: complete results, nothing reserved
            assert not [n for n in left if n.startswith(".")], share
            subprocess.run(["rm", "-rf", str(tmp_path / "r")], check=True)
        else:  # killed: at most its reservation (the staging directory is beside it)
            assert all(n.startswith(".railcheck-reserved-by.") for n in left), (share, left)
        again = _run(tmp_path, scene)
        status = again.wait(timeout=300)
        assert sorted(p.name for p in tmp_path.iterdir()) == ["r", "scene.toml"], share
        assert status == check_exit_status(tmp_path / "r"), share
        assert not [p for p in (tmp_path / "r").iterdir() if p.name.startswith(".")], share
        subprocess.run(["rm", "-rf", str(tmp_path / "r")], check=True)


@pytest.mark.slow  # two refused checks in this process, about 2 s
def test_a_refused_run_removes_the_folders_it_created_for_its_results(tmp_path, capsys):
    """A run refused after it reserved ``a/b/r`` (a mesh refusal comes after the reservation)
    leaves neither ``r`` nor the ``a/b`` it created; a folder that was there before stays."""
    from railcheck.cli import main

    scene = tmp_path / "scene.toml"
    scene.write_text(FINAL_DESIGN + '[check]\nparts = ["PF_4b_006"]\n[mesh]\nsize = "30 mm"\nhole_size = "8 mm"\n')
    (tmp_path / "kept").mkdir()
    for out in (tmp_path / "a" / "b" / "r", tmp_path / "kept" / "c" / "r"):
        assert main(["check", str(scene), "--out", str(out)]) == 2
        assert "mesh.hole_size" in capsys.readouterr().err
    assert sorted(p.name for p in tmp_path.iterdir()) == ["kept", "scene.toml"] and not list((tmp_path / "kept").iterdir())
