"""The exact pass's bookkeeping (railcheck.sweep.exact): the settings with a row beyond a
part's quasi-static tolerance are held back whole, the rest written as they came; each
held row beyond the tolerance takes the exact evaluation, every other row stays, the
setting's safe-speed columns and motor curve follow its first speed's row; the exact part's
amplification lands beside its estimate, which stays. The sweep end to end: tests/test_sweep_speeds.py."""

import numpy as np

from railcheck.sweep.exact import ExactPass, beyond_parts

SPEEDS = 2


def _chunk(settings: list[int], reasons: list[str], offset: float = 0.0) -> tuple[dict, dict]:
    """A chunk's columns (setting-major, two speeds a setting) and motor curve (every
    setting passes the checks), each value naming its row."""
    n = len(settings)
    row = np.arange(n * SPEEDS, dtype=float) + offset
    columns = {
        "setting": np.repeat(np.array(settings), SPEEDS),
        "verdict": np.array(["fail" if r else "pass" for r in reasons], dtype=object),
        "reason": np.array(reasons, dtype=object),
        "crank-rail_stress_MPa": row,
        "crank-rail_amplification_estimate": row + 0.5,
        "safe_speed_Hz": np.repeat(np.array(settings, float) + offset, SPEEDS),
    }
    curve = {"rows": np.arange(n), "torque_peak_Nm": np.array(settings, float)[:, None] * np.ones((1, 3)) + offset}
    return columns, curve


def test_the_reasons_name_the_rows_and_parts_beyond_their_tolerance():
    rows, parts = beyond_parts(
        np.array(["", None, "crank-rail quasi-static, crank-screws-O2 slip", "x stress"], dtype=object)
    )
    assert list(rows) == [False, False, True, False] and parts == {"crank-rail"}


def test_held_settings_are_merged_row_by_row_and_their_curve_follows_the_first_speed():
    exact = ExactPass(SPEEDS)
    q = "crank-rail quasi-static"
    # settings 10..12: 10 passes, 11 is beyond at its second speed, 12 at its first
    written, curve = exact.hold("four-bar", *_chunk([10, 11, 12], ["", "", "", q, q, ""]))
    assert list(written["setting"]) == [10, 10] and list(curve["rows"]) == [0]
    assert list(written["exact_dynamic"]) == [False, False]
    assert np.isnan(written["crank-rail_amplification"]).all()  # the column every row carries, null until settled
    written, curve = exact.hold("four-bar", *_chunk([13], [q, q]))
    assert written["setting"].size == 0 and curve["rows"].size == 0
    assert list(exact.settings("four-bar")) == [11, 12, 13] and exact.parts == {"four-bar": {"crank-rail"}}
    # the exact evaluation of 13 and 12 (another order, another chunk): values offset by 1000
    columns, curve = _chunk([13, 12], ["", "", "", ""], offset=1000.0)
    columns["crank-rail_amplification"] = columns.pop("crank-rail_amplification_estimate") + 7
    merged, merged_curve = exact.merged("four-bar", columns, curve)
    assert list(merged["setting"]) == [13, 13, 12, 12]
    assert list(merged["exact_dynamic"]) == [True, True, True, False]
    # beyond rows from the exact evaluation, the other row (12 at its second speed) as held
    assert list(merged["crank-rail_stress_MPa"]) == [1000.0, 1001.0, 1002.0, 5.0]
    assert list(merged["crank-rail_amplification_estimate"]) == [0.5, 1.5, 4.5, 5.5]  # the estimates, kept
    assert list(merged["crank-rail_amplification"][:3]) == [1007.5, 1008.5, 1009.5]  # the exact ones beside
    assert np.isnan(merged["crank-rail_amplification"][3])
    assert list(merged["safe_speed_Hz"]) == [1013.0, 1013.0, 1012.0, 1012.0]  # first speeds beyond: the exact's
    assert list(merged_curve["rows"]) == [0, 1] and list(merged_curve["torque_peak_Nm"][:, 0]) == [1013.0, 1012.0]
    columns, curve = _chunk([11], ["", ""], offset=2000.0)
    merged, merged_curve = exact.merged("four-bar", columns, curve)
    assert list(merged["exact_dynamic"]) == [False, True]
    assert list(merged["crank-rail_stress_MPa"]) == [2.0, 2001.0]  # the first speed's row as held
    assert list(merged["safe_speed_Hz"]) == [11.0, 11.0] and list(merged_curve["torque_peak_Nm"][:, 0]) == [11.0]


def test_a_table_written_out_of_order_reads_in_setting_order(tmp_path):
    """The held settings arrive last; the table is rewritten setting-major on closing,
    each setting's speeds in the order they came (a stable sort), in both formats."""
    from railcheck.sweep.table import TableWriter, read_table

    for fmt in ("parquet", "csv"):
        path = tmp_path / f"t.{fmt}"
        with TableWriter(path, fmt) as writer:
            writer.write({"setting": np.array([0, 0, 2, 2]), "speed_Hz": np.array([2.0, 1.0, 2.0, 1.0])})
            writer.write({"setting": np.array([1, 1]), "speed_Hz": np.array([2.0, 1.0])})
        rows = read_table(path).to_pydict()
        assert rows["setting"] == [0, 0, 1, 1, 2, 2] and rows["speed_Hz"] == [2.0, 1.0] * 3, fmt
