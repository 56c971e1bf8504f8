"""Regrouping (a project extension, 3-D; docs/methods.md §1, *Regrouping*): each track's
measurements initiated again together with the free measurements whose lines of sight meet
theirs, and the track replaced by the tracks found there when their summed score beats its
own.

Where many targets share the sky of three sensors, a third sensor's rays confirm ghosts as
well as targets: a ghost track can hold one sensor's rows of a target and other sensors'
rows of other targets, with a score like a target's. Accepted first, it leaves those
targets' remaining rows free, and no later pass can rebuild them. Started from the ghost's
own rows and the free rows that meet them, the initiation finds the targets again: the rows
of a target the ghost holds at one sensor meet that target's free rows at the others.

For each track in turn (in the pipeline's order), the neighbourhood is every free row of
another sensor, from the two of its scans around the track row's time, whose line of sight
meets the track row's within the ray gate (``ray_gate_sigmas`` standard deviations of the
crossing plus ``v_max`` times the time between them, as in the candidate formation) in front
of both sensors. The initiation on the track's rows and that neighbourhood (the same
settings, without the sweep: the track's rows start the rounds) gives tracks. Those holding
any of the track's rows replace it when their summed score, at the clutter densities of the
first result (:class:`~.score.ScoreTerms`), exceeds the track's by more than :data:`MARGIN`
plus what the free rows they take are worth on their own: the summed score of the tracks
that take those rows in the initiation on the neighbourhood alone. Without that second term
two tracks each mixing two targets could replace one target's track, the other target's
rows having been free. The track's rows the new tracks leave become free. Later passes
(:func:`regroup`) look again at the tracks whose rows meet rows freed since.
"""

from __future__ import annotations

from collections.abc import Callable
from dataclasses import dataclass
from typing import TYPE_CHECKING

import numpy as np
from numpy.typing import NDArray

from .. import _core
from ..data import MeasurementTable, SensorNetwork
from .score import ScoreTerms

if TYPE_CHECKING:
    from .._core import InitiationOutput

#: How much more (natural log) the replacing tracks' summed score must be than the track's:
#: a margin over a refit's noise. Measured with 5 (docs/methods.md §1, *Regrouping*).
MARGIN = 5.0

#: Passes over the tracks at most (:func:`regroup`). On the scaling bench's 3 × 100 scenes
#: (seeds 0 and 1) no pass after the third replaced a track (CHANGELOG.md).
MAX_PASSES = 4


@dataclass
class Found:
    """Tracks as the core returns them: ``labels`` (track per row, -1 free) and per track its
    state, covariance, closeness and fit χ². A replaced track keeps its index with no rows
    (``alive`` False) until :meth:`compact`."""

    labels: NDArray[np.int64]
    states: list[NDArray[np.float64]]
    covariances: list[NDArray[np.float64]]
    closeness: list[float]
    chi2: list[float]
    alive: list[bool]

    @classmethod
    def of(cls, out: InitiationOutput) -> Found:
        """From the core's initiation result."""
        n = len(out.chi2)
        return cls(
            np.array(out.labels, dtype=np.int64),
            [np.asarray(out.estimates[k]) for k in range(n)],
            [np.asarray(out.covariances[k]) for k in range(n)],
            [float(x) for x in out.closeness],
            [float(x) for x in out.chi2],
            [True] * n,
        )

    def compact(self) -> Found:
        """The live tracks renumbered 0, 1, ... in their order."""
        keep = [k for k, a in enumerate(self.alive) if a]
        index = np.full(len(self.alive) + 1, -1, dtype=np.int64)
        index[keep] = np.arange(len(keep))
        return Found(
            index[self.labels],  # label -1 reads the last entry, -1
            [self.states[k] for k in keep],
            [self.covariances[k] for k in keep],
            [self.closeness[k] for k in keep],
            [self.chi2[k] for k in keep],
            [True] * len(keep),
        )


class Neighbourhood:
    """The free rows whose lines of sight meet a set of rows' (module doc), by the core's ray
    gate: the candidate formation's own test."""

    def __init__(
        self,
        measurements: MeasurementTable,
        sensors: SensorNetwork,
        gate_sigmas: float | None,
        v_max: float | None,
    ) -> None:
        self._rays = _core.RayNeighbourhood(measurements, sensors, gate_sigmas, v_max)

    def of(self, rows: NDArray[np.int64], free: NDArray[np.bool_]) -> NDArray[np.int64]:
        """The free rows meeting any of ``rows``, ascending."""
        return self._rays.of(np.asarray(rows, dtype=np.int64), np.asarray(free, dtype=bool))


