"""CSV and pandas plumbing shared by the columnar tables (:class:`MeasurementTable`,
:class:`TrackTable`): flat named columns in, flat named columns out.

Floats are written with ``repr``, the shortest string that parses back to the same double,
so a table survives a CSV round trip bit for bit.
"""

from __future__ import annotations

import csv
import os
from collections.abc import Collection, Mapping
from typing import Any

import numpy as np
from numpy.typing import NDArray

__all__ = ["PANDAS_HINT", "import_pandas", "read_csv", "write_csv"]

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
        a field is not a number (``<column>: line L has ...``).
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
            raise ValueError(f"path: line {r + 2} has {len(row)} fields, header has {len(header)}")
    columns: dict[str, NDArray[Any]] = {}
    for j, name in enumerate(header):
        integer = name in integer_columns
        values = []
        for r, row in enumerate(body):
            try:
                values.append(int(row[j]) if integer else float(row[j]))
            except ValueError:
                raise ValueError(
                    f"{name}: line {r + 2} has {row[j]!r}, not {'an integer' if integer else 'a number'}"
                ) from None
        columns[name] = np.array(values, dtype=np.int64 if integer else np.float64)
    return columns


def import_pandas() -> Any:
    """The pandas module, or an ImportError that says how to install it (it is optional)."""
    try:
        import pandas as pd
    except ImportError as exc:
        raise ImportError(PANDAS_HINT) from exc
    return pd
