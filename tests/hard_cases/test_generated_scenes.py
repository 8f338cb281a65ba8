"""Generated scenes, plausible and absurd alike: railcheck never prints a traceback and
always exits 0, 1, 2 or 3 (hypothesis)."""

import json
import math
import os
import re

import pytest
from hypothesis import HealthCheck, event, given, settings
from hypothesis import strategies as st

from railcheck.cli import main

LENGTHS = st.one_of(
    st.sampled_from(
        [
            "480 mm",
            "840 mm",
            "780 mm",
            "1020 mm",
            "0.5 m",
            "60 mm",
            "1e6 m",
            "-3 mm",
            "0 mm",
            "nan mm",
            "inf m",
            "480 kg",
            "480",
            "mm",
            "",
        ]
    ),
    st.floats(allow_nan=True, allow_infinity=True).map(lambda x: f"{x} mm"),
    st.integers(-10, 3000).map(lambda x: f"{x} mm"),
    st.integers(),
    st.booleans(),
)
SPEEDS = st.one_of(
    st.sampled_from(["1 Hz", "0 Hz", "60 rpm", "1e308 Hz", "-1 Hz", "3 rad/s", "1 N"]),
    st.floats(0, 100).map(lambda x: f"{x} Hz"),
)
FORCES = st.one_of(
    st.sampled_from(["250 N", "0 N", "-1e9 N", "1 kN", "nan N", "3 m"]), st.floats(-1e7, 1e7).map(lambda x: f"{x} N")
)


def toml_value(v) -> str:
    if isinstance(v, bool):
        return "true" if v else "false"
    if isinstance(v, str):
        return json.dumps(v)
    if isinstance(v, float) and not math.isfinite(v):
        return "nan" if math.isnan(v) else ("inf" if v > 0 else "-inf")
    if isinstance(v, list):
        return "[" + ", ".join(toml_value(x) for x in v) + "]"
    return str(v)


def toml(doc: dict) -> str:
    out = []
    for table, fields in doc.items():
        out.append(f"[{table}]")
        out += [f"{k} = {toml_value(v)}" for k, v in fields.items()]
    return "\n".join(out) + "\n"


MECHANISM = st.fixed_dictionaries(
    {
        "kind": st.sampled_from(["four-bar", "four-bar", "slider-crank", "pendulum"]),
        "crank": LENGTHS,
        "coupler": LENGTHS,
        "ground": LENGTHS,
    },
    optional={
        "rocker": LENGTHS,
        "speed": SPEEDS,
        "steps": st.one_of(st.integers(-5, 3000), st.just("many")),
        "assembly": st.sampled_from(["open", "crossed", "sideways"]),
        "colour": st.just("red"),
    },
)


def run(tmp_path, doc, *argv):
    path = tmp_path / "scene.toml"
    path.write_text(toml(doc))
    try:
        return main([argv[0], str(path), *argv[1:]])
    except SystemExit as exc:  # argparse
        return exc.code


@settings(max_examples=120, deadline=None, suppress_health_check=[HealthCheck.function_scoped_fixture])
@given(mechanism=MECHANISM, formulation=st.sampled_from(["newton-euler", "seed-2013", "magic"]))
def test_generated_kinematics_scenes_never_crash(tmp_path, capsys, mechanism, formulation):
    code = run(tmp_path, {"mechanism": mechanism, "dynamics": {"formulation": formulation}}, "kinematics", "--json")
    out, err = capsys.readouterr()
    assert code in (0, 1, 2, 3), (code, err)
    assert "Traceback" not in err and "nan" not in out.lower()


PLATE = st.fixed_dictionaries(
    {
        "check": st.fixed_dictionaries(
            {"parts": st.just(["PF_4b_003_v2"])},
            optional={
                "factor": st.one_of(st.floats(-1, 1e9), st.just("big")),
                "limit": st.sampled_from(["375 MPa", "1e308 GPa", "0 Pa", "5 N"]),
                "max_deflection": LENGTHS,
                "effects": st.sampled_from([["inertia"], ["gravity"], ["wind"]]),
            },
        ),
        "loads": st.fixed_dictionaries(
            {"PF_4b_003_v2": st.fixed_dictionaries({}, optional={"longitudinal": FORCES, "transverse": FORCES})}
        ),
        "mesh": st.fixed_dictionaries({"size": st.sampled_from(["12 mm", "20 mm", "1000 m", "0.01 mm", "x"])}),
        "output": st.fixed_dictionaries({"vtk": st.just(False), "png": st.just(False), "plots": st.just(False)}),
        "geometry": st.fixed_dictionaries(
            {}, optional={"iprofile_bolt_diameter": LENGTHS, "iprofile_web_thickness": LENGTHS}
        ),
    }
)


