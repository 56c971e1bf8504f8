"""Track-to-track association under azimuth bias by reference topology (METHODS §4, paper 002).

Radars with unknown azimuth biases of several degrees report local tracks whose absolute
positions disagree by kilometres, so distance-based association collapses — but the layout
of each track's neighbours survives a rotation. Around every track a disc of radius
``radius`` is cut into ``rings`` × ``sectors`` cells; occupied cells (other tracks of the same
source) spread into their neighbours (``delta`` along a sector, ``delta_prime`` along a ring);
the fuzzy closeness W of two such vectors (eq. 3) scores a (local, system) pair; W averaged
over the last ``window`` scans decides one-to-one pairs above ``threshold``·M·N (the paper's
decision, ``decision="assignment"`` or ``"per_system_track"``).

By default (``decision="fused"``, the project's extension) the topology pairs are only the
first step: they register each local picture on the system's (the relative bias, a rigid
transform), and the pairs are decided on the registered positions' Mahalanobis distance
together with the closeness, within a gate the tracks' covariances and the bias bound set
(``gate="auto"``), so a local track whose target the system does not see stays unpaired. The
core (``rust/core/src/topology``) does all of it with the GIL released.
"""

from __future__ import annotations

import math
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
from ..track_association.streaming import ScanSide, _planar_side

__all__ = ["TopologyAssociator", "topology_vectors"]

#: A number in [0, 1].
Unit = Annotated[float, Interval(float, 0.0, 1.0)]


