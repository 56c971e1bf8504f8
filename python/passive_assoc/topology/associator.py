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

from dataclasses import dataclass
from typing import ClassVar, Literal

import numpy as np
from numpy.typing import NDArray

from .. import _core
from .._params import Boolean, Constraint, Interval, Options, validate
from .._settings import TopologySettings
from ..assignment.tracks import BiasEstimate, TrackAssociation, TrackAssociator
from ..data import TrackTable

__all__ = ["TopologyAssociator", "topology_vectors"]

UNIT = Interval(float, 0.0, 1.0)


@dataclass(frozen=True, eq=False)
class _Config:
    rings: int
    sectors: int
    radius: float
    delta: float
    delta_prime: float
    threshold: float
    window: int
    gate: float | None
    heading_reference: bool
    diffusion: Literal["additive", "at_least"]
    decision: Literal["assignment", "per_system_track"]
    correct_bias: bool
    n_threads: int | None


class TopologyAssociator(TrackAssociator):
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

    _constraints: ClassVar[dict[str, list[Constraint]]] = {
        "rings": [Interval(int, 1, None)],
        "sectors": [Interval(int, 1, None)],
        "radius": [Interval(float, 0.0, None, closed="neither")],
        "delta": [UNIT],
        "delta_prime": [UNIT],
        "threshold": [UNIT],
        "window": [Interval(int, 1, None)],
        "gate": [Interval(float, 0.0, None, closed="neither"), None],
        "heading_reference": [Boolean()],
        "diffusion": [Options("additive", "at_least")],
        "decision": [Options("assignment", "per_system_track")],
        "correct_bias": [Boolean()],
        "n_threads": [Interval(int, 1, None), None],
    }

    def __init__(
        self,
        rings: int = 4,
        sectors: int = 12,
        radius: float = 120e3,
        delta: float = 0.5,
        delta_prime: float = 0.7,
        threshold: float = 0.7,
        window: int = 6,
        gate: float | None = None,
        heading_reference: bool = False,
        diffusion: Literal["additive", "at_least"] = "additive",
        decision: Literal["assignment", "per_system_track"] = "assignment",
        correct_bias: bool = False,
        n_threads: int | None = None,
    ) -> None:
        super().__init__()
        values = dict(
            rings=rings,
            sectors=sectors,
            radius=radius,
            delta=delta,
            delta_prime=delta_prime,
            threshold=threshold,
            window=window,
            gate=gate,
            heading_reference=heading_reference,
            diffusion=diffusion,
            decision=decision,
            correct_bias=correct_bias,
            n_threads=n_threads,
        )
        self.config = _Config(**validate(values, self._constraints))

    def __repr__(self) -> str:
        fields = ", ".join(f"{k}={v!r}" for k, v in vars(self.config).items())
        return f"TopologyAssociator({fields})"

    def _settings(self) -> TopologySettings:
        c = self.config
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
            decision=c.decision,
            n_threads=c.n_threads,
        )

    def associate(self, local: TrackTable, system: TrackTable) -> TrackAssociation:
        """Associate every scan of ``local`` with the system tracks of the same time (see
        :class:`~passive_assoc.assignment.TrackAssociator`); with ``correct_bias``, twice."""
        first = super().associate(local, system)
        if not self.config.correct_bias:
            return first
        corrected = unbias(local, first.bias)
        second = super().associate(corrected, system)
        # The bias reported is the first pass's: the second sees corrected pictures.
        return TrackAssociation(second.pairs, second.unpaired_local, second.unpaired_system, first.bias)


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
    if associator.config.heading_reference and tracks.velocity is None:
        raise ValueError("tracks: the heading-referenced grid needs velocities, and the table has none")
    settings = associator._settings()
    ids = np.ascontiguousarray(tracks.track, dtype=np.int64)
    positions = np.ascontiguousarray(tracks.position[:, :2], dtype=np.float64)
    velocity = None if tracks.velocity is None else np.ascontiguousarray(tracks.velocity[:, :2], dtype=np.float64)
    return _core.topology_vectors((ids, positions, velocity), settings)
