"""Bad input end to end: exit 2, one clear line, nothing half-written, earlier results kept."""

import json
import subprocess
import sys
from pathlib import Path

import pytest

from helpers import FINAL_DESIGN, PLATE_LOADS, check_exit_status, one_line_exit_2, sweep_exit_status

PLATE = (
    PLATE_LOADS
    + """[mesh]
size = "12 mm"
hole_size = "4 mm"
"""
)

FOURBAR = FINAL_DESIGN


def check(tmp_path, scene_text, *extra, out="results"):
    scene = tmp_path / "scene.toml"
    scene.write_text(scene_text)
    return subprocess.run(
        [sys.executable, "-P", "-m", "railcheck.cli", "check", str(scene), "--out", str(tmp_path / out), *extra],
        capture_output=True,
        text=True,
        cwd=tmp_path,
    )


CASES = [
    ("malformed TOML", "[check\nparts = [", ("scene", "malformed TOML")),
    ("length in kg", FOURBAR.replace('"480 mm"', '"480 kg"'), ("mechanism.crank", "kg")),
    (
        "unknown part",
        PLATE.replace('["PF_4b_003_v2"]', '["PF_4b_003_v2", "flux-capacitor"]'),
        ("check.parts", "flux-capacitor"),
    ),
    (
        "gravity with seed-2013",
        FOURBAR + '[dynamics]\nformulation = "seed-2013"\n[check]\nparts = ["crank-rail"]\n'
        'effects = ["inertia", "gravity"]\n',
        ("check.effects", "seed-2013"),
    ),
    (
        "loads for an unchecked part",
        PLATE.replace('parts = ["PF_4b_003_v2"]', 'parts = ["PF_4b_006"]'),
        ("loads.PF_4b_003_v2",),
    ),
    ("unknown effect", PLATE.replace("[loads.", 'effects = ["wind"]\n[loads.'), ("check.effects", "wind")),
    ("hole size above size", PLATE.replace('hole_size = "4 mm"', 'hole_size = "40 mm"'), ("mesh.hole_size",)),
    (
        "mesh beyond memory",
        PLATE.replace('size = "12 mm"', 'size = "0.3 mm"').replace('hole_size = "4 mm"', ""),
        ("mesh.size", "GiB"),
    ),
    ("absurd speed", FOURBAR + 'speed = "1e308 Hz"\n', ("mechanism.speed", "50 Hz")),
    (
        "absurd limit",
        PLATE.replace('parts = ["PF_4b_003_v2"]', 'parts = ["PF_4b_003_v2"]\nlimit = "1e308 GPa"'),
        ("check.limit", "5 GPa"),
    ),
    (
        "absurd factor",
        PLATE.replace('parts = ["PF_4b_003_v2"]', 'parts = ["PF_4b_003_v2"]\nfactor = 1e9'),
        ("check.factor",),
    ),
    ("absurd load", PLATE.replace('"250 N"', '"1e12 N"'), ("loads.PF_4b_003_v2.longitudinal", "1 MN")),
    ("NUL in the results folder", PLATE + '[output]\ndir = "res\\u0000ults"\n', ("output.dir", "directory name")),
    ("absurd length", FOURBAR.replace('"1020 mm"', '"1e6 m"'), ("mechanism.ground", "10 m")),
    (
        "mesh coarser than the part",
        PLATE.replace('size = "12 mm"', 'size = "1000 m"').replace('hole_size = "4 mm"', ""),
        ("mesh.size", "too coarse"),
    ),
    (
        "rail hole wider than the rail",
        PLATE + '[geometry]\nrail_hole_diameter = "30 mm"\n',
        ("geometry.rail_hole_diameter",),
    ),
    (
        "grooves through the rail's counterbores",
        PLATE + '[geometry]\nrail_groove_radius = "8 mm"\n',
        ("geometry.rail_groove_radius", "wall"),
    ),
    (
        "grooves that overlap",
        PLATE + '[geometry]\nrail_upper_groove_z = "9 mm"\n',
        ("geometry.rail_lower_groove_z", "apart"),
    ),
    (
        "bearing seat off the plate",
        PLATE + '[geometry]\nplate_seat_diameter = "200 mm"\n',
        ("geometry.plate_seat_diameter",),
    ),
    (
        "rocker rail of a slider-crank",
        '[mechanism]\nkind = "slider-crank"\ncrank = "300 mm"\ncoupler = "800 mm"\n[check]\nparts = ["rocker-rail"]\n',
        ("check.parts", "rocker"),
    ),
]