@dataclass(eq=False)
class TopologyAssociator(StreamingTrackAssociator, Configurable):
    """Reference-topology track-to-track associator (METHODS §4).

    The published method is :meth:`paper` (the per-system-track rule on the closeness, every
    pair scored).

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
        λ as a fraction of M·N: a topology pair needs a window-averaged closeness above
        λ·M·N. The default 0.7 is the largest value that costs no recall on the paper's
        full-coverage scenes at ±5° bias (docs/experiments.md has the sensitivity table).
    window : int
        Scans over which W is averaged, the current one included; decisions are re-made
        every scan, so a wrong pairing is undone.
    gate : float or "auto", optional
        Which pairs are scored. ``"auto"`` (default): those the bias bound and the tracks'
        covariances allow, within ``2·2·max_range·sin(max_bias/2) + 3·sqrt(tr P_i + tr P_j)``
        metres (70 km plus three standard deviations at the defaults). A number: a position
        gate in metres. None: every pair (the paper's).
    heading_reference : bool
        Start each grid at the track's heading instead of north: a rotation of the whole
        picture then changes no vector. Needs velocities.
    diffusion : {"additive", "at_least"}
        Additive spread clipped at 1 (default), or the "at least Δ" reading.
    decision : {"fused", "assignment", "per_system_track"}
        ``"fused"`` (default, the project's extension, docs/methods.md §4): topology, then
        bias, then distance — the topology pairs propose each scan's registration of the
        local picture on the system's, and the pairs are decided on the registered
        Mahalanobis distance with the closeness, re-made with the refitted bias until they
        stop changing. ``"assignment"``: one-to-one pairs maximising the total closeness
        above λ. ``"per_system_track"``: the paper's rule, each system track takes its best
        local track above λ.
    max_bias_deg : float
        Each sensor's largest azimuth bias, degrees (two pictures turn by at most twice this
        relative to each other): bounds the gate and the registrations.
    max_range : float
        The sensors' range, metres: the lever of the bias bound.
    gate_probability : float
        The fused decision's gate: the probability that a true pair's registered positions
        pass it (χ² with 2 degrees of freedom, the bias estimate's own uncertainty included).
    topology_weight : float
        κ: the fused score of a gated pair is ``κ·W/(M·N) − m/2``, m its registered squared
        Mahalanobis distance; 0 decides on the distance alone.
    correct_bias : bool
        Associate twice: the second pass turns each local picture back by its estimated bias
        (rigid fit) before scoring; the bias reported is the two passes' turns composed.
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
    gate: Annotated[float | Literal["auto"] | None, Options("auto"), POSITIVE, None] = "auto"
    heading_reference: Annotated[bool, Boolean()] = False
    diffusion: Annotated[Literal["additive", "at_least"], Options("additive", "at_least")] = "additive"
    decision: Annotated[
        Literal["fused", "assignment", "per_system_track"], Options("fused", "assignment", "per_system_track")
    ] = "fused"
    max_bias_deg: Annotated[float, Interval(float, 0.0, 45.0)] = 5.0
    max_range: Annotated[float, POSITIVE] = 400e3
    gate_probability: Annotated[float, Interval(float, 0.0, 1.0, closed="neither")] = 0.999
    topology_weight: Annotated[float, Interval(float, 0.0, None)] = 10.0
    correct_bias: Annotated[bool, Boolean()] = False
    n_threads: Threads = None

    @classmethod
    def paper(cls, **changes: object) -> TopologyAssociator:
        """The published method (METHODS §4): the per-system-track rule on the window-averaged
        closeness, every pair scored (no gate); the grid, λ and window are the defaults (the
        paper gives none). ``changes`` override any parameter."""
        settings: dict[str, object] = {"decision": "per_system_track", "gate": None, **changes}
        return cls(**settings)  # type: ignore[arg-type]

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
            gate=None if isinstance(c.gate, str) else c.gate,
            auto_gate=c.gate == "auto",
            chi2_gate=None,
            decision=c.decision,
            max_bias_deg=c.max_bias_deg,
            max_range=c.max_range,
            gate_probability=c.gate_probability,
            topology_weight=c.topology_weight,
            n_threads=c.n_threads,
        )

    def _side(self, tracks: TrackTable, order: NDArray[np.int64]) -> ScanSide:
        """Planar positions and velocities, and the planar block of the position covariances
        (the fused decision's Mahalanobis distance and the auto gate read them)."""
        ids, positions, velocity, _, _ = _planar_side(tracks, order)
        covariances = None
        if tracks.covariance is not None and tracks.ndim >= 2:
            covariances = np.ascontiguousarray(tracks.covariance[order, :2, :2], dtype=np.float64)
        return ids, positions, velocity, None, covariances

    def associate(self, *, local: TrackTable, system: TrackTable, progress: ProgressArg = None) -> TrackAssociation:
        """Associate every scan of ``local`` with the system tracks of the same time (see
        :class:`~passive_assoc.track_association.StreamingTrackAssociator`); with
        ``correct_bias``, twice."""
        first = super().associate(local=local, system=system, progress=progress)
        if not self.correct_bias:
            return first
        corrected = unbias(local, first.bias)
        second = super().associate(local=corrected, system=system, progress=progress)
        # The second pass sees corrected pictures: its estimates are what the first left.
        bias = {
            source: compose(first.bias[source], b) if source in first.bias else b for source, b in second.bias.items()
        }
        return replace(second, bias=bias)


def compose(first: BiasEstimate, second: BiasEstimate) -> BiasEstimate:
    """The bias of a picture first turned back by ``first`` and then found off by ``second``:
    ``p = T₁(T₂(q))``, rotation ``θ₁ + θ₂``, translation ``R(θ₁)t₂ + t₁``. The uncertainty,
    the pairs and the reliability are the second estimate's (the first is a fixed turn)."""
    c, s = math.cos(first.rotation), math.sin(first.rotation)
    tx, ty = second.translation
    translation = (c * tx - s * ty + first.translation[0], s * tx + c * ty + first.translation[1])
    return replace(second, rotation=first.rotation + second.rotation, translation=translation)


def unbias(local: TrackTable, bias: dict[int, BiasEstimate]) -> TrackTable:
    """``local`` with each source's picture turned back by its bias: ``q = R(−θ)(p − t)``
    (velocities rotated, covariances turned with them: ``R(−θ) P R(−θ)ᵀ`` per block); sources
    without an estimate are left as they are."""
    position = np.array(local.position, dtype=np.float64)
    velocity = None if local.velocity is None else np.array(local.velocity, dtype=np.float64)
    acceleration = None if local.acceleration is None else np.array(local.acceleration, dtype=np.float64)
    covariance = None if local.covariance is None else np.array(local.covariance, dtype=np.float64)
    d = local.ndim
    for source, b in bias.items():
        rows = local.source == source
        c, s = np.cos(-b.rotation), np.sin(-b.rotation)
        turn = np.array([[c, -s], [s, c]])
        position[rows, :2] = (position[rows, :2] - np.asarray(b.translation)) @ turn.T
        for block in (velocity, acceleration):
            if block is not None:
                block[rows, :2] = block[rows, :2] @ turn.T
        if covariance is not None and d >= 2:
            # Each state block's planar axes turn: one rotation on the whole stacked state.
            full = np.eye(covariance.shape[1])
            for k in range(covariance.shape[1] // d):
                full[k * d : k * d + 2, k * d : k * d + 2] = turn
            covariance[rows] = full @ covariance[rows] @ full.T
    return TrackTable.from_arrays(
        local.source,
        local.track,
        local.time,
        position,
        velocity=velocity,
        acceleration=acceleration,
        covariance=covariance,
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