@pytest.mark.slow
@settings(max_examples=15, deadline=None, suppress_health_check=[HealthCheck.function_scoped_fixture])
@given(doc=PLATE)
def test_generated_check_scenes_never_crash(tmp_path, capsys, doc):
    code = run(tmp_path, doc, "check", "--out", str(tmp_path / "r"), "--force", "--json")
    out, err = capsys.readouterr()
    assert code in (0, 1, 2, 3), (code, err)
    assert "Traceback" not in err


VALID_RANGE = st.sampled_from([["480 mm", "480 mm"], ["60 mm", "180 mm"], ["780 mm", "840 mm"], ["1020 mm", "1080 mm"]])
RANGE = st.one_of(
    VALID_RANGE,
    VALID_RANGE,
    VALID_RANGE,
    st.lists(LENGTHS, min_size=2, max_size=2),
    st.just(["480 mm", "480 mm"]),
    st.just(["660 mm", "60 mm"]),
    LENGTHS,
    st.lists(LENGTHS, max_size=3),
)
SWEEP = st.fixed_dictionaries(
    {
        "kind": st.sampled_from(["four-bar", "slider-crank", "both", "four-bar", "crane"]),
        "steps": st.one_of(st.sampled_from([8, 16]), st.sampled_from([3, -5, 0, 10**9, "many", True, 2.5])),
        "crank": st.one_of(st.just(["480 mm", "480 mm"]), RANGE),
    },
    optional={
        "coupler": RANGE,
        "rocker": RANGE,
        "ground": RANGE,
        "offset": RANGE,
        "speeds": st.one_of(st.lists(SPEEDS, max_size=3), SPEEDS),
        "assembly": st.sampled_from(["open", "crossed", "sideways"]),
        "memory": st.sampled_from(["64 MB", "1 kB", "1e30 GB", "-1 MB", "x"]),
        "format": st.sampled_from(["parquet", "csv", "xlsx"]),
    },
)
SWEEP_ARGS = st.lists(
    st.one_of(
        st.tuples(st.just("--workers"), st.sampled_from(["1", "2", "0", "-3", "many", "1e9"])),
        st.tuples(
            st.just("--scheduler"),
            st.sampled_from(["not an address", "tcp://", "ftp://x:1", "tcp://127.0.0.1:0", "tcp://[::1", ""]),
        ),
        st.tuples(st.just("--out"), st.sampled_from(["", "/proc/railcheck", "scene.toml", "out\nx", "out"])),
        st.tuples(st.just("--serial")),
        st.tuples(st.just("--bogus")),
    ),
    max_size=3,
)


@pytest.mark.slow  # 2-8 s as the examples fall (some sweep with FE): out of the fast tier
@settings(max_examples=60, deadline=None, suppress_health_check=[HealthCheck.function_scoped_fixture])
@given(sweep=SWEEP, argv=SWEEP_ARGS, formulation=st.sampled_from(["newton-euler", "seed-2013"]))
def test_generated_sweep_scenes_and_arguments_never_crash(tmp_path, capsys, sweep, argv, formulation):
    """Generated [sweep] tables (kinematics only, few steps) and command-line arguments:
    exit 0-3, no traceback, no non-finite number in the console, and nothing left behind
    but the results directory."""
    args = ["sweep"] + [x for pair in argv for x in pair]
    if "--out" not in args:
        args += ["--out", str(tmp_path / "res")]
    if "--serial" not in args and "--scheduler" not in args:
        args.append("--serial")  # a local Dask cluster per example would take seconds
    path = tmp_path / "scene.toml"
    path.write_text(toml({"sweep": sweep, "dynamics": {"formulation": formulation}}))
    before = {p.name for p in tmp_path.iterdir()}
    here = os.getcwd()
    os.chdir(tmp_path)  # a relative or empty --out lands here, not in the checkout
    try:
        code = main([args[0], str(path), *args[1:]])
    except SystemExit as exc:  # argparse
        code = exc.code
    finally:
        os.chdir(here)
    out, err = capsys.readouterr()
    assert code in (0, 1, 2, 3), (code, err)
    event(f"exit {code}")
    assert "Traceback" not in err
    assert not re.search(r"\b(nan|inf)\b", out, re.IGNORECASE), out
    left = {p.name for p in tmp_path.iterdir()} - before
    assert not [n for n in left if n.startswith(".")], left  # no staging, no temporary