def check_here(tmp_path, scene_text, monkeypatch, capsys) -> subprocess.CompletedProcess:
    """:func:`check` through ``railcheck.cli.main`` in this process (no interpreter start
    per case): its exit status, stdout and stderr as a finished process's."""
    from railcheck.cli import main

    scene = tmp_path / "scene.toml"
    scene.write_text(scene_text)
    monkeypatch.chdir(tmp_path)
    status = main(["check", str(scene), "--out", str(tmp_path / "results")])
    out, err = capsys.readouterr()
    return subprocess.CompletedProcess([], status, out, err)


@pytest.mark.parametrize("name,text,needles", CASES, ids=[c[0] for c in CASES])
def test_bad_scene_exits_2_and_writes_nothing(tmp_path, monkeypatch, capsys, name, text, needles):
    proc = check_here(tmp_path, text, monkeypatch, capsys)
    one_line_exit_2(proc, *needles)
    assert sorted(p.name for p in tmp_path.iterdir()) == ["scene.toml"]  # nothing half-written


@pytest.mark.parametrize("name,text,needles", [c for c in CASES if c[0] in ("malformed TOML", "absurd load")])
def test_a_bad_scene_in_its_own_process_exits_2_with_one_line(tmp_path, name, text, needles):
    """The same refusals as the process's exit status and stderr (the cases above run in
    this process)."""
    proc = check(tmp_path, text)
    one_line_exit_2(proc, *needles)
    assert sorted(p.name for p in tmp_path.iterdir()) == ["scene.toml"]


def test_output_dir_that_is_a_file(tmp_path):
    (tmp_path / "results").write_text("precious")
    proc = check(tmp_path, PLATE)
    one_line_exit_2(proc, "output.dir", "not a directory")
    assert (tmp_path / "results").read_text() == "precious"


def test_output_dir_not_writable(tmp_path):
    proc = check(tmp_path, PLATE, out="/proc/railcheck-results")
    one_line_exit_2(proc, "output.dir")


@pytest.mark.parametrize(
    "option, path, needles",
    [
        ("--gif", "anim.txt", ("--gif", "*.gif", "'anim.txt'")),  # the GIF writer picks its format by the name
        ("--csv", "/proc/tracer.csv", ("--csv", "cannot write in /proc")),  # root may, /proc may not
        ("--html", "/proc/page.html", ("--html", "cannot write in /proc")),
    ],
)
def test_an_output_file_that_cannot_be_written_as_named_is_refused_first(
    tmp_path, monkeypatch, capsys, option, path, needles
):
    from railcheck.cli import main

    monkeypatch.chdir(tmp_path)
    status = main(["mechanism", "four-bar", option, path])
    out, err = capsys.readouterr()
    one_line_exit_2(subprocess.CompletedProcess([], status, out, err), *needles)
    assert not out and not list(tmp_path.iterdir())  # refused before the mechanism ran


@pytest.mark.parametrize(
    "argv, option",
    [
        (["kinematics", "--plots", "P" * 300], "--plots"),
        (["mechanism", "four-bar", "--csv", "P" * 300 + ".csv"], "--csv"),
        (["mechanism", "four-bar", "--html", "nul\0.html"], "--html"),
    ],
)
def test_an_output_name_the_file_system_cannot_hold_is_refused_naming_the_option(
    tmp_path, monkeypatch, capsys, argv, option
):
    """Too long a name (ENAMETOOLONG) or a NUL byte: looking the path up fails before the
    option's own checks; the refusal names the option and shows the name shortened."""
    from railcheck.cli import main

    monkeypatch.chdir(tmp_path)
    status = main(argv)
    out, err = capsys.readouterr()
    one_line_exit_2(subprocess.CompletedProcess([], status, out, err), f"error: {option}: cannot use")
    assert len(err) < 200 and not list(tmp_path.iterdir())


