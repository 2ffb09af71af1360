"""The results table of a batch: a CSV journal appended row by row, and JSON/Parquet at the end.

Every finished plan is appended to the CSV at once and flushed to disk, so an interrupted batch
keeps every row it finished; a re-run reads the CSV back and skips the keys it holds. A last line
cut short by the interruption is dropped (and its plan re-run). The JSON table (and Parquet, when
``pyarrow`` is installed) is written atomically from the CSV when the batch ends, in sweep order.
"""

from __future__ import annotations

import csv
import io
import json
import os
from collections.abc import Iterable, Sequence
from pathlib import Path
from typing import IO, Any

from trcopt.codes import Code
from trcopt.errors import ConfigError
from trcopt.io.atomic import OutputError, write_bytes_atomic, write_text_atomic

__all__ = ["COLUMNS", "ResultsTable", "read_rows", "write_json", "write_parquet"]

COLUMNS = (
    "key", "program", "options", "ok", "exit_status", "alarms", "first_alarm", "warnings",
    "cycle_time_s", "path_length_mm", "max_deviation_mm", "wall_time_s", "error",
)
_INT = {"exit_status", "alarms", "warnings"}
_FLOAT = {"cycle_time_s", "path_length_mm", "max_deviation_mm", "wall_time_s"}


def _cell(value: Any) -> str:
    if value is None:
        return ""
    if isinstance(value, bool):
        return "true" if value else "false"
    return str(value)


def _typed(row: dict[str, str]) -> dict[str, Any]:
    """A CSV row with its numbers and flags as values (empty cells None)."""
    out: dict[str, Any] = {}
    for k in COLUMNS:
        text = row.get(k, "")
        if k == "ok":
            out[k] = text == "true"
        elif k in _INT:
            out[k] = int(text) if text else None
        elif k in _FLOAT:
            out[k] = float(text) if text else None
        elif k in ("first_alarm",):
            out[k] = text or None
        else:
            out[k] = text
    return out


def read_rows(path: str | os.PathLike[str]) -> list[dict[str, Any]]:
    """The complete rows of a results CSV (a last line cut short is left out).

    Raises
    ------
    ConfigError
        The file is not a results table of this version (its header differs).
    """
    text = Path(path).read_text(encoding="utf-8")
    if not text:
        return []
    complete = text if text.endswith("\n") else text[: text.rfind("\n") + 1]
    reader = csv.reader(io.StringIO(complete, newline=""))
    header = next(reader, None)
    if header is None:
        return []
    if tuple(header) != COLUMNS:
        raise ConfigError(f"{path}: not a trcopt batch results table (columns {', '.join(header[:4])}…)")
    rows = []
    for cells in reader:
        if len(cells) != len(COLUMNS):
            continue  # a torn row: its plan runs again
        rows.append(_typed(dict(zip(COLUMNS, cells, strict=True))))
    return rows


class ResultsTable:
    """The CSV journal: rows already there, and :meth:`append` for each finished plan."""

    def __init__(self, path: str | os.PathLike[str], *, fresh: bool = False) -> None:
        self.path = Path(path)
        self.rows: list[dict[str, Any]] = []
        if self.path.is_dir():
            raise OutputError(f"{self.path} is a directory (the results table is a file)", self.path)
        if self.path.exists() and not fresh:
            self.rows = read_rows(self.path)
        self._fh: IO[str] | None = None

    @property
    def keys(self) -> set[str]:
        return {r["key"] for r in self.rows}

    def open(self) -> ResultsTable:
        """Start appending: the table is rewritten with its complete rows (dropping a torn last
        line) and kept open."""
        try:
            self.path.parent.mkdir(parents=True, exist_ok=True)
            buf = io.StringIO(newline="")
            w = csv.writer(buf, lineterminator="\n")
            w.writerow(COLUMNS)
            for row in self.rows:
                w.writerow([_cell(row.get(k)) for k in COLUMNS])
            write_text_atomic(self.path, buf.getvalue())
            self._fh = open(self.path, "a", encoding="utf-8", newline="")  # noqa: SIM115 (closed in close())
        except OSError as exc:
            raise OutputError(f"cannot write {self.path}: {exc.strerror or exc}", self.path, Code.OUTPUT) from exc
        return self

    def append(self, row: dict[str, Any]) -> None:
        """Add a finished row and flush it to disk."""
        assert self._fh is not None, "open() first"
        buf = io.StringIO(newline="")
        csv.writer(buf, lineterminator="\n").writerow([_cell(row.get(k)) for k in COLUMNS])
        self._fh.write(buf.getvalue())
        self._fh.flush()
        os.fsync(self._fh.fileno())
        self.rows.append(_typed({k: _cell(row.get(k)) for k in COLUMNS}))

    def close(self) -> None:
        if self._fh is not None:
            self._fh.close()
            self._fh = None

    def __enter__(self) -> ResultsTable:
        return self.open()

    def __exit__(self, *exc: object) -> None:
        self.close()

    def ordered(self, keys: Sequence[str]) -> list[dict[str, Any]]:
        """The rows in the order of ``keys`` (the sweep's), then any others the file holds."""
        by_key = {r["key"]: r for r in self.rows}
        first = [by_key[k] for k in keys if k in by_key]
        return first + [r for r in self.rows if r["key"] not in set(keys)]


def write_json(path: str | os.PathLike[str], rows: Iterable[dict[str, Any]]) -> None:
    """The table as a JSON array of row objects (schema ``trcopt.batch/1``), written atomically."""
    doc = {"schema": "trcopt.batch/1", "columns": list(COLUMNS), "rows": list(rows)}
    write_text_atomic(path, json.dumps(doc, indent=1, allow_nan=False) + "\n")


def parquet_available() -> bool:
    try:
        import pyarrow  # noqa: F401
    except ImportError:
        return False
    return True


def write_parquet(path: str | os.PathLike[str], rows: Iterable[dict[str, Any]]) -> None:
    """The table as Parquet (needs ``pyarrow``), written atomically."""
    import pyarrow as pa
    import pyarrow.parquet as pq

    rows = list(rows)
    table = pa.Table.from_pylist(rows, schema=None) if rows else pa.table({k: [] for k in COLUMNS})
    sink = pa.BufferOutputStream()
    pq.write_table(table, sink)
    write_bytes_atomic(path, sink.getvalue().to_pybytes())
