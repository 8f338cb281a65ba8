"""Two checks' parts side by side, from their summary.json files: cycle peak, fatigue
midrange and alternating stress at the governing node, fatigue factor, utilisation and
what governs (a markdown table for the docs).

    python benchmarks/compare_summaries.py BEFORE/summary.json AFTER/summary.json
"""

from __future__ import annotations

import json
import sys


def row(name: str, part: dict) -> list[str]:
    f = part["fatigue"]
    return [
        f"{part['max_von_mises_Pa'] / 1e6:.1f}",
        f"{f['sigma_m_Pa'] / 1e6:.1f}",
        f"{f['sigma_a_Pa'] / 1e6:.1f}",
        f"{f['min_safety_factor']:.2f}",
        f"{part['utilisation']:.0%}",
        part["governing_criterion"],
    ]


def main(before_path: str, after_path: str) -> None:
    before, after = (json.load(open(p)) for p in (before_path, after_path))
    heads = ["peak (MPa)", "sigma_m (MPa)", "sigma_a (MPa)", "fatigue n", "utilisation", "governs"]
    print("| part | " + " | ".join(f"{h} before / after" for h in heads) + " |")
    print("|---" * (len(heads) + 1) + "|")
    for name in after["parts"]:
        b, a = row(name, before["parts"][name]), row(name, after["parts"][name])
        print(f"| {name} | " + " | ".join(f"{x} / {y}" for x, y in zip(b, a)) + " |")


if __name__ == "__main__":
    main(*sys.argv[1:3])
