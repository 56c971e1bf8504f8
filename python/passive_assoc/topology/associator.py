"""Track-to-track association under azimuth bias by reference topology (METHODS §4, paper 002).

Radars with unknown azimuth biases of several degrees report local tracks whose absolute
positions disagree by kilometres, so distance-based association collapses — but the layout
of each track's neighbours survives a rotation. Around every track a disc of radius
``radius`` is cut into ``rings`` × ``sectors`` cells; occupied cells (other tracks of the same
source) spread into their neighbours (``delta`` along a sector, ``delta_prime`` along a ring);
the fuzzy closeness W of two such vectors (eq. 3) scores a (local, system) pair; W averaged
over the last ``window`` scans decides one-to-one pairs above ``threshold``·M·N. The core
(``rust/core/src/topology``) does all of it with the GIL released.
"""

from __future__ import annotations

from dataclasses import dataclass, replace
from typing import Annotated, Literal

import numpy as np
from numpy.typing import NDArray

from .. import _core
from .._params import COUNT, POSITIVE, Boolean, Configurable, Interval, Options, Threads
from .._progress import ProgressArg
from .._settings import TopologySettings
from ..data import TrackTable
from ..track_association import BiasEstimate, StreamingTrackAssociator, TrackAssociation

__all__ = ["TopologyAssociator", "topology_vectors"]

#: A number in [0, 1].
Unit = Annotated[float, Interval(float, 0.0, 1.0)]


@dataclass(eq=False)
class TopologyAssociator(StreamingTrackAssociator, Configurable):
    """Reference-topology track-to-track associator (METHODS §4).

    Parameters
    ----------
    rings, sectors : int
        M rings of equal width × N sectors of equal angle. Choose N so that a sector is wider
        than the largest relative bias (12 sectors of 30° for radars within ±5°).
    radius : float
        R_ref, metres: the disc around each track in which neighbours count.
    delta, delta_prime : float
        Diffusion to ring ± 1 (random error) and to sector ± 1 (error and bias), in [0, 1];
        the paper wants ``delta_prime >= delta``.
    threshold : float
        λ as a fraction of M·N: a pair needs a window-averaged closeness above λ·M·N. The
        default 0.7 is the largest value that costs no recall on the paper's full-coverage
        scenes at ±5° bias (docs/experiments.md has the sensitivity table); a higher λ leaves
        more tracks unpaired, which helps only where some targets have no partner.
    window : int
        Scans over which W is averaged, the current one included; decisions are re-made
        every scan, so a wrong pairing is undone.
    gate : float, optional
        A position gate in metres combined with topology (pairs farther apart are never
        made); it resolves formations whose slots look alike. Default: none.
    heading_reference : bool
        Start each grid at the track's heading instead of north: a rotation of the whole
        picture then changes no vector. Needs velocities.
    diffusion : {"additive", "at_least"}
        Additive spread clipped at 1 (default), or the "at least Δ" reading.
    decision : {"assignment", "per_system_track"}
        One-to-one pairs maximising the total closeness above λ (default), or the paper's
        rule: each system track takes its best local track above λ.
    correct_bias : bool
        Associate twice: the second pass turns each local picture back by its estimated bias
        (rigid fit) before scoring (the position gate, and a north-referenced grid, then see
        unbiased positions).
    n_threads : int, optional
        Threads; results are identical for any value.
    """

    rings: Annotated[int, COUNT] = 4
    sectors: Annotated[int, COUNT] = 12
    radius: Annotated[float, POSITIVE] = 120e3
    delta: Unit = 0.5
    delta_prime: Unit = 0.7
    threshold: Unit = 0.7
    window: Annotated[int, COUNT] = 6
    gate: Annotated[float | None, POSITIVE, None] = None
    heading_reference: Annotated[bool, Boolean()] = False
    diffusion: Annotated[Literal["additive", "at_least"], Options("additive", "at_least")] = "additive"
    decision: Annotated[Literal["assignment", "per_system_track"], Options("assignment", "per_system_track")] = (
        "assignment"
    )
    correct_bias: Annotated[bool, Boolean()] = False
    n_threads: Threads = None

    def _settings(self, local: TrackTable | None = None, system: TrackTable | None = None) -> TopologySettings:
        c = self
        return TopologySettings(
            scoring="topology",
            rings=c.rings,
            sectors=c.sectors,
            radius=c.radius,
            delta=c.delta,
            delta_prime=c.delta_prime,
            diffusion=c.diffusion,
            reference="heading" if c.heading_reference else "north",
            threshold=c.threshold * c.rings * c.sectors,
            window=c.window,
            gate=c.gate,
            chi2_gate=None,
            decision=c.decision,
            n_threads=c.n_threads,
        )

    def associate(self, *, local: TrackTable, system: TrackTable, progress: ProgressArg = None) -> TrackAssociation:
        """Associate every scan of ``local`` with the system tracks of the same time (see
        :class:`~passive_assoc.track_association.StreamingTrackAssociator`); with
        ``correct_bias``, twice."""
        first = super().associate(local=local, system=system, progress=progress)
        if not self.correct_bias:
            return first
        corrected = unbias(local, first.bias)
        second = super().associate(local=corrected, system=system, progress=progress)
        # The bias reported is the first pass's: the second sees corrected pictures.
        return replace(second, bias=first.bias)


def unbias(local: TrackTable, bias: dict[int, BiasEstimate]) -> TrackTable:
    """``local`` with each source's picture turned back by its bias: ``q = R(−θ)(p − t)``
    (velocities rotated too; covariances dropped, since the associators do not read them);
    sources without an estimate are left as they are."""
    position = np.array(local.position, dtype=np.float64)
    velocity = None if local.velocity is None else np.array(local.velocity, dtype=np.float64)
    for source, b in bias.items():
        rows = local.source == source
        c, s = np.cos(-b.rotation), np.sin(-b.rotation)
        turn = np.array([[c, -s], [s, c]])
        position[rows, :2] = (position[rows, :2] - np.asarray(b.translation)) @ turn.T
        if velocity is not None:
            velocity[rows, :2] = velocity[rows, :2] @ turn.T
    return TrackTable.from_arrays(
        local.source,
        local.track,
        local.time,
        position,
        velocity=velocity,
        acceleration=local.acceleration,
        truth=local.truth,
    )


def topology_vectors(tracks: TrackTable, associator: TopologyAssociator | None = None) -> NDArray[np.float64]:
    """The topology vector of every track of one scan of one source, ``(n, rings·sectors)``
    row-major (rings are rows), with ``associator``'s grid (default settings if None)."""
    if not isinstance(tracks, TrackTable):
        raise TypeError(f"tracks: expected a TrackTable, got {type(tracks).__name__}")
    associator = associator or TopologyAssociator()
    if associator.heading_reference and tracks.velocity is None:
        raise ValueError("tracks: the heading-referenced grid needs velocities, and the table has none")
    settings = associator._settings()
    ids = np.ascontiguousarray(tracks.track, dtype=np.int64)
    positions = np.ascontiguousarray(tracks.position[:, :2], dtype=np.float64)
    velocity = None if tracks.velocity is None else np.ascontiguousarray(tracks.velocity[:, :2], dtype=np.float64)
    return _core.topology_vectors((ids, positions, velocity, None, None), settings)
