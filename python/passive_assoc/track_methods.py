"""One call for every track-to-track method (METHODS §4, §5), as :func:`associate_static` is
for the static methods: :func:`associate_tracks` builds the method's associator from its
settings and runs it over every scan.

* ``"topology"``: reference topology, invariant to azimuth bias (§4),
  :class:`~passive_assoc.TopologyAssociator`;
* ``"nearest"``: least total position distance, gated,
  :class:`~passive_assoc.NearestNeighbourAssociator`;
* ``"wavelet"``: radar (system) against ESM (local) tracks by wavelets and fuzzy factors
  (§5), :class:`~passive_assoc.WaveletFuzzyAssociator`;
* ``"chi2"``: the weighted χ² test on the tracks' states,
  :class:`~passive_assoc.radar_esm.Chi2TrackAssociator`;
* ``"combined"``: the wavelet coarse gate, then the χ² test on the whole state (the project's
  extension of §5), :class:`~passive_assoc.radar_esm.WaveletChi2Associator`.
"""

from __future__ import annotations

from typing import Any, Literal

from ._progress import ProgressArg
from .data import TrackTable
from .radar_esm import Chi2TrackAssociator, WaveletChi2Associator, WaveletFuzzyAssociator
from .roles import TrackAssociator
from .topology import TopologyAssociator
from .track_association import NearestNeighbourAssociator, TrackAssociation

__all__ = ["TRACK_METHODS", "TrackMethod", "associate_tracks", "track_associator"]

TrackMethod = Literal["topology", "nearest", "wavelet", "chi2", "combined"]

#: Each method's associator class.
TRACK_METHODS: dict[str, type[Any]] = {
    "topology": TopologyAssociator,
    "nearest": NearestNeighbourAssociator,
    "wavelet": WaveletFuzzyAssociator,
    "chi2": Chi2TrackAssociator,
    "combined": WaveletChi2Associator,
}


def track_associator(method: TrackMethod = "topology", **settings: Any) -> TrackAssociator:
    """The associator of ``method``, configured with ``settings`` (its class's parameters)."""
    if method not in TRACK_METHODS:
        raise ValueError(f"method: must be one of {', '.join(map(repr, TRACK_METHODS))}, got {method!r}")
    associator: TrackAssociator = TRACK_METHODS[method](**settings)
    return associator


def associate_tracks(
    *,
    local: TrackTable,
    system: TrackTable,
    method: TrackMethod = "topology",
    progress: ProgressArg = None,
    **settings: Any,
) -> TrackAssociation:
    """Associate every scan of ``local`` with the system picture by ``method``:
    ``track_associator(method, **settings).associate(local=local, system=system)``.

    ``progress`` as :meth:`TopologyAssociator.associate`'s.

    >>> import numpy as np, passive_assoc as pa
    >>> p = np.array([[0.0, 0.0], [10e3, 0.0], [0.0, 15e3]])
    >>> def picture(source):
    ...     return pa.TrackTable.from_arrays(np.full(3, source), np.arange(3), np.zeros(3), p)
    >>> out = pa.associate_tracks(local=picture(1), system=picture(0), method="nearest")
    >>> out.termination, bool((out.pairs.local_track == out.pairs.system_track).all()), len(out.pairs)
    ('completed', True, 3)
    """
    run: Any = track_associator(method, **settings)
    out: TrackAssociation = run.associate(local=local, system=system, progress=progress)
    return out
