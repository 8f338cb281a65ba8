"""Console tables and JSON for the results. Units appear here: mm, MPa, N, N m, deg."""

from __future__ import annotations

import json
import math
from typing import Any


def _fmt(x: float, digits: int = 6) -> str:
    return f"{x:.{digits}g}"


def kinematics_table(summary: dict) -> str:
    """A readable console report of a kinematics summary."""
    m = summary["mechanism"]
    lines = []
    lengths = ", ".join(f"{k[:-3]} {_fmt(v)} mm" for k, v in m.items() if k.endswith("_mm"))
    lines.append(f"{m['kind']} ({m['assembly']}): {lengths}; {_fmt(m['speed_Hz'])} Hz, {m['steps']} steps")
    lines.append(f"inverse dynamics: {summary['formulation']}; effects: {', '.join(summary['effects']) or 'none (statics)'}")
    ta = summary["transmission_angle_deg"]
    lines.append(f"transmission angle: min {ta['min']:.4f} deg, max {ta['max']:.4f} deg")
    lines.append("")
    lines.append("checks")
    for name, c in summary["checks"].items():
        lines.append(f"  {'ok  ' if c['ok'] else 'FAIL'}  {name:<28} {c['message']}")
    lines.append("")
    lines.append(f"  {'joint':<8}{'peak reaction (N)':>20}{'at crank angle (deg)':>24}")
    for joint, value in summary["peak_reactions_N"].items():
        lines.append(f"  {joint:<8}{value:>20.4f}{summary['peak_crank_angle_deg'][joint]:>24.2f}")
    lines.append(f"  {'torque':<8}{summary['peak_torque_Nm']:>17.4f} N·m"
                 f"{summary['peak_crank_angle_deg']['torque']:>24.2f}")
    for w in summary.get("warnings", []):
        lines.append(f"warning: {w}")
    return "\n".join(lines)


def to_json(data: Any) -> str:
    """Deterministic JSON (sorted keys are not used: the order is the report's order)."""
    return json.dumps(_clean(data), indent=2, ensure_ascii=False, allow_nan=False)


def _clean(x: Any) -> Any:
    if isinstance(x, dict):
        return {str(k): _clean(v) for k, v in x.items()}
    if isinstance(x, (list, tuple)):
        return [_clean(v) for v in x]
    if hasattr(x, "item") and not isinstance(x, (str, bytes)):
        x = x.item()
    if isinstance(x, float) and not math.isfinite(x):
        return None
    return x