def regroup(
    found: Found,
    terms: ScoreTerms,
    neighbourhood: Neighbourhood,
    initiate: Callable[[NDArray[np.int64]], Found],
    report: Callable[[str, float], object] | None = None,
) -> tuple[Found, int]:
    """``found`` with each track replaced where the module doc's test says so, compacted, and
    how many were replaced. ``initiate(rows)`` runs the initiation on those rows of the table
    (ascending) and returns its tracks with labels over them.

    Up to :data:`MAX_PASSES` passes: the first looks at every track; each later one at the
    tracks with a row meeting a row freed since they were looked at or made (a replacement
    can free what another track's replacement needed). Every replacement raises the summed
    score of the partition by more than :data:`MARGIN`, so the passes cannot undo one
    another."""
    replaced, step = 0, 0
    # The step at which each row was last freed, and at which each track was looked at.
    stamp = np.zeros(len(found.labels), dtype=np.int64)
    seen: list[int | None] = [None] * len(found.alive)
    for n_pass in range(MAX_PASSES):
        todo = [k for k in range(len(found.alive)) if found.alive[k] and _stale(k, found, seen, stamp, neighbourhood)]
        if not todo:
            break
        for done, k in enumerate(todo):
            if report is not None:
                report("regroup", 1.0 - 0.5**n_pass * (1.0 - 0.5 * done / len(todo)))
            if not found.alive[k]:
                continue
            step += 1
            seen[k] = step
            own = np.flatnonzero(found.labels == k)
            taken = _replacement(k, own, found, terms, neighbourhood, initiate)
            if taken is None:
                continue
            replaced += 1
            local, held = taken
            found.labels[own] = -1
            found.alive[k] = False
            for j, mine in held.items():
                found.labels[mine] = len(found.alive)
                found.states.append(local.states[j])
                found.covariances.append(local.covariances[j])
                found.closeness.append(local.closeness[j])
                found.chi2.append(local.chi2[j])
                found.alive.append(True)
                seen.append(step)  # made from what the initiation saw at this step
            # The rows of the track that no new track took are free again.
            stamp[own[found.labels[own] < 0]] = step
    if report is not None:
        report("regroup", 1.0)
    return found.compact(), replaced


def _stale(k: int, found: Found, seen: list[int | None], stamp: NDArray[np.int64], near: Neighbourhood) -> bool:
    """Whether track ``k`` is to be looked at (again): never looked at, or a row meeting one
    of its rows was freed since it was looked at or made."""
    last = seen[k]
    if last is None:
        return True
    changed = stamp > last
    return bool(changed.any()) and len(near.of(np.flatnonzero(found.labels == k), changed)) > 0


def _replacement(
    k: int,
    own: NDArray[np.int64],
    found: Found,
    terms: ScoreTerms,
    neighbourhood: Neighbourhood,
    initiate: Callable[[NDArray[np.int64]], Found],
) -> tuple[Found, dict[int, NDArray[np.int64]]] | None:
    """The initiation around track ``k`` (rows ``own``) and its tracks that replace it, each
    with the table's rows it holds, or None when they do not (module doc)."""
    if not len(own):
        return None
    free = found.labels < 0
    rows = np.union1d(own, neighbourhood.of(own, free))
    local = initiate(rows)
    mine = found.labels[rows] == k
    held = {j: rows[local.labels == j] for j in range(len(local.alive)) if np.any(mine & (local.labels == j))}
    if not held:
        return None
    gain = sum(terms.score(held_j, local.chi2[j]) for j, held_j in held.items())
    gain -= terms.score(own, found.chi2[k])
    if gain <= MARGIN:
        return None
    # The free rows they take may hold tracks of their own: what those score is lost (a track
    # scoring below 0 is worth less than its rows left free).
    taken = np.zeros(len(found.labels), dtype=bool)
    taken[np.concatenate(list(held.values()))] = True
    others = np.setdiff1d(rows, own)
    alone = initiate(others)
    lost = sum(
        max(terms.score(others[alone.labels == i], alone.chi2[i]), 0.0)
        for i in range(len(alone.alive))
        if np.any(taken[others[alone.labels == i]])
    )
    if gain - lost <= MARGIN:
        return None
    return local, held
