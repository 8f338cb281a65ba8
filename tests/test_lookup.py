"""`railcheck lookup`: one setting's card from a sweep's table equals the check of that
setting; the command's words, exit statuses and refusals."""

from __future__ import annotations

import copy
import json
import math
from types import SimpleNamespace

import pytest

import railcheck
from helpers import sweep_table
from railcheck.cli import main
from railcheck.report.text import sweep_report
from railcheck.sweep.lookup import card_from_check, cards_from_table, parse_setting, table_path
from railcheck.units import floored

COMPONENTS = ["crank-screws-O2", "shaft-O2", "bearings-O4"]
CHECK = f'[check]\nparts = {COMPONENTS!r}\neffects = ["inertia"]\n'.replace("'", '"')


def _sweep(tmp_path, speed: str = "1 Hz"):
    text = (
        sweep_table(speeds=(speed,), steps=360, crank=(420, 540), coupler=(840, 840), rocker=(780, 780), ground=(1020, 1020))
        + CHECK
    )
    return railcheck.sweep(text, out=tmp_path / "sweep", serial=True)


def test_a_setting_read_from_the_sweeps_table_equals_the_check_of_that_setting(tmp_path):
    """Every utilisation and the safe speed of the table's card equal those of a check of
    that setting (the same components, kinematics and steps) to 1e-6; the card's speed,
    torque and power are the row's; a setting the table lacks gives no card."""
    _sweep(tmp_path)
    kind, lengths = parse_setting("420/840/780/1020")
    path = table_path(tmp_path / "sweep", kind)
    (card,) = cards_from_table(path, kind, lengths)
    scene = {
        "mechanism": {"kind": "four-bar", "crank": "420 mm", "coupler": "840 mm", "rocker": "780 mm"}
        | {"ground": "1020 mm", "speed": "1 Hz", "steps": 360},
        "check": {"parts": COMPONENTS, "effects": ["inertia"]},
    }
    run = railcheck.check(scene)
    checked = card_from_check(run.result, run.summary, kind, lengths)
    assert set(card.utilisations) == set(checked.utilisations) == set(COMPONENTS)
    for name in COMPONENTS:
        assert card.utilisations[name] == pytest.approx(checked.utilisations[name], rel=1e-6)
    assert card.safe_speed_hz == pytest.approx(checked.safe_speed_hz, rel=1e-6) and card.verdict == checked.verdict
    assert (card.safe_set_by, card.safe_criterion) == (checked.safe_set_by, checked.safe_criterion)
    assert card.torque_peak_Nm == pytest.approx(checked.torque_peak_Nm, rel=1e-6)
    assert card.power_peak_W == pytest.approx(card.torque_peak_Nm * 2 * math.pi * card.speed_hz, rel=1e-6)
    assert cards_from_table(path, kind, parse_setting("600/840/780/1020")[1]) == []
    (closed,) = cards_from_table(path, kind, parse_setting("540/840/780/1020")[1])  # fails its transmission angle
    assert closed.verdict == "FAIL" and closed.reason == "transmission_angle" and math.isnan(closed.safe_speed_hz)


def test_the_lookup_command_prints_the_card_and_refuses_a_bad_setting(tmp_path, capsys):
    _sweep(tmp_path)
    capsys.readouterr()
    status = main(["lookup", "480/840/780/1020", "--sweep", str(tmp_path / "sweep")])
    out = capsys.readouterr().out
    assert status == 1 and out.startswith("four-bar 480/840/780/1020 mm at 1 Hz: FAIL (crank-screws-O2 slip)")
    assert "safe up to 0.39" in out and "(crank-screws-O2 slip sets it)" in out and "answered from " in out
    assert "sweep-four-bar.parquet" in out
    main(["lookup", "540/840/780/1020", "--sweep", str(tmp_path / "sweep")])
    assert "a configuration check fails (transmission_angle); no speed is safe" in capsys.readouterr().out
    damaged = tmp_path / "damaged"
    damaged.mkdir()
    (damaged / "sweep-four-bar.parquet").write_bytes(b"not a table")
    assert main(["lookup", "480/840/780/1020", "--sweep", str(damaged)]) == 2
    err = capsys.readouterr().err
    assert err.startswith("railcheck: error: --sweep:") and "not a readable sweep table" in err and "Traceback" not in err
    for bad in ("480/840", "480/x/780/1020", "480/-840/780/1020", "nan/840/780/1020"):
        assert main(["lookup", bad, "--sweep", str(tmp_path / "sweep")]) == 2
        err = capsys.readouterr().err
        assert err.startswith("railcheck: error: setting:") and err.count("\n") == 1, bad


@pytest.mark.slow  # the default check (its unit fields from the store the main job filled)
def test_a_setting_no_table_holds_is_checked_and_gives_the_checks_card(tmp_path, capsys):
    """Without a sweep's table the card is the built-in scene's check at that setting: the
    default check's verdict, safe speed and what sets it, its parts among the utilisations."""
    status = main(["lookup", "480/840/780/1020", "--sweep", str(tmp_path / "no-sweep"), "--json"])
    out = capsys.readouterr().out
    (card,) = json.loads(out)["cards"]
    assert status == 1 and card["source"] == "check" and card["verdict"] == "FAIL"
    assert card["safe_set_by"] == "crank-screws-O2" and 0.39 < card["safe_speed_hz"] < 0.41
    assert {"crank-rail", "PF_4b_003_v2", "shaft-O2"} <= set(card["utilisations"])


def test_the_sweeps_lowest_safe_speed_says_fails_at_rest_instead_of_0_hz(tmp_path):
    """A lowest safe speed of 0 is a setting that fails with the crank still: the console
    says so, never "0 Hz"; a positive one is floored."""
    run = _sweep(tmp_path)
    summary = run.summary
    low = summary["by_kind"]["four-bar"]["lowest_safe_speed"]
    assert low is not None and low["safe_speed_Hz"] > 0
    text = " ".join(sweep_report(SimpleNamespace(summary=summary, target=tmp_path, seconds=1.0)).split())
    assert f"lowest safe speed {floored(low['safe_speed_Hz'])} Hz at" in text
    at_rest = copy.deepcopy(summary)
    at_rest["by_kind"]["four-bar"]["lowest_safe_speed"]["safe_speed_Hz"] = 0.0
    text = " ".join(sweep_report(SimpleNamespace(summary=at_rest, target=tmp_path, seconds=1.0)).split())
    assert "lowest safe speed: none at 480/840/780/1020 mm, which fails at rest" in text and " 0 Hz" not in text


def test_the_sweeps_report_lists_the_safe_settings_fastest_first(tmp_path):
    """report.html lists the settings that pass at the sweep's speed, fastest safe speed
    first, each floored, with their count: the table's passing rows, read independently."""
    run = _sweep(tmp_path, "0.3 Hz")  # the O2 screws hold below 0.399 Hz at 480 mm
    table = run.tables["four-bar"].to_pydict()
    passing = sorted((s, c) for s, c, v in zip(table["safe_speed_Hz"], table["crank_mm"], table["verdict"]) if v == "pass")[
        ::-1
    ]
    page = (tmp_path / "sweep" / "report.html").read_text()
    assert len(passing) >= 2
    assert f"The {len(passing)} of {len(passing)} settings safe at 0.3 Hz with the highest safe speed" in page
    listed = page.split("with the highest safe speed", 1)[1]
    positions = [listed.index(f"{c:g}/840/780/1020") for _, c in passing]
    assert positions == sorted(positions) and all(floored(s) in listed for s, _ in passing)
