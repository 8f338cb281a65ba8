"""rig.html in a real browser: headless Chromium driven by chromedriver through selenium
(Debian's chromium and chromium-driver, installed by .ci/run). Picking a setting shows its
table row's verdict, safe speed and what sets it; each list offers only the lengths that
assemble with those picked; the linkage is drawn with its joints named."""

from __future__ import annotations

import railcheck
from helpers import chromium_driver, sweep_table
from railcheck.units import floored

BARS = ("crank", "coupler", "rocker", "ground")

#: set the four lists as a user does (a value, then its change event, bar by bar) and read
#: the card's fields and the ground list's offers back, in one browser call
PICK_AND_READ = """
const bars = ["crank", "coupler", "rocker", "ground"];
bars.forEach((b, k) => { const s = document.getElementById(b); s.value = arguments[0][k];
  s.dispatchEvent(new Event("change")); });
const text = id => document.getElementById(id).textContent;
return {offered: [...document.getElementById("ground").options].map(o => Number(o.textContent)),
  verdict: text("verdict"), safe: text("safe"), setby: text("setby"), reason: text("reason"),
  "chosen-verdict": text("chosen-verdict")};
"""

CHECK = '[check]\nparts = ["crank-screws-O2", "shaft-O2"]\neffects = ["inertia"]\n'


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
    driver = chromium_driver()
    try:
        driver.get(f"file://{page}")
        for n, r in enumerate(assembled):
            if n == 0:  # through selenium's Select once, then through the same change events in one call a row
                for bar in ("crank", "coupler", "rocker", "ground"):
                    Select(driver.find_element("id", bar)).select_by_value(str(int(r[f"{bar}_mm"])))
            shown = driver.execute_script(PICK_AND_READ, [str(int(r[f"{b}_mm"])) for b in BARS])
            offered = shown["offered"]
            same = [a for a in assembled if a["crank_mm"] == r["crank_mm"]]
            assert offered == sorted(int(a["ground_mm"]) for a in same)  # only what assembles
            assert shown["verdict"] == r["verdict"].upper(), (r, shown)
            chosen = shown["chosen-verdict"]  # the page's default 0.2 Hz
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


def _cells(driver, panel: str) -> list[dict]:
    """Each drawn cell of a map panel: its setting's index, value and fill."""
    script = (
        "return [...document.querySelectorAll(`#${arguments[0]} rect.cell`)]"
        ".map(r => ({i: Number(r.dataset.i), value: r.dataset.value, fill: r.getAttribute('fill')}));"
    )
    return driver.execute_script(script, panel)


def _lengths(row: dict) -> tuple:
    return tuple(int(row[f"{b}_mm"]) for b in ("crank", "coupler", "rocker", "ground"))


def test_the_maps_show_slices_and_worst_cases_on_one_scale_with_the_1_hz_contour(tmp_path):
    text = sweep_table(
        speeds=("0.8 Hz",), steps=180, crank=(240, 360), coupler=(780, 840), rocker=(720, 780), ground=(960, 1020)
    )
    run = railcheck.sweep(text + CHECK, out=tmp_path / "s", serial=True)
    rows = [r for r in run.tables["four-bar"].to_pylist() if r["check_assembly"]]
    safe = {_lengths(r): floored(r["safe_speed_Hz"]) for r in rows if r["verdict"] != "refused"}
    assert min(map(float, safe.values())) < 1 < max(map(float, safe.values()))  # the 1 Hz contour crosses
    driver = chromium_driver()
    try:
        driver.get(f"file://{tmp_path / 's' / 'rig.html'}")
        lengths = driver.execute_script("return RIG.lengths;")
        picked = _lengths(rows[driver.execute_script("return current;")])
        assert picked == tuple(lengths[driver.execute_script("return current;")])
        fills: dict = {}
        for panel in ("slice-0", "worst-0", "slice-1", "worst-1"):
            cells = _cells(driver, panel)
            assert cells, panel
            for c in cells:
                assert fills.setdefault(c["value"], c["fill"]) == c["fill"], panel  # one scale for all panels
        for pair, panel in (((0, 1), "slice-0"), ((2, 3), "slice-1")):
            fixed = [k for k in range(4) if k not in pair]
            want = {k: v for k, v in safe.items() if all(k[f] == picked[f] for f in fixed)}
            got = {tuple(lengths[c["i"]]): c["value"] for c in _cells(driver, panel)}
            assert {k: float(v) for k, v in got.items()} == {k: float(v) for k, v in want.items()}, panel
        for pair, panel in (((0, 1), "worst-0"), ((2, 3), "worst-1")):
            worst: dict = {}
            for k, v in safe.items():
                cell = (k[pair[0]], k[pair[1]])
                worst[cell] = min(worst.get(cell, float("inf")), float(v))
            got = {(lengths[c["i"]][pair[0]], lengths[c["i"]][pair[1]]): float(c["value"]) for c in _cells(driver, panel)}
            assert got == worst, panel
        levels = driver.execute_script(
            "return [...document.querySelectorAll('#slice-0 path.contour')].map(p => Number(p.dataset.level));"
        )
        assert 1.0 in levels  # the slice over crank and coupler crosses 1 Hz
        target = next(c for c in _cells(driver, "slice-0") if c["i"] != driver.execute_script("return current;"))
        driver.execute_script(
            f"document.querySelector('#slice-0 rect.cell[data-i=\"{target['i']}\"]')"
            ".dispatchEvent(new MouseEvent('click', {bubbles: true}));"
        )
        chosen = tuple(
            int(driver.find_element("id", b).get_attribute("value")) for b in ("crank", "coupler", "rocker", "ground")
        )
        assert chosen == tuple(lengths[target["i"]])
        assert driver.find_element("id", "safe").text == f"{safe[chosen]} Hz"
    finally:
        driver.quit()
