"""The combined radar/ESM decision (the project's extension of METHODS §5; docs/methods.md §5):
the wavelet coarse gate on the tracks' histories, then the weighted χ² test on their whole
current states.

The two published stages see different things. The coarse gate compares the position
*sequences* over a window (a pair that was apart earlier fails it, however alike now); the
weighted χ² statistic ``dᵀ(P_i + P_j)⁻¹d`` over position, velocity and acceleration is the
likelihood-ratio test of the current states, and it ranks pairs by all of them, position
included, where the fuzzy factors read only velocity, acceleration and heading. So: a pair
must pass the coarse gate (at a looser probability than the wavelet-fuzzy method's, 0.9999,
so that it vetoes only pairs the history rules out, and costs the χ² test no true pair) and the
χ² gate (0.9999), and among the pairs that do, the one-to-one decision takes them by increasing
statistic (repeated minimum, as :class:`~passive_assoc.radar_esm.Chi2TrackAssociator`). On the
paper's scene it is at or above the better of the two published stages' methods at every scan
(docs/experiments.md, wavelet).
"""

from __future__ import annotations

from dataclasses import dataclass
from typing import Annotated, Literal

import numpy as np
from numpy.typing import NDArray
from scipy.stats import chi2

from .._params import COUNT, Configurable, Interval, Options, Threads
from .._progress import ProgressArg, reporting
from ..data import TrackTable
from .baselines import chi2_statistic
from .coarse import MODES, approximation_operator
from .decision import repeated_maximum
from .scan_gate import WINDOW_CAP, coarse_by_scan
from .scans import RadarEsmAssociation, all_unpaired, association, position_distance
from .sides import prepare

__all__ = ["WaveletChi2Associator"]

#: A probability in (0, 1).
Probability = Annotated[float, Interval(float, 0.0, 1.0, closed="neither")]


@dataclass(frozen=True)
class WaveletChi2Associator(Configurable):
    """The wavelet coarse gate, then the weighted χ² test on the whole state (module docs).

    Parameters
    ----------
    wavelet, level, mode, window
        The coarse gate's, as :class:`~passive_assoc.WaveletFuzzyAssociator`'s.
    gate_probability : float
        The coarse gate's probability.
    chi2_probability : float
        The χ² gate's: pairs with a statistic above ``χ²(dof, chi2_probability)`` are never
        made (dof: 3·ndim for position, velocity and acceleration).
    process_noise : float or "auto", optional
        As :class:`~passive_assoc.WaveletFuzzyAssociator`'s.
    n_threads : int, optional
        Threads; results are identical for any value.
    """

    wavelet: str = "sym2"
    level: Annotated[int, COUNT] = 3
    mode: Annotated[str, Options(*MODES)] = "symmetric"
    window: Annotated[int | None, COUNT, None] = None
    gate_probability: Probability = 0.9999
    chi2_probability: Probability = 0.9999
    process_noise: Annotated[float | Literal["auto"] | None, Options("auto"), Interval(float, 0.0, None), None] = "auto"
    n_threads: Threads = None

    #: The coarse gate reads these as the wavelet-fuzzy method's (the whitened statistic).
    whitened = True

    def __post_init__(self) -> None:
        super().__post_init__()
        approximation_operator(self.window or WINDOW_CAP, self.wavelet, self.level, self.mode)

    def associate(self, *, local: TrackTable, system: TrackTable, progress: ProgressArg = None) -> RadarEsmAssociation:
        """Associate every scan: ``local`` the ESM's tracks or reports, ``system`` the radar's
        (as :meth:`WaveletFuzzyAssociator.associate`). A pair's score is minus its χ²
        statistic; the result's candidates are the pairs both gates passed. ``progress``:
        stages ``"coarse"`` and ``"fine"``."""
        sides = prepare(local, system, self.process_noise, self.n_threads)
        times, r, e = sides.times, sides.radar, sides.esm
        if (trivial := all_unpaired(times, r, e)) is not None:
            return trivial
        with reporting(progress) as report:
            passed: NDArray[np.bool_] = coarse_by_scan(self, sides.coarse_radar, sides.coarse_esm, times, sides.sigma)
            if report is not None:
                report("coarse", 1.0)
            statistic = chi2_statistic(r, e, 3)
            allowed = passed & (statistic <= chi2.ppf(self.chi2_probability, 3 * r.ndim))
            pairs = repeated_maximum(-statistic, allowed, -np.inf, position_distance(r, e), self.n_threads)
            if report is not None:
                report("fine", 1.0)
        return association(times, r, e, pairs, -statistic, candidates=allowed)
