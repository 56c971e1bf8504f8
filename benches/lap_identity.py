"""Whether two builds' ``linear_assignment`` agree: dumps the answers (the total, the columns,
or the error) on 700 fixed random matrices, then compares with another build's dump. 400 are
mixed (rectangular, tie-heavy, some with a third of their pairs forbidden), 300 hold 30–85 %
forbidden pairs, square and not. A change that claims the same answers is checked this way;
one that may pick another optimum among ties compares the totals alone (``--totals``, against
any dump).

    PYTHONPATH=<old package> python3 benches/lap_identity.py --out old.pkl
    python3 benches/lap_identity.py --against old.pkl [--totals]
"""

from __future__ import annotations

import argparse
from typing import Any

import numpy as np
import passive_assoc as pa
from build_dump import dump_and_compare


def matrices() -> list[np.ndarray]:
    out = []
    rng = np.random.default_rng(5)
    for k in range(400):
        nr, nc = rng.integers(1, 120, 2)
        c = rng.random((nr, nc))
        if k % 3 == 0:
            c = np.round(c * 4)  # ties
        if k % 4 == 1:
            c[rng.random((nr, nc)) < 0.3] = np.inf
        out.append(c)
    rng = np.random.default_rng(9)
    for k in range(300):
        n = int(rng.integers(2, 150))
        m = n if k % 2 else int(rng.integers(2, 150))
        c = rng.random((n, m))
        if k % 3 == 0:
            c = np.round(c * 4)
        c[rng.random((n, m)) < [0.3, 0.6, 0.85][k % 3]] = np.inf
        out.append(c)
    return out


def answers() -> list[Any]:
    out: list[Any] = []
    for c in matrices():
        try:
            rows, cols, total = pa.linear_assignment(c)
            out.append((total, rows.tolist(), cols.tolist()))
        except ValueError as e:
            out.append(("error", str(e)))
    return out


def total_or_error(entry: Any) -> Any:
    """An answer's total, or its error (a bare total is a dump of ``--totals`` before it
    kept the assignments)."""
    if isinstance(entry, tuple) and entry[0] != "error":
        return entry[0]
    return entry


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--out", help="write this build's answers here")
    parser.add_argument("--against", help="compare this build's answers with a dump")
    parser.add_argument("--totals", action="store_true", help="compare the totals and errors only")
    args = parser.parse_args()
    what = "totals or errors" if args.totals else "totals, assignments or errors"
    key = total_or_error if args.totals else (lambda entry: entry)
    dump_and_compare(answers(), args.out, args.against, "matrices", what, key)


if __name__ == "__main__":
    main()
