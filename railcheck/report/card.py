"""The rig's card for the bench: ``card.pdf`` (every page) and ``card.png`` (its first
page; ``card-2.png``… the others), A4 portrait, from a four-bar sweep's table. Every setting
safe at 1 Hz (its checks pass and its safe speed is at least 1 Hz) with that safe speed:
one section per crank length, one row per coupler and rocker, one column per ground
length, the cell the safe speed in Hz floored to two digits ("·": it assembles and is
checked but is not safe at 1 Hz; blank: it does not assemble or a configuration check
refuses it)."""

from __future__ import annotations

import math
from dataclasses import dataclass
from pathlib import Path

import numpy as np

from railcheck.files import atomic_path
from railcheck.sweep.table import read_table
from railcheck.units import floored

#: the speed the card lists the safe settings at (Hz)
CARD_SPEED_HZ = 1.0

#: the body's size and leading (pt) and the lines an A4 page holds below its heading
#: (:func:`page_layout`: from 36 pt below the title's line to the bottom margin)
FONT_PT = 6.6
LEADING_PT = 7.6
LINES_PER_PAGE = 92


@dataclass(frozen=True)
class CardSection:
    """One crank length's table: ``grounds`` (mm) its columns; ``rows`` (coupler mm,
    rocker mm, one cell text per ground)."""

    crank_mm: int
    grounds: tuple[int, ...]
    rows: tuple[tuple[int, int, tuple[str, ...]], ...]


def card_sections(table_path: Path, speed_hz: float, at_hz: float = CARD_SPEED_HZ) -> list[CardSection]:
    """The card's sections from the four-bar table at ``table_path`` (its rows at the
    sweep's ``speed_hz``; the safe speed does not depend on it): only the rows with at
    least one setting safe at ``at_hz``, only the ground lengths that have one."""
    table = read_table(table_path, speed_hz=speed_hz)
    col = {c: np.asarray(table.column(c).to_numpy(zero_copy_only=False)) for c in table.column_names}
    lengths = np.rint(np.stack([col[f"{b}_mm"] for b in ("crank", "coupler", "rocker", "ground")], axis=1)).astype(int)
    checked = np.asarray(col["check_assembly"], bool) & (col["verdict"] != "refused")
    safe_hz = np.where(checked, np.asarray(col["safe_speed_Hz"], float), np.nan)
    is_safe = checked & (np.nan_to_num(safe_hz, nan=-1.0) >= at_hz)
    where = {tuple(k): i for i, k in enumerate(lengths.tolist())}  # (crank, coupler, rocker, ground) mm -> row
    sections = []
    for crank in np.unique(lengths[is_safe, 0]).tolist():
        mine = lengths[is_safe & (lengths[:, 0] == crank)]
        grounds = tuple(np.unique(mine[:, 3]).tolist())
        rows = tuple(
            (c, r, tuple(_cell(where.get((crank, c, r, g)), is_safe, checked, safe_hz) for g in grounds))
            for c, r in sorted({(int(a), int(b)) for a, b in mine[:, 1:3].tolist()})
        )
        sections.append(CardSection(int(crank), grounds, rows))
    return sections


def _cell(row: int | None, is_safe: np.ndarray, checked: np.ndarray, safe_hz: np.ndarray) -> str:
    """One cell's text, of the table's ``row`` (None: no such setting): the safe speed
    (floored, 2 digits; "any" when unlimited), "·" for a checked setting not safe at the
    card's speed, blank for none."""
    if row is None or not checked[row]:
        return ""
    if not is_safe[row]:
        return "·"
    value = float(safe_hz[row])
    if math.isinf(value):
        return "any"
    return f"{float(floored(value, 2)):.1f}" if value < 10 else floored(value, 2)


