"""The whole rig's figures in README.md and docs/sweep.md are one sweep's: their tables are
``benchmarks/rig_figures.py``'s rendering of the committed docs/data/rig-figures.json,
which that script wrote from one ``railcheck sweep`` of the built-in scene (issue 75: the
README and docs/sweep.md had drifted apart)."""

from __future__ import annotations

import json
from pathlib import Path

from helpers import benchmark_module

ROOT = Path(__file__).resolve().parents[1]


def _script():
    return benchmark_module("rig_figures")


def test_the_readme_and_the_sweep_page_give_the_committed_runs_table():
    script = _script()
    table = script.table(json.loads(script.FIGURES.read_text()))
    for page in ("README.md", "docs/sweep.md"):
        assert table in (ROOT / page).read_text(), f"{page}: rerun benchmarks/rig_figures.py and paste its table"


def test_the_sweep_pages_figures_beside_the_table_are_the_committed_runs():
    script = _script()
    text = " ".join((ROOT / "docs" / "sweep.md").read_text().split())  # across line breaks
    for phrase in script.sweep_page_facts(json.loads(script.FIGURES.read_text())):
        assert phrase in text, phrase


def test_the_sweep_pages_hypotheses_table_is_the_committed_runs():
    script = _script()
    fig = json.loads(script.FIGURES.read_text())
    assert len(fig["hypotheses"]) == 5
    assert script.hypotheses_table(fig) in (ROOT / "docs" / "sweep.md").read_text()


def test_the_figures_are_computed_from_the_rows_and_a_planted_change_shows(tmp_path):
    """:func:`kind_figures` on three hand-made rows: counts, the worst, the safe speeds
    and the motor torques are the rows' own, and the table prints them."""
    script = _script()
    base = {"crank_mm": 480.0, "coupler_mm": 840.0, "rocker_mm": 780.0, "ground_mm": 1020.0}
    rows = [
        base
        | {
            "checks_passed": True,
            "verdict": "pass",
            "reason": "",
            "utilisation": 0.5,
            "governing_part": "crank-rail",
            "governing_criterion": "stress",
            "safe_speed_Hz": 1.5,
            "safe_speed_part": "crank-rail",
            "safe_speed_criterion": "stress",
            "torque_peak_Nm": 20.0,
            "torque_peak_at_safe_Nm": 40.0,
            "crank-rail_stress_MPa": 100.0,
            "crank-rail_utilisation": 0.5,
            "rocker-rail_stress_MPa": 120.0,
            "rocker-rail_utilisation": 0.25,
        },
        base
        | {
            "checks_passed": True,
            "verdict": "fail",
            "reason": "crank-screws-O2 slip",
            "utilisation": 2.0,
            "governing_part": "crank-screws-O2",
            "governing_criterion": "slip",
            "safe_speed_Hz": 0.5,
            "safe_speed_part": "crank-screws-O2",
            "safe_speed_criterion": "slip",
            "torque_peak_Nm": 90.0,
            "torque_peak_at_safe_Nm": 25.0,
        },
        base
        | {
            "checks_passed": False,
            "verdict": "refused",
            "reason": "grashof",
            "utilisation": float("nan"),
            "governing_part": "",
            "governing_criterion": "",
            "safe_speed_Hz": None,
            "safe_speed_part": "",
            "safe_speed_criterion": "",
            "torque_peak_Nm": None,
            "torque_peak_at_safe_Nm": None,
        },
    ]
    f = script.kind_figures(
        rows, {"screw_needs": {"crank-screws-O2": {"every_setting": "M6 12.9", "settings": {"M6 12.9": 2}}}}, "four-bar"
    )
    assert (f["settings"], f["passing_checks"], f["passing"]) == (3, 2, 1)
    assert f["failing_by"] == {"crank-screws-O2": 1} and f["worst"]["utilisation"] == 2.0
    assert f["safe_speed_Hz"]["lowest"] == 0.5 and f["safe_speed_Hz"]["highest"] == 1.5
    assert f["motor_Nm"] == {"every_assemblable": 90.0, "safe": 20.0, "at_own_safe_speed": 40.0}
    final = f["final_design"]  # the first row at 480/840/780/1020: the most used part by utilisation, not stress
    assert (final["most_used_part"], final["most_used_part_utilisation"], final["parts_pass"]) == ("crank-rail", 0.5, True)
    assert (final["governing"], final["safe_speed_Hz"]) == ("crank-rail stress", 1.5)
    text = script.table({"speed_Hz": 1.0, "kinds": {"four-bar": f}})
    assert "| 3 / 2 |" in text and "480/840/780/1020: crank-screws-O2 slip 2" in text and "90 / 20 / 40" in text
