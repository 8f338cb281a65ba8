"""rig.html in a real browser: headless Chromium driven by chromedriver through selenium
(Debian's chromium and chromium-driver, installed by .ci/run). Picking a setting shows its
table row's verdict, safe speed and what sets it; each list offers only the lengths that
assemble with those picked; the linkage is drawn with its joints named."""

from __future__ import annotations

import os
import shutil

import pytest

import railcheck
from helpers import sweep_table
from railcheck.units import floored

CHECK = '[check]\nparts = ["crank-screws-O2", "shaft-O2"]\neffects = ["inertia"]\n'


def _driver():
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


def test_picking_a_setting_shows_its_table_rows_values(tmp_path):
    from selenium.webdriver.support.ui import Select

    text = sweep_table(
        speeds=("0.3 Hz",), steps=360, crank=(420, 540), coupler=(840, 840), rocker=(780, 780), ground=(1020, 2280)
    )
    run = railcheck.sweep(text + CHECK, out=tmp_path / "s", serial=True)
    rows = run.tables["four-bar"].to_pylist()
    page = tmp_path / "s" / "rig.html"
    assert "<script src" not in page.read_text() and "http" not in page.read_text()  # offline
    assembled = [r for r in rows if r["check_assembly"]]
    assert 0 < len(assembled) < len(rows)  # the grounds beyond crank + coupler + rocker do not assemble
    assert len({r["safe_speed_Hz"] for r in assembled if r["checks_passed"]}) >= 2  # rows a mix-up would show
    assert not all(r["checks_passed"] for r in assembled)
    driver = _driver()
    try:
        driver.get(f"file://{page}")
        for r in assembled:
            for bar in ("crank", "coupler", "rocker", "ground"):
                Select(driver.find_element("id", bar)).select_by_value(str(int(r[f"{bar}_mm"])))
            offered = [int(o.text) for o in Select(driver.find_element("id", "ground")).options]
            same = [a for a in assembled if a["crank_mm"] == r["crank_mm"]]
            assert offered == sorted(int(a["ground_mm"]) for a in same)  # only what assembles
            shown = {k: driver.find_element("id", k).text for k in ("verdict", "safe", "setby", "reason")}
            assert shown["verdict"] == r["verdict"].upper(), (r, shown)
            chosen = driver.find_element("id", "chosen-verdict").text  # the page's default 0.2 Hz
            if r["checks_passed"]:
                assert chosen.startswith("safe" if r["safe_speed_Hz"] >= 0.2 else "not safe"), (r, chosen)
                assert shown["safe"] == f"{floored(r['safe_speed_Hz'])} Hz", (r, shown)
                assert shown["setby"] == f"({r['safe_speed_part']} {r['safe_speed_criterion']} sets it)"
            else:
                assert shown["safe"] == "no speed" and r["reason"] in shown["reason"]
                assert chosen == "not safe at any speed"
        r = next(r for r in assembled if r["checks_passed"])
        for bar in ("crank", "coupler", "rocker", "ground"):
            Select(driver.find_element("id", bar)).select_by_value(str(int(r[f"{bar}_mm"])))
        speed = 'const e = document.getElementById("speed"); e.value = arguments[0]; e.dispatchEvent(new Event("input"));'
        for share, words in ((0.98, "safe (at or below"), (1.01, "not safe (above")):
            driver.execute_script(speed, f"{r['safe_speed_Hz'] * share:.4f}")
            assert driver.find_element("id", "chosen-verdict").text.startswith(words), share
        svg = driver.find_element("id", "linkage").get_attribute("innerHTML")
        assert all(f">{j}</text>" in svg for j in ("O2", "A", "B", "O4"))
    finally:
        driver.quit()
