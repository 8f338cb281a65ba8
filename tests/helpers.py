"""What the tests share: scene texts (TOML), the one factory of scenes (:func:`make_scene`,
merging texts and tables) and of [sweep] tables, the sweep's runs and rows, the check of a
sweep row's setting, and the pictures' and pages' checks. Test modules import these from
here, never from each other."""

import json
import os
import shutil
import tomllib
from pathlib import Path

import numpy as np
import pytest

#: the repository's top folder
ROOT = Path(__file__).resolve().parents[1]

#: seed 000's final design ("CUMPLE Y MONTABLE", 3.3.6), mechanism only
FINAL_DESIGN = """
[mechanism]
kind = "four-bar"
crank = "480 mm"
coupler = "840 mm"
rocker = "780 mm"
ground = "1020 mm"
"""


def sweep_table(kind: str = "four-bar", speeds=("1 Hz",), steps: int = 90, **ranges) -> str:
    """A [sweep] table: ``kind``, ``speeds`` (with units), ``steps`` and each bar's range
    ``bar=(low, high)`` in mm (a bar not named keeps the rails' whole range)."""
    lines = ["", "[sweep]", f'kind = "{kind}"', "speeds = [" + ", ".join(f'"{s}"' for s in speeds) + "]", f"steps = {steps}"]
    lines += [f'{bar} = ["{low} mm", "{high} mm"]' for bar, (low, high) in ranges.items()]
    return "\n".join(lines) + "\n"


#: a rail meshed coarsely: linear elements at 30 mm (7 mm at the holes), no grooves (a
#: second to mesh), and no VTU, PNG or plots: the [mesh], [geometry] and [output] tables
COARSE_RAILS = """[mesh]
order = 1
size = "30 mm"
hole_size = "7 mm"
[geometry]
rail_groove_radius = "0 mm"
[output]
vtk = false
png = false
plots = false
"""


#: seed 000's final design's bar lengths (mm), a range of one setting each
FINAL_DESIGN_RANGES = {"crank": (480, 480), "coupler": (840, 840), "rocker": (780, 780), "ground": (1020, 1020)}

#: a sweep of seed 000's final design alone (one setting), at 1 Hz and 90 steps
FINAL_DESIGN_SWEEP = sweep_table(**FINAL_DESIGN_RANGES)

#: a four-bar sweep of 8 settings round the final design with every part checked by FE at
#: its kind's default mesh (the one `railcheck check` of the default scene, CI's main job,
#: meshes and stores, so the sweep tests share its meshes and unit fields)
FE_SWEEP = (
    sweep_table(steps=360, crank=(480, 540), coupler=(840, 840), rocker=(780, 840), ground=(1020, 1080))
    + """
[check]
parts = ["crank-rail", "coupler-rail", "rocker-rail", "PF_4b_006", "PF_4b_003_v2"]

[loads.PF_4b_003_v2]
longitudinal = "250 N"
transverse = "250 N"
"""
)

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


def run_sweep_text(tmp_path, text: str, name: str = "out", **kw):
    """`railcheck sweep` of the scene ``text`` into ``tmp_path``/``name`` (keywords as
    :func:`railcheck.sweep.run.run_sweep`)."""
    from railcheck.scene import parse_scene
    from railcheck.sweep.run import run_sweep

    return run_sweep(parse_scene(tomllib.loads(text), "test"), str(tmp_path / name), **kw)


def table_rows(run, kind: str = "four-bar") -> dict:
    """A sweep's table of ``kind`` as column -> numpy array."""
    from railcheck.sweep.table import read_table

    table = read_table(run.tables[kind])
    return {k: np.asarray(v.to_numpy(zero_copy_only=False)) for k, v in zip(table.column_names, table.columns)}


def scene_doc(*pieces) -> dict:
    """One scene document from ``pieces``, each a TOML text or a document (dict), merged
    table by table in order: a later piece's keys replace an earlier one's, its tables
    merge into theirs (``[loads.NAME]`` part by part). The one way the tests compose
    scenes: no text is split or spliced."""
    doc: dict = {}
    for piece in pieces:
        _merge(doc, tomllib.loads(piece) if isinstance(piece, str) else piece)
    return doc


def _merge(into: dict, doc: dict) -> None:
    for key, value in doc.items():
        if isinstance(value, dict) and isinstance(into.get(key), dict):
            _merge(into[key], value)
        else:
            into[key] = json.loads(json.dumps(value)) if isinstance(value, (dict, list)) else value


