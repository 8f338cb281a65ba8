"""Generated scenes, plausible and absurd alike: railcheck never prints a traceback and
always exits 0, 1, 2 or 3 (hypothesis)."""

import json
import math

import pytest
from hypothesis import HealthCheck, given, settings
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
