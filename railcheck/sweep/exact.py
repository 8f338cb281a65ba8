"""The settings the certificate cannot decide, settled on their exact dynamic response, as
``railcheck check`` settles them: a row whose part's one-mode amplification estimate
exceeds its tolerance (it would fail on ``PART quasi-static``, which is not an overload
but a quasi-static verdict not given) is evaluated again with that part's FE modes and
the mode-acceleration correction (the ``dynamic`` effect, for that part only, the others
as they were), and fails only where a real criterion does.

:class:`ExactPass` holds such settings back from the table as their chunks arrive
(:meth:`ExactPass.hold`), builds the parts' dynamic models for their settings alone
(their modes solved or read from the store: only the hole pairs those settings use) and
evaluates them again (:meth:`ExactPass.jobs`); :meth:`ExactPass.merged` puts each row
beyond the tolerance from the exact evaluation and every other row as it was. The safe
speed is a property of the setting, read at the first speed: from the exact evaluation
where the first speed's row is beyond the tolerance, else as it was (the certificate's,
capped where the estimate reaches the tolerance, as the check at that speed gives it).
Those rows say so: ``exact_dynamic`` true, and each exact part's amplification (dynamic
over quasi-static cycle peak) in its ``PART_amplification`` column (null on the other
rows), its estimate kept beside it.
"""

from __future__ import annotations

import numpy as np

#: a setting's columns that its first speed's evaluation sets for all its rows
SETTING_COLUMNS = (
    "safe_speed_Hz",
    "safe_speed_part",
    "safe_speed_criterion",
    "safe_speed_unlimited",
    "torque_peak_at_safe_Nm",
    "torque_rms_at_safe_Nm",
    "power_peak_at_safe_W",
)

#: the words a row's reason gives a part's quasi-static criterion beyond the tolerance
BEYOND = " quasi-static"


def beyond_parts(reasons: np.ndarray) -> tuple[np.ndarray, set[str]]:
    """((R,) bool: the rows failing on some part's quasi-static criterion, the parts that
    do) from the rows' ``reason`` texts ("crank-rail quasi-static, crank-screws-O2 slip")."""
    rows = np.zeros(reasons.size, dtype=bool)
    parts: set[str] = set()
    for i, reason in enumerate(reasons.tolist()):
        named = [c[: -len(BEYOND)] for c in str(reason or "").split(", ") if c.endswith(BEYOND)]
        if named:
            rows[i] = True
            parts.update(named)
    return rows, parts


class ExactPass:
    """The settings of a sweep held back for their exact dynamic response, per kind."""

    def __init__(self, n_speeds: int):
        self.n_speeds = n_speeds
        self.held: dict[str, list[tuple[dict, dict, np.ndarray]]] = {}  # kind -> [(columns, curve, beyond rows)]
        self.parts: dict[str, set[str]] = {}  # kind -> the parts beyond their tolerance

    def hold(self, kind: str, columns: dict, curve: dict) -> tuple[dict, dict]:
        """A chunk's (columns, motor curve) without its settings that have a row beyond
        the tolerance, which are kept for :meth:`jobs`; every row gains ``exact_dynamic``
        and each certified part's ``PART_amplification`` (null until settled)."""
        columns["exact_dynamic"] = np.zeros(columns["setting"].size, dtype=bool)
        for key in [k for k in columns if k.endswith("_amplification_estimate")]:  # the exact one, where settled
            columns.setdefault(key[: -len("_estimate")], np.full(columns["setting"].size, np.nan))
        if not np.any(columns["verdict"] == "fail"):
            return columns, curve
        beyond, parts = beyond_parts(columns["reason"])
        if not parts:
            return columns, curve
        per_setting = np.asarray(beyond.reshape(-1, self.n_speeds).any(axis=1), dtype=bool)
        rows = np.repeat(per_setting, self.n_speeds)
        self.held.setdefault(kind, []).append((_rows(columns, rows), _curve_rows(curve, per_setting), beyond[rows]))
        self.parts.setdefault(kind, set()).update(parts)
        return _rows(columns, ~rows), _curve_rows(curve, ~per_setting)

    def settings(self, kind: str) -> np.ndarray:
        """The held settings' ids of ``kind``, in the order they were held."""
        return np.concatenate([c["setting"][:: self.n_speeds] for c, _, _ in self.held.get(kind, [])]).astype(np.int64)

    def merged(self, kind: str, columns: dict, curve: dict) -> tuple[dict, dict]:
        """The held rows of the settings in ``columns`` (an exact evaluation of some held
        settings of ``kind``, setting-major) with each row beyond the tolerance taken from
        it, the setting's columns too where its first speed's row is, and the motor curve
        likewise."""
        old, old_curve, beyond = self._held_for(kind, columns["setting"])
        exact = columns
        first = beyond.reshape(-1, self.n_speeds)[:, 0]
        out = {}
        for key, values in old.items():
            take = beyond if key not in SETTING_COLUMNS else np.repeat(first, self.n_speeds)
            out[key] = np.where(take, exact[key], values) if key in exact else values
        out["exact_dynamic"] = beyond
        if not np.array_equal(curve["rows"], old_curve["rows"]):  # the same settings pass the checks
            raise AssertionError("the exact evaluation's motor curve is not the held settings'")
        merged_curve = dict(old_curve)
        keep = first[old_curve["rows"]]  # the curve's settings (passing the checks) whose safe speed is the exact one
        for q, v in curve.items():
            if q != "rows":
                merged_curve[q] = np.where(keep[:, None], v, old_curve[q])
        return out, merged_curve

    def _held_for(self, kind: str, settings: np.ndarray) -> tuple[dict, dict, np.ndarray]:
        """The held (columns, curve, beyond rows) of ``settings`` (their rows' ids, in
        this order)."""
        cols = {k: np.concatenate([c[k] for c, _, _ in self.held[kind]]) for k in self.held[kind][0][0]}
        beyond = np.concatenate([b for _, _, b in self.held[kind]])
        curves = [cv for _, cv, _ in self.held[kind]]
        offsets = np.cumsum([0] + [c["setting"].size // self.n_speeds for c, _, _ in self.held[kind]])
        curve = {"rows": np.concatenate([cv["rows"] + o for cv, o in zip(curves, offsets)])}
        curve |= {q: np.concatenate([cv[q] for cv in curves]) for q in curves[0] if q != "rows"}
        order = {int(s): i for i, s in enumerate(cols["setting"][:: self.n_speeds])}
        pick = np.array([order[int(s)] for s in settings[:: self.n_speeds]], dtype=np.int64)
        rows = (pick[:, None] * self.n_speeds + np.arange(self.n_speeds)).reshape(-1)
        position = np.full(len(order), -1)
        position[pick] = np.arange(pick.size)
        kept = np.flatnonzero(position[curve["rows"]] >= 0)
        kept = kept[np.argsort(position[curve["rows"][kept]], kind="stable")]  # in the settings' order
        sub_curve = {"rows": position[curve["rows"][kept]]} | {q: v[kept] for q, v in curve.items() if q != "rows"}
        return {k: v[rows] for k, v in cols.items()}, sub_curve, beyond[rows]


def _rows(columns: dict, rows: np.ndarray) -> dict:
    return {k: v[rows] for k, v in columns.items()}


def _curve_rows(curve: dict, settings: np.ndarray) -> dict:
    """The motor curve of the chunk's ``settings`` (mask over its settings): its rows
    renumbered among them."""
    position = np.cumsum(settings) - 1
    kept = settings[curve["rows"]]
    return {"rows": position[curve["rows"][kept]]} | {q: v[kept] for q, v in curve.items() if q != "rows"}
