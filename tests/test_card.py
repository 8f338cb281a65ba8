"""The rig's card (card.pdf, card.png): every setting safe at 1 Hz, once, with its safe
speed floored, the settings checked but not safe marked, nothing else; A4 pages that never
split a section's heading from its header; the PNG looked at in headless Chromium."""

from __future__ import annotations

import math
import re

import pytest

import railcheck
import railcheck.sweep  # noqa: F401 - before railcheck.report.card, which the sweep's run imports
from helpers import chromium_driver, sweep_table
from railcheck.report.card import (
    A4_PT,
    LINES_PER_PAGE,
    MARGIN_PT,
    MONO_ADVANCE,
    card_lines,
    card_pages,
    card_sections,
    page_layout,
    png_image,
)
from railcheck.units import floored

CHECK = '[check]\nparts = ["crank-screws-O2", "shaft-O2"]\neffects = ["inertia"]\n'


@pytest.fixture(scope="module")
def sweep(tmp_path_factory):
    """A sweep whose safe speeds straddle 1 Hz (crank 240 to 360 mm) and with settings
    that do not assemble (the longest grounds)."""
    out = tmp_path_factory.mktemp("card") / "s"
    text = sweep_table(
        speeds=("0.8 Hz",), steps=180, crank=(240, 360), coupler=(600, 720), rocker=(600, 720), ground=(960, 2040)
    )
    run = railcheck.sweep(text + CHECK, out=out, serial=True)
    return out, run.tables["four-bar"].to_pylist()


def _key(row: dict) -> tuple:
    return tuple(int(row[f"{b}_mm"]) for b in ("crank", "coupler", "rocker", "ground"))


@pytest.mark.parametrize("at", ["1 Hz", "a row's own safe speed"])
def test_the_card_lists_every_setting_safe_at_1_hz_once_with_its_safe_speed(sweep, at):
    out, rows = sweep
    checked = {_key(r): r for r in rows if r["check_assembly"] and r["verdict"] != "refused"}
    speeds = sorted(r["safe_speed_Hz"] for r in checked.values())
    at_hz = 1.0 if at == "1 Hz" else speeds[len(speeds) // 2]  # the boundary itself: at least, not above
    cells = {
        (s.crank_mm, c, r, g): v
        for s in card_sections(out / "sweep-four-bar.parquet", 0.8, at_hz=at_hz)
        for c, r, vs in s.rows
        for g, v in zip(s.grounds, vs)
    }
    safe = {k: r["safe_speed_Hz"] for k, r in checked.items() if r["safe_speed_Hz"] >= at_hz}
    assert safe and len(safe) < len(checked)  # some settings are not safe at that speed
    assert {k for k, v in cells.items() if v not in ("", "·")} == set(safe)
    for k, hz in safe.items():
        assert float(cells[k]) <= hz < float(cells[k]) + 0.1 + 1e-9, (k, hz, cells[k])  # floored, never up
        assert cells[k] == f"{float(floored(hz, 2)):.1f}"
    for k, v in cells.items():
        if v == "·":
            assert k in checked and checked[k]["safe_speed_Hz"] < at_hz
        elif v == "":
            assert k not in checked  # blank: does not assemble or is refused


def test_the_card_is_a4_pages_in_pdf_and_png(sweep):
    out, _ = sweep
    pages = card_pages(card_lines(card_sections(out / "sweep-four-bar.parquet", 0.8)))
    pdf = (out / "card.pdf").read_bytes()
    boxes = re.findall(rb"/MediaBox \[ *0 0 ([\d.]+) ([\d.]+) *\]", pdf)
    assert len(boxes) == len(pages) >= 1
    for w, h in boxes:
        assert math.isclose(float(w), A4_PT[0], abs_tol=0.01) and math.isclose(float(h), A4_PT[1], abs_tol=0.01)
    # a sound file: every cross-reference offset opens its object, and the pages' text is the card's lines
    xref = int(re.search(rb"startxref\n(\d+)", pdf).group(1))
    offsets = [int(o) for o in re.findall(rb"(\d{10}) 00000 n", pdf[xref:])]
    assert all(pdf[o:].startswith(b"%d 0 obj" % (i + 1)) for i, o in enumerate(offsets))
    strings = re.findall(rb"\(((?:\\.|[^\\)])*)\) Tj", pdf)  # PDF strings, their ( ) \\ escaped
    shown = [re.sub(r"\\(.)", r"\1", t.decode("cp1252")) for t in strings]
    assert [line for line in shown if line.startswith(("crank ", "coupler/", " "))] == [x for p in pages for x in p if x]
    pngs = [out / ("card.png" if k == 0 else f"card-{k + 1}.png") for k in range(len(pages))]
    assert all(p.exists() for p in pngs) and not (out / f"card-{len(pages) + 1}.png").exists()
    driver = chromium_driver()
    try:
        driver.get(f"file://{pngs[0]}")
        w, h = driver.execute_script("const i = document.images[0]; return [i.naturalWidth, i.naturalHeight];")
        assert math.isclose(h / w, A4_PT[1] / A4_PT[0], rel_tol=2e-3)  # A4 portrait
    finally:
        driver.quit()


def test_pages_hold_their_lines_and_a_split_section_repeats_its_heading():
    lines = []
    for crank in (60, 120):
        lines += ["", f"crank {crank} mm        ground (mm) ->", "coupler/rocker   720"]
        lines += [f"    600/{600 + k:<6}   1.0" for k in range(150)]
    pages = card_pages(lines[1:], per_page=100)
    assert all(len(p) <= 100 for p in pages)
    body = [line for p in pages for line in p if "/" in line and not line.startswith("coupler")]
    assert body == [line for line in lines if "/" in line and not line.startswith("coupler")]  # nothing lost
    for p in pages:
        assert p[0].startswith("crank ") and p[1].startswith("coupler/rocker")
    assert sum(p[0].endswith("(cont.)") for p in pages) >= 2


def test_a_full_page_of_the_widest_lines_fits_on_a4():
    from PIL import ImageDraw, ImageFont

    from railcheck.report.card import PNG_DPI, font_path

    widest = "    900/900    " + "".join(f"{'any':>5}" for _ in range(21))  # 21 ground lengths: 60 to 1260 mm
    layout = page_layout([widest] * LINES_PER_PAGE, 0, 1, "a scene with a long name " * 8)
    body = [t for t in layout if t.face == "Courier"]
    assert min(t.y for t in body) >= MARGIN_PT  # the last line above the bottom margin
    assert all(t.x + MONO_ADVANCE * t.size * len(t.words) <= A4_PT[0] - MARGIN_PT / 2 for t in body)
    image = png_image(layout)
    draw, px = ImageDraw.Draw(image), PNG_DPI / 72.0
    for t in layout:  # every line's glyphs inside the sheet, as drawn
        font = ImageFont.truetype(str(font_path(t.face)), round(t.size * px))
        x0, y0, x1, y1 = draw.textbbox((t.x * px, image.height - t.y * px), t.words, font=font, anchor="ls")
        assert x0 >= 0 and y0 >= 0 and x1 <= image.width and y1 <= image.height, t.words[:40]
