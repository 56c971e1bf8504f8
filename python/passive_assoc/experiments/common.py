"""Plumbing shared by the paper reproductions: per-run seeds, a progress bar over runs that
may execute on several worker threads, and JSON output."""

from __future__ import annotations

import argparse
import json
import math
import sys
from collections.abc import Callable, Iterable
from concurrent.futures import ThreadPoolExecutor
from pathlib import Path
from typing import Any, TypeVar

import numpy as np
from tqdm import tqdm

from ..distributed import current_client, map_on_client

R = TypeVar("R")


def int_at_least(minimum: int) -> Callable[[str], int]:
    """argparse type: an integer ≥ ``minimum``, so ``--workers 0`` or ``--window 3`` is a usage
    error naming the option rather than a traceback or a silent fallback. The returned
    function carries ``minimum`` (the CLI's option test reads it)."""

    def parse(text: str) -> int:
        try:
            value = int(text)
        except ValueError:
            raise argparse.ArgumentTypeError(f"expected an integer >= {minimum}, got {text!r}") from None
        if value < minimum:
            raise argparse.ArgumentTypeError(f"expected an integer >= {minimum}, got {value}")
        return value

    parse.minimum = minimum  # type: ignore[attr-defined]
    parse.__name__ = f"integer >= {minimum}"
    return parse


#: argparse type: an integer ≥ 1 (``--runs``, ``--workers``).
positive_int = int_at_least(1)
#: argparse type: an integer ≥ 0 (counts that may be zero: ``--demo-runs``, ``--clutter``).
nonnegative_int = int_at_least(0)


def finite_float(text: str) -> float:
    """argparse type: a finite number (``inf``, ``nan`` and ``1e400`` are usage errors, not
    tracebacks from deep inside a run)."""
    try:
        value = float(text)
    except ValueError:
        raise argparse.ArgumentTypeError(f"expected a number, got {text!r}") from None
    if not math.isfinite(value):
        raise argparse.ArgumentTypeError(f"expected a finite number, got {text!r}")
    return value


#: argparse type: a seed NumPy accepts, an integer ≥ 0.
seed_int = int_at_least(0)


def output_file(text: str) -> str:
    """argparse type: a file to write, non-empty, in a directory that exists (checked before a
    long run, not after it)."""
    if not text.strip():
        raise argparse.ArgumentTypeError("expected a file name, got an empty string")
    parent = Path(text).expanduser().resolve().parent
    if not parent.is_dir():
        raise argparse.ArgumentTypeError(f"the directory {str(parent)!r} does not exist")
    return text


def scheduler_address(text: str) -> str:
    """argparse type: a Dask scheduler address, or ``local``."""
    if not text.strip():
        raise argparse.ArgumentTypeError("expected a scheduler address (tcp://host:8786) or 'local'")
    return text.strip()


scheduler_address.bad_values = ["", "   "]  # type: ignore[attr-defined]


def run_seeds(seed: int, runs: int) -> list[np.random.SeedSequence]:
    """Independent, reproducible seed sequences for ``runs`` Monte-Carlo runs."""
    return np.random.SeedSequence(seed).spawn(runs)


def map_runs(work: Callable[[int], R], runs: int, workers: int, desc: str) -> list[R]:
    """``[work(r) for r in range(runs)]`` with a progress bar, on ``workers`` threads (or on
    the Dask cluster of :func:`passive_assoc.distributed.using`).

    The Rust core releases the GIL, so threads run runs in parallel; results come back in run
    order, so they do not depend on ``workers``.
    """
    bar = tqdm(total=runs, desc=desc, unit="run", file=sys.stderr, disable=None, leave=False)
    try:
        client = current_client()
        if client is not None:  # --scheduler: the runs go to a Dask cluster
            return map_on_client(client, work, runs, bar.update)
        if workers <= 1:
            out = []
            for r in range(runs):
                out.append(work(r))
                bar.update()
            return out
        with ThreadPoolExecutor(max_workers=workers) as pool:
            futures = [pool.submit(work, r) for r in range(runs)]
            results: list[R] = []
            for f in futures:
                results.append(f.result())
                bar.update()
            return results
    finally:
        bar.close()


def _jsonable(value: Any) -> Any:
    if isinstance(value, dict):
        return {str(k): _jsonable(v) for k, v in value.items()}
    if isinstance(value, list | tuple):
        return [_jsonable(v) for v in value]
    if isinstance(value, np.ndarray):
        return _jsonable(value.tolist())
    if isinstance(value, np.generic):
        return _jsonable(value.item())
    if isinstance(value, float) and not math.isfinite(value):
        return None
    return value


def write_json(path: str | Path, record: dict[str, Any]) -> None:
    """Write ``record`` as JSON (NumPy values converted, NaN as null)."""
    Path(path).write_text(json.dumps(_jsonable(record), indent=2) + "\n")


def fmt(value: float | None, digits: int = 3) -> str:
    """A number for a table cell, with a fixed number of significant digits."""
    if value is None or not math.isfinite(value):
        return "-"
    return f"{value:.{digits}g}"


def print_rows(rows: Iterable[Iterable[str]], widths: Iterable[int]) -> None:
    """Print right-aligned columns."""
    w = list(widths)
    for row in rows:
        print(" ".join(cell.rjust(width) for cell, width in zip(row, w, strict=True)))
