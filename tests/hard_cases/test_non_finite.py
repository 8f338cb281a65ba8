"""No non-finite number reaches a person or a table: an unlimited safe speed is null in the
table with a flag, the seed's hypotheses that a sweep does not cover say so in words, and a
part that nothing loads is reported as NO LOAD without being meshed or solved."""

import json
import math
import re
import sys
import tomllib

import numpy as np
import pytest

from helpers import FINAL_DESIGN
from railcheck.check.pipeline import run_pipeline
from railcheck.scene import parse_scene
from railcheck.sweep.run import run_sweep
from railcheck.sweep.table import read_table

NON_FINITE = re.compile(r"\b(nan|inf|infinity|none)\b", re.IGNORECASE)


def _columns(path):
    table = read_table(path)
    return {k: v.to_pylist() for k, v in zip(table.column_names, table.columns)}


@pytest.mark.slow  # both variants: the lighter one's free-body sweep takes 6.5 s cold since the pin pressures
@pytest.mark.parametrize("slow_tier", [False, True])
def test_an_unlimited_safe_speed_is_null_with_a_flag_and_never_inf(tmp_path, slow_tier):
    """Only a constant-load part (explicit loads): no speed limits the setting. The table
    holds null and safe_speed_unlimited = true, in Parquet and CSV alike."""
    text = """
[sweep]
kind = "four-bar"
speeds = ["1 Hz"]
steps = 16
crank = ["480 mm", "480 mm"]
coupler = ["840 mm", "840 mm"]
rocker = ["780 mm", "780 mm"]
ground = ["1020 mm", "1020 mm"]
format = "FORMAT"
[check]
parts = ["PF_4b_003_v2"]
[loads.PF_4b_003_v2]
longitudinal = "250 N"
transverse = "250 N"
[mesh]
size = "8 mm"
hole_size = "4 mm"
"""
    for fmt in ("parquet", "csv") if slow_tier else ("parquet",):
        run = run_sweep(parse_scene(tomllib.loads(text.replace("FORMAT", fmt)), "t"), str(tmp_path / fmt), serial=True)
        rows = _columns(run.tables["four-bar"])
        assert rows["verdict"] == ["pass"] and rows["safe_speed_unlimited"] == [True]
        assert rows["safe_speed_Hz"] == [None]
        for name, values in rows.items():
            assert not any(isinstance(v, float) and not math.isfinite(v) for v in values), name
        if fmt == "csv":
            assert not NON_FINITE.search(run.tables["four-bar"].read_text().replace("PF_4b", "")), "csv text"


def test_hypotheses_a_sweep_does_not_cover_say_so_in_words(tmp_path):
    """A narrowed sweep holds none of the seed's H1/H2 families: their evidence reads "not in
    this sweep", and no hypothesis text prints nan, inf or none."""
    text = '[sweep]\nkind = "four-bar"\nsteps = 16\ncrank = ["480 mm", "480 mm"]\ncoupler = ["840 mm", "840 mm"]\n'
    text += "[output]\nplots = false\n"
    run = run_sweep(parse_scene(tomllib.loads(text), "t"), str(tmp_path / "s"), serial=True)
    hyps = {h["id"]: h for h in run.summary["seed_hypotheses"]}
    for hid in ("3.3.2 H1", "3.3.2 H2", "3.3.5 H3.2"):
        assert hyps[hid]["holds"] is None and hyps[hid]["evidence"].startswith("not in this sweep"), hyps[hid]
    for h in hyps.values():
        assert not NON_FINITE.search(h["evidence"]), h


def test_a_part_with_no_load_is_reported_without_fe():
    """Speed 0, no in-plane weight, clamped rails (the 2013 model: no out-of-plane weight):
    every load is zero. NO LOAD, and no mesh, solve or stress stage ran (gmsh is not even
    imported)."""
    before = "gmsh" in sys.modules
    text = (
        FINAL_DESIGN
        + """speed = "0 Hz"
[check]
parts = ["crank-rail", "PF_4b_006"]
support = "clamped"
"""
    )
    result = run_pipeline(parse_scene(tomllib.loads(text), "t"))
    assert result.unloaded == ("crank-rail", "PF_4b_006") and result.parts == {}
    assert result.stages_run == ("scene", "kinematics", "loads", "geometry", "report")
    assert not result.failures
    assert before or "gmsh" not in sys.modules
    from railcheck.check.summary import summary_of

    summary = summary_of(result)
    assert summary["verdict"] == "NO LOAD" and summary["unloaded_parts"] == ["crank-rail", "PF_4b_006"]
    json.dumps(summary, allow_nan=False)  # nothing non-finite in the data


@pytest.mark.slow
def test_a_loaded_part_beside_an_unloaded_one_is_still_checked():
    text = (
        FINAL_DESIGN
        + """speed = "0 Hz"
[check]
parts = ["crank-rail", "PF_4b_003_v2"]
support = "clamped"
[loads.PF_4b_003_v2]
longitudinal = "250 N"
transverse = "250 N"
[mesh]
size = "8 mm"
hole_size = "4 mm"
"""
    )
    result = run_pipeline(parse_scene(tomllib.loads(text), "t"))
    assert result.unloaded == ("crank-rail",) and list(result.parts) == ["PF_4b_003_v2"]
    assert np.any(result.parts["PF_4b_003_v2"].cycle.C) and "mesh" in result.stages_run
