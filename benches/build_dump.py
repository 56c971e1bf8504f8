"""One build's results written to a file and compared, entry by entry, with another build's:
the step the identity benches (``initiation_identity.py``, ``enumeration_identity.py``) share.
"""

from __future__ import annotations

import pickle
from collections.abc import Callable
from typing import Any


def dump_and_compare(
    mine: list[Any],
    out: str | None,
    against: str | None,
    what: str,
    compared: str,
    key: Callable[[Any], Any] = lambda entry: entry,
) -> None:
    """Writes ``mine`` to ``out`` and compares it with the dump at ``against`` (each when
    given), printing how many of the ``what`` differ in ``compared`` and the first of them.
    The entries are compared through ``key`` (by default as they are)."""
    if out:
        with open(out, "wb") as f:
            pickle.dump(mine, f)
        print(f"written to {out}")
    if against:
        with open(against, "rb") as f:
            theirs = pickle.load(f)
        differ = [k for k, (a, b) in enumerate(zip(theirs, mine, strict=True)) if key(a) != key(b)]
        print(f"{len(mine)} {what}: {len(differ)} differ ({compared}) {differ[:10]}")
