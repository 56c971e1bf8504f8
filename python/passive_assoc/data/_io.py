"""CSV and pandas plumbing shared by the columnar tables (:class:`MeasurementTable`,
:class:`TrackTable`): flat named columns in, flat named columns out.

Floats are written with ``repr``, the shortest string that parses back to the same double,
so a table survives a CSV round trip bit for bit.
"""

from __future__ import annotations

import csv
import os
import secrets
from collections.abc import Callable, Collection, Mapping
from pathlib import Path
from typing import Any

import numpy as np
from numpy.typing import NDArray

__all__ = [
    "PANDAS_HINT",
    "import_pandas",
    "is_numeric",
    "parse_column",
    "read_csv",
    "read_csv_text",
    "write_atomically",
    "write_csv",
    "zip_columns",
]

PANDAS_HINT = "pandas is required for this; install it with `pip install passive-assoc[pandas]`"


def write_csv(path: str | os.PathLike[str], columns: Mapping[str, NDArray[Any]]) -> None:
    """Write ``columns`` (equal lengths) as a CSV file with a header row."""
    names = list(columns)
    text = [[str(int(v)) if columns[n].dtype.kind == "i" else repr(float(v)) for v in columns[n]] for n in names]
    with open(path, "w", newline="", encoding="utf-8") as fh:
        writer = csv.writer(fh)
        writer.writerow(names)
        writer.writerows(zip(*text, strict=True))


def read_csv(path: str | os.PathLike[str], integer_columns: Collection[str]) -> dict[str, NDArray[Any]]:
    """Read a CSV file with a header row into named columns.

    Columns named in ``integer_columns`` become int64, every other column float64.

    Raises
    ------
    ValueError
        If the file is empty, a line has the wrong number of fields (``path: line L ...``) or
        a field is not a number (``<column>: line L has ... (file ...)``).
    """
    header, rows = read_csv_text(path)
    return {
        name: parse_column(path, name, column, name in integer_columns) for name, column in zip_columns(header, rows)
    }


def read_csv_text(path: str | os.PathLike[str]) -> tuple[list[str], list[list[str]]]:
    """The header (names stripped of surrounding spaces) and the rows of a CSV file, as text.

    Raises
    ------
    ValueError
        If the file is not readable CSV, is empty, or a line has the wrong number of fields.
    """
    # utf-8-sig: a file saved by Excel starts with a byte-order mark, which would otherwise
    # become part of the first column's name.
    with open(path, newline="", encoding="utf-8-sig") as fh:
        try:
            rows = list(csv.reader(fh))
        except csv.Error as err:  # e.g. a field over the csv module's size limit
            raise ValueError(f"path: {os.fspath(path)!r} is not a readable CSV file: {err}") from None
    if not rows:
        raise ValueError(f"path: {os.fspath(path)!r} is empty (no header row)")
    header, body = [name.strip() for name in rows[0]], rows[1:]
    for r, row in enumerate(body):
        if len(row) != len(header):
            raise ValueError(
                f"path: line {r + 2} has {len(row)} fields, header has {len(header)} (file {os.fspath(path)!r})"
            )
    return header, body


def zip_columns(header: list[str], rows: list[list[str]]) -> list[tuple[str, list[str]]]:
    """``(name, values)`` per column of :func:`read_csv_text`'s rows."""
    return [(name, [row[j] for row in rows]) for j, name in enumerate(header)]


def parse_column(path: str | os.PathLike[str], name: str, values: list[str], integer: bool) -> NDArray[Any]:
    """One column's text as int64 or float64 (surrounding spaces allowed), or a ValueError
    naming the column, the line and the file."""
    out = []
    for r, text in enumerate(values):
        try:
            value = int(text) if integer else float(text)
        except ValueError:
            kind = "an integer" if integer else "a number"
            raise ValueError(f"{name}: line {r + 2} has {text!r}, not {kind} (file {os.fspath(path)!r})") from None
        if integer and not _INT64_MIN <= value <= _INT64_MAX:  # NumPy's cast would raise a bare OverflowError
            raise ValueError(
                f"{name}: line {r + 2} has {text!r}, beyond the 64-bit integer range (file {os.fspath(path)!r})"
            )
        out.append(value)
    return np.array(out, dtype=np.int64 if integer else np.float64)


_INT64_MIN, _INT64_MAX = -(2**63), 2**63 - 1


def is_numeric(values: list[str]) -> bool:
    """Whether every value of a text column parses as a number (an empty column does)."""
    try:
        for text in values:
            float(text)
    except ValueError:
        return False
    return True


def write_atomically(path: Path, write: Callable[[Path], None]) -> None:
    """``write(temporary path)`` then rename over ``path``: a failure leaves no half file. The
    file gets the permissions ``open(path, "w")`` gives a new file, 0666 less the umask (not
    the 0600 of :func:`tempfile.mkstemp`)."""
    path.parent.mkdir(parents=True, exist_ok=True)
    temporary = _new_temporary(path)
    try:
        write(temporary)
        os.replace(temporary, path)
    except BaseException:
        temporary.unlink(missing_ok=True)
        raise


def _new_temporary(path: Path) -> Path:
    """A new empty file beside ``path``: same folder (so the rename is atomic), same suffix
    (matplotlib reads the format off it), created exclusively with mode 0666 so that the
    umask applies as to any new file; the writers reopen it, which keeps the mode."""
    for _ in range(100):
        temporary = path.with_name(f".{path.stem}.{secrets.token_hex(4)}{path.suffix}")
        try:
            os.close(os.open(temporary, os.O_WRONLY | os.O_CREAT | os.O_EXCL, 0o666))
        except FileExistsError:
            continue
        return temporary
    raise FileExistsError(f"no free temporary name beside {str(path)!r}")


def import_pandas() -> Any:
    """The pandas module, or an ImportError that says how to install it (it is optional)."""
    try:
        import pandas as pd
    except ImportError as exc:
        raise ImportError(PANDAS_HINT) from exc
    return pd