def card_lines(sections: list[CardSection]) -> list[str]:
    """The card's text, one string a line in a fixed-width font: per section a heading,
    the ground lengths' header and one line per coupler/rocker row."""
    lines: list[str] = []
    for s in sections:
        lines += ["", f"crank {s.crank_mm} mm        ground (mm) ->"]
        lines.append("coupler/rocker " + "".join(f"{g:>5}" for g in s.grounds))
        lines += [f"{c:>7}/{r:<6} " + "".join(f"{v:>5}" for v in cells) for c, r, cells in s.rows]
    return lines[1:]


def card_pages(lines: list[str], per_page: int = LINES_PER_PAGE) -> list[list[str]]:
    """``lines`` cut into pages of at most ``per_page`` lines, never between a section's
    heading and its header, a heading repeated (cont.) where a section runs on."""
    pages: list[list[str]] = [[]]
    heading: list[str] = []
    for line in lines:
        if line.startswith("crank "):
            heading = [line]
        elif line.startswith("coupler/rocker"):
            heading.append(line)
        starts = line.startswith("crank ")
        if len(pages[-1]) + (3 if starts else 1) > per_page:
            pages.append([] if starts or not line else [heading[0] + " (cont.)", heading[1]])
        if line or pages[-1]:
            pages[-1].append(line)
    return [p for p in pages if p]


def write_card(directory: Path, table_path: Path, speed_hz: float, source: str = "") -> list[Path]:
    """Write ``card.pdf`` and its pages as PNG into ``directory``; return the paths
    written (none when no setting is safe at the card's speed: the card is not written)."""
    lines = card_lines(card_sections(table_path, speed_hz))
    if not lines:
        return []
    pages = card_pages(lines)
    layouts = [page_layout(page, k, len(pages), source) for k, page in enumerate(pages)]
    written = [directory / "card.pdf"] + [
        directory / ("card.png" if k == 0 else f"card-{k + 1}.png") for k in range(len(pages))
    ]
    with atomic_path(written[0]) as tmp:
        tmp.write_bytes(pdf_bytes(layouts))
    for layout, path in zip(layouts, written[1:]):
        with atomic_path(path) as tmp:
            png_image(layout).save(tmp, format="PNG")
    return written


#: A4 portrait in PDF points, the margin (pt), the PNG's resolution (dpi)
A4_PT = (595.276, 841.890)
MARGIN_PT = 36.0
PNG_DPI = 150

#: the card's faces: PDF standard font -> the PNG's TrueType (matplotlib's DejaVu)
FACES = {"Courier": "DejaVuSansMono.ttf", "Helvetica": "DejaVuSans.ttf", "Helvetica-Bold": "DejaVuSans-Bold.ttf"}

#: a fixed-width character's advance, of the font size (Courier and DejaVu Sans Mono: 0.6)
MONO_ADVANCE = 0.6


@dataclass(frozen=True)
class Text:
    """One line of a page: its face (:data:`FACES`), size and baseline's start (pt, from
    the page's lower left) and its words."""

    face: str
    size: float
    x: float
    y: float
    words: str


def page_layout(page: list[str], k: int, pages: int, source: str) -> list[Text]:
    """One page's lines, placed: the title, how to read it, the page number and the
    source, then the page's lines in a fixed-width face."""
    top = A4_PT[1] - MARGIN_PT
    head = [
        Text("Helvetica-Bold", 13.0, MARGIN_PT, top - 13.0, f"railcheck: the rig's settings safe at {CARD_SPEED_HZ:g} Hz"),
        Text(
            "Helvetica",
            7.0,
            MARGIN_PT,
            top - 27.0,
            f"each cell: the setting's safe crank speed (Hz, rounded down); · assembles, not safe at "
            f"{CARD_SPEED_HZ:g} Hz; blank: does not assemble or is refused",
        ),
        Text("Helvetica", 7.0, MARGIN_PT, top - 36.0, f"page {k + 1} of {pages}, from {Path(source).name or source}"[:110]),
    ]
    first = top - 36.0 - 2.0 * LEADING_PT
    return head + [Text("Courier", FONT_PT, MARGIN_PT, first - i * LEADING_PT, line) for i, line in enumerate(page)]


