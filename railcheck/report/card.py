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

#: A4 portrait (inches), the text's size (points) and the lines a page holds
A4_INCHES = (8.27, 11.69)
FONT_PT = 6.6
LINES_PER_PAGE = 96


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
    sections = []
    for crank in np.unique(lengths[is_safe, 0]):
        mine = lengths[:, 0] == crank
        grounds = tuple(int(g) for g in np.unique(lengths[mine & is_safe, 3]))
        rows = []
        for coupler, rocker in sorted({(int(r[1]), int(r[2])) for r in lengths[mine & is_safe]}):
            cells = []
            for ground in grounds:
                hit = np.flatnonzero(
                    mine & (lengths[:, 1] == coupler) & (lengths[:, 2] == rocker) & (lengths[:, 3] == ground)
                )
                cells.append(_cell(hit, is_safe, checked, safe_hz))
            rows.append((coupler, rocker, tuple(cells)))
        sections.append(CardSection(int(crank), grounds, tuple(rows)))
    return sections


def _cell(hit: np.ndarray, is_safe: np.ndarray, checked: np.ndarray, safe_hz: np.ndarray) -> str:
    """One cell's text: the safe speed (floored, 2 digits; "any" when unlimited), "·" for
    a checked setting not safe at the card's speed, blank for none."""
    if hit.size == 0 or not checked[hit[0]]:
        return ""
    if not is_safe[hit[0]]:
        return "·"
    value = float(safe_hz[hit[0]])
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
    import matplotlib

    matplotlib.use("Agg")
    import matplotlib.pyplot as plt
    from matplotlib.backends.backend_pdf import PdfPages

    pages = card_pages(lines)
    written = [directory / "card.pdf"] + [
        directory / ("card.png" if k == 0 else f"card-{k + 1}.png") for k in range(len(pages))
    ]
    with atomic_path(written[0]) as pdf_path, PdfPages(pdf_path) as pdf:
        for k, page in enumerate(pages):
            fig = page_figure(page, k, len(pages), source)
            pdf.savefig(fig)
            with atomic_path(written[k + 1]) as png:
                fig.savefig(png, dpi=150, format="png")
            plt.close(fig)
    return written


def page_figure(page: list[str], k: int, pages: int, source: str):
    """One A4 page: a title, how to read it, the page's lines in a fixed-width font."""
    import matplotlib.pyplot as plt

    fig = plt.figure(figsize=A4_INCHES)
    fig.text(0.06, 0.965, f"railcheck: the rig's settings safe at {CARD_SPEED_HZ:g} Hz", fontsize=13, weight="bold")
    fig.text(
        0.06,
        0.948,
        f"each cell: the setting's safe crank speed (Hz, rounded down); · assembles, not safe at "
        f"{CARD_SPEED_HZ:g} Hz; blank: does not assemble or is refused",
        fontsize=7,
    )
    fig.text(0.06, 0.936, f"page {k + 1} of {pages}, from {Path(source).name or source}"[:120], fontsize=7)
    fig.text(0.06, 0.922, "\n".join(page), fontsize=FONT_PT, family="monospace", va="top", linespacing=1.18)
    return fig
