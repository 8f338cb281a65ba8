"""What the sweep's lab pages cost: ``card.pdf``/``card.png`` and ``rig.html`` from a
sweep's four-bar table, written into a scratch folder, median of ``--repeat`` runs.

    railcheck sweep --out /tmp/rig            # the built-in scene, every setting
    python benchmarks/report_pages.py /tmp/rig --repeat 3
"""

from __future__ import annotations

import argparse
import statistics
import tempfile
import time
from pathlib import Path

import railcheck.sweep  # noqa: F401 - before the report modules the sweep's run imports
from railcheck.report.card import write_card
from railcheck.report.rig_page import write_rig_page


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("sweep", type=Path, help="a sweep's results folder (with sweep-four-bar.parquet)")
    parser.add_argument("--repeat", type=int, default=3)
    args = parser.parse_args()
    table = args.sweep / "sweep-four-bar.parquet"
    times: dict[str, list[float]] = {"card (pdf + png)": [], "rig.html": []}
    with tempfile.TemporaryDirectory() as scratch:
        out = Path(scratch)
        for _ in range(args.repeat):
            t = time.perf_counter()
            pages = write_card(out, table, 1.0, str(table))
            times["card (pdf + png)"].append(time.perf_counter() - t)
            t = time.perf_counter()
            write_rig_page(out / "rig.html", table, 1.0, str(table))
            times["rig.html"].append(time.perf_counter() - t)
    for what, seconds in times.items():
        print(f"{what}: median {statistics.median(seconds):.2f} s of {args.repeat}")
    print(f"card: {len(pages) - 1} page(s)")


if __name__ == "__main__":
    main()
