"""The whole rig's figures that README.md and docs/sweep.md quote, from one sweep's output.

    railcheck sweep --out /tmp/rig            # the built-in scene, every setting
    python benchmarks/rig_figures.py /tmp/rig  # writes docs/data/rig-figures.json and the map, prints the tables

The figures come from the sweep's summary.json and its tables (the first speed's rows), so
every count, speed and torque the documents give is one run's; ``tests/test_docs_figures.py``
checks that the README's and docs/sweep.md's tables are :func:`table` of the committed JSON,
so they cannot drift from it. Units: mm, Hz, N m.
"""

from __future__ import annotations

import argparse
import json
import math
import shutil
from collections import Counter
from pathlib import Path

FIGURES = Path(__file__).resolve().parents[1] / "docs" / "data" / "rig-figures.json"
MAP = FIGURES.parents[1] / "img" / "sweep-map-four-bar.png"  # the run's four-bar map, shown in docs/sweep.md
BARS = {"four-bar": ("crank", "coupler", "rocker", "ground"), "slider-crank": ("crank", "coupler")}
FINAL_DESIGN = "480/840/780/1020"  # seed 000's final design, the built-in scene's setting


def _lengths(row: dict, kind: str) -> str:
    return "/".join(f"{row[f'{b}_mm']:.0f}" for b in BARS[kind])