def test_a_write_that_fails_names_the_file_asked_for_and_leaves_no_temporary(tmp_path):
    """A writer's error about the temporary name (a full disk) is reported with the
    target's name, its errno kept; nothing is left beside it."""
    from railcheck.files import atomic_path

    target = tmp_path / "tracer.csv"
    with pytest.raises(OSError) as caught:
        with atomic_path(target) as tmp:
            tmp.write_text("half")
            raise OSError(28, "No space left on device", str(tmp))
    assert (caught.value.errno, caught.value.filename) == (28, str(target))
    assert not list(tmp_path.iterdir())


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
    proc = subprocess.run(
        [sys.executable, "-P", "-m", "railcheck.cli", "kinematics", str(scene)], capture_output=True, text=True
    )
    one_line_exit_2(proc, "crank angle 0 deg")


@pytest.mark.slow
def test_two_runs_into_one_out_both_survive(tmp_path):
    scene = tmp_path / "scene.toml"
    scene.write_text(PLATE + "[output]\nvtk = false\npng = false\n")
    cmd = [sys.executable, "-P", "-m", "railcheck.cli", "check", str(scene), "--out", str(tmp_path / "r")]
    procs = [
        subprocess.Popen(cmd, stdout=subprocess.DEVNULL, stderr=subprocess.PIPE, text=True, cwd=tmp_path) for _ in range(2)
    ]
    for p in procs:
        assert p.wait(timeout=300) == 0, p.stderr.read()
    dirs = sorted(p.name for p in tmp_path.iterdir() if p.is_dir())
    assert dirs == ["r", "r-2"]
    for d in dirs:
        assert json.loads((tmp_path / d / "summary.json").read_text())["verdict"] == "PASS"


def _started(tmp_path, command: str, scene_text: str) -> subprocess.Popen:
    """`railcheck COMMAND scene.toml --out r` started in ``tmp_path`` (its stderr piped),
    as from a terminal: SIGINT at its default disposition. (A test run started in the
    background of a non-interactive shell inherits SIGINT ignored, as Unix shells set it
    for background jobs; railcheck, like any program, then keeps ignoring it, and a CI
    rehearsal started that way saw the sweep finish instead of stopping.)"""
    import signal

    scene = tmp_path / "scene.toml"
    scene.write_text(scene_text)
    return subprocess.Popen(
        [sys.executable, "-P", "-m", "railcheck.cli", command, str(scene), "--out", str(tmp_path / "r")],
        stdout=subprocess.DEVNULL,
        stderr=subprocess.PIPE,
        text=True,
        cwd=tmp_path,
        preexec_fn=lambda: signal.signal(signal.SIGINT, signal.SIG_DFL),
    )


@pytest.mark.slow  # two subprocess runs, 2 s: the fast tier keeps the other interruption cases
def test_sigterm_cleans_up_and_the_next_run_removes_dead_staging(tmp_path):
    import os
    import signal
    import time

    proc = _started(tmp_path, "check", FOURBAR + 'steps = 200\n[check]\nparts = ["crank-rail"]\n[mesh]\nsize = "8 mm"\n')
    deadline = time.time() + 60
    while not list(tmp_path.glob(".r.staging.*")) and time.time() < deadline:
        time.sleep(0.05)
    proc.send_signal(signal.SIGTERM)
    assert proc.wait(timeout=60) == 143
    assert not list(tmp_path.glob(".r.staging.*")) and not (tmp_path / "r").exists()
    # a run killed outright (SIGKILL) leaves its staging directory: the next run removes it
    dead = tmp_path / f".r.staging.{2**22 + 12345}.abc"
    dead.mkdir()
    os.utime(dead)
    check(tmp_path, PLATE + "[output]\nvtk = false\npng = false\n", out="r")
    assert not dead.exists()


