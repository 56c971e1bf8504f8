"""Paper 004's published numbers (EXPERIMENTS ``formation``): Tables 2 and 3, the misprints
read as such, and the acceptance bar, for :mod:`.formation`."""

from __future__ import annotations

import numpy as np

__all__ = ["CELL_BAR", "MEAN_BAR", "MISPRINTS", "PAPER_TABLE2", "PAPER_TABLE3"]

#: Table 2 as printed (azimuth only), correct-association %, rows targets, columns σθ.
PAPER_TABLE2 = np.array(
    [
        [57.6, 46.3, 33.6, 27.6],
        [100.0, 54.4, 30.6, 20.0],
        [41.6, 24.5, 19.5, 13.9],
        [100.0, 58.5, 49.7, 42.5],
        [100.0, 86.1, 78.4, 64.0],
        [63.4, 17.2, 0.98, 0.92],
    ]
)
#: Table 3 as printed (azimuth and attributes).
PAPER_TABLE3 = np.array(
    [
        [100.0, 89.8, 70.8, 54.9],
        [100.0, 100.0, 100.0, 100.0],
        [100.0, 100.0, 96.6, 90.1],
        [100.0, 75.2, 68.6, 63.6],
        [100.0, 100.0, 90.6, 73.8],
        [100.0, 95.2, 78.6, 63.7],
    ]
)
#: Target 6's Table 2 cells at 1.5° and 2°: 0.98 % and 0.92 % of 1000 runs are not whole runs,
#: so they are read as misprints of 9.8 % and 9.2 % and judged against those (EXPERIMENTS).
MISPRINTS = {(5, 2): 9.8, (5, 3): 9.2}
#: The paper's bar: every cell within this many points, and the mean |difference| per table.
CELL_BAR, MEAN_BAR = 4.0, 2.5