SUBSETS = st.lists(st.sampled_from(["inertia", "rail-inertia", "gravity", "dynamic"]), max_size=3, unique=True)
PART_SETS = st.lists(
    st.sampled_from(["crank-rail", "coupler-rail", "rocker-rail", "PF_4b_006", "PF_4b_003_v2"]),
    min_size=1,
    max_size=3,
    unique=True,
)
LINKAGE = {
    "crank": st.just("120 mm"),  # one length per bar: few meshes, cached after the first examples
    "coupler": st.just("300 mm"),
    "speed": st.sampled_from(["0 Hz", "1 Hz", "3 Hz", "120 rpm"]),
    "steps": st.integers(24, 60),
    "assembly": st.sampled_from(["open", "crossed"]),
}
CHECK_SCENES = st.fixed_dictionaries(
    {
        "mechanism": st.one_of(
            st.fixed_dictionaries(
                {
                    "kind": st.just("four-bar"),
                    "rocker": st.just("240 mm"),
                    "ground": st.sampled_from(["300 mm", "360 mm"]),
                    **LINKAGE,
                }
            ),
            st.fixed_dictionaries(
                {"kind": st.just("slider-crank"), "ground": st.sampled_from(["0 mm", "30 mm"]), **LINKAGE}
            ),
        ),
        "dynamics": st.fixed_dictionaries({"formulation": st.sampled_from(["newton-euler", "seed-2013"])}),
        "check": st.fixed_dictionaries(
            {"parts": PART_SETS, "effects": SUBSETS},
            optional={
                "support": st.sampled_from(["free-body", "clamped"]),
                "bolt_position": st.sampled_from(["worst", "actual"]),
                "material": st.sampled_from(["steel", "S235", "ABS"]),
            },
        ),
        "mesh": st.just({"size": "30 mm", "hole_size": "6.5 mm"}),
        "geometry": st.fixed_dictionaries(
            {"rail_groove_radius": st.just("0 mm")},
            optional={"rail_width": st.sampled_from(["23 mm", "25 mm"]), "plate_thickness": st.sampled_from(["12 mm"])},
        ),
        "output": st.just({"vtk": False, "png": False, "plots": False}),
    }
)


def _valid_check_scene_runs_or_refuses_in_one_line(tmp_path, capsys, doc):
    code = run(tmp_path, doc, "check", "--out", str(tmp_path / "r"), "--force", "--json")
    out, err = capsys.readouterr()
    event(f"exit {code}")
    assert code in (0, 1, 2, 3), (code, err)
    assert "Traceback" not in err and not re.search(r"\b(nan|inf)\b", out, re.IGNORECASE)
    if code in (2, 3):
        last = err.strip().splitlines()[-1]
        event(last[:90])
        tables = "mechanism|dynamics|check|mesh|geometry|output|loads|fatigue|dynamic|scene"
        assert re.match(rf"railcheck: (error|numerical failure): ({tables})(\.[A-Za-z_0-9]+)*: ", last), last


@settings(max_examples=10, deadline=None, derandomize=True, suppress_health_check=[HealthCheck.function_scoped_fixture])
@given(doc=CHECK_SCENES)
def test_generated_valid_check_scenes_run_or_refuse_in_one_line(tmp_path, capsys, doc):
    """Accepted scenes over every combination of effects, supports, parts, formulations,
    kinds, speeds (0 included), materials and geometry overrides in their validated
    ranges, on small meshes (solid rails, 30 mm): exit 0, 1, 2 or 3, never a traceback,
    and a refusal is one line naming a field of the scene (it found "hole_1: is not a
    bore", a mesh group's name, for PF_4b_006 at hole_size 6.5 mm). Ten examples in the
    fast tier (about 7 s), sixty in the slow one."""
    _valid_check_scene_runs_or_refuses_in_one_line(tmp_path, capsys, doc)


@pytest.mark.slow  # sixty examples, about 60 s
@settings(max_examples=60, deadline=None, suppress_health_check=[HealthCheck.function_scoped_fixture])
@given(doc=CHECK_SCENES)
def test_many_generated_valid_check_scenes_run_or_refuse_in_one_line(tmp_path, capsys, doc):
    _valid_check_scene_runs_or_refuses_in_one_line(tmp_path, capsys, doc)