@pytest.mark.slow  # a subprocess sweep, about 5 s
@pytest.mark.parametrize(("sig", "status"), [("SIGINT", 130), ("SIGTERM", 143)])
def test_a_local_sweep_stops_at_once_on_a_signal_and_leaves_nothing(tmp_path, sig, status):
    """A kinematics-only sweep of the whole rig at 5,000 steps (processes forked from this
    one, or threads where the platform does not fork; each chunk about a second):
    interrupted or terminated after its first chunk, it exits within 5 s with its status
    and one line, and leaves no results, no staging and no running process."""
    import signal
    import time

    proc = _started(tmp_path, "sweep", '[sweep]\nkind = "both"\nsteps = 5000\n')
    first = proc.stderr.readline() + proc.stderr.readline()
    assert "forked from this one" in first or "threads in this process" in first
    assert "settings/s" in proc.stderr.readline()  # the first chunk is done: the workers are busy
    t = time.time()
    proc.send_signal(getattr(signal, sig))
    assert proc.wait(timeout=60) == status and time.time() - t < 5
    rest = proc.stderr.read()
    assert "Traceback" not in rest and rest.strip().splitlines()[-1] in ("railcheck: interrupted", "railcheck: terminated")
    assert sorted(p.name for p in tmp_path.iterdir()) == ["scene.toml"]
    time.sleep(0.5)
    assert not _running_with(str(tmp_path / "scene.toml"))  # no forked child left behind


def _running_with(argument: str) -> list[int]:
    """The pids of the running (not zombie) processes with ``argument`` on their command line."""
    import os

    found = []
    for entry in os.listdir("/proc") if os.path.isdir("/proc") else []:
        try:
            with open(f"/proc/{entry}/cmdline", "rb") as f:
                args = f.read().split(b"\0")
            with open(f"/proc/{entry}/stat") as f:
                zombie = f.read().rsplit(")", 1)[1].split()[0] == "Z"
        except OSError:
            continue
        if argument.encode() in args and not zombie:
            found.append(int(entry))
    return found


def test_bad_output_path_fails_before_any_meshing(tmp_path):
    import os

    cache = tmp_path / "cache"
    scene = tmp_path / "scene.toml"
    scene.write_text(PLATE)
    (tmp_path / "taken").write_text("a file where the results should go")
    proc = subprocess.run(
        [sys.executable, "-P", "-m", "railcheck.cli", "check", str(scene), "--out", str(tmp_path / "taken" / "results")],
        capture_output=True,
        text=True,
        cwd=tmp_path,
        env={**os.environ, "RAILCHECK_CACHE": str(cache)},
    )
    one_line_exit_2(proc, "output.dir")
    assert not cache.exists() or not any(cache.iterdir())  # no mesh was built


@pytest.mark.slow  # a full check on a tiny disk: 6.4 s cold; the fast tier stays under 90 s
def test_full_disk_gives_one_line_and_leaves_nothing(tmp_path):
    disk = tmp_path / "small"
    disk.mkdir()
    mounted = subprocess.run(["mount", "-t", "tmpfs", "-o", "size=64k", "tmpfs", str(disk)], capture_output=True)
    if mounted.returncode != 0:
        pytest.skip("cannot mount a small tmpfs here (needs root)")
    try:
        proc = check(tmp_path, PLATE, out=str(disk / "results"))
        assert proc.returncode == 2 and "Traceback" not in proc.stderr, proc.stderr
        assert "No space left" in proc.stderr
        assert list(disk.iterdir()) == []  # no staging, no half results
    finally:
        subprocess.run(["umount", str(disk)], capture_output=True)