def pdf_bytes(layouts: list[list[Text]]) -> bytes:
    """A PDF of the pages ``layouts``: A4, the standard fonts (nothing embedded), the text
    in WinAnsi (its middle dot included)."""
    faces = {face: f"F{i}" for i, face in enumerate(FACES, 1)}
    objects: list[bytes] = []
    pages = []
    for layout in layouts:
        stream = b"".join(
            f"BT /{faces[t.face]} {t.size:g} Tf {t.x:.2f} {t.y:.2f} Td (".encode() + _pdf_string(t.words) + b") Tj ET\n"
            for t in layout
        )
        objects.append(b"<< /Length %d >>\nstream\n" % len(stream) + stream + b"endstream")
        pages.append(len(objects) + 3)  # numbers: 1 the catalogue, 2 the page tree, then content, page, ...
        objects.append(b"")  # this page, written below once the fonts are numbered
    first_font = len(objects) + 3
    fonts = " ".join(f"/{faces[f]} {first_font + i} 0 R" for i, f in enumerate(FACES))
    box = f"[0 0 {A4_PT[0]:.3f} {A4_PT[1]:.3f}]"
    for n in pages:
        objects[n - 3] = (
            f"<< /Type /Page /Parent 2 0 R /MediaBox {box} /Contents {n - 1} 0 R /Resources << /Font << {fonts} >> >> >>"
        ).encode()
    objects += [f"<< /Type /Font /Subtype /Type1 /BaseFont /{f} /Encoding /WinAnsiEncoding >>".encode() for f in FACES]
    kids = " ".join(f"{n} 0 R" for n in pages)
    head = [b"<< /Type /Catalog /Pages 2 0 R >>", f"<< /Type /Pages /Kids [{kids}] /Count {len(pages)} >>".encode()]
    return _pdf_file(head + objects)


def _pdf_string(words: str) -> bytes:
    raw = words.encode("cp1252", errors="replace")
    return raw.replace(b"\\", b"\\\\").replace(b"(", b"\\(").replace(b")", b"\\)")


def _pdf_file(objects: list[bytes]) -> bytes:
    """The PDF file of numbered ``objects`` (1, 2, ...), with its cross-reference table."""
    out, offsets = bytearray(b"%PDF-1.4\n"), []
    for i, body in enumerate(objects, 1):
        offsets.append(len(out))
        out += b"%d 0 obj\n" % i + body + b"\nendobj\n"
    xref = len(out)
    out += b"xref\n0 %d\n0000000000 65535 f \n" % (len(objects) + 1)
    out += b"".join(b"%010d 00000 n \n" % o for o in offsets)
    out += b"trailer\n<< /Size %d /Root 1 0 R >>\nstartxref\n%d\n%%%%EOF\n" % (len(objects) + 1, xref)
    return bytes(out)


def png_image(layout: list[Text]):
    """The page as a PIL image at :data:`PNG_DPI` (A4 portrait), the same layout as the
    PDF's in matplotlib's DejaVu faces."""
    from PIL import Image, ImageDraw, ImageFont

    px = PNG_DPI / 72.0
    image = Image.new("RGB", (round(A4_PT[0] * px), round(A4_PT[1] * px)), "white")
    draw = ImageDraw.Draw(image)
    for t in layout:
        font = ImageFont.truetype(str(font_path(t.face)), max(1, round(t.size * px)))
        draw.text((t.x * px, image.height - t.y * px), t.words, font=font, fill="black", anchor="ls")
    return image


def font_path(face: str) -> Path:
    """The TrueType file that draws a PDF face in the PNG (matplotlib's own DejaVu)."""
    import matplotlib

    return Path(matplotlib.get_data_path()) / "fonts" / "ttf" / FACES[face]