def kind_figures(rows: list[dict], summary: dict, kind: str) -> dict:
    """One kind's figures from its first-speed ``rows`` (dicts of the table's columns)
    and its summary.json entry."""
    ok = [r for r in rows if r["checks_passed"]]
    passed = [r for r in ok if r["verdict"] == "pass"]
    failing = Counter(c.split(" ")[0] for r in ok if r["verdict"] == "fail" for c in r["reason"].split(", "))
    safe = sorted((r["safe_speed_Hz"], i) for i, r in enumerate(ok) if r["safe_speed_Hz"] is not None)
    finite = [s for s, _ in safe if math.isfinite(s)]
    lowest = ok[safe[0][1]] if safe else None
    worst = max(ok, key=lambda r: r["utilisation"])
    at_safe = [r["torque_peak_at_safe_Nm"] for r in ok if r.get("torque_peak_at_safe_Nm") is not None]
    needs = summary.get("screw_needs", {})
    return {
        "settings": len(rows),
        "passing_checks": len(ok),
        "passing": len(passed),
        "failing_by": dict(failing.most_common()),
        "worst": {
            "lengths": _lengths(worst, kind),
            "part": worst["governing_part"],
            "criterion": worst["governing_criterion"],
            "utilisation": worst["utilisation"],
        },
        "safe_speed_Hz": {
            "lowest": finite[0] if finite else None,
            "lowest_at": _lengths(lowest, kind) if lowest else None,
            "lowest_set_by": f"{lowest['safe_speed_part']} {lowest['safe_speed_criterion']}" if lowest else None,
            "median": finite[len(finite) // 2] if finite else None,
            "highest": finite[-1] if finite else None,
        },
        "safe_speed_set_by": dict(Counter(r["safe_speed_part"] for r in ok if r["safe_speed_part"]).most_common()),
        "motor_Nm": {
            "every_assemblable": max((r["torque_peak_Nm"] for r in ok), default=None),
            "safe": max((r["torque_peak_Nm"] for r in passed), default=None),
            "at_own_safe_speed": max(at_safe, default=None),
        },
        "screws_every_setting": {name: n["every_setting"] for name, n in needs.items()},
        "screws_by_setting": {name: n["settings"] for name, n in needs.items()},
        "assemble": summary.get("settings_assemblable"),
        "revolve": summary.get("settings_revolving"),
        "shortest_bearing_life": summary.get("shortest_bearing_life"),
        "final_design": final_design(rows, kind),
    }


def final_design(rows: list[dict], kind: str) -> dict | None:
    """The final design's row (:data:`FINAL_DESIGN`) in brief: its verdict, the most used
    FE part (a part has a ``_stress_MPa`` column), what governs and its safe speed (Hz)."""
    row = next((r for r in rows if _lengths(r, kind) == FINAL_DESIGN), None)
    if row is None:
        return None
    parts = {c.removesuffix("_stress_MPa") for c in row if c.endswith("_stress_MPa") and row[c] is not None}
    most = max(sorted(parts), key=lambda p: row[f"{p}_utilisation"], default=None)
    return {
        "verdict": row["verdict"],
        "parts_pass": all(row[f"{p}_utilisation"] <= 1.0 for p in parts),
        "most_used_part": most,
        "most_used_part_utilisation": None if most is None else row[f"{most}_utilisation"],
        "governing": f"{row['governing_part']} {row['governing_criterion']}",
        "utilisation": row["utilisation"],
        "safe_speed_Hz": row["safe_speed_Hz"],
    }


def figures(out: Path) -> dict:
    """kind -> :func:`kind_figures` of the sweep written to ``out``."""
    import pyarrow.parquet as pq

    summary = json.loads((out / "summary.json").read_text())
    speed = summary["speeds_Hz"][0]
    wall = sum(json.loads((out / "timings.json").read_text()).values())
    hypotheses = [{k: h[k] for k in ("id", "holds", "evidence")} for h in summary.get("seed_hypotheses", [])]
    result = {"speed_Hz": speed, "wall_s": wall, "hypotheses": hypotheses, "kinds": {}}
    for kind, name in summary["tables"].items():
        table = pq.read_table(out / name).to_pylist()
        rows = [r for r in table if math.isclose(r["speed_Hz"], speed, rel_tol=1e-12)]
        result["kinds"][kind] = kind_figures(rows, summary["by_kind"][kind], kind)
    return result


def _top(counts: dict, n: int = 4) -> str:
    """The ``n`` largest counts, largest first (ties by name), and how many more there are."""
    ranked = sorted(counts.items(), key=lambda kv: (-kv[1], kv[0]))
    more = f" (+{len(ranked) - n} more)" if len(ranked) > n else ""
    return (", ".join(f"{name} {k:,}" for name, k in ranked[:n]) + more) or "none"


def _hz(x: float | None) -> str:
    return "-" if x is None else f"{x:.3g}"


def _lowest(x: float | None) -> str:
    return "0 (at rest)" if x == 0.0 else f"{_hz(x)} Hz"


def _row(label: str, cells: list[str]) -> str:
    return "| " + " | ".join([label, *cells]) + " |"


def table(fig: dict) -> str:
    """The README's markdown table of the whole rig's figures ``fig`` (rows within the
    README's 120 characters)."""
    kinds = list(fig["kinds"])
    k = [fig["kinds"][n] for n in kinds]
    hz = f"{fig['speed_Hz']:g} Hz"
    rows = [
        ("settings / pass the configuration checks", [f"{x['settings']:,} / {x['passing_checks']:,}" for x in k]),
        (f"pass every check at {hz}", [f"{x['passing']:,}" for x in k]),
        (f"failing at {hz}", [_top(x["failing_by"], 3) for x in k]),
        (
            "worst (utilisation)",
            [f"{w['lengths']}: {w['part']} {w['criterion']} {w['utilisation']:.3g}" for w in _of(k, "worst")],
        ),
        (
            "lowest safe speed",
            [f"{_lowest(s['lowest'])} at {s['lowest_at']}, {s['lowest_set_by']}" for s in _of(k, "safe_speed_Hz")],
        ),
        ("median / highest safe speed (Hz)", [f"{_hz(s['median'])} / {_hz(s['highest'])}" for s in _of(k, "safe_speed_Hz")]),
        ("safe speeds set by", [_top(x["safe_speed_set_by"], 2) for x in k]),
        (
            f"motor at {hz} (N·m): all / safe settings / at own safe speed",
            [" / ".join(_hz(m[q]) for q in ("every_assemblable", "safe", "at_own_safe_speed")) for m in _of(k, "motor_Nm")],
        ),
        ("the O2 screw that passes at every setting", [x["screws_every_setting"].get("crank-screws-O2", "-") for x in k]),
    ]
    lines = [_row("", kinds), "| --- |" + " --- |" * len(kinds)]
    return "\n".join(lines + [_row(label, cells) for label, cells in rows])


def _of(kinds: list[dict], key: str) -> list:
    return [x[key] for x in kinds]


def _screw_rank(screw: str) -> tuple[float, float]:
    """ "M5 8.8" -> (5, 8.8): smaller size first, then the weaker class; "none" last."""
    if screw == "none":
        return (math.inf, math.inf)
    size, grade = screw.split()
    return (float(size[1:]), float(grade))


def sweep_page_facts(fig: dict) -> list[str]:
    """The phrases docs/sweep.md quotes beside the table, from ``fig``'s four-bar figures."""
    k = fig["kinds"]["four-bar"]
    life = k["shortest_bearing_life"]
    screws = sorted(k["screws_by_setting"]["crank-screws-O2"].items(), key=lambda kv: _screw_rank(kv[0]))
    final = k["final_design"]
    passes = "every part passes" if final["parts_pass"] else "a part fails"
    at = "/".join(f"{life['lengths_m'][bar] * 1000:.0f}" for bar in BARS["four-bar"])
    others = [n for name, n in k["screws_every_setting"].items() if name != "crank-screws-O2"]
    return [
        f"{fig['wall_s']:.0f} s wall",
        f"{k['assemble']:,} four-bar settings assemble and {k['revolve']:,} revolve",
        f"{life['hours']:.3g} h, static safety {life['static_safety']:.2f}, at {at} mm",
        f"the other screw groups pass with {max(others, key=_screw_rank)} everywhere",
        ", ".join(f"{screw} at {n:,}" for screw, n in screws),
        f"{FINAL_DESIGN} mm: {passes} (the most used, {final['most_used_part']}, at "
        f"{final['most_used_part_utilisation']:.2f}), {final['governing']} at {final['utilisation']:.3g}, "
        f"safe up to {math.floor(final['safe_speed_Hz'] * 1000) / 1000:.3f} Hz",
    ]


def hypotheses_table(fig: dict) -> str:
    """docs/sweep.md's table of seed 000's hypotheses of 3.3 as the run's summary.json tests them."""
    lines = ["| seed | on this rig | evidence |", "| --- | --- | --- |"]
    lines += [f"| {h['id']} | {'**holds**' if h['holds'] else '**fails**'} | {h['evidence']} |" for h in fig["hypotheses"]]
    return "\n".join(lines)


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("out", type=Path, help="a sweep's output folder (railcheck sweep --out)")
    out = parser.parse_args().out
    fig = figures(out)
    FIGURES.parent.mkdir(parents=True, exist_ok=True)
    FIGURES.write_text(json.dumps(fig, indent=1, sort_keys=True) + "\n")
    shutil.copyfile(out / "map-four-bar.png", MAP)
    print(table(fig))
    print()
    print(hypotheses_table(fig))
    print()
    print("\n".join(sweep_page_facts(fig)))


if __name__ == "__main__":
    main()