@pytest.mark.slow  # two sweeps in subprocesses, 3 s
def test_a_sweep_killed_with_sigkill_leaves_nothing_after_the_next_run(tmp_path):
    """SIGKILL gives no chance to clean up: the killed sweep leaves its reservation and its
    staging directory. The next run reclaims the reservation (it writes ``res``, not
    ``res-2``) and removes the staging; afterwards only the results are left."""
    import os
    import signal
    import time

    scene = tmp_path / "scene.toml"
    scene.write_text('[sweep]\nkind = "four-bar"\nsteps = 720\ncrank = ["60 mm", "660 mm"]\n')
    proc = subprocess.Popen(
        [sys.executable, "-P", "-m", "railcheck.cli", "sweep", str(scene), "--out", str(tmp_path / "res"), "--serial"],
        stdout=subprocess.DEVNULL,
        stderr=subprocess.DEVNULL,
        cwd=tmp_path,
    )
    deadline = time.time() + 60
    while not list(tmp_path.glob(".res.staging.*")) and time.time() < deadline:
        time.sleep(0.02)
    os.kill(proc.pid, signal.SIGKILL)
    assert proc.wait(timeout=60) == -signal.SIGKILL
    assert (tmp_path / "res").is_dir() and list(tmp_path.glob(".res.staging.*"))  # what SIGKILL leaves
    scene.write_text('[sweep]\nkind = "four-bar"\nsteps = 16\ncrank = ["480 mm", "480 mm"]\n')
    again = subprocess.run(
        [sys.executable, "-P", "-m", "railcheck.cli", "sweep", str(scene), "--out", str(tmp_path / "res"), "--serial"],
        capture_output=True,
        text=True,
        cwd=tmp_path,
        timeout=120,
    )
    assert sorted(p.name for p in tmp_path.iterdir()) == ["res", "scene.toml"]
    assert again.returncode == sweep_exit_status(tmp_path / "res"), again.stderr
    assert not [p for p in (tmp_path / "res").iterdir() if p.name.startswith(".")]


@pytest.mark.slow
def test_a_second_run_says_first_where_its_results_go(tmp_path):
    """The results directory exists: before any work the run names the one it writes, so a
    report open in a browser is not taken for this run's (#24)."""
    text = PLATE + "[output]\nvtk = false\npng = false\nplots = false\n"
    first = check(tmp_path, text, out="r")
    assert first.returncode == check_exit_status(tmp_path / "r") and "exists" not in first.stderr
    second = check(tmp_path, text, out="r")
    assert second.returncode == check_exit_status(tmp_path / "r-2")
    assert "r/ exists: this run's results go to" in second.stderr.splitlines()[0] and "r-2/" in second.stderr.splitlines()[0]


def _status(pid: int) -> bytes:
    try:
        return Path(f"/proc/{pid}/status").read_bytes()
    except OSError:
        return b"State:\tZ"  # gone


def _mesher_children(parent: int) -> list[int]:
    """Pids of the gmsh children whose command line names ``parent`` as theirs."""
    found = []
    for proc in Path("/proc").iterdir():
        try:
            if proc.name.isdigit() and f"_child_main({parent})".encode() in (proc / "cmdline").read_bytes():
                found.append(int(proc.name))
        except OSError:
            continue
    return found


@pytest.mark.slow  # a rail meshed finely in a subprocess, killed after a few seconds
@pytest.mark.skipif(not sys.platform.startswith("linux"), reason="PR_SET_PDEATHSIG is Linux's")
def test_a_check_killed_with_sigkill_while_it_meshes_takes_its_gmsh_child_with_it(tmp_path):
    """Issue 79: ``kill -9`` of a check while it meshed left its gmsh child running until
    the mesh was done. The child now dies with its parent."""
    import os
    import signal
    import time

    script = (  # a SIGTERM handler, as the command line has: gmsh then runs in a child
        "import signal; signal.signal(signal.SIGTERM, lambda *a: None)\n"
        "from railcheck.geometry import mesh_part, rail\n"
        "mesh_part(rail(1.0), 3e-3, 1e-3, cache=False)\n"  # a minute or more of meshing
    )
    proc = subprocess.Popen([sys.executable, "-P", "-c", script], stdout=subprocess.DEVNULL, stderr=subprocess.DEVNULL)
    deadline = time.time() + 60
    while not _mesher_children(proc.pid) and time.time() < deadline:
        time.sleep(0.05)
    children = _mesher_children(proc.pid)
    assert children, "the mesher's child never started"
    time.sleep(1.0)  # meshing
    os.kill(proc.pid, signal.SIGKILL)
    proc.wait(timeout=30)
    deadline = time.time() + 10
    while any(Path(f"/proc/{c}").exists() for c in children) and time.time() < deadline:
        time.sleep(0.05)
    alive = [c for c in children if Path(f"/proc/{c}").exists() and b"State:\tZ" not in _status(c)]
    assert not alive, "the gmsh child outlived its killed parent"
