"""The four roles the library's methods play, as Stone Soup has ``Initiator`` and
``DataAssociator``: every method of a role has the same call, with the same argument names
for the same meaning, and returns a result that starts with ``termination``, ``success`` and
``message`` (:class:`~passive_assoc.outcome.Outcome`).

* :class:`Initiator` — ``initiate(measurements, sensors, *, t0)`` → tracks and clutter:
  :class:`~passive_assoc.FuzzyTrackInitiator` (§1).
* :class:`ScanAssociator` — ``associate(measurements, sensors)`` → one scan's targets and
  clutter: :class:`~passive_assoc.StaticAssociator` (§2).
* :class:`Locator` — ``locate(measurements, sensors)`` → located targets and clutter:
  :class:`~passive_assoc.FormationLocator` (§3).
* :class:`TrackAssociator` — ``associate(*, local, system)`` → pairs, unpaired tracks and
  biases: :class:`~passive_assoc.TopologyAssociator` (§4),
  :class:`~passive_assoc.NearestNeighbourAssociator`,
  :class:`~passive_assoc.WaveletFuzzyAssociator` (§5),
  :class:`~passive_assoc.radar_esm.Chi2TrackAssociator` and
  :class:`~passive_assoc.radar_esm.WaveletChi2Associator`.

The protocols are structural: a class of your own with the same method is accepted wherever
the library takes a role (``isinstance(obj, TrackAssociator)`` checks the method is there).
"""

from __future__ import annotations

from typing import TYPE_CHECKING, Protocol, runtime_checkable

if TYPE_CHECKING:
    from .data import MeasurementTable, SensorNetwork, TrackTable
    from .formation import FormationResult
    from .fti import InitiationResult
    from .static_los import StaticAssociation
    from .track_association import TrackAssociation

__all__ = ["Initiator", "Locator", "ScanAssociator", "TrackAssociator"]


@runtime_checkable
class Initiator(Protocol):
    """Finds the targets in a window of several scans of angle-only measurements, and their
    initial states: every measurement ends in one track or in the clutter set."""

    def initiate(
        self, measurements: MeasurementTable, sensors: SensorNetwork, *, t0: float | None = None
    ) -> InitiationResult: ...


@runtime_checkable
class ScanAssociator(Protocol):
    """Associates one scan of angle-only reports across sensors: every report ends in one
    target or in the clutter set."""

    def associate(self, measurements: MeasurementTable, sensors: SensorNetwork) -> StaticAssociation: ...


@runtime_checkable
class Locator(Protocol):
    """Associates and locates targets in one snapshot of bearings (formation targets with
    emitter attributes): every report ends in one located group or in the clutter set."""

    def locate(self, measurements: MeasurementTable, sensors: SensorNetwork) -> FormationResult: ...


@runtime_checkable
class TrackAssociator(Protocol):
    """Pairs local tracks with the system picture scan by scan: every track of every scan
    ends in one pair or unpaired. Both sides are keyword-only and named alike by every
    implementation."""

    def associate(self, *, local: TrackTable, system: TrackTable) -> TrackAssociation: ...
