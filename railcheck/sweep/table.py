"""The sweep's tables on disk: rows streamed to Parquet (one row group per chunk) or CSV
under a temporary name and renamed at the end (:class:`TableWriter`), and read back in
batches (:func:`read_table`). pyarrow is imported inside the functions only."""

from __future__ import annotations

from pathlib import Path
from typing import Any

import numpy as np

__all__ = ["TableWriter", "read_table"]


class TableWriter:
    """Rows streamed to a Parquet file (one row group per chunk) or a CSV file, written
    under a temporary name and renamed at the end. NaN (not applicable) and infinity
    (unlimited: a safe speed no load limits, the fatigue factor of an unstressed part)
    become null, never "inf" or "nan"."""

    def __init__(self, path: Path, fmt: str):
        self.path, self.fmt = Path(path), fmt
        self.tmp = self.path.with_name(f".{self.path.name}.part")
        self.writer: Any = None  # a pyarrow Parquet or CSV writer once the first rows arrive
        self.rows = 0
        self.last_setting = -1  # the largest setting written so far
        self.out_of_order = False  # a chunk came after a later setting's (the exact pass's, held back)

    def __enter__(self):
        return self

    def write(self, columns: dict) -> None:
        import pyarrow as pa

        table = pa.table({k: _arrow(v) for k, v in columns.items()})
        if self.writer is None:
            if self.fmt == "parquet":
                import pyarrow.parquet as pq

                self.writer = pq.ParquetWriter(self.tmp, table.schema, compression="zstd")
            else:
                import pyarrow.csv as pcsv

                self.writer = pcsv.CSVWriter(self.tmp, table.schema)
        self.writer.write_table(table)
        self.rows += table.num_rows
        if "setting" in columns and len(columns["setting"]):
            settings = np.asarray(columns["setting"])
            self.out_of_order |= bool(settings.min() < self.last_setting)
            self.last_setting = max(self.last_setting, int(settings.max()))

    def __exit__(self, exc_type, exc, tb):
        if self.writer is not None:
            self.writer.close()
        if exc_type is None and self.writer is not None:
            if self.out_of_order:
                self._sort_by_setting()
            self.tmp.replace(self.path)
        else:
            self.tmp.unlink(missing_ok=True)
        return False

    def _sort_by_setting(self) -> None:
        """Rewrite the written rows in setting order, each setting's speeds as they came
        (a stable sort): the table reads setting-major, whatever order the chunks came in."""
        import pyarrow.compute as pc
        import pyarrow.csv as pcsv
        import pyarrow.parquet as pq

        if self.fmt == "parquet":
            table = pq.read_table(self.tmp)
        else:
            table = pcsv.read_csv(self.tmp, convert_options=pcsv.ConvertOptions(strings_can_be_null=True))
        table = table.take(pc.sort_indices(table, sort_keys=[("setting", "ascending")]))
        sorted_tmp = self.tmp.with_name(self.tmp.name + ".sorted")
        if self.fmt == "parquet":
            pq.write_table(table, sorted_tmp, compression="zstd")
        else:
            pcsv.write_csv(table, sorted_tmp)
        sorted_tmp.replace(self.tmp)


def _arrow(values: np.ndarray):
    import pyarrow as pa

    if values.dtype == object:  # text; empty (nothing to name) is null
        return pa.array([v or None for v in values.tolist()], type=pa.string())
    if values.dtype.kind == "f":  # no number for infinity in data: null (a flag column says "unlimited")
        return pa.array(values, mask=~np.isfinite(values))
    return pa.array(values)


def read_table(path: Path, columns: list[str] | None = None, speed_hz: float | None = None):
    """The sweep table (pyarrow.Table) of a Parquet or CSV file: ``columns`` only, and
    only the rows at ``speed_hz`` when given (scanned in batches: the whole table is
    never in memory)."""
    import pyarrow.csv as pcsv
    import pyarrow.dataset as ds

    path = Path(path)
    fmt = (
        "parquet"
        if path.suffix == ".parquet"
        else ds.CsvFileFormat(convert_options=pcsv.ConvertOptions(strings_can_be_null=True))
    )
    data = ds.dataset(path, format=fmt)
    where = None if speed_hz is None else (ds.field("speed_Hz") == speed_hz)
    return data.to_table(columns=columns, filter=where)