def make_scene(*pieces, source: str = "test"):
    """The :class:`~railcheck.scene.Scene` of :func:`scene_doc` of ``pieces``."""
    from railcheck.scene import parse_scene

    return parse_scene(scene_doc(*pieces), source)


def check_scene_of_row(row: dict, speed_hz: float, sweep_text: str = FE_SWEEP, steps: int = 360):
    """The scene of `railcheck check` of a sweep row's setting (four-bar or slider-crank)
    at ``speed_hz``: the sweep scene's tables but [sweep], its [mechanism] (the plane
    included) set to the row's bar lengths, speed and ``steps``, and the bolts at the
    setting's own holes (as the sweep loads them)."""
    slider = row.get("kind") == "slider-crank"
    bars = ("crank", "coupler", "offset") if slider else ("crank", "coupler", "rocker", "ground")
    mechanism = {"ground" if b == "offset" else b: f"{row[f'{b}_mm']:.6f} mm" for b in bars}
    mechanism |= {"kind": row.get("kind", "four-bar"), "speed": f"{speed_hz:.17g} Hz", "steps": steps}
    doc = {k: v for k, v in scene_doc(sweep_text).items() if k != "sweep"}
    return make_scene(doc, {"mechanism": mechanism, "check": {"bolt_position": "actual"}}, source="check")


def package_dirs() -> dict[str, Path]:
    """Dotted package -> source folder, from pyproject.toml's setuptools mapping."""
    config = tomllib.loads((ROOT / "pyproject.toml").read_text())["tool"]["setuptools"]
    mapping = config["package-dir"]
    return {
        pkg: ROOT / mapping.get(pkg, mapping.get(pkg.split(".")[0], "") and pkg.replace(".", "/"))
        for pkg in config["packages"]
    }


def utilisation_at_safe_speed(part, criterion: str | None = None) -> float:
    """A checked part's utilisation as the sweep's safe speed reads it
    (:func:`railcheck.model.utilisation.margin_utilisations` of its figures and its
    certificate's estimate; without a certificate its own utilisations); ``criterion`` one
    of them, else the largest. (A check at the safe speed gives the quasi-static verdict
    with the estimate beside it; the sweep's safe speed takes the estimate as a margin.)"""
    from railcheck.model.utilisation import margin_utilisations

    c = part.job.certificate
    if c is None:
        u = part.utilisations
    else:
        figures = (part.verdict_stress, part.cycle.fatigue.min_safety_factor, part.cycle.envelope.max_tip)
        u = {k: float(v) for k, v in margin_utilisations(part.limits, *figures, c.estimate).items()}
    return u[criterion] if criterion else max(u.values())


def chromium_driver():
    """A headless Chromium under selenium, or a skip off CI (CI must have both)."""
    chromedriver, chromium = shutil.which("chromedriver"), shutil.which("chromium")
    try:
        from selenium import webdriver
        from selenium.webdriver.chrome.options import Options
        from selenium.webdriver.chrome.service import Service
    except ImportError:
        chromedriver = None
    if not (chromedriver and chromium):
        if os.environ.get("CI"):
            pytest.fail("CI needs selenium, chromium and chromedriver (.ci/run installs them)")
        pytest.skip("no selenium / chromium / chromedriver here")
    options = Options()
    for flag in ("--headless", "--no-sandbox", "--disable-gpu", "--disable-dev-shm-usage"):
        options.add_argument(flag)
    options.binary_location = chromium
    return webdriver.Chrome(service=Service(chromedriver), options=options)


def benchmark_module(name: str):
    """The script ``benchmarks/NAME.py`` loaded as a module (the benchmarks are no package)."""
    import importlib.util

    spec = importlib.util.spec_from_file_location(name, ROOT / "benchmarks" / f"{name}.py")
    assert spec is not None and spec.loader is not None
    module = importlib.util.module_from_spec(spec)
    spec.loader.exec_module(module)
    return module


def check_exit_status(out) -> int:
    """The exit status a check whose results are in ``out`` owes: 0 for its summary.json's
    PASS, 1 for FAIL (``railcheck check --help``); anything else is not a verdict."""
    verdict = json.loads((Path(out) / "summary.json").read_text())["verdict"]
    return {"PASS": 0, "FAIL": 1}[verdict]


def sweep_exit_status(out) -> int:
    """The exit status a sweep whose results are in ``out`` owes: 0 when some setting of
    every linkage kind passes, else 1 (``railcheck sweep --help``)."""
    by_kind = json.loads((Path(out) / "summary.json").read_text())["by_kind"]
    return 0 if all(k["settings_passing"] > 0 for k in by_kind.values()) else 1
